#include "common/window_readback.h"

#include <cstring>

#include "common/gl_state.h"
#include "common/gles.h"

namespace glcast {
namespace {

// OpenGL ES 2 reads the bound framebuffer's only colour buffer: there is no glReadBuffer.
void read_from(const GlApi& gl, GLenum buffer) {
    const auto* version = gl.has(OP_glGetString) ? reinterpret_cast<const char*>(gl.glGetString(GL_VERSION)) : nullptr;
    if (!gles_lacks(GL_READ_BUFFER, gles_version(version))) gl.glReadBuffer(buffer);
}

}  // namespace

std::vector<uint8_t> read_window(const GlApi& gl, GLenum buffer, int width, int height) {
    std::vector<uint8_t> rgba, scratch;
    read_window_into(gl, buffer, width, height, rgba, scratch);
    return rgba;
}

void read_window_rows(const GlApi& gl, GLenum buffer, int width, int height, uint8_t* rows, int row_pixels) {
    GlStateGuard guard(gl, kGuardWindowRead | kGuardPixelPack);
    read_from(gl, buffer);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.glPixelStorei(GL_PACK_ROW_LENGTH, row_pixels);
    gl.glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rows);
}

void read_window_into(const GlApi& gl, GLenum buffer, int width, int height, std::vector<uint8_t>& rgba,
                      std::vector<uint8_t>& bottom_up) {
    bottom_up.resize(size_t(width) * height * 4);
    rgba.resize(bottom_up.size());
    {
        GlStateGuard guard(gl, kGuardWindowRead | kGuardPixelPack);
        read_from(gl, buffer);
        gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
        gl.glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
    }
    const size_t row_bytes = size_t(width) * 4;
    for (int y = 0; y < height; ++y)
        std::memcpy(rgba.data() + size_t(y) * row_bytes, bottom_up.data() + size_t(height - 1 - y) * row_bytes, row_bytes);
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
}

}  // namespace glcast
