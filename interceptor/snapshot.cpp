#include "interceptor/snapshot.h"

#include <sys/stat.h>

#include <atomic>
#include <cinttypes>
#include <cstdio>
#include <vector>

#include "common/gl_headers.h"
#include "common/image.h"
#include "common/window_readback.h"
#include "glcast_commands.h"
#include "interceptor/config.h"
#include "interceptor/shim.h"

namespace glcast {

template <class Fn>
static Fn real(uint32_t op) { return reinterpret_cast<Fn>(real_proc(op)); }

void snapshot_back_buffer(int width, int height) {
    static std::atomic<uint64_t> frame{0};
    const uint64_t n = frame++;
    const std::string& dir = shim_config().snapshot_dir;
    if (width <= 0 || height <= 0) return;
    ReadbackGl gl;
    gl.GetIntegerv = real<decltype(gl.GetIntegerv)>(OP_glGetIntegerv);
    gl.BindFramebuffer = real<decltype(gl.BindFramebuffer)>(OP_glBindFramebuffer);
    gl.BindBuffer = real<decltype(gl.BindBuffer)>(OP_glBindBuffer);
    gl.ReadBuffer = real<decltype(gl.ReadBuffer)>(OP_glReadBuffer);
    gl.PixelStorei = real<decltype(gl.PixelStorei)>(OP_glPixelStorei);
    gl.ReadPixels = real<decltype(gl.ReadPixels)>(OP_glReadPixels);
    if (!gl.GetIntegerv || !gl.ReadBuffer || !gl.PixelStorei || !gl.ReadPixels) return;
    const slave::Image image{width, height, read_window(gl, GL_BACK, width, height)};
    mkdir(dir.c_str(), 0755);
    char path[4096];
    std::snprintf(path, sizeof path, "%s/frame-%06" PRIu64 ".png", dir.c_str(), n);
    std::string error;
    if (!slave::write_png(path, image, error)) std::fprintf(stderr, "glcast: snapshot: %s\n", error.c_str());
}

}  // namespace glcast
