// The program's window framebuffer (name 0) is the backend's default framebuffer, at the size
// the master's drawable had (slave/backend.h says why it is not an FBO).
#include "slave/window_system.h"

#include <cstdio>

#include <algorithm>

#include "common/gl_headers.h"
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

constexpr int kMaxSamples = 64;  // GL implementations offer up to 32

ContextRequest glx_request(const PtrRecord& attribs) {
    ContextRequest r;
    r.major = attrib_value(attribs, GLX_CONTEXT_MAJOR_VERSION_ARB, 0, 4);
    r.minor = attrib_value(attribs, GLX_CONTEXT_MINOR_VERSION_ARB, 0, 4);
    const int flags = attrib_value(attribs, GLX_CONTEXT_FLAGS_ARB, 0, 4);
    const int profile = attrib_value(attribs, GLX_CONTEXT_PROFILE_MASK_ARB, GLX_CONTEXT_CORE_PROFILE_BIT_ARB, 4);
    r.core = r.major * 10 + r.minor >= 32 && (profile & GLX_CONTEXT_CORE_PROFILE_BIT_ARB);
    r.forward_compatible = flags & GLX_CONTEXT_FORWARD_COMPATIBLE_BIT_ARB;
    r.debug = flags & GLX_CONTEXT_DEBUG_BIT_ARB;
    r.no_error = attrib_value(attribs, GLX_CONTEXT_OPENGL_NO_ERROR_ARB, 0, 4);
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
    r.no_error = attrib_value(attribs, EGL_CONTEXT_OPENGL_NO_ERROR_KHR, 0, 4);
    if (r.major == 1 && r.minor == 0) r.major = 0;
    return r;
}

}  // namespace

bool WindowSystem::wants(uint32_t opcode, const CommandInfo* info) const {
    if (!info)
        return opcode == kSynthContext || opcode == kSynthDrawableSize || opcode == kSynthContextFormat ||
               opcode == kSynthContextBits;
    return info->sem.context != ContextOp::Nothing;
}

bool WindowSystem::replace_call(const Call& c) {
    if (c.opcode == kSynthContextFormat) {
        SynthContextFormat t;
        read_synthetic(c, t);
        if (t.samples < 0 || t.samples > kMaxSamples)
            throw ReplayError("a context format of " + std::to_string(t.samples) + " samples (at most " +
                              std::to_string(kMaxSamples) + ")");
        auto request = pending_.find(t.handle);
        if (request != pending_.end()) request->second.samples = t.samples;  // else its creation failed
        return true;
    }
    if (c.opcode == kSynthContextBits) {
        SynthContextBits t;
        read_synthetic(c, t);
        const auto within = [](int32_t v, int32_t most) { return v >= 0 && v <= most; };
        if (!within(t.alpha, 32) || !within(t.depth, 32) || !within(t.stencil, 16))
            throw ReplayError("a context of " + std::to_string(t.alpha) + " alpha, " + std::to_string(t.depth) +
                              " depth and " + std::to_string(t.stencil) + " stencil bits (at most 32, 32 and 16)");
        auto request = pending_.find(t.handle);
        if (request == pending_.end()) return true;  // its creation failed
        request->second.alpha = t.alpha;
        // The passes and a tile's adaptation read and test depth (and stencil) in the window
        // framebuffer: with either on, a slave keeps at least its own 24 and 8 bits (what the
        // program asks of them then differs; said once). (A 2x2 mosaic of a depth-less program
        // differed from its canvas in 24,576 pixels without them.)
        const bool passes = core_.options().effects.followed() || core_.options().tile.enabled;
        request->second.depth = passes ? std::max(t.depth, 24) : t.depth;
        request->second.stencil = passes ? std::max(t.stencil, 8) : t.stencil;
        if (passes && (t.depth < 24 || t.stencil < 8) && !said_passes_keep_depth_) {
            said_passes_keep_depth_ = true;
            std::fprintf(stderr, "glcast slave: the program's window has %d depth and %d stencil bits; the passes and tiles keep "
                                 "the slave's 24 and 8\n", t.depth, t.stencil);
        }
        return true;
    }
    if (c.opcode == kSynthContext) {
        SynthContext t;
        read_synthetic(c, t);
        const auto request = pending_.find(t.handle);
        ContextRequest wanted = request != pending_.end() ? request->second : ContextRequest{};
        wanted.es = is_es(ContextApi(t.api));
        if (request != pending_.end()) pending_.erase(request);
        core_.add_context(t.id, t.handle, t.share, wanted);
        ids_by_handle_[t.handle] = t.id;
        return true;
    }
    if (c.opcode == kSynthDrawableSize) {
        SynthDrawableSize t;
        read_synthetic(c, t);
        const uint64_t limit = core_.options().limits.drawable_dimension;
        if (t.width < 0 || t.height < 0 || uint64_t(t.width) > limit || uint64_t(t.height) > limit)
            throw ReplayError("drawable of " + std::to_string(t.width) + "x" + std::to_string(t.height) +
                              " is over the limit drawable_dimension=" + std::to_string(limit));
        keep_drawable_size(t.drawable, t.width, t.height);
        return true;
    }
    const CommandSemantics& sem = c.info->sem;
    const uint64_t arg = sem.context_param >= 0 ? c.args[size_t(sem.context_param)].bits : 0;
    switch (sem.context) {
    case ContextOp::Create:
        if (!c.ret.bits) break;  // the master's call failed
        // Each is answered by its glcast.context tuple; a stream of creations without them
        // would grow this map: no more waiting than contexts may live.
        if (pending_.size() >= core_.options().limits.contexts && !pending_.count(c.ret.bits))
            throw ReplayError("more than " + std::to_string(core_.options().limits.contexts) +
                              " context creations wait for their glcast.context tuple (limit contexts)");
        if (sem.context_param < 0) pending_[c.ret.bits] = ContextRequest{};
        else if (sem.flags & kSemEgl) pending_[c.ret.bits] = egl_request(c.args[size_t(sem.context_param)].ptr);
        else pending_[c.ret.bits] = glx_request(c.args[size_t(sem.context_param)].ptr);
        break;
    case ContextOp::MakeCurrent:
        if (c.ret.bits) make_current(c.context, arg);  // else the master's call failed
        break;
    case ContextOp::Swap: end_frame(); break;
    case ContextOp::Destroy: {
        auto it = ids_by_handle_.find(arg);
        if (it == ids_by_handle_.end()) break;
        core_.remove_context(it->second);
        ids_by_handle_.erase(it);
        break;
    }
    case ContextOp::Nothing: break;
    }
    return true;
}

void WindowSystem::reset() {
    pending_.clear();
    ids_by_handle_.clear();
    drawable_sizes_.clear();
}

void WindowSystem::window_size(uint64_t drawable, int& width, int& height) const {
    const ReplayOptions& o = core_.options();
    if (o.tile.enabled) {  // a tile of the wall, whatever the master's window
        width = o.tile.width;
        height = o.tile.height;
        return;
    }
    auto it = drawable_sizes_.find(drawable);
    width = o.width ? o.width : it != drawable_sizes_.end() ? it->second.first : 0;
    height = o.height ? o.height : it != drawable_sizes_.end() ? it->second.second : 0;
}

void WindowSystem::switch_to(SlaveContext& ctx) { make_current(ctx.id, ctx.drawable); }

void WindowSystem::make_current(uint32_t id, uint64_t drawable) {
    if (id == 0) {
        core_.make_current(0, 0, 0, 0);
        return;
    }
    SlaveContext* ctx = core_.context(id);
    if (!ctx) throw ReplayError("make-current of context " + std::to_string(id) + ", which does not exist");
    int w = 0, h = 0;
    window_size(drawable, w, h);  // the shim sends the size before the make-current
    auto size = drawable_sizes_.find(drawable);
    if (size != drawable_sizes_.end()) {
        ctx->master_width = size->second.first;
        ctx->master_height = size->second.second;
    }
    core_.make_current(id, drawable, w, h);
}

// Used at the next make-current or swap of the drawable. How many are kept is bounded too
// (limit drawables): a stream naming ever more drawables is refused past it.
void WindowSystem::keep_drawable_size(uint64_t drawable, int width, int height) {
    const uint64_t limit = core_.options().limits.drawables;
    if (!drawable_sizes_.count(drawable) && drawable_sizes_.size() >= limit)
        throw ReplayError("more than " + std::to_string(limit) + " drawables (limit drawables=" + std::to_string(limit) +
                          ")");
    drawable_sizes_[drawable] = {width, height};
}

void WindowSystem::end_frame() {
    SlaveContext& ctx = core_.current();
    core_.finish_frame();
    // A resize the master announced before this swap applies from the next frame on.
    int w = 0, h = 0;
    window_size(ctx.drawable, w, h);
    auto size = drawable_sizes_.find(ctx.drawable);
    const bool master_resized = size != drawable_sizes_.end() &&
                                (size->second.first != ctx.master_width || size->second.second != ctx.master_height);
    if (((w != ctx.width || h != ctx.height) && w > 0 && h > 0) || master_resized) make_current(ctx.id, ctx.drawable);
}

}  // namespace glcast::slave
