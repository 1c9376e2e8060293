// Where the shadow map looks from (docs/shadows.md, "Light" and "Shadow map"). Pure geometry,
// no GL: every tile of a wall computes the same light frame from the main view's projection
// alone (never from its tile), so the tiles share one shadow map.
//
// Spaces: "eye" is the program's eye space of the main view (FrameView::projection maps it to
// the program's clip space); "light view" is a right-handed frame whose -z axis points from the
// light into the scene; "light depth" z = -light_view.z, the distance along that axis.
#pragma once

#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "slave/effects/frame_view.h"
#include "slave/effects/shadows/shadow_settings.h"

namespace glcast::slave::effects {

struct ShadowLight {
    bool directional = true;
    glm::dvec3 position{0.0};            // positional: eye space
    glm::dvec3 direction{0.0, 1.0, 0.0}; // directional: unit vector from the scene towards the light
};

// A light at the eye or shining along the view axis (within 10 degrees): a viewer's headlight
// (osgviewer's default). Every shadow it casts lies behind its caster, out of sight.
bool is_headlight(const glm::dvec4& eye_gl_position);

// The program's first enabled light when it has one, settings allow and it is no headlight,
// else the settings' light (FrameView::light and the fallback are both eye-space GL_POSITIONs).
ShadowLight choose_light(const FrameView& view, const ShadowSettings& settings);

// How far into the main view the shadows reach, eye-space units: shadows.max_distance, or when
// it is 0 (the default) 120 near-plane distances of `projection` but at least 60, and not past
// its far plane: the same share of the view for programs of a larger scale (60 for a near
// plane at 0.5, 480 for Quake's 4).
constexpr double kShadowReachInNearPlanes = 120, kShadowReachAtLeast = 60;
double shadow_reach(const ShadowSettings& settings, const glm::dmat4& projection);

// The 8 corners (near then far, each (-1,-1), (1,-1), (-1,1), (1,1) in NDC) of the frustum
// of `projection` in eye space, the far ones pulled in to eye distance `max_distance` when
// they lie further.
std::array<glm::dvec3, 8> view_frustum_corners(const glm::dmat4& projection, double max_distance);

struct LightFrame {
    bool orthographic = true;
    glm::dmat4 view{1.0};        // L: eye -> light view
    glm::dmat4 projection{1.0};  // P_light: light view -> light clip
    double near = 0, far = 1;    // light depths of the map's depth range 0 and 1
    // Shadow-map uv per eye-space unit across the light axis: for an orthographic frame exact,
    // for a perspective one at light depth 1 (divide by the depth).
    glm::dvec2 uv_per_unit{1.0};
    glm::dmat4 clip_from_eye() const { return projection * view; }
};

// The frame of the shadow map that sees the whole `corners` volume from `light`: for a
// directional light an orthographic box around it (extended towards the light by its own
// depth, so casters outside the view still cast); for a positional light a square
// perspective frustum from the light towards the volume's centre, as wide as the volume needs
// but at most `max_fov_deg`.
LightFrame fit_light_frame(const ShadowLight& light, const std::array<glm::dvec3, 8>& corners, double max_fov_deg);

// `count` point lights spread evenly (a Vogel spiral: equal areas) over the area light: a disk
// of diameter `size` across the axis of `center_frame` for a positional light, a cone of
// directions of angular diameter `angle_deg` for a directional one. The reference method
// averages their hard shadows.
std::vector<ShadowLight> area_light_samples(const ShadowLight& light, const LightFrame& center_frame, double size,
                                            double angle_deg, int count);

// The full width, across the light direction, of the penumbra a blocker at light depth
// `blocker` casts on a receiver at light depth `receiver` (the parallel-planes estimate of
// Fernando's PCSS): size * (receiver - blocker) / blocker for a positional light,
// 2 tan(angle / 2) * (receiver - blocker) for a directional one. Eye-space units.
double penumbra_width(const ShadowLight& light, double size, double angle_deg, double receiver, double blocker);

}  // namespace glcast::slave::effects
