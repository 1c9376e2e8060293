#include "interceptor/dl_hooks.h"

#include <dlfcn.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "glcast_commands.h"
#include "interceptor/lifetime.h"
#include "interceptor/shim.h"
#include "protocol/command_info.h"

namespace glcast {

using DlopenFn = void* (*)(const char*, int);
using DlsymFn = void* (*)(void*, const char*);

static DlsymFn dlsym_fn() {
    // dlvsym is not interposed; glibc 2.34 moved dlsym into libc under a new version.
    static const DlsymFn fn = [] {
        void* p = dlvsym(RTLD_NEXT, "dlsym", "GLIBC_2.34");
        if (!p) p = dlvsym(RTLD_NEXT, "dlsym", "GLIBC_2.2.5");
        if (!p) { std::fprintf(stderr, "glcast: cannot find the real dlsym\n"); std::abort(); }
        return reinterpret_cast<DlsymFn>(p);
    }();
    return fn;
}

void* real_dlsym(void* handle, const char* name) { return dlsym_fn()(handle, name); }

void* real_dlopen(const char* file, int flags) {
    static const DlopenFn fn = reinterpret_cast<DlopenFn>(real_dlsym(RTLD_NEXT, "dlopen"));
    return fn(file, flags);
}

static std::atomic<bool> g_egl{false};
bool egl_in_use() { return g_egl.load(std::memory_order_relaxed); }
void note_egl_in_use() { g_egl.store(true, std::memory_order_relaxed); }

// Handles of GL libraries the program opened itself; dlsym on them returns our wrappers.
static std::mutex g_mutex;
[[maybe_unused]] static const bool g_mutex_held_across_fork = (hold_across_fork(g_mutex), true);  // a child may dlopen
static void* g_gl_handles[16];
static int g_gl_handle_count = 0;

static bool is_gl_library(const char* file) {
    if (!file) return false;
    const char* base = std::strrchr(file, '/');
    base = base ? base + 1 : file;
    for (const char* prefix : {"libGL.so", "libGLX.so", "libOpenGL.so", "libEGL.so", "libGLESv2.so", "libGLESv1_CM.so"})
        if (std::strncmp(base, prefix, std::strlen(prefix)) == 0) return true;
    return false;
}

static bool is_gl_handle(void* handle) {
    std::lock_guard lock(g_mutex);
    for (int i = 0; i < g_gl_handle_count; ++i)
        if (g_gl_handles[i] == handle) return true;
    return false;
}

}  // namespace glcast

using namespace glcast;

extern "C" __attribute__((visibility("default"))) void* dlopen(const char* file, int flags) {
    // RTLD_DEEPBIND would make the library prefer its own symbols over ours.
    void* h = real_dlopen(file, is_gl_library(file) ? flags & ~RTLD_DEEPBIND : flags);
    if (h && is_gl_library(file)) {
        if (std::strstr(file, "libEGL")) note_egl_in_use();
        std::lock_guard lock(g_mutex);
        bool known = false;
        for (int i = 0; i < g_gl_handle_count; ++i) known |= g_gl_handles[i] == h;
        if (!known && g_gl_handle_count < int(sizeof g_gl_handles / sizeof *g_gl_handles))
            g_gl_handles[g_gl_handle_count++] = h;
    }
    return h;
}

extern "C" __attribute__((visibility("default"))) void* dlsym(void* handle, const char* name) {
    void* real = real_dlsym(handle, name);
    if (real && (name[0] == 'g' || name[0] == 'e') &&
        (std::strncmp(name, "gl", 2) == 0 || std::strncmp(name, "egl", 3) == 0) &&
        (handle == RTLD_DEFAULT || handle == RTLD_NEXT || is_gl_handle(handle))) {
        const int op = opcode_by_name(name);
        if (op >= 0) return kEntryPoints[op];
    }
    return real;
}
