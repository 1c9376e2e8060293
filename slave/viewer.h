// The viewer of an immersive wall (docs/immersive.md): where the head is, and which of its eyes
// a tile renders for. Room coordinates are metres, x right, y up, z towards the viewer.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace glcast::slave {

struct HeadPose {
    glm::dvec3 position{0.0};
    glm::dquat orientation{1, 0, 0, 0};  // w, x, y, z: the identity looks down -z
    double eye_separation = -1;          // metres; < 0: unchanged (a pose may change it while running)
};

enum class Eye { centre, left, right };

// Both eyes in one output (slave/stereo.h): none (one eye), GL_BACK_LEFT and GL_BACK_RIGHT of a
// stereo window, the left eye in the left (top) half, or red from the left eye and green and
// blue from the right.
enum class StereoMode { none, quad_buffer, side_by_side, top_bottom, anaglyph };

struct Viewer {
    HeadPose head;
    double eye_separation = 0.064;  // metres between the eyes
    Eye eye = Eye::centre;          // the one this tile shows
};

// The viewer with the head at `head` (and its eye separation, when the pose gives one).
inline Viewer with_head(Viewer v, const HeadPose& head) {
    v.head.position = head.position;
    v.head.orientation = head.orientation;
    if (head.eye_separation >= 0) v.eye_separation = head.eye_separation;
    return v;
}

// The eye's position: half the separation along the head's right axis, to the left or right.
inline glm::dvec3 eye_position(const Viewer& v) {
    const double side = v.eye == Eye::left ? -0.5 : v.eye == Eye::right ? 0.5 : 0.0;
    return v.head.position + v.head.orientation * glm::dvec3(side * v.eye_separation, 0, 0);
}

}  // namespace glcast::slave
