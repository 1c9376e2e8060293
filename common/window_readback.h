// Reading the window framebuffer back, for the shim's snapshots of the program's own frames and
// for the slave's frames: the same pixels must come out of both. Every piece of state it
// touches (read framebuffer and buffer, pack buffer, pack alignment and skips) is restored.
#pragma once

#include <cstdint>
#include <vector>

#include "glcast_gl_api.h"

namespace glcast {

// `buffer` (GL_BACK or GL_FRONT) of framebuffer 0 as RGBA rows from the top, alpha 255 (a window
// shows none). Through the caller's table of the driver's functions (glBindFramebuffer and
// glBindBuffer are used where the driver has them: GL 1.x has neither).
std::vector<uint8_t> read_window(const GlApi& gl, GLenum buffer, int width, int height);
// The same into `rgba`, with `scratch` for the rows as GL gives them: both keep their memory from
// frame to frame (a slave reads every frame back; fresh buffers cost page faults each time).
void read_window_into(const GlApi& gl, GLenum buffer, int width, int height, std::vector<uint8_t>& rgba,
                      std::vector<uint8_t>& scratch);
// The rows as GL gives them (bottom to top, RGBA, alpha as the buffer has it) into `rows`, each
// `row_pixels` wide: one eye's image into its half of a stereo tile's image, with no copy between.
void read_window_rows(const GlApi& gl, GLenum buffer, int width, int height, uint8_t* rows, int row_pixels);

}  // namespace glcast
