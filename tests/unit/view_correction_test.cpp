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

TEST(ViewCorrection, AnUpsideDownProjectionTurnsUpsideDown) {
    // pillars --fbo --mirror, Wine's way: drawn upside down into a target the program shows
    // flipped. The tile's picture must be upside down in that target too, its rows flipped back
    // by the program's blit; else the tile shows the world on its head.
    const glm::dmat4 upright = glm::frustum(-0.5, 0.5, -0.375, 0.375, 0.5, 100.0);
    const glm::dmat4 flipped = glm::frustum(-0.5, 0.5, 0.375, -0.375, 0.5, 100.0);
    for (double yaw : {0.0, 60.0}) {
        const ViewCorrection v = tile(yaw);
        for (const glm::dvec3 eye : {at_yaw(yaw + 10, 6) + glm::dvec3(0, 1, 0), at_yaw(yaw - 20, 9) - glm::dvec3(0, 2, 0)}) {
            const glm::dvec3 a = ndc(v.correction(upright) * upright, eye);
            const glm::dvec3 b = ndc(v.correction(flipped) * flipped, eye);
            EXPECT_NEAR(b.x, a.x, 1e-9) << yaw;
            EXPECT_NEAR(b.y, -a.y, 1e-9) << yaw;
            EXPECT_NEAR(b.z, a.z, 1e-9) << yaw;
        }
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

// Screens in metres (docs/immersive.md): where a room point lands on a screen seen from an eye,
// computed here by intersecting the eye's ray with the screen's plane.
namespace {

struct Wall {
    glm::dvec3 bottom_left, bottom_right, top_left;
};

// The point's position on the wall as normalized device coordinates (-1..1 across and up).
glm::dvec2 on_wall(const Wall& w, const glm::dvec3& eye, const glm::dvec3& p) {
    const glm::dvec3 across = w.bottom_right - w.bottom_left, up = w.top_left - w.bottom_left;
    const glm::dvec3 normal = glm::normalize(glm::cross(across, up));
    const double t = glm::dot(w.bottom_left - eye, normal) / glm::dot(p - eye, normal);
    const glm::dvec3 hit = eye + t * (p - eye) - w.bottom_left;
    return {2 * glm::dot(hit, across) / glm::dot(across, across) - 1, 2 * glm::dot(hit, up) / glm::dot(up, up) - 1};
}

ViewCorrection screen_tile(const Wall& w, const glm::dvec3& eye, double units_per_metre = 1) {
    ViewCorrection v;
    v.enabled = true;
    v.screen = true;
    v.bottom_left = w.bottom_left, v.bottom_right = w.bottom_right, v.top_left = w.top_left;
    v.units_per_metre = units_per_metre;
    EXPECT_TRUE(v.set_eye(eye));
    return v;
}

const Wall kFront{{-1.5, -1.5, -1.5}, {1.5, -1.5, -1.5}, {-1.5, 1.5, -1.5}};
const Wall kLeft{{-1.5, -1.5, 1.5}, {-1.5, -1.5, -1.5}, {-1.5, 1.5, 1.5}};
const Wall kFloor{{-1.5, -1.5, 1.5}, {1.5, -1.5, 1.5}, {-1.5, -1.5, -1.5}};

}  // namespace

TEST(ViewCorrection, AScreenSeenFromTheCentreIsTheAngleTileOfTheSameFrustum) {
    const glm::dmat4 app = glm::frustum(-0.5, 0.5, -0.375, 0.375, 0.5, 100.0);
    struct Case {
        Wall wall;
        double yaw, pitch;
    } cases[] = {{kFront, 0, 0}, {kLeft, -90, 0}, {kFloor, 0, -90}};
    for (const Case& c : cases) {
        ViewCorrection angles;
        angles.enabled = true;
        angles.yaw_deg = c.yaw, angles.pitch_deg = c.pitch;
        angles.left_deg = angles.bottom_deg = -45, angles.right_deg = angles.top_deg = 45;
        const glm::dmat4 a = angles.correction(app), s = screen_tile(c.wall, glm::dvec3(0.0)).correction(app);
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) EXPECT_NEAR(a[i][j], s[i][j], 1e-9) << c.yaw << " " << c.pitch << " " << i << j;
    }
}

TEST(ViewCorrection, AScreenPutsARoomPointWhereTheEyesRayMeetsIt) {
    const glm::dmat4 app = glm::frustum(-0.5, 0.5, -0.375, 0.375, 0.5, 100.0);
    const glm::dvec3 eyes[] = {{0.5, 0, 0}, {-0.3, 0.4, 0.5}, {0.032, -0.2, -0.6}};
    const glm::dvec3 points[] = {{0.4, 0.3, -2.5}, {-2.2, 0.5, -0.4}, {0.3, -2.4, 0.2}, {0.1, -0.2, -1.0}};
    for (const Wall& w : {kFront, kLeft, kFloor})
        for (const glm::dvec3& eye : eyes)
            for (const glm::dvec3& p : points) {
                const glm::dvec3 n = glm::normalize(glm::cross(w.bottom_right - w.bottom_left, w.top_left - w.bottom_left));
                if (glm::dot(p - eye, n) >= 0) continue;  // behind the eye for this wall
                const ViewCorrection v = screen_tile(w, eye);
                const glm::dvec3 got = ndc(v.correction(app) * app, p);
                const glm::dvec2 want = on_wall(w, eye, p);
                EXPECT_NEAR(got.x, want.x, 1e-9);
                EXPECT_NEAR(got.y, want.y, 1e-9);
            }
}

TEST(ViewCorrection, ProgramUnitsScaleTheRoom) {
    // A program whose eye space is in centimetres: the room point (0.4, 0.3, -2.5) m is (40, 30, -250).
    const glm::dmat4 app = glm::frustum(-50.0, 50.0, -37.5, 37.5, 50.0, 10000.0);
    const ViewCorrection v = screen_tile(kFront, {0.5, 0.2, 0.1}, 100);
    const glm::dvec3 got = ndc(v.correction(app) * app, {40, 30, -250});
    const glm::dvec2 want = on_wall(kFront, {0.5, 0.2, 0.1}, {0.4, 0.3, -2.5});
    EXPECT_NEAR(got.x, want.x, 1e-9);
    EXPECT_NEAR(got.y, want.y, 1e-9);
}

TEST(ViewCorrection, AnEyeBehindOrOnTheScreenIsRefusedAndTheLastKept) {
    ViewCorrection v = screen_tile(kFront, {0.1, 0, 0});
    const glm::dmat4 app = glm::frustum(-0.5, 0.5, -0.375, 0.375, 0.5, 100.0);
    const glm::dmat4 before = v.correction(app);
    EXPECT_FALSE(v.set_eye({0, 0, -1.5}));
    EXPECT_FALSE(v.set_eye({0, 0, -2}));
    EXPECT_FALSE(v.set_eye({std::nan(""), 0, 0}));
    EXPECT_EQ(v.eye, glm::dvec3(0.1, 0, 0));
    EXPECT_EQ(v.correction(app), before);
}
