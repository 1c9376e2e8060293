// Contexts, the window framebuffer, frames, and glcast's synthetic tuples on the slave.
//
// The program's window framebuffer (name 0) is the backend's default framebuffer, at the size
// the master's drawable had (slave/backend.h says why it is not an FBO).
#include <cinttypes>
#include <cstdio>

#include "common/gl_headers.h"
#include "common/window_readback.h"
#include "slave/effects_frame.h"
#include "slave/replayer.h"

namespace glcast::slave {
namespace {

int32_t attrib_value(const PtrRecord& list, int64_t key, int32_t fallback, size_t elem_bytes) {
    if (list.tag != PtrTag::Data) return fallback;
    for (uint32_t k = 0; k + 1 < list.count; k += 2) {
        int64_t kk = 0, vv = 0;
        std::memcpy(&kk, list.data + k * elem_bytes, elem_bytes);
        std::memcpy(&vv, list.data + (k + 1) * elem_bytes, elem_bytes);
        if (elem_bytes == 4) { kk = int32_t(kk); vv = int32_t(vv); }
        if (kk == key) return int32_t(vv);
    }
    return fallback;
}

ContextRequest glx_request(const PtrRecord& attribs) {
    ContextRequest r;
    r.major = attrib_value(attribs, GLX_CONTEXT_MAJOR_VERSION_ARB, 0, 4);
    r.minor = attrib_value(attribs, GLX_CONTEXT_MINOR_VERSION_ARB, 0, 4);
    const int flags = attrib_value(attribs, GLX_CONTEXT_FLAGS_ARB, 0, 4);
    const int profile = attrib_value(attribs, GLX_CONTEXT_PROFILE_MASK_ARB, GLX_CONTEXT_CORE_PROFILE_BIT_ARB, 4);
    r.core = r.major * 10 + r.minor >= 32 && (profile & GLX_CONTEXT_CORE_PROFILE_BIT_ARB);
    r.forward_compatible = flags & GLX_CONTEXT_FORWARD_COMPATIBLE_BIT_ARB;
    r.debug = flags & GLX_CONTEXT_DEBUG_BIT_ARB;
    if (r.major == 1 && r.minor == 0) r.major = 0;  // GLX's default: any compatible context
    return r;
}

ContextRequest egl_request(const PtrRecord& attribs) {
    ContextRequest r;
    r.major = attrib_value(attribs, EGL_CONTEXT_MAJOR_VERSION, 0, 4);
    r.minor = attrib_value(attribs, EGL_CONTEXT_MINOR_VERSION, 0, 4);
    const int profile = attrib_value(attribs, EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, 4);
    r.core = r.major * 10 + r.minor >= 32 && (profile & EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT);
    r.forward_compatible = attrib_value(attribs, EGL_CONTEXT_OPENGL_FORWARD_COMPATIBLE, 0, 4);
    r.debug = attrib_value(attribs, EGL_CONTEXT_OPENGL_DEBUG, 0, 4);
    if (r.major == 1 && r.minor == 0) r.major = 0;
    return r;
}

template <class T>
T read(ByteReader& r) { return r.get<T>(); }

}  // namespace

void Replayer::window_system(const Call& c) {
    switch (c.opcode) {
    case OP_glXCreateContext:
    case OP_glXCreateNewContext:
        if (c.ret.bits) pending_[c.ret.bits] = ContextRequest{};
        break;
    case OP_glXCreateContextAttribsARB:
        if (c.ret.bits) pending_[c.ret.bits] = glx_request(c.args[4].ptr);
        break;
    case OP_eglCreateContext:
        if (c.ret.bits) pending_[c.ret.bits] = egl_request(c.args[3].ptr);
        break;
    case OP_glXMakeCurrent:
    case OP_glXMakeContextCurrent:
    case OP_eglMakeCurrent:
        if (c.ret.bits) make_current(c.context, c.args[1].bits);  // else the master's call failed
        break;
    case OP_glXSwapBuffers:
    case OP_eglSwapBuffers:
        end_frame();
        break;
    case OP_glXDestroyContext:
    case OP_eglDestroyContext: {
        auto it = ids_by_handle_.find(c.args[1].bits);
        if (it == ids_by_handle_.end()) break;
        const uint32_t id = it->second;
        if (current_ && current_->id == id) make_current(0, 0);
        backend_->destroy_context(id);
        contexts_.erase(id);
        ids_by_handle_.erase(it);
        break;
    }
    default:
        break;  // queries and configuration: the slave has its own window system
    }
}

void Replayer::window_size(uint64_t drawable, int& width, int& height) const {
    if (options_.tile.enabled) {  // a tile of the wall, whatever the master's window
        width = options_.tile.width;
        height = options_.tile.height;
        return;
    }
    auto it = drawable_sizes_.find(drawable);
    width = options_.width ? options_.width : it != drawable_sizes_.end() ? it->second.first : 0;
    height = options_.height ? options_.height : it != drawable_sizes_.end() ? it->second.second : 0;
}

void Replayer::apply_window_rects() {
    SlaveContext& ctx = current();
    const TileMapping& t = options_.tile;
    const int32_t* v = ctx.viewport;
    const int32_t* s = ctx.scissor;
    const auto viewport = gl<decltype(&::glViewport)>(OP_glViewport);
    const auto scissor = gl<decltype(&::glScissor)>(OP_glScissor);
    if (!t.enabled || !ctx.drawing_to_window) {
        viewport(v[0], v[1], v[2], v[3]);
        scissor(s[0], s[1], s[2], s[3]);
        return;
    }
    const int W = ctx.master_width, H = ctx.master_height;
    viewport(GLint(t.map_x(v[0], W)), GLint(t.map_y(v[1], H)), GLsizei(t.map_w(v[0], v[2], W)),
             GLsizei(t.map_h(v[1], v[3], H)));
    scissor(GLint(t.map_x(s[0], W)), GLint(t.map_y(s[1], H)), GLsizei(t.map_w(s[0], s[2], W)),
            GLsizei(t.map_h(s[1], s[3], H)));
}

void Replayer::make_current(uint32_t id, uint64_t drawable) {
    std::string error;
    if (id == 0) {
        backend_->make_current(0, 0, 0, error);
        current_ = nullptr;
        return;
    }
    auto it = contexts_.find(id);
    if (it == contexts_.end()) throw ReplayError("make-current of context " + std::to_string(id) + ", which does not exist");
    SlaveContext& ctx = *it->second;
    ctx.drawable = drawable;
    int w = 0, h = 0;
    window_size(drawable, w, h);  // the shim sends the size before the make-current
    if (!backend_->make_current(id, w, h, error)) throw ReplayError(error);
    current_ = &ctx;
    ctx.width = w;
    ctx.height = h;
    auto size = drawable_sizes_.find(drawable);
    if (size != drawable_sizes_.end()) {
        ctx.master_width = size->second.first;
        ctx.master_height = size->second.second;
    }
    if (!ctx.made_current) {
        // GLX starts a context with viewport and scissor box covering the window it is first
        // made current to; backends differ (a 1x1 buffer, a window created at another size).
        ctx.made_current = true;
        GLboolean db = GL_TRUE;
        gl<decltype(&::glGetBooleanv)>(OP_glGetBooleanv)(GL_DOUBLEBUFFER, &db);
        ctx.double_buffered = db;
        const int mw = ctx.master_width ? ctx.master_width : w, mh = ctx.master_height ? ctx.master_height : h;
        if (mw > 0 && mh > 0) {
            const int32_t window[4] = {0, 0, mw, mh};
            std::memcpy(ctx.viewport, window, sizeof window);
            std::memcpy(ctx.scissor, window, sizeof window);
            apply_window_rects();
        }
    }
    if (!first_context_done_) {
        first_context_done_ = true;
        if (on_first_context) on_first_context(*this);
    }
}

void Replayer::end_frame() {
    SlaveContext& ctx = current();
    if (options_.effects.any()) run_effects();
    if (frame_ >= options_.first_frame && frame_ <= options_.last_frame && on_frame && ctx.width > 0 && ctx.height > 0) {
        ReadbackGl readback;
        readback.GetIntegerv = gl<decltype(readback.GetIntegerv)>(OP_glGetIntegerv);
        readback.BindFramebuffer = gl<decltype(readback.BindFramebuffer)>(OP_glBindFramebuffer);
        readback.BindBuffer = gl<decltype(readback.BindBuffer)>(OP_glBindBuffer);
        readback.ReadBuffer = gl<decltype(readback.ReadBuffer)>(OP_glReadBuffer);
        readback.PixelStorei = gl<decltype(readback.PixelStorei)>(OP_glPixelStorei);
        readback.ReadPixels = gl<decltype(readback.ReadPixels)>(OP_glReadPixels);
        const int w = ctx.width, h = ctx.height;
        const std::vector<uint8_t> rgba = read_window(readback, ctx.double_buffered ? GL_BACK : GL_FRONT, w, h);
        on_frame(frame_, w, h, rgba);
    }
    if (before_present) before_present(frame_);
    backend_->present();
    frame_++;
    stats_.frames++;
    // A resize the master announced before this swap applies from the next frame on.
    int w = 0, h = 0;
    window_size(ctx.drawable, w, h);
    auto size = drawable_sizes_.find(ctx.drawable);
    const bool master_resized = size != drawable_sizes_.end() &&
                                (size->second.first != ctx.master_width || size->second.second != ctx.master_height);
    if (((w != ctx.width || h != ctx.height) && w > 0 && h > 0) || master_resized) make_current(ctx.id, ctx.drawable);
}

// --- synthetic tuples ------------------------------------------------------------------

void Replayer::synthetic(const Call& c) {
    ByteReader r(c.body, c.body_bytes, c.offset + kTupleHeaderBytes);
    switch (c.opcode) {
    case kSynthContext: {
        const uint32_t id = r.get<uint32_t>();
        const uint64_t handle = r.get<uint64_t>();
        const uint32_t share = r.get<uint32_t>();
        const ContextRequest request = pending_.count(handle) ? pending_[handle] : ContextRequest{};
        pending_.erase(handle);
        if (share && !contexts_.count(share))
            throw ReplayError("context " + std::to_string(id) + " shares with context " + std::to_string(share) +
                              ", which does not exist");
        std::string error;
        if (!backend_->create_context(id, share, request, error)) throw ReplayError(error);
        auto ctx = std::make_unique<SlaveContext>();
        ctx->id = id;
        ctx->handle = handle;
        ctx->names.shared = share ? contexts_[share]->names.shared : std::make_shared<ShareGroup>();
        contexts_[id] = std::move(ctx);
        ids_by_handle_[handle] = id;
        break;
    }
    case kSynthDrawableSize: {
        const uint64_t drawable = r.get<uint64_t>();
        const int32_t w = r.get<int32_t>();
        const int32_t h = r.get<int32_t>();
        drawable_sizes_[drawable] = {w, h};  // used at the next make-current or swap
        break;
    }
    case kSynthClientArrays: client_arrays(c); break;
    case kSynthBufferWrite: buffer_write(c); break;
    case kSynthUnserialized: {
        const uint32_t op = r.get<uint32_t>();
        stats_.unserialized++;
        if (unserialized_seen_[op]++ == 0 && command_info(op))
            std::fprintf(stderr, "glcast replay: the master could not serialize %s: this frame may differ\n",
                         command_info(op)->name);
        break;
    }
    default:
        break;
    }
}

}  // namespace glcast::slave
