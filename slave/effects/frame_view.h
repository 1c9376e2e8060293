// What an injected pass knows about the frame it decorates (docs/effects.md). Filled by the
// replayer at the end of each frame, before present, with the program's window framebuffer
// bound as the draw framebuffer and the viewport covering the whole tile.
//
// Coordinates. The program draws into its window; the wall stretches that window over the
// canvas and each slave shows one tile of it. Three spaces matter to a pass:
//   - tile pixels: gl_FragCoord in the window framebuffer of this slave (width x height);
//   - canvas pixels: tile pixels + (canvas_x, canvas_y) (GL convention, origin bottom left).
//     Every random choice is indexed by canvas pixels and the master's frame number, so the
//     tiles of a wall join without seams and a rerun is identical;
//   - the program's eye space (the "main view": the projection and modelview of the frame's
//     first draw to the window with a perspective projection, or to the framebuffer object
//     that holds a scene the program draws offscreen; docs/effects.md).
// tile_clip_from_eye maps eye space to this tile's clip space (projection, the wall's
// stretch or the rotated tile's correction included); eye_from_tile_clip is its inverse.
#pragma once

#include <cstdint>
#include <functional>

#include <glm/glm.hpp>

#include "common/gl_headers.h"

namespace glcast::slave::effects {

struct SceneLight {
    bool known = false;        // false: the program has no light glcast recognises (docs/effects.md)
    glm::dvec4 eye_position{0, 0, 1, 0};  // GL's GL_POSITION in eye space (w = 0: directional)
    // A direction from a shader program's uniform, which engines keep either way (towards the
    // sun, or the way its light travels): the sign that points to the sky is taken.
    bool sign_from_up = false;
};

// The world's +Y, -Y, +Z or -Z, whichever `modelview` turns most towards the eye's up: for a
// camera without roll and within 45 degrees of level, the world's up, Y-up (OpenGL's habit) and
// Z-up (Quake, CAD and modelling tools) alike. (A view 60 degrees up and one 30 degrees down,
// turned by a quarter, are the same rotation: the nearer to level wins.) +Y on a tie. The
// cover's up (cover.up_space=auto) and the side of the sky a program's sun is on.
inline glm::dvec3 world_up_seen(const glm::dmat4& modelview) {
    const glm::dvec3 axes[] = {{0, 1, 0}, {0, 0, 1}, {0, -1, 0}, {0, 0, -1}};
    glm::dvec3 best = axes[0];
    double best_score = -1e300;
    for (const glm::dvec3& axis : axes) {
        const glm::dvec3 seen = glm::dmat3(modelview) * axis;
        if (glm::length(seen) < 1e-12) continue;
        const double score = glm::normalize(seen).y;
        if (score > best_score + 1e-6) best = axis, best_score = score;
    }
    return best;
}

// A light whose direction's sign is not known (SceneLight::sign_from_up) turned to the side of the
// sky the main view's `modelview` shows (world_up_seen): a sun lights a scene from above.
inline SceneLight light_from_the_sky(SceneLight light, const glm::dmat4& modelview) {
    if (!light.known || !light.sign_from_up || light.eye_position.w != 0) return light;
    const glm::dvec3 up = glm::dmat3(modelview) * world_up_seen(modelview);
    if (glm::dot(glm::dvec3(light.eye_position), up) < 0) light.eye_position = -light.eye_position;
    light.sign_from_up = false;
    return light;
}

struct FrameView {
    uint64_t frame = 0;           // the master's frame number (swap count of this context)
    double time = 0;              // frame * frame_time: seconds of stream time, deterministic
    double frame_time = 1.0 / 60;  // nominal display interval
    int width = 0, height = 0;    // the tile's framebuffer
    int canvas_x = 0, canvas_y = 0, canvas_width = 0, canvas_height = 0;

    bool view_known = false;      // false: no perspective draw this frame; the matrices below are identities
    glm::dmat4 projection{1.0};   // P_app of the main view
    glm::dmat4 modelview{1.0};    // the modelview of the main view's first draw
    glm::dmat4 tile_clip_from_app_clip{1.0};  // T: the wall's stretch of this tile, or a rotated tile's M
    glm::dmat4 tile_clip_from_eye{1.0};       // T * P_app
    glm::dmat4 eye_from_tile_clip{1.0};
    SceneLight light;

    // Copies of the window framebuffer, made on a pass's first call in a frame and then cached
    // for the frame: RGBA8 color and DEPTH24_STENCIL8 depth, texel (x, y) = tile pixel. The
    // color is the window as the passes that ran before the first call left it (the program's
    // own image when the first pass asks); the depth is always the program's (no pass writes it):
    // of a scene drawn offscreen, that framebuffer object's, at the tile's size.
    std::function<GLuint()> color_texture;
    std::function<GLuint()> depth_texture;
    // False when the program's depth is not in the passes' convention (reversed, clip depth
    // 0..1, its own depth range: slave/scene/depth_convention.h), or the scene was drawn into a
    // framebuffer object: depth_texture() is then the scene's depth (converted), and the window's
    // depth buffer must not be tested against.
    bool window_depth_matches = true;

    // Re-renders the frame's draws of the main view (those made to the window with the main
    // view's projection) into whatever framebuffer, viewport and program are bound, with
    //     clip = correction * P_app * modelview * vertex
    // and the program's own fragment state, vertex-array object and 2D textures (as the frame
    // left them) and face culling as each draw had it, except: color, depth and stencil state,
    // blending, polygon offset, scissor, the bound program (0 for the program's fixed-function
    // shading) and the bound framebuffer are the caller's. Empty when
    // the stream cannot be re-rendered.
    // When redraw_binds_programs is true (the frame draws with shader programs) the draws bind
    // the program's own programs, textures and uniforms: the caller's program is not used, and
    // what the fragment shaders write goes to the bound framebuffer's colour attachments.
    std::function<void(const glm::dmat4& correction)> redraw;
    bool redraw_binds_programs = false;

    // The correction that makes redraw() render this tile plus `guard` pixels on every side
    // into a (width + 2 guard) x (height + 2 guard) framebuffer: screen-space steps that read
    // neighbouring pixels see, at the tile's border, what the neighbouring tile sees.
    glm::dmat4 guard_band(int guard) const {
        glm::dmat4 s(1.0);
        s[0][0] = double(width) / (width + 2 * guard);
        s[1][1] = double(height) / (height + 2 * guard);
        return s * tile_clip_from_app_clip;
    }
};

}  // namespace glcast::slave::effects
