// A stereo tile for glcast replay and glcast slave (slave/stereo.h): both eyes' replayers, the
// window that shows them when the backend is "window" (the eyes then replay headless, on EGL),
// and their frames as PNGs.
#pragma once

#include <memory>
#include <string>

#include "slave/backends/stereo_window.h"
#include "slave/stereo.h"

namespace glcast::cli {

struct StereoTile {
    std::unique_ptr<slave::StereoPair> pair;
    std::unique_ptr<slave::StereoWindow> window;  // null: headless
};

// False with `error` set when an eye's backend or the window cannot be had.
bool open_stereo_tile(const std::string& backend_kind, const slave::ReplayOptions& options, StereoTile& out, std::string& error);

// DIR/frame-NNNNNN.png, the composed tile; quad-buffer: frame-NNNNNN-left.png and -right.png.
bool write_stereo_frame(const std::string& dir, uint64_t frame, slave::StereoMode mode, const slave::Image& tile,
                        const slave::Image& left, const slave::Image& right, std::string& error);

}  // namespace glcast::cli
