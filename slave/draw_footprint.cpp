// A draw's footprint in the master's window (draw_footprint.h).
#include "slave/draw_footprint.h"

#include <algorithm>
#include <cmath>

#include "slave/effects/gl_util.h"

namespace glcast::slave {

void DrawFootprint::begin(const GlApi& gl, int master_w, int master_h, const int32_t viewport[4]) {
    master_w = std::max(1, master_w), master_h = std::max(1, master_h);
    scale_ = std::min(1.0, double(kMaxSide) / std::max(master_w, master_h));
    const int W = std::max(1, int(std::lround(master_w * scale_))), H = std::max(1, int(std::lround(master_h * scale_)));
    master_[0] = master_w, master_[1] = master_h;
    if (size_[0] != W || size_[1] != H) {
        if (framebuffer_) gl.glDeleteFramebuffers(1, &framebuffer_), gl.glDeleteTextures(1, &depth_);
        framebuffer_ = depth_ = 0;
        size_[0] = size_[1] = 0;
        depth_ = effects::make_texture(gl, GL_DEPTH_COMPONENT24, W, H);
        framebuffer_ = effects::make_framebuffer(gl, 0, depth_);
        size_[0] = W, size_[1] = H;
    }
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_);
    gl.glViewport(GLint(std::lround(viewport[0] * scale_)), GLint(std::lround(viewport[1] * scale_)),
                  GLsizei(std::lround(viewport[2] * scale_)), GLsizei(std::lround(viewport[3] * scale_)));
    gl.glDisable(GL_SCISSOR_TEST);  // (the program's box is the tile's, mapped)
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_ALWAYS);
    gl.glDepthMask(GL_TRUE);
    gl.glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.glClearDepth(1.0);
    gl.glClear(GL_DEPTH_BUFFER_BIT);
    gl.glDepthRange(0, 0);
}

void DrawFootprint::cover(const GlApi& gl, const int32_t rect[4]) {
    GLint box[4] = {};
    gl.glGetIntegerv(GL_SCISSOR_BOX, box);
    const GLint x0 = GLint(std::lround(rect[0] * scale_)), y0 = GLint(std::lround(rect[1] * scale_));
    const GLint x1 = GLint(std::lround(rect[2] * scale_)), y1 = GLint(std::lround(rect[3] * scale_));
    gl.glEnable(GL_SCISSOR_TEST);
    gl.glScissor(x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0));
    gl.glClearDepth(0.0);
    gl.glClear(GL_DEPTH_BUFFER_BIT);
    gl.glScissor(box[0], box[1], box[2], box[3]);
    gl.glDisable(GL_SCISSOR_TEST);
}

bool DrawFootprint::measure(const GlApi& gl, int32_t out[4]) {
    const int W = size_[0], H = size_[1];
    if (!framebuffer_) return false;
    pixels_.assign(size_t(W) * size_t(H), 255);
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    if (gl.has(OP_glBindBuffer)) gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    gl.glPixelStorei(GL_PACK_SKIP_ROWS, 0);
    gl.glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
    gl.glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_UNSIGNED_BYTE, pixels_.data());
    int x0 = W, y0 = H, x1 = 0, y1 = 0;
    for (int y = 0; y < H; ++y) {
        const uint8_t* row = pixels_.data() + size_t(y) * size_t(W);
        for (int x = 0; x < W; ++x) {
            if (row[x] == 255) continue;
            x0 = std::min(x0, x), x1 = std::max(x1, x + 1), y0 = std::min(y0, y), y1 = std::max(y1, y + 1);
        }
    }
    if (x0 >= x1 || y0 >= y1) return false;
    if (scale_ < 1) {  // back to the master's pixels
        x0 = int(std::floor(x0 / scale_)), y0 = int(std::floor(y0 / scale_));
        x1 = std::min(master_[0], int(std::ceil(x1 / scale_))), y1 = std::min(master_[1], int(std::ceil(y1 / scale_)));
    }
    out[0] = x0, out[1] = y0, out[2] = x1, out[3] = y1;
    return true;
}

}  // namespace glcast::slave
