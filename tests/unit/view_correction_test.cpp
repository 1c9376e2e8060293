// The rotated tile's projection (slave/view_correction.h), as numbers: where a point of the
// program's eye space lands on a tile, and that the program's own depth mapping survives.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "slave/view_correction.h"

using glcast::slave::ViewCorrection;

namespace {

constexpr double kPi = 3.14159265358979323846;

glm::dvec3 ndc(const glm::dmat4& m, const glm::dvec3& eye) {
    const glm::dvec4 c = m * glm::dvec4(eye, 1.0);
    return glm::dvec3(c) / c.w;
}

// A point `distance` away at `yaw_deg` (positive to the right), at eye height.
glm::dvec3 at_yaw(double yaw_deg, double distance) {
    const double a = yaw_deg * kPi / 180;
    return {distance * std::sin(a), 0, -distance * std::cos(a)};
}

ViewCorrection tile(double yaw) {
    ViewCorrection v;
    v.enabled = true;
    v.yaw_deg = yaw;
    return v;  // 60 degrees across, -20 .. +30 up and down
}

}  // namespace

TEST(ViewCorrection, APointAtTheTilesYawLandsAtItsCentreColumn) {
    const glm::dmat4 app = glm::frustum(-0.5, 0.5, -0.375, 0.375, 0.5, 100.0);
    for (double yaw : {0.0, 60.0, -120.0}) {
        const ViewCorrection v = tile(yaw);
        const glm::dvec3 p = ndc(v.correction(app) * app, at_yaw(yaw, 6));
        EXPECT_NEAR(p.x, 0, 1e-9) << yaw;
        const glm::dvec3 edge = ndc(v.correction(app) * app, at_yaw(yaw + 30, 6));
        EXPECT_NEAR(edge.x, 1, 1e-9) << "the tile's right edge is 30 degrees to the right";
    }
}

TEST(ViewCorrection, TheProgramsDepthMappingIsKept) {
    // glFrustum's: the same depths as the program's own for a point straight ahead.
    const glm::dmat4 standard = glm::frustum(-0.5, 0.5, -0.375, 0.375, 0.5, 100.0);
    const ViewCorrection v = tile(60);
    for (double d : {1.0, 6.0, 90.0})
        EXPECT_NEAR(ndc(v.correction(standard) * standard, at_yaw(60, d)).z, ndc(standard, at_yaw(0, d)).z, 1e-9);
    // Reversed depth with an infinite far plane (clip control GL_ZERO_TO_ONE): the near plane at
    // 1, farther points smaller, infinity towards 0, never outside [0, 1].
    glm::dmat4 reversed(0.0);
    reversed[0][0] = 0.5 / 0.2887, reversed[1][1] = 0.5 / 0.2165;
    reversed[2][3] = -1, reversed[3][2] = 0.5;
    double last = 2;
    for (double d : {0.5, 1.0, 6.0, 1000.0, 1e6}) {
        const double z = ndc(v.correction(reversed) * reversed, at_yaw(60, d)).z;
        EXPECT_LT(z, last) << d;
        EXPECT_GT(z, 0) << d;
        EXPECT_LE(z, 1 + 1e-12) << d;
        last = z;
    }
    EXPECT_NEAR(ndc(v.correction(reversed) * reversed, at_yaw(60, 0.5)).z, 1, 1e-9);
}

// A projection read back through an inverted correction carries rounding where a perspective
// one has zeros (1e-16 in its w row): it is still the same projection, its depth mapping kept.
TEST(ViewCorrection, RoundingInTheWRowDoesNotChangeTheCorrection) {
    const glm::dmat4 app = glm::frustum(-0.276142, 0.276142, -0.207107, 0.207107, 0.5, 100.0);
    glm::dmat4 rounded = app;
    rounded[0][3] = 2.2e-16, rounded[2][0] = 1.1e-16;
    const ViewCorrection v = tile(60);
    const glm::dmat4 a = v.correction(app) * app, b = v.correction(rounded) * rounded;
    for (double d : {0.6, 6.0, 90.0}) EXPECT_NEAR(ndc(a, at_yaw(60, d)).z, ndc(b, at_yaw(60, d)).z, 1e-9) << d;
}

// A left-handed eye space (looking down +Z, w = +z: Irrlicht's): the same turn, written with z
// mirrored. Before, it went through the fallback for non-frustums and every point lay behind the eye.
TEST(ViewCorrection, ALeftHandedProjectionTurnsAsARightHandedOne) {
    glm::dmat4 left = glm::frustum(-0.5, 0.5, -0.375, 0.375, 0.5, 100.0);
    left[2] = -left[2];  // P * diag(1, 1, -1, 1): eye z mirrored
    for (double yaw : {0.0, 60.0, -120.0}) {
        const ViewCorrection v = tile(yaw);
        glm::dvec3 ahead = at_yaw(yaw, 6), edge = at_yaw(yaw + 30, 6);
        ahead.z = -ahead.z, edge.z = -edge.z;
        const glm::dmat4 m = v.correction(left) * left;
        EXPECT_NEAR(ndc(m, ahead).x, 0, 1e-9) << yaw;
        EXPECT_NEAR(ndc(m, edge).x, 1, 1e-9) << yaw;
        EXPECT_GT((m * glm::dvec4(ahead, 1.0)).w, 0) << "in front of the eye";
        EXPECT_NEAR(ndc(m, ahead).z, ndc(left, glm::dvec3(0, 0, 6)).z, 1e-9) << "its depth mapping kept";
    }
}
