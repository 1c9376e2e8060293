// Where a draw lands in the master's window, whatever matrix or vertices put it there: the draw
// runs in the master's window coordinates (the program's viewport, no tile mapping) into a
// depth-only target cleared to 1, with every fragment at depth 0; the target is the draw's
// footprint, and its bounding rectangle is read back once. Used to place a scene the program
// shows in part of its window: by the passes (scene_lending.h, which draw the program's draw
// again) and by rotated tiles (shown_scene.h, which redirect the program's own draw).
#pragma once

#include <cstdint>
#include <vector>

#include "common/gl_headers.h"
#include "slave/effects/gl_api.h"

namespace glcast::slave {

class DrawFootprint {
public:
    // A stream may claim a window of 16384 squared: the target is at most this a side, and the
    // footprint then to a few of the master's pixels.
    static constexpr int kMaxSide = 4096;

    // Binds the target (made, or made again, for a master window of master_w x master_h),
    // clears it, and sets the viewport (the program's `viewport`, scaled), the depth test
    // (GL_ALWAYS, written) and the depth range (0, 0) the draw then runs with. The caller saves
    // and restores the program's state around it. Throws std::runtime_error if the target cannot
    // be made.
    void begin(const GlApi& gl, int master_w, int master_h, const int32_t viewport[4]);
    // Instead of a draw, between begin and measure: a rectangle's footprint (x0, y0, x1, y1 in
    // the master's window pixels; a blit's destination).
    void cover(const GlApi& gl, const int32_t rect[4]);
    // After the draw: the rectangle it covered (x0, y0, x1, y1 in the master's window pixels, GL's
    // y up). False: it drew nothing. Leaves the target bound for reading.
    bool measure(const GlApi& gl, int32_t out[4]);
    // The footprint as a depth texture over the master's window: 0 where the draw drew.
    GLuint depth_texture() const { return depth_; }

private:
    GLuint framebuffer_ = 0, depth_ = 0;
    int size_[2] = {0, 0};
    int master_[2] = {0, 0};
    double scale_ = 1;
    std::vector<uint8_t> pixels_;  // the depth read back, one byte a pixel
};

}  // namespace glcast::slave
