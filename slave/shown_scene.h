// A scene the program draws into a framebuffer object and shows in part of its window (a
// content suite's 3D viewport among its toolbars, as Blender composites its regions), on a
// rotated tile (docs/wall.md "A scene shown in part of the window"). The tile adapter turns
// what is drawn into that target as it turns the window's scene; this shows the result: the
// program's own draw that shows the scene runs into a footprint of the master's window
// (draw_footprint.h) instead of the tile, which says where on the program's screen the scene
// is; then the turned scene covers the tile wherever the tile does not see the program's
// screen, and where that footprint lies on it. The interface the program drew around it before
// stays on the program's screen; what it draws after lands over it.
#pragma once

#include <cstdint>
#include <functional>

#include <glm/glm.hpp>

#include "common/gl_headers.h"
#include "slave/draw_footprint.h"
#include "slave/effects/gl_api.h"

namespace glcast::slave {

class ShownScene {
public:
    // The program's draw about to run shows the scene: it goes into the footprint of a master
    // window of master_w x master_h, with the program's `viewport`. The program's state that
    // this changes is saved. Throws std::runtime_error if the footprint cannot be made.
    void begin(const GlApi& gl, int master_w, int master_h, const int32_t viewport[4]);
    // After it: the program's state back, and where the draw put the scene (x0, y0, x1, y1 in the
    // master's window pixels). False: it drew nothing.
    bool end(const GlApi& gl, int32_t rect[4]);
    bool redirected() const { return redirected_; }
    // Instead of begin, a draw and end: the program showed the scene by a blit into `rect` (x0,
    // y0, x1, y1 of a master window of master_w x master_h), its footprint. Returns end's.
    bool cover(const GlApi& gl, int master_w, int master_h, const int32_t rect[4], int32_t out[4]);
    // The program's draw that showed the scene, run again by `draw` into a target of the tile's size
    // with its viewport (`viewport`, the master's window pixels) scaled so that where it put the
    // scene (`rect`) covers the target: the picture the program's own shader makes of its targets
    // (Blender's blends its engines' colour with its overlays), across the tile. Returns that
    // target's colour texture.
    GLuint draw_stretched(const GlApi& gl, const int32_t rect[4], const int32_t viewport[4], int tile_w, int tile_h,
                          const std::function<void()>& draw);
    // Draws `scene` (the texture the program's draw showed, holding the tile's frustum) over
    // `viewport` of the window (the program's window mapped onto the tile) but where
    // `tile_to_screen` (tile clip x, y, w to the program's window clip x, y, 1, as in
    // shown_scene.frag) finds the program's screen outside the footprint.
    // Also marks those pixels in mask() (of the tile's size, `tile_w` x `tile_h`).
    void composite(const GlApi& gl, GLuint scene, const glm::dmat3& tile_to_screen, const int32_t viewport[4],
                   int tile_w, int tile_h);
    // Where the last composite drew the scene: 1, elsewhere 0.
    GLuint mask() const { return mask_.texture; }

private:
    DrawFootprint footprint_;
    bool redirected_ = false;
    // The program's state the redirection changes.
    GLint draw_framebuffer_ = 0, read_framebuffer_ = 0, viewport_[4] = {}, depth_func_ = GL_LESS;
    GLboolean depth_test_ = GL_FALSE, scissor_test_ = GL_FALSE, depth_mask_ = GL_TRUE, colour_mask_[4] = {};
    GLdouble depth_range_[2] = {0, 1};
    GLfloat clear_depth_ = 1;
    struct Program {
        GLuint name = 0;
        GLint scene = -1, footprint = -1, tile_to_screen = -1;
    };
    Program picture_, marks_;
    // A colour target of the tile's size, made again when that changes (making it binds it).
    struct TileTarget {
        GLuint texture = 0, framebuffer = 0;
        int size[2] = {0, 0};
        void fit(const GlApi& gl, GLenum format, int width, int height);
    };
    TileTarget mask_, stretched_;
    GLuint vao_ = 0;
};

}  // namespace glcast::slave
