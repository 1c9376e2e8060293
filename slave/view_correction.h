// Rotated and asymmetric tiles (cylinders, CAVEs; docs/wall.md): the tile shows what a camera
// turned by the tile's yaw/pitch/roll sees through its own asymmetric frustum. Applied after
// the program's own transform as a clip-space correction
//
//     M = P_tile * R_tile^T * P_app^-1
//
// premultiplied into GL_PROJECTION for fixed-function programs. Lighting stays in the
// program's eye space, so it agrees on every tile. Near and far come from the program's
// projection, so depth keeps its range.
#pragma once

#include <glm/glm.hpp>

namespace glcast::slave {

struct ViewCorrection {
    bool enabled = false;
    double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;
    double left_deg = -30, right_deg = 30, bottom_deg = -20, top_deg = 30;
    // Shader programs: their projection, which the stream does not show (from the display
    // config's program_projection); 0 = unknown, shader programs are then left alone.
    double program_fov_y_deg = 0, program_near = 0.1, program_far = 1000;

    // The correction for a program projection `app` (column-major, as GL stores it).
    glm::dmat4 correction(const glm::dmat4& app) const;
    // The program_projection for a window of this aspect (width / height).
    glm::dmat4 program_projection(double aspect) const;
};

}  // namespace glcast::slave
