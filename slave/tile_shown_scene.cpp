// Rotated tiles: a scene the program draws into a framebuffer object of another shape than its
// window's and shows in part of the window (shown_scene.h). Its target's draws are turned as
// the window's scene is (tile_turn.cpp); here the draw that shows it is found and redirected,
// and the turned scene drawn over the tile in its stead.
#include <cstdio>
#include <stdexcept>

#include "common/gl_headers.h"
#include "slave/replayer.h"
#include "slave/tile_adapter.h"
#include "slave/tile_adapter_state.h"

namespace glcast::slave {

namespace {

// The frustum of the program's whole window on its screen, from the scene's view: `projection`
// over `view` (a viewport of its target, whose colour is a texture of `texture` size) shown whole
// at `rect` of a window of `window` size. Window clip -> the view's clip is a scale and an offset
// on each axis, the projection's depth rows are kept.
bool window_frustum(const glm::dmat4& projection, const int32_t view[4], const int32_t texture[2], const int32_t rect[4],
                    const int window[2], glm::dmat4& out) {
    glm::dmat4 window_to_view(1.0);
    for (int axis = 0; axis < 2; ++axis) {
        const double size = window[axis], r0 = rect[axis], rw = rect[axis + 2] - rect[axis];
        const double t = texture[axis], v0 = view[axis], vw = view[axis + 2];
        if (!(size > 0 && rw > 0 && t > 0 && vw > 0)) return false;
        window_to_view[axis][axis] = size * t / (rw * vw);
        window_to_view[3][axis] = 2 * ((size / 2 - r0) / rw * t - v0) / vw - 1;
    }
    out = glm::inverse(window_to_view) * projection;
    return true;
}

}  // namespace

// The draw that shows the scene samples a texture of its view's size (the target's own colour,
// a resolve's or a post-processing copy's); the toolbars and panels drawn around it do not.
bool TileAdapter::shows_scene_in_part(const SlaveContext& ctx) {
    State& s = state();
    const GlApi& gl = core_.api();
    const bool fixed_function = program_in_use() == 0;
    GLint active = GL_TEXTURE0, bound = 0, size[2] = {0, 0};
    gl.glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    GLuint found = 0;
    for (int unit = 0; unit < 8 && !found; ++unit) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
        if (!bound || (fixed_function && !gl.glIsEnabled(GL_TEXTURE_2D))) continue;
        gl.glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &size[0]);
        gl.glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &size[1]);
        if (size[0] == s.part_viewport[2] && size[1] == s.part_viewport[3]) found = GLuint(bound);
    }
    gl.glActiveTexture(GLenum(active));
    if (!found) return false;
    s.part_found = true;
    s.showing_texture = found;
    s.showing_size[0] = size[0], s.showing_size[1] = size[1];
    int32_t viewport[4];
    program_viewport(viewport);
    try {
        if (!s.shown) s.shown = std::make_shared<ShownScene>();
        s.shown->begin(gl, ctx.master_width, ctx.master_height, viewport);
    } catch (const std::runtime_error& e) {
        s.shown->end(gl, viewport);
        std::fprintf(stderr, "glcast: cannot show the scene shown in part of the window on this tile: %s\n", e.what());
    }
    return true;
}

void TileAdapter::finish_shown_scene() {
    State& s = state();
    if (!s.shown || !s.shown->redirected()) return;
    const SlaveContext& ctx = core_.current();
    const GlApi& gl = core_.api();
    int32_t rect[4];
    if (!s.shown->end(gl, rect)) return;  // it drew nothing: nor does the tile
    const int window[2] = {ctx.master_width, ctx.master_height};
    if (!window_frustum(s.scene_projection, s.part_viewport, s.showing_size, rect, window, s.window_screen)) return;
    s.window_screen_known = true;
    // The interface lies on the program's screen, (x, y, 0, 1) of the window's clip space, and the
    // tile's correction takes it to (X, Y, W): those rows and columns, inverted, find it.
    const glm::dmat4 m = core_.options().view.correction(s.window_screen);
    const int rows[3] = {0, 1, 3};
    glm::dmat3 screen_to_tile;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) screen_to_tile[c][r] = m[rows[c]][rows[r]];
    // Over the program's whole window as the tile maps it: the scene's target holds the tile's frustum.
    const TileMapping& t = core_.options().tile;
    const int W = ctx.master_width, H = ctx.master_height;
    int32_t viewport[4] = {0, 0, W, H};
    if (t.enabled)
        viewport[0] = int32_t(t.map_x(0, W)), viewport[1] = int32_t(t.map_y(0, H)),
        viewport[2] = int32_t(t.map_w(0, W, W)), viewport[3] = int32_t(t.map_h(0, H, H));
    try {
        s.shown->composite(gl, s.showing_texture, glm::inverse(screen_to_tile), viewport, ctx.width, ctx.height);
        s.shown_in_frame = core_.frame() + 1;
    } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "glcast: cannot show the scene shown in part of the window on this tile: %s\n", e.what());
    }
}

GLuint TileAdapter::scene_over_tile() {
    const State& s = state();
    return s.shown && s.shown_in_frame == core_.frame() + 1 ? s.shown->mask() : 0;
}

}  // namespace glcast::slave
