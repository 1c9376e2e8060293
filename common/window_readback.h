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

}  // namespace glcast
