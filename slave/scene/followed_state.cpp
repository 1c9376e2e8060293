// Following the draw state from the calls (followed_state.h). The commands read here are the
// few whose meaning the classifier needs; everything else either leaves these values alone or,
// where it may change them unseen, makes them unknown.
#include "slave/scene/followed_state.h"

#include <cstring>

#include "glcast_commands.h"
#include "protocol/command_info.h"

namespace glcast::slave {

namespace {

uint32_t u32(const Call& c, int i) { return uint32_t(c.args[size_t(i)].bits); }

double f64(const Call& c, int i, bool single) {
    const uint64_t bits = c.args[size_t(i)].bits;
    if (single) {
        float f;
        const uint32_t b = uint32_t(bits);
        std::memcpy(&f, &b, 4);
        return f;
    }
    double d;
    std::memcpy(&d, &bits, 8);
    return d;
}

GLuint slave_name(ContextNames& names, Ns ns, uint64_t master) {
    uint64_t slave = 0;
    return master && names.map(ns).find(master, slave) ? GLuint(slave) : 0;
}

}  // namespace

void FollowedState::forget() {
    const bool compiling = compiling_list;
    *this = FollowedState{};
    compiling_list = compiling;
}

void FollowedState::follow(const Call& c, ContextNames& names) {
    if (!c.info) return;
    const CommandSemantics& sem = c.info->sem;
    if (sem.list == ListOp::New) {
        compiling_list = u32(c, sem.subject_params[1]) == GL_COMPILE;
        return;
    }
    if (sem.redraw == RedrawKind::EndList) {
        compiling_list = false;
        return;
    }
    if (compiling_list) return;  // recorded into the list, not run
    if (sem.list == ListOp::Call || sem.list == ListOp::CallMany) return forget();  // a list may set anything
    if ((sem.flags & kSemDeletes) && sem.state == StateGroup::Nothing) {
        // A bound framebuffer deleted falls back to the window.
        draw_framebuffer.reset();
        read_framebuffer.reset();
        return;
    }
    switch (sem.twin) {
    case OP_glPopAttrib: return forget();
    case OP_glEnable:
    case OP_glDisable: {
        const bool on = sem.twin == OP_glEnable;
        if (u32(c, 0) == GL_DEPTH_TEST) depth_test = on;
        if (u32(c, 0) == GL_CULL_FACE) cull_face = on;
        if (u32(c, 0) == GL_BLEND) blend = on;
        if (u32(c, 0) == GL_ALPHA_TEST) alpha_test = on;
        return;
    }
    case OP_glEnablei:
    case OP_glDisablei:  // (blending per draw buffer: the driver says what glIsEnabled sees)
        if (u32(c, 0) == GL_BLEND) blend.reset();
        return;
    case OP_glAlphaFunc: alpha_func = u32(c, 0), alpha_ref = f64(c, 1, true); return;
    case OP_glDepthMask: depth_mask = u32(c, 0) != 0; return;
    case OP_glDepthFunc: depth_func = u32(c, 0); return;
    case OP_glDepthRange: depth_range = std::make_pair(f64(c, 0, false), f64(c, 1, false)); return;
    case OP_glDepthRangef: depth_range = std::make_pair(f64(c, 0, true), f64(c, 1, true)); return;
    case OP_glDepthRangeIndexed:
    case OP_glDepthRangeArrayv: depth_range.reset(); return;
    case OP_glCullFace: cull_face_mode = u32(c, 0); return;
    case OP_glFrontFace: front_face = u32(c, 0); return;
    case OP_glBindFramebuffer: {
        const GLenum target = u32(c, 0);
        const GLuint fb = slave_name(names, Ns::framebuffer, c.args[1].bits);
        if (target == GL_FRAMEBUFFER || target == GL_DRAW_FRAMEBUFFER) draw_framebuffer = fb;
        if (target == GL_FRAMEBUFFER || target == GL_READ_FRAMEBUFFER) read_framebuffer = fb;
        return;
    }
    default: return;
    }
}

}  // namespace glcast::slave
