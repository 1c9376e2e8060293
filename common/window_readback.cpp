#include "common/window_readback.h"

#include <cstring>

namespace glcast {

std::vector<uint8_t> read_window(const ReadbackGl& gl, GLenum buffer, int width, int height) {
    GLint read_fb = 0, pack_buffer = 0, read_buffer = GL_BACK, align = 4, row = 0, skip_rows = 0, skip_pixels = 0;
    gl.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb);
    gl.GetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer);
    gl.GetIntegerv(GL_PACK_ALIGNMENT, &align);
    gl.GetIntegerv(GL_PACK_ROW_LENGTH, &row);
    gl.GetIntegerv(GL_PACK_SKIP_ROWS, &skip_rows);
    gl.GetIntegerv(GL_PACK_SKIP_PIXELS, &skip_pixels);
    if (gl.BindFramebuffer) gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl.GetIntegerv(GL_READ_BUFFER, &read_buffer);
    gl.ReadBuffer(buffer);
    if (gl.BindBuffer && pack_buffer) gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.PixelStorei(GL_PACK_ROW_LENGTH, 0);
    gl.PixelStorei(GL_PACK_SKIP_ROWS, 0);
    gl.PixelStorei(GL_PACK_SKIP_PIXELS, 0);
    std::vector<uint8_t> bottom_up(size_t(width) * height * 4), rgba(bottom_up.size());
    gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
    gl.PixelStorei(GL_PACK_ALIGNMENT, align);
    gl.PixelStorei(GL_PACK_ROW_LENGTH, row);
    gl.PixelStorei(GL_PACK_SKIP_ROWS, skip_rows);
    gl.PixelStorei(GL_PACK_SKIP_PIXELS, skip_pixels);
    if (gl.BindBuffer && pack_buffer) gl.BindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(pack_buffer));
    gl.ReadBuffer(GLenum(read_buffer));
    if (gl.BindFramebuffer) gl.BindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fb));
    const size_t row_bytes = size_t(width) * 4;
    for (int y = 0; y < height; ++y)
        std::memcpy(rgba.data() + size_t(y) * row_bytes, bottom_up.data() + size_t(height - 1 - y) * row_bytes, row_bytes);
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
    return rgba;
}

}  // namespace glcast
