// Shared pieces of the snow cover and icicle pass (docs/winter.md): what each frame's stages
// agree on (the guard band, "up" and the light in eye space, the canvas), and small GL helpers.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "slave/effects/frame_view.h"
#include "slave/effects/gl_api.h"
#include "slave/effects/winter/winter_settings.h"

namespace glcast::slave::effects {

struct WinterFrame {
    int guard = 1;                   // pixels of re-rendered border around the tile
    int buffer_width = 0, buffer_height = 0;  // the tile plus the guard band
    int canvas_width = 0, canvas_height = 0;  // the tile's own size when it is the whole canvas
    glm::dvec3 up_eye{0, 1, 0};      // the direction opposite to the snowfall, main view's eye space
    glm::dmat4 world_from_eye{1.0};  // where the snow patches are anchored (identity: eye space)
    glm::dvec4 light_eye{0, 1, 0, 0};  // the program's light, or a light from above and in front
    double cover_fraction = 1;       // cover.density scale from the build-up over frames
    double edge_cos = 0;             // cos(cover.edge_angle)
    double lip_px = 0;               // mean lip thickness, canvas pixels
    int lip_rows = 0;                // the thickest lip, rounded up
    unsigned lip_seed = 1;
    // Icicle sizes in canvas pixels.
    double spacing_px = 0, radius_min_px = 0, radius_max_px = 0, length_max_px = 0;
};

// The guard band holds every pixel a screen-space step reads: the thickest lip and the longest
// icicle below it above the tile (they hang from edges that far above a pixel), plus the row
// the edge test reads.
// `up` replaces settings.cover.up (cover.up_space=auto: world_up_seen's).
WinterFrame winter_frame(const FrameView& view, const WinterSettings& settings, bool icicles, const glm::dvec3& up);


// build_program with winter_noise.glsl and the GLSL files `libraries` prepended to both shaders.
GLuint build_winter_program(const GlApi& gl, const std::string& vertex_file, const std::string& fragment_file,
                            const std::vector<std::string>& libraries = {});
// The uniforms of winter_edges.glsl.
void set_edge_uniforms(const GlApi& gl, GLuint program, const WinterFrame& frame);

// Uniform setters by name (a name the driver optimized away is skipped, as GL does for -1).
void set_uniform(const GlApi& gl, GLuint program, const char* name, int value);
void set_uniform(const GlApi& gl, GLuint program, const char* name, double value);
void set_uniform(const GlApi& gl, GLuint program, const char* name, const glm::dvec2& value);
void set_uniform(const GlApi& gl, GLuint program, const char* name, const glm::dvec3& value);
void set_uniform(const GlApi& gl, GLuint program, const char* name, const glm::dvec4& value);
void set_uniform(const GlApi& gl, GLuint program, const char* name, const glm::dmat4& value);
// A seed: the unsigned bits through glUniform1i, read in GLSL as uint(int).
void set_seed_uniform(const GlApi& gl, GLuint program, const char* name, unsigned value);
// Copies the window (framebuffer 0, its draw buffer) into `texture` (RGBA8, created or
// replaced when `size` is not width x height). Leaves framebuffer 0 bound for reading.
void copy_window(const GlApi& gl, GLuint& texture, glm::ivec2& size, int width, int height);

// Binds `texture` to unit `unit` and points sampler `name` at it.
void bind_sampler(const GlApi& gl, GLuint program, const char* name, int unit, GLuint texture);

}  // namespace glcast::slave::effects
