// The window a stereo tile is shown in (slave/stereo.h): both eyes replay headless, and their
// composed frame (side by side, top and bottom, anaglyph) is drawn into this window; quad-buffer
// stereo draws the left eye into GL_BACK_LEFT and the right into GL_BACK_RIGHT of a window with
// a stereo visual, which only a display that offers one (GLFW_STEREO: a professional GPU's
// driver with stereo enabled) can give; elsewhere opening it fails and says so.
#pragma once

#include <memory>
#include <string>

#include "common/image.h"

namespace glcast::slave {

class StereoWindow {
public:
    // Null with `error` set when the window (or its stereo visual) cannot be had.
    static std::unique_ptr<StereoWindow> open(int width, int height, bool quad_buffer, std::string& error);
    ~StereoWindow();
    // Shows one frame: `tile` (composed), or `left` and `right` (quad-buffer), and swaps; returns
    // once it is shown. Called on the main thread (GLFW polls events there).
    void show(const Image& tile, const Image& left, const Image& right);

private:
    StereoWindow() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace glcast::slave
