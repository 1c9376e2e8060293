// The soft-shadow computation of one tile (docs/shadows.md): from a FrameView to a visibility
// texture (1 = lit, 0 = in umbra) covering the tile and a guard band around it, then the
// darkening of the window framebuffer by it. The steps follow the seed (Klein, Obermeier,
// Nischwitz: "Contact Hardening Soft Shadows using Erosion"):
//   shadow map      the frame's draws re-rendered from the light, depth only;
//   hard shadows    the camera depth of tile + guard band, then per pixel: lit or not, the
//                   parallel-planes penumbra width of its blocker, its light and eye depths;
//   edge detection  3x3 Laplacian of the hard shadows, kept where the shadow map has a
//                   silhouette, carrying the penumbra width; least-squares lines (direct only);
//   erosion         min-max mipmap of the edges, then per pixel the eroded penumbra region
//                   (PCF solution) or the shadow factor from the distance to the edge (direct);
//   shading         PCF scaled by the penumbra in the eroded region, and the darkening.
// PCSS (8/32/64 blocker samples) and the area-light reference run in the same frame set-up.
//
// Work area: the tile plus `max_penumbra` pixels on each side, widened on the left and bottom
// so that its origin sits on a multiple of the coarsest mipmap block in canvas pixels: every
// tile of a wall then builds the same min-max blocks and erodes the same way.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "slave/effects/frame_view.h"
#include "slave/effects/gl_api.h"
#include "slave/effects/shadows/shadow_light.h"
#include "slave/effects/shadows/shadow_settings.h"

namespace glcast::slave::effects {

// Milliseconds per step of the last frame (glFinish + steady clock; only when profiling).
struct ShadowStepTimes {
    double shadow_map = 0, hard_shadows = 0, edge_detection = 0, erosion = 0, shading = 0;
    double total() const { return shadow_map + hard_shadows + edge_detection + erosion + shading; }
};

class ShadowRenderer {
public:
    // Compiles the programs of settings.method (throws std::runtime_error naming the shader).
    ShadowRenderer(const GlApi& gl, const ShadowSettings& settings);
    ~ShadowRenderer();
    ShadowRenderer(const ShadowRenderer&) = delete;
    ShadowRenderer& operator=(const ShadowRenderer&) = delete;

    // Another method for the next frames (tests, benchmark); compiles its programs if needed.
    void set_method(ShadowMethod method);
    const ShadowSettings& settings() const { return settings_; }
    void set_profiling(bool on) { profiling_ = on; }
    const ShadowStepTimes& last_times() const { return times_; }

    // Computes the visibility of the tile of `view`. A frame whose draws cannot be re-rendered
    // (no redraw) is shadowed by the screen-space method from the window's depth, whatever the
    // method. False (and nothing drawn) when the frame cannot be shadowed: no main view, or
    // neither a redraw nor a depth; `why` says which. Leaves GL state changed (run it inside a
    // StateGuard).
    bool render(const FrameView& view, std::string& why);
    // The last render() marched the depth (screen-space) rather than using a shadow map.
    bool used_screen_space() const { return screen_space_; }
    // Multiplies the framebuffer bound for drawing (the tile, viewport 0,0,width,height) by
    // 1 - strength * (1 - visibility); pixels of visibility 1 are not written.
    void composite(const FrameView& view);

    // Results of the last render(), for tests and pictures.
    GLuint visibility_texture() const { return visibility_.texture; }   // RG32F, work area: visibility, facing
    GLuint hard_shadow_texture() const { return hard_.texture; }        // RGBA32F: lit, width, light depth, eye depth
    GLuint edges_texture() const { return edges_.texture; }             // RGBA32F: 0 on edges, width, eye depth
    GLuint erosion_texture() const { return erosion_.texture; }         // RG32F (erosion-pcf): width, 1 in a region
    glm::ivec2 work_size() const { return work_size_; }
    glm::ivec2 tile_offset() const { return tile_offset_; }  // work texel of tile pixel (0, 0)
    const ShadowLight& light() const { return light_; }
    const LightFrame& light_frame() const { return frame_; }
    // Channel `channel` of `texture` (a work-area texture above) over the tile, rows bottom up.
    std::vector<float> read_tile(GLuint texture, int channel) const;

private:
    struct Target {
        GLuint texture = 0, framebuffer = 0;
        int width = 0, height = 0;
    };
    struct Programs {
        GLuint hard = 0, candidates = 0, edges = 0, minmax = 0, lines = 0, erode = 0, shade = 0, reference = 0,
               screen_space = 0, screen_filter = 0, composite = 0;
    };

    // fullscreen.vert, or shadow_blocks.vert when `blocks`; `common`: shadow_common.glsl first.
    GLuint program(const std::string& fragment, const std::string& defines, bool common, bool blocks = false);
    void build_programs(ShadowMethod method);
    void ensure_targets(const FrameView& view, bool rerender_depth);
    void release_targets();
    void set_common_uniforms(GLuint program) const;
    void set_light_uniforms(GLuint program, const ShadowLight& light, const LightFrame& frame) const;
    void draw_into(const Target& target, GLuint program) const;
    void clear(const Target& target, float red) const;  // to (red, 0, 0, 0)
    // The blocks of the work area that have an edge of `cull` (a min-max mipmap) within
    // `reach` blocks, and `by_width`: within that edge's penumbra reach (shadow_blocks.vert).
    void draw_blocks(const Target& target, GLuint program, GLuint cull, int reach, bool by_width) const;
    void reduce(const Target& target, int levels, GLuint minmax);  // its min-max mipmap
    void render_shadow_map(const FrameView& view, const LightFrame& frame);
    void render_camera_depth(const FrameView& view, const glm::dmat4& correction);
    void hard_shadows(const Programs& p);
    void detect_edges(const Programs& p);
    void build_min_max(const Programs& p);
    void erode(const Programs& p);
    void shade(const Programs& p);
    void reference(const FrameView& view, const Programs& p);
    void march_screen_space(const Programs& p);   // into hard_: marched shadows, penumbra widths
    void soften_screen_space(const Programs& p);  // hard_ into visibility_
    void step_done(double ShadowStepTimes::*step);

    const GlApi& gl_;
    ShadowSettings settings_;
    Programs programs_[7];  // by ShadowMethod
    std::map<std::string, GLuint> program_cache_;  // by fragment file and defines
    GLuint empty_vao_ = 0;
    bool profiling_ = false;
    ShadowStepTimes times_;
    double step_start_ = 0;

    // Per frame.
    ShadowLight light_;
    LightFrame frame_;
    glm::ivec2 tile_size_{0}, work_size_{0}, tile_offset_{0}, canvas_origin_{0};
    int levels_ = 0, edge_levels_ = -1;  // coarsest min-max mipmap level (wanted, allocated)
    int block_level_ = 0, block_reach_ = 0;  // culled steps: blocks of 2^block_level_ pixels
    glm::ivec2 blocks_{0};
    std::array<glm::dvec3, 8> corners_{};  // the main view's frustum, eye space
    double reach_ = 60;                     // how far into it the shadows reach (shadow_reach)
    GLint target_framebuffer_ = 0;         // bound for drawing when render() was called
    glm::dmat4 eye_from_work_clip_{1.0};
    double focal_px_ = 1;
    GLuint camera_depth_texture_ = 0;  // ours or the window's copy
    bool screen_space_ = false;

    Target shadow_map_, camera_depth_, hard_, candidates_, edges_, lines_, erosion_, visibility_;
};

}  // namespace glcast::slave::effects
