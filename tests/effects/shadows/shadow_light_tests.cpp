// The light geometry of the soft-shadow pass (slave/effects/shadows/shadow_light.h), without GL.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "slave/effects/effect_params.h"
#include "slave/effects/shadows/shadow_light.h"

using namespace glcast::slave::effects;

namespace {

const glm::dmat4 kProjection = glm::perspective(glm::radians(45.0), 4.0 / 3.0, 0.5, 100.0);

// Every corner of the view volume lies inside the light's clip volume.
void expect_covers(const LightFrame& frame, const std::array<glm::dvec3, 8>& corners) {
    for (const auto& c : corners) {
        const glm::dvec4 clip = frame.clip_from_eye() * glm::dvec4(c, 1.0);
        ASSERT_GT(clip.w, 0);
        const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
        EXPECT_LE(std::abs(ndc.x), 1.0 + 1e-9);
        EXPECT_LE(std::abs(ndc.y), 1.0 + 1e-9);
        EXPECT_LE(ndc.z, 1.0 + 1e-9);
        EXPECT_GE(ndc.z, -1.0 - 1e-9);
        // The light depth of the map's range agrees with the view matrix.
        const double depth = -(frame.view * glm::dvec4(c, 1.0)).z;
        EXPECT_GE(depth, frame.near - 1e-9);
        EXPECT_LE(depth, frame.far + 1e-9);
    }
}

}  // namespace

TEST(ShadowLight, FrustumCornersArePulledInToTheMaximumDistance) {
    const auto corners = view_frustum_corners(kProjection, 20.0);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(-corners[i].z, 0.5, 1e-9);
    for (int i = 4; i < 8; ++i) EXPECT_NEAR(-corners[i].z, 20.0, 1e-9);
    // The far corners stay on the rays through the near ones.
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 a = glm::normalize(corners[i]), b = glm::normalize(corners[i + 4]);
        EXPECT_NEAR(glm::dot(a, b), 1.0, 1e-12);
    }
    const auto unclamped = view_frustum_corners(kProjection, 1e6);
    EXPECT_NEAR(-unclamped[4].z, 100.0, 1e-6);
}

// Programs with shadow volumes (the Castle Game Engine's view3dscene) project with an infinite far
// plane: NDC z = 1 lies at infinity. The far corners are then the rays' points at the maximum
// distance; before, they were inf/NaN and the shadow map was empty (no shadow on view3dscene).
TEST(ShadowLight, FrustumCornersOfAnInfiniteFarPlaneAreAtTheMaximumDistance) {
    const glm::dmat4 infinite = glm::infinitePerspective(glm::radians(45.0), 4.0 / 3.0, 0.06);
    const auto corners = view_frustum_corners(infinite, 60.0);
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(corners[i][k])) << "corner " << i;
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(-corners[i].z, 0.06, 1e-9);
    for (int i = 4; i < 8; ++i) EXPECT_NEAR(-corners[i].z, 60.0, 1e-6);
    for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(glm::dot(glm::normalize(corners[i]), glm::normalize(corners[i + 4])), 1.0, 1e-12);
    ShadowLight light;
    light.directional = true;
    light.direction = glm::normalize(glm::dvec3(0.4, 1.0, 0.5));
    expect_covers(fit_light_frame(light, corners, 150), corners);
}

// The shadows reach as far into a view at every scale: 120 near-plane distances, not past the far
// plane, unless shadows.max_distance says otherwise.
TEST(ShadowLight, TheShadowsReachFollowsTheProgramsScale) {
    ShadowSettings s;  // max_distance 0: from the projection
    EXPECT_NEAR(shadow_reach(s, glm::frustum(-0.3, 0.3, -0.2, 0.2, 0.5, 100.0)), 60, 1e-6);
    EXPECT_NEAR(shadow_reach(s, glm::frustum(-3.0, 3.0, -2.0, 2.0, 5.0, 1000.0)), 600, 1e-4);   // ten times the scale
    EXPECT_NEAR(shadow_reach(s, glm::frustum(-0.3, 0.3, -0.2, 0.2, 0.5, 20.0)), 20, 1e-6);     // the far plane first
    EXPECT_NEAR(shadow_reach(s, glm::infinitePerspective(1.0, 1.5, 4.0)), 480, 1e-4);           // Quake's near plane
    // VTK's near plane, a thousandth of its far plane, says nothing of the scene's size
    EXPECT_NEAR(shadow_reach(s, glm::frustum(-0.01, 0.01, -0.008, 0.008, 0.0286, 28.6)), 28.6, 1e-6);
    EXPECT_NEAR(shadow_reach(s, glm::infinitePerspective(1.0, 1.5, 0.01)), 60, 1e-6);
    s.max_distance = 35;
    EXPECT_EQ(shadow_reach(s, glm::frustum(-0.3, 0.3, -0.2, 0.2, 0.5, 100.0)), 35);
    s.max_distance = 0;
    EXPECT_EQ(shadow_reach(s, glm::ortho(-1.0, 1.0, -1.0, 1.0, 0.0, 10.0)), 60);  // no perspective: the old default
}

TEST(ShadowLight, DirectionalFrameIsOrthographicAlongTheLightAndCoversTheView) {
    ShadowLight light;
    light.directional = true;
    light.direction = glm::normalize(glm::dvec3(0.3, 1.0, 0.2));
    const auto corners = view_frustum_corners(kProjection, 30.0);
    const LightFrame frame = fit_light_frame(light, corners, 150);
    EXPECT_TRUE(frame.orthographic);
    expect_covers(frame, corners);
    // Light depth grows away from the light.
    const double a = -(frame.view * glm::dvec4(light.direction * 10.0, 1.0)).z;
    const double b = -(frame.view * glm::dvec4(glm::dvec3(0.0), 1.0)).z;
    EXPECT_NEAR(b - a, 10.0, 1e-9);
    // Casters up to the volume's extent towards the light are inside the depth range.
    EXPECT_LT(frame.near, -(frame.view * glm::dvec4(corners[4] + light.direction * 15.0, 1.0)).z);
}

TEST(ShadowLight, PositionalFrameLooksFromTheLightAndCoversTheView) {
    ShadowLight light;
    light.directional = false;
    light.position = {3.0, 12.0, -4.0};  // above the view volume, outside it
    const auto corners = view_frustum_corners(kProjection, 40.0);
    const LightFrame frame = fit_light_frame(light, corners, 150);
    EXPECT_FALSE(frame.orthographic);
    expect_covers(frame, corners);
    EXPECT_NEAR(glm::length(glm::dvec3(frame.view * glm::dvec4(light.position, 1.0))), 0.0, 1e-9);
    EXPECT_GT(frame.near, 0);
}

TEST(ShadowLight, PositionalLightInsideTheViewGetsTheWidestMapAndANearPlaneCloseToIt) {
    ShadowLight light;
    light.directional = false;
    light.position = {0.0, 0.0, -5.0};  // inside the view volume
    const auto corners = view_frustum_corners(kProjection, 40.0);
    const LightFrame frame = fit_light_frame(light, corners, 150);
    EXPECT_NEAR(frame.projection[1][1], 1.0 / std::tan(glm::radians(75.0)), 1e-9);
    EXPECT_NEAR(frame.near, frame.far * 1e-3, 1e-12);
}

TEST(ShadowLight, AreaSamplesSpreadEvenlyOverTheDisk) {
    ShadowLight light;
    light.directional = false;
    light.position = {1.0, 8.0, -3.0};
    const auto corners = view_frustum_corners(kProjection, 30.0);
    const LightFrame frame = fit_light_frame(light, corners, 150);
    const auto samples = area_light_samples(light, frame, 2.0, 0.0, 512);
    ASSERT_EQ(samples.size(), 512u);
    const glm::dvec3 axis = -glm::dvec3(frame.view[0][2], frame.view[1][2], frame.view[2][2]);
    glm::dvec3 mean(0.0);
    double inner = 0;
    for (const ShadowLight& s : samples) {
        const glm::dvec3 d = s.position - light.position;
        EXPECT_NEAR(glm::dot(d, axis), 0.0, 1e-9);  // on the disk across the light's axis
        EXPECT_LE(glm::length(d), 1.0 + 1e-9);
        inner += glm::length(d) < std::sqrt(0.5) ? 1 : 0;  // half the area
        mean += d;
    }
    EXPECT_LT(glm::length(mean / 512.0), 0.01);
    EXPECT_NEAR(inner / 512, 0.5, 0.01);

    ShadowLight sun;
    sun.direction = glm::normalize(glm::dvec3(0.2, 1.0, 0.1));
    const auto rays = area_light_samples(sun, fit_light_frame(sun, corners, 150), 0.0, 4.0, 64);
    for (const ShadowLight& s : rays) EXPECT_LE(std::acos(glm::dot(s.direction, sun.direction)), glm::radians(2.0) + 1e-9);
}

TEST(ShadowLight, ParallelPlanesEstimate) {
    ShadowLight point;
    point.directional = false;
    EXPECT_NEAR(penumbra_width(point, 1.0, 0.0, 5.0, 4.0), 0.25, 1e-12);
    EXPECT_EQ(penumbra_width(point, 1.0, 0.0, 4.0, 4.5), 0.0);  // blocker behind: no penumbra
    ShadowLight sun;
    EXPECT_NEAR(penumbra_width(sun, 0.0, 2.0, 7.0, 4.0), 3.0 * 2 * std::tan(glm::radians(1.0)), 1e-12);
}

TEST(ShadowLight, ProgramLightUnlessTheSettingsSayOtherwise) {
    FrameView view;
    view.light.known = true;
    view.light.eye_position = {2.0, 4.0, -6.0, 2.0};
    ShadowSettings s;
    ShadowLight l = choose_light(view, s);
    EXPECT_FALSE(l.directional);
    EXPECT_EQ(l.position, glm::dvec3(1.0, 2.0, -3.0));
    s.use_program_light = false;
    s.fallback_light = {0.0, 3.0, 4.0, 0.0};
    l = choose_light(view, s);
    EXPECT_TRUE(l.directional);
    EXPECT_NEAR(glm::length(l.direction - glm::dvec3(0.0, 0.6, 0.8)), 0.0, 1e-12);
    view.light.known = false;
    s.use_program_light = true;
    EXPECT_TRUE(choose_light(view, s).directional);
}

// osgviewer lights its scene with a headlight (GL_LIGHT0 at (0, 0, 1, 0) in eye space): its shadows
// would all lie behind the boxes that cast them. The settings' light is used instead.
TEST(ShadowLight, AHeadlightGivesWayToTheSettingsLight) {
    EXPECT_TRUE(is_headlight({0.0, 0.0, 1.0, 0.0}));
    EXPECT_TRUE(is_headlight({0.0, 0.1, 1.0, 0.0}));   // 5.7 degrees off the axis
    EXPECT_FALSE(is_headlight({0.0, 0.3, 1.0, 0.0}));  // 16.7 degrees
    EXPECT_TRUE(is_headlight({0.0, 0.0, 0.0, 1.0}));   // at the eye
    EXPECT_TRUE(is_headlight({0.0, 0.0, 2.0, 2.0}));   // behind the eye, on the axis
    EXPECT_FALSE(is_headlight({5.0, 10.0, -4.0, 1.0}));
    EXPECT_FALSE(is_headlight({0.0, 0.0, -1.0, 0.0}));  // facing the viewer from behind the scene
    FrameView view;
    view.light.known = true;
    view.light.eye_position = {0.0, 0.0, 1.0, 0.0};
    ShadowSettings s;
    s.fallback_light = {0.0, 3.0, 4.0, 0.0};
    const ShadowLight l = choose_light(view, s);
    EXPECT_NEAR(glm::length(l.direction - glm::dvec3(0.0, 0.6, 0.8)), 0.0, 1e-12);
}

TEST(ShadowSettings, ParametersAreReadAndBadMethodsNamed) {
    EffectParams params;
    std::string error;
    ASSERT_TRUE(params.set("shadows.method", "pcss-64", error)) << error;
    ASSERT_TRUE(params.set("shadows.light_size", "2.5", error)) << error;
    ShadowSettings s = shadow_settings_from(params);
    EXPECT_EQ(s.method, ShadowMethod::Pcss64);
    EXPECT_EQ(pcss_blocker_samples(s.method), 64);
    EXPECT_EQ(s.light_size, 2.5);
    EXPECT_FALSE(params.set("shadows.map_size", "100000", error));
    EXPECT_NE(error.find("shadows.map_size"), std::string::npos);
    ASSERT_TRUE(params.set("shadows.method", "pcss-16", error));
    try {
        shadow_settings_from(params);
        FAIL() << "pcss-16 accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("shadows.method"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("pcss-32"), std::string::npos) << e.what();
    }
    for (const std::string& name : method_names()) {
        ShadowMethod m;
        ASSERT_TRUE(parse_method(name, m));
        EXPECT_EQ(name, method_name(m));
    }
}
