#include "cli/stereo_tile.h"

#include <cinttypes>
#include <cstdio>

namespace glcast::cli {

using namespace glcast::slave;

bool open_stereo_tile(const std::string& backend_kind, const ReplayOptions& options, StereoTile& out, std::string& error) {
    const bool windowed = backend_kind == "window";
    const std::string eyes_backend = windowed ? "egl" : backend_kind;
    out.pair = std::make_unique<StereoPair>([&eyes_backend](std::string& e) { return make_backend(eyes_backend, e); }, options);
    if (!out.pair->valid()) {
        error = out.pair->error();
        return false;
    }
    if (!windowed) return true;
    const StereoMode mode = options.stereo;
    const int w = options.tile.width * (mode == StereoMode::side_by_side ? 2 : 1);
    const int h = options.tile.height * (mode == StereoMode::top_bottom ? 2 : 1);
    out.window = StereoWindow::open(w, h, mode == StereoMode::quad_buffer, error);
    return out.window != nullptr;
}

bool write_stereo_frame(const std::string& dir, uint64_t frame, StereoMode mode, const Image& tile, const Image& left,
                        const Image& right, std::string& error) {
    char name[48];
    if (mode != StereoMode::quad_buffer) {
        std::snprintf(name, sizeof name, "/frame-%06" PRIu64 ".png", frame);
        return write_png(dir + name, tile, error);
    }
    std::snprintf(name, sizeof name, "/frame-%06" PRIu64 "-left.png", frame);
    if (!write_png(dir + name, left, error)) return false;
    std::snprintf(name, sizeof name, "/frame-%06" PRIu64 "-right.png", frame);
    return write_png(dir + name, right, error);
}

}  // namespace glcast::cli
