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


void snapshot_back_buffer(int width, int height) {
    static std::atomic<uint64_t> frame{0};
    const uint64_t n = frame++;
    const std::string& dir = shim_config().snapshot_dir;
    if (width <= 0 || height <= 0 || n < shim_config().snapshot_from) return;
    const GlApi& gl = real_gl();
    for (uint32_t op : {OP_glGetIntegerv, OP_glReadBuffer, OP_glPixelStorei, OP_glReadPixels})
        if (!gl.has(op)) return;
    const slave::Image image{width, height, read_window(gl, GL_BACK, width, height)};
    mkdir(dir.c_str(), 0755);
    char path[4096];
    std::snprintf(path, sizeof path, "%s/frame-%06" PRIu64 ".png", dir.c_str(), n);
    std::string error;
    if (!slave::write_png(path, image, error)) std::fprintf(stderr, "glcast: snapshot: %s\n", error.c_str());
}

}  // namespace glcast
