// dlopen/dlsym interposition, so programs that load GL themselves (GLFW, SDL, Quake-style
// engines) get glcast's entry points too (apitrace's dlsym.cpp, VirtualGL's dlfaker).
#pragma once

namespace glcast {
void* real_dlopen(const char* file, int flags);
void* real_dlsym(void* handle, const char* name);
bool egl_in_use();   // the program has loaded libEGL or called an EGL entry point
void note_egl_in_use();
}  // namespace glcast
