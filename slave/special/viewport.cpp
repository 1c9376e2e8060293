// Window coordinates on a tile (slave/tile_mapping.h): the program's viewport and scissor box
// are kept as it set them and applied mapped while the window framebuffer is drawn to, as they
// are while one of its own framebuffer objects is; pixel-sized state scales with the canvas.
#include "common/gl_headers.h"
#include "slave/replayer.h"

namespace glcast::slave::replay_special {
namespace {

bool mapping(Replayer& r) { return r.tile().enabled && r.current().drawing_to_window; }
double scale(Replayer& r) {
    const SlaveContext& ctx = r.current();
    return 0.5 * (r.tile().sx(ctx.master_width) + r.tile().sy(ctx.master_height));
}

}  // namespace

void glViewport(Replayer& r, const Call& c) {
    SlaveContext& ctx = r.current();
    for (int i = 0; i < 4; ++i) ctx.viewport[i] = r.value<int32_t>(c, i);
    if (!r.tile().enabled) {
        r.gl<decltype(&::glViewport)>(OP_glViewport)(ctx.viewport[0], ctx.viewport[1], ctx.viewport[2], ctx.viewport[3]);
        return;
    }
    r.apply_window_rects();
}

void glScissor(Replayer& r, const Call& c) {
    SlaveContext& ctx = r.current();
    for (int i = 0; i < 4; ++i) ctx.scissor[i] = r.value<int32_t>(c, i);
    if (!r.tile().enabled) {
        r.gl<decltype(&::glScissor)>(OP_glScissor)(ctx.scissor[0], ctx.scissor[1], ctx.scissor[2], ctx.scissor[3]);
        return;
    }
    r.apply_window_rects();
}

void glBindFramebuffer(Replayer& r, const Call& c) {
    const GLenum target = r.value<GLenum>(c, 0);
    const GLuint fb = r.name<GLuint>(Ns::framebuffer, c, 1);
    r.gl<decltype(&::glBindFramebuffer)>(OP_glBindFramebuffer)(target, fb);
    if (target == GL_FRAMEBUFFER || target == GL_DRAW_FRAMEBUFFER) {
        SlaveContext& ctx = r.current();
        const bool window = c.args[1].bits == 0;
        if (window != ctx.drawing_to_window) {
            ctx.drawing_to_window = window;
            if (r.tile().enabled) r.apply_window_rects();
        }
    }
}

void glLineWidth(Replayer& r, const Call& c) {
    GLfloat w = r.value<GLfloat>(c, 0);
    if (mapping(r)) w = GLfloat(w * scale(r));
    r.gl<decltype(&::glLineWidth)>(OP_glLineWidth)(w);
}

void glPointSize(Replayer& r, const Call& c) {
    GLfloat s = r.value<GLfloat>(c, 0);
    if (mapping(r)) s = GLfloat(s * scale(r));
    r.gl<decltype(&::glPointSize)>(OP_glPointSize)(s);
}

void glPixelZoom(Replayer& r, const Call& c) {
    GLfloat x = r.value<GLfloat>(c, 0), y = r.value<GLfloat>(c, 1);
    if (mapping(r)) {
        const SlaveContext& ctx = r.current();
        x = GLfloat(x * r.tile().sx(ctx.master_width));
        y = GLfloat(y * r.tile().sy(ctx.master_height));
    }
    r.gl<decltype(&::glPixelZoom)>(OP_glPixelZoom)(x, y);
}

// Into the window: the destination rectangle is window coordinates. (Reading the window back
// on a tile would need the other tiles' pixels; that source is left as it is.)
void glBlitFramebuffer(Replayer& r, const Call& c) {
    GLint v[8];
    for (int i = 0; i < 8; ++i) v[i] = r.value<GLint>(c, i);
    if (mapping(r)) {
        const SlaveContext& ctx = r.current();
        const TileMapping& t = r.tile();
        v[4] = GLint(t.map_x(v[4], ctx.master_width));
        v[6] = GLint(t.map_x(v[6], ctx.master_width));
        v[5] = GLint(t.map_y(v[5], ctx.master_height));
        v[7] = GLint(t.map_y(v[7], ctx.master_height));
    }
    r.gl<decltype(&::glBlitFramebuffer)>(OP_glBlitFramebuffer)(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7],
                                                              r.value<GLbitfield>(c, 8), r.value<GLenum>(c, 9));
}

}  // namespace glcast::slave::replay_special
