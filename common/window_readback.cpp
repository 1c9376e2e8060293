#include "common/window_readback.h"

#include <cstring>

namespace glcast {

std::vector<uint8_t> read_window(const GlApi& gl, GLenum buffer, int width, int height) {
    const bool fbo = gl.has(OP_glBindFramebuffer), buffers = gl.has(OP_glBindBuffer);
    GLint read_fb = 0, pack_buffer = 0, read_buffer = GL_BACK, align = 4, row = 0, skip_rows = 0, skip_pixels = 0;
    gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb);
    gl.glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer);
    gl.glGetIntegerv(GL_PACK_ALIGNMENT, &align);
    gl.glGetIntegerv(GL_PACK_ROW_LENGTH, &row);
    gl.glGetIntegerv(GL_PACK_SKIP_ROWS, &skip_rows);
    gl.glGetIntegerv(GL_PACK_SKIP_PIXELS, &skip_pixels);
    if (fbo) gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl.glGetIntegerv(GL_READ_BUFFER, &read_buffer);
    gl.glReadBuffer(buffer);
    if (buffers && pack_buffer) gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    gl.glPixelStorei(GL_PACK_SKIP_ROWS, 0);
    gl.glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
    std::vector<uint8_t> bottom_up(size_t(width) * height * 4), rgba(bottom_up.size());
    gl.glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
    gl.glPixelStorei(GL_PACK_ALIGNMENT, align);
    gl.glPixelStorei(GL_PACK_ROW_LENGTH, row);
    gl.glPixelStorei(GL_PACK_SKIP_ROWS, skip_rows);
    gl.glPixelStorei(GL_PACK_SKIP_PIXELS, skip_pixels);
    if (buffers && pack_buffer) gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(pack_buffer));
    gl.glReadBuffer(GLenum(read_buffer));
    if (fbo) gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fb));
    const size_t row_bytes = size_t(width) * 4;
    for (int y = 0; y < height; ++y)
        std::memcpy(rgba.data() + size_t(y) * row_bytes, bottom_up.data() + size_t(height - 1 - y) * row_bytes, row_bytes);
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
    return rgba;
}

}  // namespace glcast
