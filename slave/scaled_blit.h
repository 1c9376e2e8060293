// glBlitFramebuffer from a multisampled framebuffer to a rectangle of another size, which GL
// refuses (it resolves samples only at the same size): on a tile of another scale than the
// master's window, a program's resolve into its window (the blit that shows a multisampled
// scene) left the tile black there. The source rectangle is resolved first into a
// single-sampled target of its own size and format, and that one blitted as the program asked.
// Per context (framebuffer objects are not shared).
#pragma once

#include <cstdint>

#include "common/gl_headers.h"
#include "slave/effects/gl_api.h"

namespace glcast::slave {

class ScaledBlit {
public:
    // Whether a blit of `source` to `destination` (x0, y0, x1, y1 each) from the bound read
    // framebuffer needs it: the sizes differ and that framebuffer is multisampled.
    static bool needed(const GlApi& gl, const int32_t source[4], const int32_t destination[4]);
    // The blit's colour, resolved first, into the bound draw framebuffer with the program's
    // scissor as the program's own blit would have had it; bindings are put back. (Depth and
    // stencil are never scaled from samples: GL has no way to, and no program asks it.)
    // Throws std::runtime_error if the read buffer's format is not found or its target cannot
    // be made.
    void blit(const GlApi& gl, const int32_t source[4], const int32_t destination[4], GLbitfield mask, GLenum filter);

private:
    // The read framebuffer's read buffer's internal format (0: none).
    static GLenum read_format(const GlApi& gl);
    void fit(const GlApi& gl, GLenum format, int width, int height);

    GLuint framebuffer_ = 0, renderbuffer_ = 0;
    GLenum format_ = 0;
    int size_[2] = {0, 0};
};

}  // namespace glcast::slave
