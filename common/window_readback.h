// Reading the window framebuffer back, for the shim's snapshots of the program's own frames and
// for the slave's frames: the same pixels must come out of both. Every piece of state it
// touches (read framebuffer and buffer, pack buffer, pack alignment and skips) is restored.
#pragma once

#include <cstdint>
#include <vector>

#include "common/gl_headers.h"

namespace glcast {

struct ReadbackGl {  // the driver's functions, however the caller resolves them
    decltype(&::glGetIntegerv) GetIntegerv = nullptr;
    decltype(&::glBindFramebuffer) BindFramebuffer = nullptr;
    decltype(&::glBindBuffer) BindBuffer = nullptr;
    decltype(&::glReadBuffer) ReadBuffer = nullptr;
    decltype(&::glPixelStorei) PixelStorei = nullptr;
    decltype(&::glReadPixels) ReadPixels = nullptr;
};

// `buffer` (GL_BACK or GL_FRONT) of framebuffer 0 as RGBA rows from the top, alpha 255 (a window
// shows none).
std::vector<uint8_t> read_window(const ReadbackGl& gl, GLenum buffer, int width, int height);

}  // namespace glcast
