// The passes' depth convention (slave/scene/depth_convention.h), as numbers: which programs'
// depth needs converting, and that the converted depth is what the standard projection gives
// the same point.
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "slave/scene/depth_convention.h"

using glcast::slave::depth_convention;
using glcast::slave::DepthConvention;
using glcast::slave::ProgramDepthState;
using glcast::slave::to_pass_depth;

namespace {

constexpr double kNear = 0.5;

// tests/apps_extra/pillars.c --reversed: GL_ZERO_TO_ONE, near at depth 1, no far plane.
glm::dmat4 reversed_infinite() {
    glm::dmat4 p = glm::frustum(-0.29, 0.29, -0.22, 0.22, kNear, 100.0);
    p[2][2] = 0, p[3][2] = kNear;  // z = near: NDC z = near / depth
    return p;
}

// The window depth the program writes for eye point `eye` (its NDC, its depth range).
glm::dvec3 program_window(const glm::dmat4& p, const ProgramDepthState& s, const glm::dvec3& eye) {
    const glm::dvec4 c = p * glm::dvec4(eye, 1.0);
    const glm::dvec3 ndc = glm::dvec3(c) / c.w;
    const double t = s.zero_to_one ? ndc.z : ndc.z * 0.5 + 0.5;
    return {ndc.x, s.flipped() ? -ndc.y : ndc.y, s.range_near + t * (s.range_far - s.range_near)};
}

// The window depth the passes' standard projection gives it.
double pass_window(const DepthConvention& c, const glm::dvec3& eye) {
    const glm::dvec4 q = c.pass_projection * glm::dvec4(eye, 1.0);
    return q.z / q.w * 0.5 + 0.5;
}

void expect_converted(const glm::dmat4& p, const ProgramDepthState& s) {
    const DepthConvention c = depth_convention(p, s);
    ASSERT_FALSE(c.standard);
    for (const glm::dvec3& eye : {glm::dvec3(0, 0, -0.6), glm::dvec3(1, -2, -6), glm::dvec3(-3, 1, -40),
                                  glm::dvec3(2, 3, -90), glm::dvec3(10, 0, -900)}) {
        if (-eye.z > c.far) continue;  // beyond the program's own far plane: never drawn
        const glm::dvec3 w = program_window(p, s, eye);
        const glm::dmat4 m = c.pass_projection * glm::inverse(c.program_projection);
        EXPECT_NEAR(to_pass_depth(c, m, w.x, w.y, w.z), pass_window(c, eye), 2e-7)
            << "eye depth " << -eye.z;
    }
    EXPECT_EQ(to_pass_depth(c, glm::dmat4(1.0), 0.1, 0.2, s.clear_depth), 1.0);  // the background
}

}  // namespace

TEST(DepthConvention, AStandardProgramIsLeftAsItIs) {
    const glm::dmat4 p = glm::frustum(-0.29, 0.29, -0.22, 0.22, kNear, 100.0);
    const DepthConvention c = depth_convention(p, ProgramDepthState{});
    EXPECT_TRUE(c.standard);
    EXPECT_EQ(c.pass_projection, p);
    glm::dmat4 infinite = p;  // a standard infinite far plane: NDC z -> 1, as the passes read it
    infinite[2][2] = -1, infinite[3][2] = -2 * kNear;
    EXPECT_TRUE(depth_convention(infinite, ProgramDepthState{}).standard);
    EXPECT_TRUE(depth_convention(glm::ortho(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0), ProgramDepthState{}).standard);
}

TEST(DepthConvention, ReversedInfiniteZeroToOneBecomesStandardDepth) {
    ProgramDepthState s;
    s.zero_to_one = true;
    s.clear_depth = 0;
    const DepthConvention c = depth_convention(reversed_infinite(), s);
    EXPECT_NEAR(c.near, kNear, 1e-12);
    EXPECT_NEAR(c.far, kNear * glcast::slave::kInfiniteFarInNears, 1e-6);
    for (int r : {0, 1, 3})  // the same picture: x, y and w rows are the program's
        for (int k = 0; k < 4; ++k) EXPECT_EQ(c.pass_projection[k][r], reversed_infinite()[k][r]);
    expect_converted(reversed_infinite(), s);
}

TEST(DepthConvention, ReversedFiniteAndDepthRangesAndOriginsAreConverted) {
    glm::dmat4 reversed = glm::frustum(-0.29, 0.29, -0.22, 0.22, kNear, 1000.0);
    // Reversed with GL_NEGATIVE_ONE_TO_ONE: NDC z = -(standard NDC z).
    for (int k = 0; k < 4; ++k) reversed[k][2] = -reversed[k][2];
    ProgramDepthState s;
    s.clear_depth = 0;
    expect_converted(reversed, s);

    ProgramDepthState range;
    range.range_near = 0.2, range.range_far = 0.8, range.clear_depth = 0.8;
    expect_converted(glm::frustum(-0.29, 0.29, -0.22, 0.22, kNear, 100.0), range);

    ProgramDepthState upper;
    upper.upper_left = true, upper.zero_to_one = true, upper.clear_depth = 0;
    expect_converted(reversed_infinite(), upper);
    // The passes' picture is the window's: y flipped with the origin.
    const DepthConvention c = depth_convention(reversed_infinite(), upper);
    EXPECT_EQ(c.pass_projection[1][1], -reversed_infinite()[1][1]);
}

TEST(DepthConvention, AStandardSceneShownUpsideDownIsReadAsAnUpperLeftOrigin) {
    // Drawn with GL's own convention into a target, shown by a blit that swaps its rows (pillars
    // --fbo --mirror; Wine's way): the window's picture is the target's upside down.
    const glm::dmat4 p = glm::frustum(-0.29, 0.29, -0.22, 0.22, kNear, 100.0);
    ProgramDepthState mirrored;
    mirrored.shown_mirrored = true;
    expect_converted(p, mirrored);
    const DepthConvention c = depth_convention(p, mirrored);
    EXPECT_EQ(c.pass_projection[1][1], -p[1][1]);
    EXPECT_NEAR(c.near, kNear, 1e-9);
    ProgramDepthState both = mirrored;  // an upper-left origin shown upside down: upright again
    both.upper_left = true;
    EXPECT_TRUE(depth_convention(p, both).standard);
}

TEST(DepthConvention, ASceneDrawnMirroredAndShownMirroredBackIsReadUnmirrored) {
    // Drawn with glFrustum's left and right swapped into a target, shown by a blit that swaps its
    // columns (pillars --fbo --mirror-columns): the window's picture is the target's mirrored back.
    const glm::dmat4 p = glm::frustum(0.29, -0.29, -0.22, 0.22, kNear, 100.0);
    ProgramDepthState mirrored;
    mirrored.shown_mirrored_columns = true;
    expect_converted(p, mirrored);
    const DepthConvention c = depth_convention(p, mirrored);
    EXPECT_EQ(c.pass_projection[0][0], -p[0][0]);
    EXPECT_GT(c.pass_projection[0][0], 0);  // as the window shows it: a standard frustum
    EXPECT_NEAR(c.near, kNear, 1e-9);
}

TEST(DepthConvention, ARedrawCorrectedByPassFromProgramLandsAsThePassesProjectionPutsIt) {
    for (bool upper_left : {false, true}) {
        ProgramDepthState s;
        s.zero_to_one = true, s.clear_depth = 0, s.upper_left = upper_left;
        const DepthConvention c = depth_convention(reversed_infinite(), s);
        const glm::dmat4 redrawn = c.pass_from_program * reversed_infinite();
        for (int k = 0; k < 4; ++k)
            for (int r = 0; r < 4; ++r) EXPECT_NEAR(redrawn[k][r], c.pass_projection[k][r], 1e-9);
    }
}
