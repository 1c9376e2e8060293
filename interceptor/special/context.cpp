// Contexts and frames. Tuples carry small context ids instead of driver handles; a
// kSynthContext tuple after each creation call says which handle got which id, and a
// kSynthDrawableSize tuple says how big the window is whenever that changes. A frame ends
// at every swap, after the swap's own tuple.
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>

#include "glcast_commands.h"
#include "glcast_gl_api.h"
#include "glcast_synthetic_encode.h"
#include "glcast_encode.h"
#include "glcast_special.h"
#include "common/immortal.h"
#include "interceptor/dl_hooks.h"
#include "interceptor/lifetime.h"
#include "interceptor/shim.h"
#include "interceptor/config.h"
#include "interceptor/shim_internal.h"
#include "interceptor/snapshot.h"
#include "protocol/format.h"
#include "protocol/size_queries.h"

namespace glcast {
namespace {

std::mutex g_mutex;
Immortal<std::map<const void*, uint32_t>> g_context_ids;
uint32_t g_next_id = 1;
Immortal<std::map<uint64_t, std::pair<int32_t, int32_t>>> g_drawable_sizes;

// Asking the window system for a drawable's size is a server round trip: at a swap it is
// done at most every 100 ms per thread (a resize reaches the stream within that time), and
// always at make-current.
bool size_check_due(bool force) {
    static thread_local std::chrono::steady_clock::time_point last;
    const auto now = std::chrono::steady_clock::now();
    if (!force && now - last < std::chrono::milliseconds(100)) return false;
    last = now;
    return true;
}

uint32_t id_of(const void* handle) {
    std::lock_guard lock(g_mutex);
    auto it = g_context_ids->find(handle);
    return it == g_context_ids->end() ? 0 : it->second;
}

bool glx_attribs_ask_es(const int* attribs) {
    for (const int* a = attribs; a && a[0] != None; a += 2)
        if (a[0] == GLX_CONTEXT_PROFILE_MASK_ARB) return a[1] & GLX_CONTEXT_ES_PROFILE_BIT_EXT;
    return false;
}

// Of the visual or config a context was made for: a slave makes its window framebuffer the same
// (a program reads its alpha back, asks its depth and stencil sizes). What a slave has without
// being told (one sample, no alpha, 24 depth and 8 stencil bits) goes without a tuple.
struct FramebufferBits {
    int samples = 0, alpha = 0, depth = 24, stencil = 8;
};

void created(CallScope& scope, const void* handle, const void* share, ContextApi api, const FramebufferBits& bits) {
    if (!handle) return;
    if (bits.samples > 1) {
        encode_synth_context_format(scope.begin_synthetic(kSynthContextFormat), reinterpret_cast<uintptr_t>(handle),
                                    bits.samples);
        scope.commit_synthetic();
    }
    if (bits.alpha != 0 || bits.depth != 24 || bits.stencil != 8) {
        encode_synth_context_bits(scope.begin_synthetic(kSynthContextBits), reinterpret_cast<uintptr_t>(handle),
                                  bits.alpha, bits.depth, bits.stencil);
        scope.commit_synthetic();
    }
    uint32_t id;
    {
        std::lock_guard lock(g_mutex);
        id = (*g_context_ids)[handle] = g_next_id++;
    }
    encode_synth_context(scope.begin_synthetic(kSynthContext), id, reinterpret_cast<uintptr_t>(handle), id_of(share), uint8_t(api));
    scope.commit_synthetic();
}

void destroyed(const void* handle) {
    std::lock_guard lock(g_mutex);
    g_context_ids->erase(handle);
}

void drawable_size(CallScope& scope, uint64_t drawable, int32_t w, int32_t h) {
    {
        std::lock_guard lock(g_mutex);
        auto& size = (*g_drawable_sizes)[drawable];
        if (size == std::make_pair(w, h)) return;
        size = {w, h};
    }
    encode_synth_drawable_size(scope.begin_synthetic(kSynthDrawableSize), drawable, w, h);
    scope.commit_synthetic();
}

void glx_drawable_size(CallScope& scope, Display* dpy, GLXDrawable drawable, bool force) {
    if (!dpy || !drawable || !size_check_due(force)) return;
    static const auto query = reinterpret_cast<PFNGLXQUERYDRAWABLEPROC>(real_proc(OP_glXQueryDrawable));
    unsigned w = 0, h = 0;
    if (query) {
        query(dpy, drawable, GLX_WIDTH, &w);
        query(dpy, drawable, GLX_HEIGHT, &h);
    }
    drawable_size(scope, drawable, int32_t(w), int32_t(h));
}

void egl_drawable_size(CallScope& scope, EGLDisplay dpy, EGLSurface surface, bool force) {
    if (!dpy || !surface || !size_check_due(force)) return;
    static const auto query = reinterpret_cast<PFNEGLQUERYSURFACEPROC>(real_proc(OP_eglQuerySurface));
    EGLint w = 0, h = 0;
    if (query) {
        query(dpy, surface, EGL_WIDTH, &w);
        query(dpy, surface, EGL_HEIGHT, &h);
    }
    drawable_size(scope, reinterpret_cast<uintptr_t>(surface), w, h);
}

// `get(attribute, value)`: true when the driver answered.
template <class Get>
FramebufferBits framebuffer_bits(Get&& get, int samples, int alpha, int depth, int stencil) {
    FramebufferBits bits;
    int v = 0;
    if (get(samples, v)) bits.samples = v;
    if (get(alpha, v)) bits.alpha = v;
    if (get(depth, v)) bits.depth = v;
    if (get(stencil, v)) bits.stencil = v;
    return bits;
}

FramebufferBits glx_visual_bits(Display* dpy, XVisualInfo* vis) {
    static const auto get = reinterpret_cast<int (*)(Display*, XVisualInfo*, int, int*)>(real_proc(OP_glXGetConfig));
    if (!get || !dpy || !vis) return {};
    return framebuffer_bits([&](int a, int& v) { return get(dpy, vis, a, &v) == 0; }, GLX_SAMPLES, GLX_ALPHA_SIZE,
                            GLX_DEPTH_SIZE, GLX_STENCIL_SIZE);
}

FramebufferBits glx_config_bits(Display* dpy, GLXFBConfig config) {
    static const auto get = reinterpret_cast<PFNGLXGETFBCONFIGATTRIBPROC>(real_proc(OP_glXGetFBConfigAttrib));
    if (!get || !dpy || !config) return {};
    return framebuffer_bits([&](int a, int& v) { return get(dpy, config, a, &v) == 0; }, GLX_SAMPLES, GLX_ALPHA_SIZE,
                            GLX_DEPTH_SIZE, GLX_STENCIL_SIZE);
}

// The shim's own queries must ask only what the context's API has (an OpenGL ES context lacks
// some pixel-store values): a query it lacks would leave an error for the program's glGetError.
void made_current(uint32_t id) {
    set_current_context(id);
    const bool asks = id && real_gl().has(OP_glGetString);
    thread_state().es_version = asks ? gles_version(reinterpret_cast<const char*>(real_gl().glGetString(GL_VERSION))) : 0;
}

template <class F>
void record(CallScope& scope, F&& f) {
    if (scope.recording()) scope.record(f);
}

}  // namespace

GLXContext special::glXCreateContext(glXCreateContext_fn real, CallScope& scope, Display* dpy, XVisualInfo* vis,
                                     GLXContext shareList, Bool direct) {
    GLXContext ret = real(dpy, vis, shareList, direct);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) { encode_glXCreateContext(e, sz, dpy, vis, shareList, direct, ret); });
    created(scope, ret, shareList, ContextApi::Glx, glx_visual_bits(dpy, vis));
    return ret;
}

GLXContext special::glXCreateNewContext(glXCreateNewContext_fn real, CallScope& scope, Display* dpy,
                                        GLXFBConfig config, int render_type, GLXContext share_list, Bool direct) {
    GLXContext ret = real(dpy, config, render_type, share_list, direct);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) {
        encode_glXCreateNewContext(e, sz, dpy, config, render_type, share_list, direct, ret);
    });
    created(scope, ret, share_list, ContextApi::Glx, glx_config_bits(dpy, config));
    return ret;
}

GLXContext special::glXCreateContextAttribsARB(glXCreateContextAttribsARB_fn real, CallScope& scope, Display* dpy,
                                               GLXFBConfig config, GLXContext share_context, Bool direct,
                                               const int* attrib_list) {
    GLXContext ret = real(dpy, config, share_context, direct, attrib_list);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) {
        encode_glXCreateContextAttribsARB(e, sz, dpy, config, share_context, direct, attrib_list, ret);
    });
    created(scope, ret, share_context, glx_attribs_ask_es(attrib_list) ? ContextApi::GlxEs : ContextApi::Glx,
            glx_config_bits(dpy, config));
    return ret;
}

Bool special::glXMakeCurrent(glXMakeCurrent_fn real, CallScope& scope, Display* dpy, GLXDrawable drawable,
                             GLXContext ctx) {
    Bool ret = real(dpy, drawable, ctx);
    if (ret && g_recording) made_current(ctx ? id_of(ctx) : 0);
    if (!scope.recording()) return ret;
    if (ret && ctx) glx_drawable_size(scope, dpy, drawable, true);  // the slave sizes its window first
    record(scope, [&](Encoder& e, SizeQueries& sz) { encode_glXMakeCurrent(e, sz, dpy, drawable, ctx, ret); });
    return ret;
}

Bool special::glXMakeContextCurrent(glXMakeContextCurrent_fn real, CallScope& scope, Display* dpy,
                                    GLXDrawable draw, GLXDrawable read, GLXContext ctx) {
    Bool ret = real(dpy, draw, read, ctx);
    if (ret && g_recording) made_current(ctx ? id_of(ctx) : 0);
    if (!scope.recording()) return ret;
    if (ret && ctx) glx_drawable_size(scope, dpy, draw, true);
    record(scope, [&](Encoder& e, SizeQueries& sz) { encode_glXMakeContextCurrent(e, sz, dpy, draw, read, ctx, ret); });
    return ret;
}

void special::glXDestroyContext(glXDestroyContext_fn real, CallScope& scope, Display* dpy, GLXContext ctx) {
    if (g_recording) forget_mappings_of_context(id_of(ctx));
    real(dpy, ctx);
    record(scope, [&](Encoder& e, SizeQueries& sz) { encode_glXDestroyContext(e, sz, dpy, ctx); });
    if (g_recording) destroyed(ctx);
}

// In snapshot mode, swaps of several threads are serialized so that the snapshots are numbered
// in the order the swaps enter the stream (the replay numbers frames that way).
std::mutex g_snapshot_swap_mutex;
std::unique_lock<std::mutex> snapshot_lock() {
    return shim_config().snapshot_dir.empty() || in_forked_child() ? std::unique_lock<std::mutex>()
                                              : std::unique_lock<std::mutex>(g_snapshot_swap_mutex);
}

void special::glXSwapBuffers(glXSwapBuffers_fn real, CallScope& scope, Display* dpy, GLXDrawable drawable) {
    const auto serialized = snapshot_lock();
    if (!shim_config().snapshot_dir.empty() && !in_forked_child() && thread_state().depth == 1) {
        static const auto query = reinterpret_cast<PFNGLXQUERYDRAWABLEPROC>(real_proc(OP_glXQueryDrawable));
        unsigned w = 0, h = 0;
        query(dpy, drawable, GLX_WIDTH, &w);
        query(dpy, drawable, GLX_HEIGHT, &h);
        snapshot_back_buffer(int(w), int(h));
    }
    if (!scope.recording()) return real(dpy, drawable);
    glx_drawable_size(scope, dpy, drawable, false);
    real(dpy, drawable);
    ship_mapped_writes_at_frame_end(scope);
    scope.record([&](Encoder& e, SizeQueries& sz) { encode_glXSwapBuffers(e, sz, dpy, drawable); });
    on_frame_end();
}

EGLContext special::eglCreateContext(eglCreateContext_fn real, CallScope& scope, EGLDisplay dpy, EGLConfig config,
                                     EGLContext share_context, const EGLint* attrib_list) {
    note_egl_in_use();
    EGLContext ret = real(dpy, config, share_context, attrib_list);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) {
        encode_eglCreateContext(e, sz, dpy, config, share_context, attrib_list, ret);
    });
    static const auto get = reinterpret_cast<PFNEGLGETCONFIGATTRIBPROC>(real_proc_by_name("eglGetConfigAttrib"));
    FramebufferBits bits;
    if (ret && get && config)
        bits = framebuffer_bits([&](EGLint a, int& v) { return get(dpy, config, a, &v) == EGL_TRUE; }, EGL_SAMPLES,
                                EGL_ALPHA_SIZE, EGL_DEPTH_SIZE, EGL_STENCIL_SIZE);
    static const auto query = reinterpret_cast<PFNEGLQUERYCONTEXTPROC>(real_proc_by_name("eglQueryContext"));
    EGLint client = EGL_OPENGL_API;
    if (ret && query && !query(dpy, ret, EGL_CONTEXT_CLIENT_TYPE, &client)) client = EGL_OPENGL_API;
    created(scope, ret, share_context, client == EGL_OPENGL_ES_API ? ContextApi::EglEs : ContextApi::Egl, bits);
    return ret;
}

EGLBoolean special::eglMakeCurrent(eglMakeCurrent_fn real, CallScope& scope, EGLDisplay dpy, EGLSurface draw,
                                   EGLSurface read, EGLContext ctx) {
    note_egl_in_use();
    EGLBoolean ret = real(dpy, draw, read, ctx);
    if (ret && g_recording) made_current(ctx ? id_of(ctx) : 0);
    if (!scope.recording()) return ret;
    if (ret && ctx) egl_drawable_size(scope, dpy, draw, true);
    record(scope, [&](Encoder& e, SizeQueries& sz) { encode_eglMakeCurrent(e, sz, dpy, draw, read, ctx, ret); });
    return ret;
}

EGLBoolean special::eglDestroyContext(eglDestroyContext_fn real, CallScope& scope, EGLDisplay dpy, EGLContext ctx) {
    if (g_recording) forget_mappings_of_context(id_of(ctx));
    EGLBoolean ret = real(dpy, ctx);
    record(scope, [&](Encoder& e, SizeQueries& sz) { encode_eglDestroyContext(e, sz, dpy, ctx, ret); });
    if (g_recording) destroyed(ctx);
    return ret;
}

EGLBoolean special::eglSwapBuffers(eglSwapBuffers_fn real, CallScope& scope, EGLDisplay dpy, EGLSurface surface) {
    const auto serialized = snapshot_lock();
    if (!shim_config().snapshot_dir.empty() && !in_forked_child() && thread_state().depth == 1) {
        static const auto query = reinterpret_cast<PFNEGLQUERYSURFACEPROC>(real_proc(OP_eglQuerySurface));
        EGLint w = 0, h = 0;
        query(dpy, surface, EGL_WIDTH, &w);
        query(dpy, surface, EGL_HEIGHT, &h);
        snapshot_back_buffer(w, h);
    }
    if (!scope.recording()) return real(dpy, surface);
    egl_drawable_size(scope, dpy, surface, false);
    EGLBoolean ret = real(dpy, surface);
    ship_mapped_writes_at_frame_end(scope);
    scope.record([&](Encoder& e, SizeQueries& sz) { encode_eglSwapBuffers(e, sz, dpy, surface, ret); });
    on_frame_end();
    return ret;
}

}  // namespace glcast
