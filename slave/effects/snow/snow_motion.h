// How falling snow moves on the image (docs/snow.md): a flake with eye-space
// velocity u at depth d seen at normalized image position a = X / -Z moves with
//
//     da/dt = (u_xy + a u_z) / d,
//
// uniform when only the snow moves (u_z = 0), radial from the focus of expansion
// a_foe = -u_xy / u_z when the camera moves through it. The spectral layer's regions take their
// C and theta from this velocity at their centres: theta points from the FOE (away from it when
// the camera moves forward) and C grows with the distance from it.
#pragma once

#include <glm/glm.hpp>

namespace glcast::slave::effects {

// Canvas pixels per second of a flake at depth `depth` (eye units, > 0) moving with eye-space
// velocity `u`, seen at canvas pixel `q` of a canvas_w x canvas_h canvas whose whole area the
// projection `p` covers.
glm::dvec2 image_velocity(const glm::dmat4& p, double canvas_w, double canvas_h, glm::dvec2 q, glm::dvec3 u,
                          double depth);

// The focus of expansion in canvas pixels for eye-space velocity u (false: u_z ~ 0, at infinity).
bool focus_of_expansion(const glm::dmat4& p, double canvas_w, double canvas_h, glm::dvec3 u, glm::dvec2& foe);

// Eye-space velocity of the camera between two view transforms (world -> eye), dt seconds apart.
glm::dvec3 camera_velocity_eye(const glm::dmat4& previous_view, const glm::dmat4& view, double dt);

// Eq. 6's C (rad/s) and theta (rad) that make the spectral texture's fastest band (|w| =
// min_frequency_fraction * M) move with `texels_per_second`. The texture drifts towards
// theta + pi (spectral_snow.h), so theta is the opposite of the motion.
void spectral_c_theta(glm::dvec2 texels_per_second, double min_frequency_fraction, double& c, double& theta);

}  // namespace glcast::slave::effects
