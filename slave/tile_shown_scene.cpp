// Rotated tiles: a scene the program draws into a framebuffer object of another shape than its
// window's and shows in part of the window (shown_scene.h). Its target's draws are turned as
// the window's scene is (tile_turn.cpp); here the draw that shows it is found and redirected,
// and the turned scene drawn over the tile in its stead.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <stdexcept>

#include "common/gl_headers.h"
#include "slave/replayer.h"
#include "slave/scaled_blit.h"
#include "slave/tile_adapter.h"
#include "slave/tile_adapter_state.h"

namespace glcast::slave {

namespace {

// A context that presented in the last frames may draw a frame of its own: it lends nothing.
constexpr uint64_t kLendsAfterFrames = 2;

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

const TileAdapter::State* TileAdapter::scene_in_part(const SlaveContext& ctx) {
    const State& s = state();
    if (!ctx.drawing_to_window) return nullptr;
    if (s.scene_view && s.scene_in_part && s.part_turned) return &s;
    const State* lender = lender_of(s);
    return lender && lender->scene_in_part && lender->part_turned && !lender->part_refused ? lender : nullptr;
}

TileAdapter::State* TileAdapter::lender_of(const State& s) {
    if (!s.lender) return nullptr;
    auto it = states_.find(s.lender);
    return it == states_.end() ? nullptr : it->second.get();
}

// A context of the share group that drew a view into a target of colour and depth and never
// draws to its window (a toolkit's GL widget): when a flat draw to the window samples a texture
// of that view's size, it lends the window its scene, which is turned from its next drawing on.
void TileAdapter::find_lender(const SlaveContext& ctx) {
    State& s = state();
    if (s.lender && lender_of(s)) return;
    s.lender = 0;  // (none yet, or its context is gone)
    for (auto& [id, other] : states_) {
        // (Blender's draw manager's context swaps its hidden window once when it is made)
        const bool presents = other->presented && other->presented_frame + kLendsAfterFrames >= core_.frame();
        if (id == ctx.id || !other->frame_part_target || other->part_refused || presents) continue;
        const auto context = core_.contexts().find(id);
        if (context == core_.contexts().end() || context->second->names.shared.get() != ctx.names.shared.get()) continue;
        GLuint texture = 0;
        if (!samples_texture_of_size(other->part_viewport + 2, texture)) continue;
        s.lender = id;
        other->scene_target = other->frame_part_target;
        other->scene_in_part = other->scene_target_known = true;
        return;
    }
}

// The draw that shows the scene samples a texture of its view's size (the target's own colour,
// a resolve's or a post-processing copy's); the toolbars and panels drawn around it do not.
bool TileAdapter::samples_texture_of_size(const int32_t size[2], GLuint& texture) {
    const GlApi& gl = core_.api();
    const bool fixed_function = program_in_use() == 0;
    GLint active = GL_TEXTURE0, bound = 0, w = 0, h = 0;
    gl.glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    texture = 0;
    for (int unit = 0; unit < 8 && !texture; ++unit) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
        if (!bound || (fixed_function && !gl.glIsEnabled(GL_TEXTURE_2D))) continue;
        gl.glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &w);
        gl.glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &h);
        if (w == size[0] && h == size[1]) texture = GLuint(bound);
    }
    gl.glActiveTexture(GLenum(active));
    return texture != 0;
}

bool TileAdapter::shows_scene_in_part(const SlaveContext& ctx, const State& scene) {
    State& s = state();
    GLuint found = 0;
    if (!samples_texture_of_size(scene.part_viewport + 2, found)) return false;
    s.part_found = true;
    s.showing_texture = found;
    s.showing_repeatable = !opening_begin_;
    s.showing_size[0] = scene.part_viewport[2], s.showing_size[1] = scene.part_viewport[3];
    s.shown_projection = scene.scene_projection;
    std::copy(scene.part_viewport, scene.part_viewport + 4, s.shown_viewport);
    int32_t viewport[4];
    program_viewport(viewport);
    try {
        if (!s.shown) s.shown = std::make_shared<ShownScene>();
        s.shown->begin(core_.api(), ctx.master_width, ctx.master_height, viewport);
    } catch (const std::runtime_error& e) {
        s.shown->end(core_.api(), viewport);
        std::fprintf(stderr, "glcast: cannot show the scene shown in part of the window on this tile: %s\n", e.what());
    }
    return true;
}

void TileAdapter::finish_shown_scene(const Call& c) {
    State& s = state();
    if (!s.shown || !s.shown->redirected()) return;
    const SlaveContext& ctx = core_.current();
    const GlApi& gl = core_.api();
    int32_t rect[4];
    if (!s.shown->end(gl, rect)) return;  // it drew nothing: nor does the tile
    show_over_tile(rect, [&] {
        // A draw that can be run again (not glBegin/glEnd's) shows the scene as the program's own
        // shader makes it, stretched over the tile; else its texture is shown as it is.
        if (!s.showing_repeatable || !kReplay[c.opcode]) return s.showing_texture;
        int32_t program[4];
        program_viewport(program);
        return s.shown->draw_stretched(gl, rect, program, ctx.width, ctx.height,
                                       [this, &c] {
                                           correct_fragcoord(program_in_use());  // (the stretched viewport)
                                           kReplay[c.opcode](core_, c);
                                       });
    });
}

// A scene shown by glBlitFramebuffer from its target (or a resolve's or a copy's of its size)
// into the window: the blit is the draw that shows it, its destination is where. On the tile the
// blit stretches the turned scene over a tile-sized target (resolving a multisampled one first).
bool TileAdapter::shows_scene_by_blit(const int32_t source[4], const int32_t destination[4], GLbitfield mask) {
    State& s = state();
    const SlaveContext& ctx = core_.current();
    if (!core_.options().view.enabled || s.scene_shown || !(mask & GL_COLOR_BUFFER_BIT)) return false;
    // (a lender's targets are its own context's: never read by this one's blit)
    if (scene_in_part(ctx) != &s || int64_t(source[2]) - source[0] != s.part_viewport[2] ||
        int64_t(source[3]) - source[1] != s.part_viewport[3] || destination[2] <= destination[0] ||
        destination[3] <= destination[1])
        return false;
    s.scene_shown = s.part_found = true;
    s.showing_size[0] = s.part_viewport[2], s.showing_size[1] = s.part_viewport[3];
    s.shown_projection = s.scene_projection;
    s.shown_viewport[0] = s.part_viewport[0] - source[0], s.shown_viewport[1] = s.part_viewport[1] - source[1];
    s.shown_viewport[2] = s.part_viewport[2], s.shown_viewport[3] = s.part_viewport[3];
    const GlApi& gl = core_.api();
    int32_t rect[4];
    try {
        if (!s.shown) s.shown = std::make_shared<ShownScene>();
        if (!s.shown->cover(gl, ctx.master_width, ctx.master_height, destination, rect)) return true;
    } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "glcast: cannot show the scene shown in part of the window on this tile: %s\n", e.what());
        return true;
    }
    show_over_tile(destination, [&] {
        const int32_t whole[4] = {destination[0], destination[1], destination[2] - destination[0],
                                  destination[3] - destination[1]};
        return s.shown->draw_stretched(gl, destination, whole, ctx.width, ctx.height, [&] {
            const int32_t tile[4] = {0, 0, ctx.width, ctx.height};
            if (ScaledBlit::needed(gl, source, tile)) {
                if (!s.scaled_blit) s.scaled_blit = std::make_shared<ScaledBlit>();
                s.scaled_blit->blit(gl, source, tile, GL_COLOR_BUFFER_BIT, GL_LINEAR);
            } else {
                gl.glBlitFramebuffer(source[0], source[1], source[2], source[3], 0, 0, ctx.width, ctx.height,
                                     GL_COLOR_BUFFER_BIT, GL_LINEAR);
            }
        });
    });
    return true;
}

// The scene the program showed at `rect` of its window (x0, y0, x1, y1: the footprint's), turned,
// over the tile: where the tile does not see the program's screen, and where the footprint lies
// on it. `picture` makes the texture to show.
void TileAdapter::show_over_tile(const int32_t rect[4], const std::function<GLuint()>& picture) {
    State& s = state();
    const SlaveContext& ctx = core_.current();
    const GlApi& gl = core_.api();
    const int window[2] = {ctx.master_width, ctx.master_height};
    if (!window_frustum(s.shown_projection, s.shown_viewport, s.showing_size, rect, window, s.window_screen)) return;
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
        s.shown->composite(gl, picture(), glm::inverse(screen_to_tile), viewport, ctx.width, ctx.height);
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
