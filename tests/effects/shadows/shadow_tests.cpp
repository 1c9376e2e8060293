// The soft-shadow pass in-process (docs/shadows.md): an EGL compatibility context, synthetic
// scenes drawn like a fixed-function program (shadow_scene.h), a FrameView with a redraw as
// the replayer fills it. Checks: hard shadows where ray casting puts them; penumbra widths as
// the parallel-planes estimate predicts; error against the area-light reference for every
// method; frames untouched outside shadows; a wall's tiles equal the canvas.
//
//   run: ./shadow_tests   (GLCAST_TEST_OUT=dir keeps visibility PNGs of failed checks)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "slave/effects/gl_util.h"
#include "slave/effects/pipeline.h"
#include "slave/effects/shadows/shadow_renderer.h"
#include "tests/effects/shadows/shadow_scene.h"

using namespace glcast::slave::effects;
using glcast::slave::Image;
using shadow_test::Scene;
using shadow_test::SceneContext;
using shadow_test::Tile;

namespace {

SceneContext& context() {
    static std::unique_ptr<SceneContext> ctx = std::make_unique<SceneContext>();
    return *ctx;
}

ShadowSettings settings_for(const Scene& scene) {
    ShadowSettings s;
    s.light_size = scene.light_size;
    s.light_angle_deg = scene.light_angle_deg;
    s.max_distance = 20;
    return s;
}

const Tile kCanvas{0, 0, 640, 480, 640, 480};

// Draws the scene's frame into the tile and runs `method`; the tile's visibility.
std::vector<float> visibility(ShadowRenderer& r, const Scene& scene, const Tile& tile, ShadowMethod method) {
    SceneContext& ctx = context();
    ctx.draw_frame(scene, tile);
    const FrameView view = ctx.frame_view(scene, tile);
    r.set_method(method);
    std::string why;
    StateGuard guard(ctx.gl());
    EXPECT_TRUE(r.render(view, why)) << why;
    return r.read_tile(r.visibility_texture(), 0);
}

float sample(const std::vector<float>& image, const Tile& t, glm::dvec2 p) {
    p -= 0.5;  // pixel centres
    const int x = int(std::floor(p.x)), y = int(std::floor(p.y));
    if (x < 0 || y < 0 || x + 1 >= t.width || y + 1 >= t.height) return -1;
    const double fx = p.x - x, fy = p.y - y;
    auto at = [&](int i, int j) { return double(image[size_t(j) * t.width + i]); };
    return float((at(x, y) * (1 - fx) + at(x + 1, y) * fx) * (1 - fy) + (at(x, y + 1) * (1 - fx) + at(x + 1, y + 1) * fx) * fy);
}

// World position of each tile pixel from the window's depth (NaN for the background).
std::vector<glm::dvec3> world_positions(const Scene& scene, const Tile& t) {
    const auto depth = context().read_depth(t);
    const glm::dmat4 inv = glm::inverse(scene.projection(double(t.canvas_width) / t.canvas_height) * scene.view());
    std::vector<glm::dvec3> out(depth.size(), glm::dvec3(NAN));
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x) {
            const float d = depth[size_t(y) * t.width + x];
            if (d >= 1.0f) continue;
            const glm::dvec4 ndc((x + 0.5) / t.width * 2 - 1, (y + 0.5) / t.height * 2 - 1, 2.0 * d - 1, 1);
            const glm::dvec4 w = inv * ndc;
            out[size_t(y) * t.width + x] = glm::dvec3(w) / w.w;
        }
    return out;
}

// 5%-95% width of a round light's penumbra of full width 1: visibility on the lit side of an
// edge at signed distance u (in half-widths) is 1 - (acos u - u sqrt(1 - u^2)) / pi.
double disk_profile_width() {
    auto lit = [](double u) { return 1 - (std::acos(u) - u * std::sqrt(1 - u * u)) / M_PI; };
    auto solve = [&](double target) {
        double lo = -1, hi = 1;
        for (int i = 0; i < 60; ++i) (lit(0.5 * (lo + hi)) < target ? lo : hi) = 0.5 * (lo + hi);
        return 0.5 * (lo + hi);
    };
    return (solve(0.95) - solve(0.05)) / 2;
}

}  // namespace

// ---- hard shadows -----------------------------------------------------------------------------

// Every ground pixel the hard-shadow buffer calls shadowed (lit) is so by ray casting towards the
// light's centre, or lies within 3 pixels of a pixel that is.
void expect_hard_shadows_match_geometry(const Scene& scene) {
    ShadowRenderer r(context().gl(), settings_for(scene));
    visibility(r, scene, kCanvas, ShadowMethod::ErosionPcf);
    const auto hard = r.read_tile(r.hard_shadow_texture(), 0);
    const auto world = world_positions(scene, kCanvas);
    const int w = kCanvas.width, h = kCanvas.height;
    std::vector<int8_t> predicted(world.size(), -1);  // -1: not ground
    for (size_t i = 0; i < world.size(); ++i)
        if (std::abs(world[i].y) < 2e-3) predicted[i] = scene.occluded(world[i]) ? 0 : 1;
    int ground = 0, shadowed = 0, mismatched = 0, far_off = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * w + x;
            if (predicted[i] < 0) continue;
            ++ground;
            const int measured = hard[i] > 0.5f ? 1 : 0;
            shadowed += measured == 0;
            if (measured == predicted[i]) continue;
            ++mismatched;
            bool near = false;
            for (int dy = -3; dy <= 3 && !near; ++dy)
                for (int dx = -3; dx <= 3 && !near; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < w && yy < h) near = predicted[size_t(yy) * w + xx] == measured;
                }
            far_off += !near;
        }
    std::printf("%s: %d ground pixels, %d in hard shadow, %d differ from ray casting, %d of them more than 3 px "
                "from the predicted boundary\n", scene.name.c_str(), ground, shadowed, mismatched, far_off);
    EXPECT_GT(shadowed, 2000);
    EXPECT_EQ(far_off, 0);
    EXPECT_LT(mismatched, shadowed / 10);
}

TEST(ShadowsGL, HardShadowsFallWhereGeometryPredictsPositionalLight) {
    expect_hard_shadows_match_geometry(shadow_test::blocks_scene());
}
TEST(ShadowsGL, HardShadowsFallWhereGeometryPredictsDirectionalLight) {
    expect_hard_shadows_match_geometry(shadow_test::fence_scene());
}

// ---- penumbra widths --------------------------------------------------------------------------

// Across the +z edge of each plate's shadow (a light straight above, plates at several
// heights): the 5%-95% width of the visibility, averaged along the edge, against the
// parallel-planes estimate L h / (H - h) of a round light of diameter L at height H.
TEST(ShadowsGL, PenumbraIsNarrowAtContactAndWidensWithBlockerDistanceAsEstimated) {
    const Scene scene = shadow_test::plates_scene();
    ShadowRenderer r(context().gl(), settings_for(scene));
    const double H = scene.light.y, L = scene.light_size, k = disk_profile_width();
    const double px_per_unit = 480 / 2 / std::tan(glm::radians(scene.fov_y_deg / 2)) / glm::length(scene.eye);
    for (ShadowMethod method : {ShadowMethod::ErosionPcf, ShadowMethod::Reference, ShadowMethod::Pcss32,
                                ShadowMethod::ErosionDirect}) {
        const auto vis = visibility(r, scene, kCanvas, method);
        std::vector<double> measured_widths;
        for (const glm::dmat4& plate : scene.boxes) {
            const glm::dvec3 c = glm::dvec3(plate[3]);
            const double top = c.y + plate[1][1];            // the silhouette towards the light
            const double scale = H / (H - top);               // from the plate to the ground
            const double predicted = L * top / (H - top);     // full penumbra width on the ground
            const double edge_z = (c.z + plate[2][2]) * scale, span = 1.3 * predicted + 0.06;
            std::vector<double> profile;
            const int steps = 400;
            for (int i = 0; i <= steps; ++i) {
                const double t = -span + 2 * span * i / steps;
                double sum = 0;
                int n = 0;
                for (int j = 0; j < 24; ++j) {  // the middle half of the edge
                    const double x = (c.x + plate[0][0] * (-0.5 + j / 23.0)) * scale;
                    const float v = sample(vis, kCanvas, shadow_test::project_to_tile(scene, kCanvas, {x, 0, edge_z + t}));
                    if (v >= 0) sum += v, ++n;
                }
                profile.push_back(n ? sum / n : 1);
            }
            auto crossing = [&](double level) {
                for (int i = 1; i <= steps; ++i)
                    if (profile[i] >= level && profile[i - 1] < level)
                        return -span + 2 * span * (i - 1 + (level - profile[i - 1]) / (profile[i] - profile[i - 1])) / steps;
                return double(NAN);
            };
            const double width = crossing(0.95) - crossing(0.05), expected = k * predicted;
            std::printf("%-14s plate at %.2f: 5-95%% width %.4f (%.1f px), estimate %.4f (%.1f px)\n", method_name(method),
                        top, width, width * px_per_unit, expected, expected * px_per_unit);
            measured_widths.push_back(width);
            if (method == ShadowMethod::ErosionDirect) continue;  // a linear ramp: printed only
            if (expected * px_per_unit < 2.5) {
                EXPECT_LT(width * px_per_unit, 3.0) << "near contact";
            } else {
                EXPECT_NEAR(width / expected, 1.0, 0.2) << method_name(method) << " plate at " << top;
            }
        }
        if (method == ShadowMethod::ErosionDirect) continue;
        // Ordered by height: 0.52, 1.02, 1.82, 0.10 (scene order).
        EXPECT_LT(measured_widths[3], measured_widths[0]);
        EXPECT_LT(measured_widths[0], measured_widths[1]);
        EXPECT_LT(measured_widths[1], measured_widths[2]);
    }
}

// ---- quality against the reference --------------------------------------------------------------

// RMSE of each method's visibility against the average of 512 hard shadows from points on the
// area light, over the shadows and 8 pixels around them. Erosion/PCF must be within 10% of
// PCSS-32's error or better.
void compare_methods(const Scene& scene) {
    ShadowRenderer r(context().gl(), settings_for(scene));
    const auto reference = visibility(r, scene, kCanvas, ShadowMethod::Reference);
    double pcf = 0, pcss32 = 0;
    for (ShadowMethod m : {ShadowMethod::ErosionPcf, ShadowMethod::ErosionDirect, ShadowMethod::Pcss8,
                           ShadowMethod::Pcss32, ShadowMethod::Pcss64}) {
        const auto e = shadow_test::visibility_error(visibility(r, scene, kCanvas, m), reference, kCanvas.width,
                                                     kCanvas.height);
        std::printf("%-7s %-15s RMSE %.4f over %zu shadow pixels (%.4f over all)\n", scene.name.c_str(), method_name(m),
                    e.shadows, e.shadow_pixels, e.all);
        EXPECT_GT(e.shadow_pixels, 5000u);
        EXPECT_LT(e.shadows, 0.15) << method_name(m);
        if (m == ShadowMethod::ErosionPcf) pcf = e.shadows;
        if (m == ShadowMethod::Pcss32) pcss32 = e.shadows;
    }
    EXPECT_LE(pcf, 1.1 * pcss32) << scene.name;
}

TEST(ShadowsGL, QualityAgainstReferenceBlocks) { compare_methods(shadow_test::blocks_scene()); }
TEST(ShadowsGL, QualityAgainstReferenceFence) { compare_methods(shadow_test::fence_scene()); }
TEST(ShadowsGL, QualityAgainstReferenceRamp) { compare_methods(shadow_test::ramp_scene()); }
TEST(ShadowsGL, QualityAgainstReferencePlates) { compare_methods(shadow_test::plates_scene()); }

// ---- screen-space shadows ---------------------------------------------------------------------

namespace {

// Only the window's depth, the projection and the light (frames whose draws cannot be
// re-rendered): against the reference, the share of its shadowed pixels (visibility < 0.5)
// that screen-space marching shadows too, and the lit pixels (> 0.95) it darkens wrongly.
// With GLCAST_TEST_OUT set: DIR/NAME.png, the visibilities side by side (rows bottom up in).
void keep_visibilities(const std::string& name, const std::vector<std::vector<float>>& images) {
    const char* dir = std::getenv("GLCAST_TEST_OUT");
    if (!dir) return;
    const int w = kCanvas.width, h = kCanvas.height, n = int(images.size());
    Image out{w * n, h, std::vector<uint8_t>(size_t(w) * n * h * 4, 255)};
    for (int k = 0; k < n; ++k)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float v = std::clamp(images[k][size_t(y) * w + x], 0.0f, 1.0f);
                uint8_t* px = &out.rgba[(size_t(h - 1 - y) * w * n + size_t(k) * w + x) * 4];
                px[0] = px[1] = px[2] = uint8_t(std::lround(v * 255));
            }
    std::string err;
    glcast::slave::write_png(std::string(dir) + "/" + name + ".png", out, err);
}

void screen_space_against_reference(const Scene& scene, double min_found, double max_false) {
    ShadowRenderer r(context().gl(), settings_for(scene));
    const auto reference = visibility(r, scene, kCanvas, ShadowMethod::Reference);
    const auto marched = visibility(r, scene, kCanvas, ShadowMethod::ScreenSpace);
    size_t shadowed = 0, found = 0, lit = 0, wrong = 0;
    for (size_t i = 0; i < reference.size(); ++i) {
        if (reference[i] < 0.5f) {
            ++shadowed;
            found += marched[i] < 0.5f;
        } else if (reference[i] > 0.95f) {
            ++lit;
            wrong += marched[i] < 0.5f;
        }
    }
    keep_visibilities("screen-space-" + scene.name, {reference, marched});
    if (const char* dir = std::getenv("GLCAST_TEST_OUT")) {
        std::string err;
        glcast::slave::write_png(std::string(dir) + "/screen-space-" + scene.name + "-color.png",
                                 context().read_color(kCanvas), err);
    }
    const auto e = shadow_test::visibility_error(marched, reference, kCanvas.width, kCanvas.height);
    std::printf("%-7s screen-space: %zu of %zu shadowed pixels found (%.1f%%), %zu of %zu lit pixels darkened "
                "(%.2f%%), RMSE %.4f over the shadows\n",
                scene.name.c_str(), found, shadowed, 100.0 * found / std::max<size_t>(shadowed, 1), wrong, lit,
                100.0 * wrong / std::max<size_t>(lit, 1), e.shadows);
    EXPECT_GT(shadowed, 5000u);
    EXPECT_GE(double(found), min_found * double(shadowed)) << scene.name;
    EXPECT_LE(double(wrong), max_false * double(lit)) << scene.name;
}

}  // namespace

TEST(ShadowsGL, ScreenSpaceFindsTheShadowsOfBlocks) { screen_space_against_reference(shadow_test::blocks_scene(), 0.8, 0.02); }
TEST(ShadowsGL, ScreenSpaceFindsTheShadowsOfRamp) { screen_space_against_reference(shadow_test::ramp_scene(), 0.8, 0.02); }
TEST(ShadowsGL, ScreenSpaceFindsTheShadowsOfPlates) { screen_space_against_reference(shadow_test::plates_scene(), 0.8, 0.02); }
// Slats 0.08 wide: the gaps between them are thinner than the thickness the march assumes.
TEST(ShadowsGL, ScreenSpaceFindsTheShadowsOfFence) { screen_space_against_reference(shadow_test::fence_scene(), 0.8, 0.02); }

// ---- the pass in a frame ----------------------------------------------------------------------

namespace {

EffectsSettings pass_settings(const Scene& scene, const std::string& method) {
    EffectsSettings s;
    std::string error;
    EXPECT_TRUE(s.enable("shadows", error)) << error;
    for (const std::string& a : {"shadows.light_size=" + std::to_string(scene.light_size),
                                 "shadows.light_angle=" + std::to_string(scene.light_angle_deg),
                                 std::string("shadows.max_distance=20"), "shadows.method=" + method})
        EXPECT_TRUE(s.params.set_assignment(a, error)) << error;
    return s;
}

struct GlSnapshot {
    GLint viewport[4], program, framebuffer, texture0, active, depth_func, blend_src, matrix_mode;
    GLboolean blend, depth_test, depth_mask;
    explicit GlSnapshot(const GlApi& gl) {
        gl.glGetIntegerv(GL_VIEWPORT, viewport);
        gl.glGetIntegerv(GL_CURRENT_PROGRAM, &program);
        gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
        gl.glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
        gl.glActiveTexture(GL_TEXTURE0);
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &texture0);
        gl.glActiveTexture(GLenum(active));
        gl.glGetIntegerv(GL_DEPTH_FUNC, &depth_func);
        gl.glGetIntegerv(GL_BLEND_SRC_RGB, &blend_src);
        gl.glGetIntegerv(GL_MATRIX_MODE, &matrix_mode);
        blend = gl.glIsEnabled(GL_BLEND);
        depth_test = gl.glIsEnabled(GL_DEPTH_TEST);
        gl.glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask);
    }
    bool operator==(const GlSnapshot& o) const {
        return std::equal(viewport, viewport + 4, o.viewport) && program == o.program && framebuffer == o.framebuffer &&
               texture0 == o.texture0 && active == o.active && depth_func == o.depth_func && blend_src == o.blend_src &&
               blend == o.blend && depth_test == o.depth_test && depth_mask == o.depth_mask;
    }
};

}  // namespace

// Through the pipeline, as the replayer runs it: pixels of visibility exactly 1 keep their
// bytes; shadowed ones are multiplied by 1 - strength * facing * (1 - visibility) with facing
// in [0, 1] (1 on surfaces the light falls on squarely: all of the ground here); the program's
// state is handed back.
TEST(ShadowsGL, PassChangesOnlyShadowedPixels) {
    SceneContext& ctx = context();
    const Scene scene = shadow_test::blocks_scene();
    const EffectsSettings settings = pass_settings(scene, "erosion-pcf");
    Pipeline pipeline(ctx.gl(), settings);
    ShadowRenderer r(ctx.gl(), shadow_settings_from(settings.params));
    const auto vis = visibility(r, scene, kCanvas, ShadowMethod::ErosionPcf);
    const auto world = world_positions(scene, kCanvas);

    ctx.draw_frame(scene, kCanvas);
    const Image before = ctx.read_color(kCanvas);
    const GlSnapshot state_before(ctx.gl());
    pipeline.run(ctx.frame_view(scene, kCanvas));
    EXPECT_TRUE(GlSnapshot(ctx.gl()) == state_before);
    const Image after = ctx.read_color(kCanvas);

    const double strength = settings.params.number("shadows.strength");
    int unchanged = 0, darkened = 0, ground = 0, wrong = 0;
    for (int y = 0; y < kCanvas.height; ++y)
        for (int x = 0; x < kCanvas.width; ++x) {
            const size_t gl_index = size_t(kCanvas.height - 1 - y) * kCanvas.width + x;  // rows bottom up
            const float v = vis[gl_index];
            const uint8_t* a = &before.rgba[(size_t(y) * kCanvas.width + x) * 4];
            const uint8_t* b = &after.rgba[(size_t(y) * kCanvas.width + x) * 4];
            if (v >= 1.0f) {
                wrong += !std::equal(a, a + 4, b);
                ++unchanged;
                continue;
            }
            ++darkened;
            const double full = 1 - strength * (1 - v);
            // Ground with ground around: a pixel touching a box may take its plane from the box.
            auto is_ground = [&](int i, int j) {
                return i >= 0 && j >= 0 && i < kCanvas.width && j < kCanvas.height &&
                       std::abs(world[size_t(kCanvas.height - 1 - j) * kCanvas.width + i].y) < 2e-3;
            };
            const bool on_ground = is_ground(x, y) && is_ground(x - 1, y) && is_ground(x + 1, y) &&
                                   is_ground(x, y - 1) && is_ground(x, y + 1);
            ground += on_ground;
            for (int c = 0; c < 3; ++c) {
                if (on_ground) wrong += std::abs(b[c] - a[c] * full) > 1.01;
                else wrong += b[c] > a[c] + 1 || b[c] < a[c] * full - 1.01;
            }
        }
    std::printf("%d pixels untouched, %d darkened (%d of them ground), %d not as the visibility says\n", unchanged,
                darkened, ground, wrong);
    EXPECT_EQ(wrong, 0);
    EXPECT_GT(ground, 8000);
    EXPECT_GT(unchanged, 200000);
}

// The four tiles of a 2x2 wall, each with its guard band, give the canvas's visibility.
TEST(ShadowsGL, WallTilesJoinWithoutSeams) {
    const Scene scene = shadow_test::ramp_scene();
    ShadowRenderer r(context().gl(), settings_for(scene));
    for (ShadowMethod method : {ShadowMethod::ErosionPcf, ShadowMethod::ErosionDirect, ShadowMethod::Pcss32}) {
        const auto canvas = visibility(r, scene, kCanvas, method);
        double worst = 0;
        int differing = 0;
        for (int ty = 0; ty < 2; ++ty)
            for (int tx = 0; tx < 2; ++tx) {
                const Tile tile{tx * 320, ty * 240, 320, 240, 640, 480};
                const auto part = visibility(r, scene, tile, method);
                for (int y = 0; y < tile.height; ++y)
                    for (int x = 0; x < tile.width; ++x) {
                        const double d = std::abs(part[size_t(y) * tile.width + x] -
                                                  canvas[size_t(y + tile.y) * kCanvas.width + x + tile.x]);
                        worst = std::max(worst, d);
                        differing += d > 1.0 / 255;
                    }
            }
        std::printf("%-14s 2x2 wall against the canvas: %d pixels differ by more than 1/255, largest difference %.4f\n",
                    method_name(method), differing, worst);
        EXPECT_LE(differing, 50) << method_name(method);
    }
}

// Without a re-rendered depth the pass reads the window's depth (no guard band): the same
// shadows inside the tile, away from its border.
TEST(ShadowsGL, WindowDepthFallbackGivesTheSameShadowsInside) {
    const Scene scene = shadow_test::blocks_scene();
    ShadowSettings settings = settings_for(scene);
    ShadowRenderer guarded(context().gl(), settings);
    settings.rerender_depth = false;
    ShadowRenderer window(context().gl(), settings);
    const auto a = visibility(guarded, scene, kCanvas, ShadowMethod::ErosionPcf);
    const auto b = visibility(window, scene, kCanvas, ShadowMethod::ErosionPcf);
    EXPECT_EQ(window.tile_offset(), glm::ivec2(0));
    int differing = 0, shadowed = 0;
    for (int y = 30; y < kCanvas.height - 30; ++y)
        for (int x = 30; x < kCanvas.width - 30; ++x) {
            const size_t i = size_t(y) * kCanvas.width + x;
            differing += std::abs(a[i] - b[i]) > 0.02f;
            shadowed += b[i] < 0.5f;
        }
    std::printf("window depth: %d of the interior's pixels differ from the guarded pass (%d shadowed)\n", differing, shadowed);
    EXPECT_GT(shadowed, 5000);
    EXPECT_LT(differing, 200);
}

TEST(ShadowsGL, FramesThatCannotBeShadowedAreLeftAlone) {
    SceneContext& ctx = context();
    const Scene scene = shadow_test::blocks_scene();
    ShadowRenderer r(ctx.gl(), settings_for(scene));
    ctx.draw_frame(scene, kCanvas);
    FrameView view = ctx.frame_view(scene, kCanvas);
    std::string why;
    view.redraw = nullptr;
    view.depth_texture = nullptr;
    EXPECT_FALSE(r.render(view, why));
    EXPECT_NE(why.find("re-rendered"), std::string::npos) << why;
    view.view_known = false;
    EXPECT_FALSE(r.render(view, why));
    EXPECT_NE(why.find("perspective"), std::string::npos) << why;

    const EffectsSettings settings = pass_settings(scene, "erosion-pcf");
    Pipeline pipeline(ctx.gl(), settings);
    const Image before = ctx.read_color(kCanvas);
    pipeline.run(view);
    EXPECT_EQ(glcast::slave::compare(before, ctx.read_color(kCanvas)).differing_pixels, 0);
}

// A frame whose draws cannot be re-rendered (a lender's vertex arrays, a record that
// overflowed) is shadowed from its depth alone: screen-space, said once by the pass.
TEST(ShadowsGL, FramesWithoutARedrawGetScreenSpaceShadows) {
    SceneContext& ctx = context();
    const Scene scene = shadow_test::blocks_scene();
    ctx.draw_frame(scene, kCanvas);
    FrameView view = ctx.frame_view(scene, kCanvas);
    view.redraw = nullptr;
    ShadowRenderer r(ctx.gl(), settings_for(scene));
    std::string why;
    {
        StateGuard guard(ctx.gl());
        ASSERT_TRUE(r.render(view, why)) << why;
    }
    EXPECT_TRUE(r.used_screen_space());
    const auto v = r.read_tile(r.visibility_texture(), 0);
    const size_t shadowed = std::count_if(v.begin(), v.end(), [](float x) { return x < 0.5f; });
    EXPECT_GT(shadowed, 5000u);

    const Image before = ctx.read_color(kCanvas);
    Pipeline pipeline(ctx.gl(), pass_settings(scene, "erosion-pcf"));
    pipeline.run(view);
    EXPECT_GT(glcast::slave::compare(before, ctx.read_color(kCanvas)).differing_pixels, 5000);
}

TEST(ShadowsGL, UnknownMethodIsRefusedByName) {
    EffectsSettings settings;
    std::string error;
    ASSERT_TRUE(settings.enable("shadows", error));
    ASSERT_TRUE(settings.params.set("shadows.method", "soft", error));
    try {
        Pipeline pipeline(context().gl(), settings);
        FAIL() << "an unknown method was accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("shadows.method"), std::string::npos) << e.what();
    }
}
