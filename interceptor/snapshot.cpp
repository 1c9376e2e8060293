#include "interceptor/snapshot.h"

#include <sys/stat.h>

#include <atomic>
#include <cinttypes>
#include <cstdio>
#include <vector>

#include "glcast_commands.h"
#include "interceptor/config.h"
#include "interceptor/shim.h"
#include "master/gl_headers.h"
#include "slave/image.h"

namespace glcast {

template <class Fn>
static Fn real(uint32_t op) { return reinterpret_cast<Fn>(real_proc(op)); }

void snapshot_back_buffer(int width, int height) {
    static std::atomic<uint64_t> frame{0};
    const uint64_t n = frame++;
    const std::string& dir = shim_config().snapshot_dir;
    if (width <= 0 || height <= 0) return;
    static const auto geti = real<decltype(&::glGetIntegerv)>(OP_glGetIntegerv);
    static const auto bind_fb = real<decltype(&::glBindFramebuffer)>(OP_glBindFramebuffer);
    static const auto bind_buffer = real<decltype(&::glBindBuffer)>(OP_glBindBuffer);
    static const auto read_buffer = real<decltype(&::glReadBuffer)>(OP_glReadBuffer);
    static const auto pstore = real<decltype(&::glPixelStorei)>(OP_glPixelStorei);
    static const auto read = real<decltype(&::glReadPixels)>(OP_glReadPixels);
    if (!geti || !read || !read_buffer || !pstore) return;
    GLint read_fb = 0, pack_buffer = 0, saved_read_buffer = GL_BACK, align = 4, row = 0, skip_rows = 0, skip_pixels = 0;
    geti(GL_READ_FRAMEBUFFER_BINDING, &read_fb);
    geti(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer);
    geti(GL_PACK_ALIGNMENT, &align);
    geti(GL_PACK_ROW_LENGTH, &row);
    geti(GL_PACK_SKIP_ROWS, &skip_rows);
    geti(GL_PACK_SKIP_PIXELS, &skip_pixels);
    if (bind_fb) bind_fb(GL_READ_FRAMEBUFFER, 0);
    geti(GL_READ_BUFFER, &saved_read_buffer);
    read_buffer(GL_BACK);
    if (bind_buffer && pack_buffer) bind_buffer(GL_PIXEL_PACK_BUFFER, 0);
    pstore(GL_PACK_ALIGNMENT, 1);
    pstore(GL_PACK_ROW_LENGTH, 0);
    pstore(GL_PACK_SKIP_ROWS, 0);
    pstore(GL_PACK_SKIP_PIXELS, 0);
    std::vector<uint8_t> bottom_up(size_t(width) * height * 4);
    read(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
    pstore(GL_PACK_ALIGNMENT, align);
    pstore(GL_PACK_ROW_LENGTH, row);
    pstore(GL_PACK_SKIP_ROWS, skip_rows);
    pstore(GL_PACK_SKIP_PIXELS, skip_pixels);
    if (bind_buffer && pack_buffer) bind_buffer(GL_PIXEL_PACK_BUFFER, GLuint(pack_buffer));
    read_buffer(GLenum(saved_read_buffer));
    if (bind_fb) bind_fb(GL_READ_FRAMEBUFFER, GLuint(read_fb));

    slave::Image image{width, height, std::vector<uint8_t>(bottom_up.size())};
    const size_t row_bytes = size_t(width) * 4;
    for (int y = 0; y < height; ++y)
        std::memcpy(image.rgba.data() + size_t(y) * row_bytes, bottom_up.data() + size_t(height - 1 - y) * row_bytes,
                    row_bytes);
    for (size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;  // a window shows no alpha
    mkdir(dir.c_str(), 0755);
    char path[4096];
    std::snprintf(path, sizeof path, "%s/frame-%06" PRIu64 ".png", dir.c_str(), n);
    std::string error;
    if (!slave::write_png(path, image, error)) std::fprintf(stderr, "glcast: snapshot: %s\n", error.c_str());
}

}  // namespace glcast
