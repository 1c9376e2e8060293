// Rotated, asymmetric and physical tiles (cylinders, CAVEs, powerwalls; docs/wall.md,
// docs/immersive.md): the tile shows what its own camera sees, a camera placed relative to the
// program's. Applied after the program's own transform as a clip-space correction
//
//     M = P_tile * V_tile * P_app^-1
//
// premultiplied into GL_PROJECTION for fixed-function programs. V_tile takes the program's eye
// space into the tile camera's: a turn by yaw, pitch and roll, or, for a screen given by its
// corners in metres, the screen's axes and the eye's offset from the room's origin (the
// generalized perspective projection). Lighting stays in the program's eye space, so it agrees
// on every tile. Near and far come from the program's projection, so depth keeps its range.
#pragma once

#include <glm/glm.hpp>

namespace glcast::slave {

struct ViewCorrection {
    bool enabled = false;
    double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;
    double left_deg = -30, right_deg = 30, bottom_deg = -20, top_deg = 30;
    // A screen in the room (metres: x right, y up, z towards the viewer; the program's camera at
    // the origin looking down -z) instead of the angles: three corners of its rectangle.
    bool screen = false;
    glm::dvec3 bottom_left{0.0}, bottom_right{0.0}, top_left{0.0};
    double units_per_metre = 1;  // the program's eye-space units in a metre
    // Where the eye this tile renders for is, in metres (the viewer's head and which eye).
    glm::dvec3 eye{0.0};
    // Shader programs: their projection, which the stream does not show (from the display
    // config's program_projection); 0 = unknown, shader programs are then left alone.
    double program_fov_y_deg = 0, program_near = 0.1, program_far = 1000;

    // The correction for a program projection `app` (column-major, as GL stores it).
    glm::dmat4 correction(const glm::dmat4& app) const;
    // The program_projection for a window of this aspect (width / height).
    glm::dmat4 program_projection(double aspect) const;
    // Moves the eye; false (the eye kept) for a position that is not finite or, on a screen
    // tile, not at least a millimetre in front of the screen.
    bool set_eye(const glm::dvec3& position);
    // Where a point of the program's eye space lands in this tile's image: u to the right, v
    // down, 0..1 across the tile (an MPCDI 3D region's screen points); false behind the tile's
    // camera.
    bool image_position(const glm::dvec3& point, glm::dvec2& uv) const;

private:
    // The tile camera: its frustum as tangents of the edges' angles from its axis, and V_tile.
    struct Camera {
        double left, right, bottom, top;
        glm::dmat4 view;
    };
    Camera camera() const;
};

}  // namespace glcast::slave
