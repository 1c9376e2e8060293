// Finding the driver's functions: from the real libraries, never from ourselves.
// Resolved once per opcode on first use; libraries are opened only then, so a process that
// never calls GL (a shell the program starts) never loads them.
#include <dlfcn.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "glcast_commands.h"
#include "common/immortal.h"
#include "interceptor/dl_hooks.h"
#include "interceptor/shim.h"
#include "glcast_gl_api.h"
#include "protocol/command_info.h"

namespace glcast {

static std::atomic<void*> g_real[kOpcodeCount];
static void* const kMissing = reinterpret_cast<void*>(uintptr_t(1));

static void* open_real(const char* const* names) {
    for (const char* const* n = names; *n; ++n)
        if (void* h = real_dlopen(*n, RTLD_LAZY | RTLD_LOCAL)) return h;
    return nullptr;
}

static void* libgl() {
    static void* h = [] { const char* n[] = {"libGL.so.1", "libGL.so", nullptr}; return open_real(n); }();
    return h;
}
static void* libopengl() {
    static void* h = [] { const char* n[] = {"libOpenGL.so.0", "libOpenGL.so", nullptr}; return open_real(n); }();
    return h;
}
static void* libegl() {
    static void* h = [] { const char* n[] = {"libEGL.so.1", "libEGL.so", nullptr}; return open_real(n); }();
    return h;
}

using GetProc = void* (*)(const char*);

void* real_proc_by_name(const char* name) {
    void* p = nullptr;
    if (std::strncmp(name, "egl", 3) == 0) {
        if (void* h = libegl()) p = real_dlsym(h, name);
        return p;
    }
    if (std::strncmp(name, "glX", 3) == 0) {
        if (void* h = libgl()) p = real_dlsym(h, name);
        if (!p && libgl()) {
            static const auto gpa = reinterpret_cast<GetProc>(real_dlsym(libgl(), "glXGetProcAddressARB"));
            if (gpa) p = gpa(name);
        }
        return p;
    }
    // GL: the ABI libraries export the core functions; extensions come from GetProcAddress of
    // whichever window-system library the program uses (EGL first if it has loaded it).
    if (void* h = libopengl()) p = real_dlsym(h, name);
    if (!p && libgl()) p = real_dlsym(libgl(), name);
    if (!p && egl_in_use() && libegl()) {
        static const auto gpa = reinterpret_cast<GetProc>(real_dlsym(libegl(), "eglGetProcAddress"));
        if (gpa) p = gpa(name);
    }
    if (!p && libgl()) {
        static const auto gpa = reinterpret_cast<GetProc>(real_dlsym(libgl(), "glXGetProcAddressARB"));
        if (gpa) p = gpa(name);
    }
    return p;
}

void* real_proc(uint32_t opcode) {
    void* p = g_real[opcode].load(std::memory_order_acquire);
    if (p) return p == kMissing ? nullptr : p;
    const char* name = command_info(opcode)->name;
    p = real_proc_by_name(name);
    if (p == kEntryPoints[opcode]) {
        std::fprintf(stderr, "glcast: symbol lookup recursion: %s resolved to glcast itself\n", name);
        std::abort();
    }
    g_real[opcode].store(p ? p : kMissing, std::memory_order_release);
    return p;
}

const GlApi& real_gl() {
    static const Immortal<GlApi> gl([](void*, uint32_t opcode) { return real_proc(opcode); }, nullptr);
    return *gl;
}

}  // namespace glcast
