// Falling snow and rain, and the replayer's support for injected passes, on real Mesa contexts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "common/image.h"
#include "slave/effects/gl_util.h"
#include "slave/effects/pipeline.h"
#include "slave/effects/snow/snow_motion.h"
#include "slave/replayer.h"
#include "tests/effects/snow/effects_test_support.h"

namespace glcast::slave::effects {
namespace {

using testing::TestContext;

const std::string kData = std::string(GLCAST_SOURCE_DIR) + "/tests/data/";

std::string frame_name(uint64_t frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame-%06llu.png", static_cast<unsigned long long>(frame));
    return name;
}

std::unique_ptr<TestContext> context(int w, int h) {
    std::string error;
    auto t = TestContext::create(w, h, error);
    if (!t) ADD_FAILURE() << "no EGL context: " << error;
    return t;
}

// Replays a committed capture with `effects` and the given parameters; returns its frames.
std::map<uint64_t, Image> replay(const std::string& capture, const std::string& effects,
                                 const std::vector<std::string>& params,
                                 std::function<void(Replayer&, const FrameView&)> after = nullptr) {
    std::string error;
    ReplayOptions options;
    EXPECT_TRUE(options.effects.enable(effects, error)) << error;
    for (const std::string& p : params) EXPECT_TRUE(options.effects.params.set_assignment(p, error)) << error;
    auto backend = make_backend("egl", error);
    EXPECT_TRUE(backend) << error;
    Replayer r(std::move(backend), options);
    std::map<uint64_t, Image> frames;
    r.on_frame = [&](uint64_t f, int w, int h, const std::vector<uint8_t>& rgba) { frames[f] = Image{w, h, rgba}; };
    if (after) r.after_effects = [&](const FrameView& v) { after(r, v); };
    CaptureReader reader(open_file_source(kData + capture));
    r.replay(reader);
    EXPECT_EQ(r.stats().errors, 0u);
    return frames;
}

// redraw() re-renders the main view: with the tile's own correction, its depth equals the
// window's where the program drew; and everything it changes is put back, so the replay is still
// pixel-exact against the program's own frames.
void check_redraw(const std::string& name) {
    uint64_t covered = 0, equal = 0, redraws = 0;
    auto frames = replay(name + ".glcs", "snow", {"snow.particles=0", "snow.spectral=0"},
                         [&](Replayer& r, const FrameView& v) {
        ASSERT_TRUE(v.view_known);
        ASSERT_TRUE(v.redraw);
        Backend& b = r.backend();
        GlApi gl;
        std::string error;
        ASSERT_TRUE(gl.load([&b](const char* n) { return b.proc_address(n); }, error)) << error;
        std::vector<float> window(size_t(v.width) * v.height), again(window.size());
        {
            StateGuard guard(gl);
            gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
            gl.glReadPixels(0, 0, v.width, v.height, GL_DEPTH_COMPONENT, GL_FLOAT, window.data());
            GLuint depth = make_texture(gl, GL_DEPTH24_STENCIL8, v.width, v.height);
            GLuint fb = make_framebuffer(gl, 0, depth, GL_DEPTH_STENCIL_ATTACHMENT);
            gl.glViewport(0, 0, v.width, v.height);
            gl.glClearDepth(1.0);
            gl.glClear(GL_DEPTH_BUFFER_BIT);
            gl.glEnable(GL_DEPTH_TEST);
            gl.glDepthFunc(GL_LESS);
            gl.glDepthMask(GL_TRUE);
            gl.glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
            v.redraw(v.tile_clip_from_app_clip);
            gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, fb);
            gl.glReadPixels(0, 0, v.width, v.height, GL_DEPTH_COMPONENT, GL_FLOAT, again.data());
            gl.glDeleteFramebuffers(1, &fb);
            gl.glDeleteTextures(1, &depth);
        }
        redraws++;
        for (size_t i = 0; i < window.size(); ++i) {
            if (window[i] >= 1.0f) continue;
            covered++;
            equal += std::abs(window[i] - again[i]) < 1e-6f;
        }
    });
    ASSERT_GT(redraws, 0u);
    ASSERT_GT(covered, 0u);
    std::printf("%s: redraw depth equals the window's at %llu of %llu covered pixels\n", name.c_str(),
                static_cast<unsigned long long>(equal), static_cast<unsigned long long>(covered));
    EXPECT_GE(double(equal), 0.999 * double(covered));
    for (const auto& [f, image] : frames) {
        Image golden;
        std::string error;
        ASSERT_TRUE(read_png(kData + name + "/" + frame_name(f), golden, error)) << error;
        const ImageDiff d = compare(image, golden);
        EXPECT_FALSE(d.size_mismatch);
        EXPECT_EQ(d.differing_pixels, 0) << name << " frame " << f;
    }
}

TEST(EffectsReplay, RedrawOfFixedFunctionSceneMatchesWindowDepth) { check_redraw("ff_scene"); }
TEST(EffectsReplay, RedrawOfGlxgearsMatchesWindowDepth) { check_redraw("glxgears"); }

TEST(EffectsReplay, SnowReplaysIdentically) {
    auto a = replay("ff_scene.glcs", "snow", {});
    auto b = replay("ff_scene.glcs", "snow", {});
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [f, image] : a) EXPECT_EQ(compare(image, b[f]).differing_pixels, 0) << "frame " << f;
    // ... and the snow is there: the frames differ from the program's own.
    Image golden;
    std::string error;
    ASSERT_TRUE(read_png(kData + "ff_scene/" + frame_name(2), golden, error)) << error;
    EXPECT_GT(compare(a[2], golden).differing_pixels, a[2].width * a[2].height / 4);
}

// A frame of the pass over a synthetic view: projection p, a still camera at the origin.
FrameView synthetic_view(const TestContext& t, const glm::dmat4& p, uint64_t frame, const glm::dmat4& view) {
    FrameView v;
    v.frame = frame;
    v.time = frame / 60.0;
    v.width = v.canvas_width = t.width;
    v.height = v.canvas_height = t.height;
    v.view_known = true;
    v.projection = p;
    v.modelview = view;
    v.tile_clip_from_eye = p;
    v.eye_from_tile_clip = glm::inverse(p);
    return v;
}

void run_pass(TestContext& t, Pass& pass, const FrameView& v) {
    StateGuard guard(t.gl);
    t.gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    t.gl.glViewport(0, 0, t.width, t.height);
    pass.run(t.gl, v);
}

EffectParams params(const std::vector<std::string>& assignments) {
    EffectParams p;
    std::string error;
    for (const std::string& a : assignments) EXPECT_TRUE(p.set_assignment(a, error)) << error;
    return p;
}

// Particles are depth-tested against the program's depth: a wall just beyond the near plane
// over the left half of the image hides every flake there; the same wall far away does not.
int flakes_over_wall(double wall_z) {
    auto t = context(320, 240);
    if (!t) return -1;
    const glm::dmat4 p = glm::frustum(-0.4, 0.4, -0.3, 0.3, 0.5, 100.0);
    auto pass = make_precipitation_pass(t->gl, params({"snow.particles=20000", "snow.spectral=0"}), false);
    int over_wall = 0, elsewhere = 0;
    for (uint64_t frame = 0; frame < 3; ++frame) {
        t->gl.glClearColor(0, 0, 0, 1);
        t->gl.glClearDepth(1);
        t->gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        t->draw_eye_quad(p, -1, 0, wall_z, 0.5);
        const std::vector<uint8_t> before = t->read_rgb();
        run_pass(*t, *pass, synthetic_view(*t, p, frame, glm::dmat4(1.0)));
        const std::vector<uint8_t> after = t->read_rgb();
        for (int y = 0; y < t->height; ++y)
            for (int x = 0; x < t->width; ++x) {
                const size_t i = (size_t(y) * t->width + x) * 3;
                if (before[i] == after[i] && before[i + 1] == after[i + 1] && before[i + 2] == after[i + 2]) continue;
                (x < t->width / 2 - 1 ? over_wall : elsewhere)++;
            }
    }
    EXPECT_GT(elsewhere, 200) << "no flakes at all";
    return over_wall;
}

TEST(Precipitation, ParticlesNeverCoverANearerSurface) {
    const int hidden = flakes_over_wall(-0.51);
    const int visible = flakes_over_wall(-90);
    std::printf("pixels changed over the wall: %d with the wall at 0.51 (near plane 0.5), %d with it at 90\n", hidden,
                visible);
    EXPECT_EQ(hidden, 0);
    EXPECT_GT(visible, 200);  // the test can see flakes over that half
}

// The window as an image (rows from the top).
Image window_image(TestContext& t) {
    const std::vector<uint8_t> rgb = t.read_rgb();
    Image image{t.width, t.height, std::vector<uint8_t>(size_t(t.width) * t.height * 4, 255)};
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x)
            for (int c = 0; c < 3; ++c)
                image.rgba[(size_t(t.height - 1 - y) * t.width + x) * 4 + c] = rgb[(size_t(y) * t.width + x) * 3 + c];
    return image;
}

// With the camera moving forward, the spectral snow of each quadrant moves away from the focus
// of expansion (measured from consecutive frames by block matching).
TEST(Precipitation, SpectralSnowFlowsAwayFromTheFocusOfExpansion) {
    auto t = context(320, 240);
    if (!t) return;
    const glm::dmat4 p = glm::frustum(-0.4, 0.4, -0.3, 0.3, 0.5, 100.0);
    // Forward at 20 near-plane distances per second, snow falling at 4: the FOE lies above the centre.
    const double forward = 20.0, fall = 4.0;
    auto pass = make_precipitation_pass(
        t->gl, params({"snow.particles=0", "snow.spectral_opacity=1", "snow.regions=4", "snow.scale=1",
                       "snow.fall_speed=4", "snow.spectral_depth=6"}), false);
    glm::dvec2 foe;
    ASSERT_TRUE(focus_of_expansion(p, t->width, t->height, glm::dvec3(0, -fall * 0.5, forward * 0.5), foe));
    std::printf("focus of expansion at (%.1f, %.1f)\n", foe.x, foe.y);
    Image previous;
    const int qw = t->width / 2, qh = t->height / 2, r = 8;
    std::map<int, glm::dvec2> motion;  // canvas pixels, y up
    for (uint64_t frame = 0; frame < 12; ++frame) {
        const glm::dmat4 view = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, forward * 0.5 * frame / 60.0));
        t->gl.glClearColor(0, 0, 0, 1);
        t->gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        run_pass(*t, *pass, synthetic_view(*t, p, frame, view));
        Image now = window_image(*t);
        if (frame >= 4)
            for (int q = 0; q < 4; ++q) {  // quadrant q: column q % 2, row q / 2 counted from the bottom
                const int x0 = (q % 2) * qw, y0 = (1 - q / 2) * qh;
                const Shift s = estimate_shift(previous, now, x0 + r + 4, y0 + r + 4, qw - 2 * r - 8, qh - 2 * r - 8, r);
                motion[q] += glm::dvec2(s.dx, -s.dy);
            }
        previous = std::move(now);
    }
    for (int q = 0; q < 4; ++q) {
        const glm::dvec2 centre((q % 2 + 0.5) * qw, (q / 2 + 0.5) * qh);
        const glm::dvec2 away = glm::normalize(centre - foe), measured = motion[q];
        ASSERT_GT(glm::length(measured), 1.0) << "quadrant " << q << " does not move";
        const double angle = std::acos(glm::dot(away, glm::normalize(measured))) * 180 / 3.14159265;
        std::printf("quadrant %d: moved (%.0f, %.0f) px over 8 frames, %.1f degrees from the direction away from the FOE\n",
                    q, measured.x, measured.y, angle);
        EXPECT_LT(angle, 30.0) << "quadrant " << q;
    }
}

// Rain: high C with the temporal blur leaves only components whose motion is slow, those whose
// wave vector is nearly horizontal: vertical streaks. Snow has no preferred direction.
double streak_ratio(bool rain) {
    auto t = context(256, 256);
    if (!t) return 0;
    const glm::dmat4 p = glm::frustum(-0.4, 0.4, -0.4, 0.4, 0.5, 100.0);
    const std::string k = rain ? "rain" : "snow";
    auto pass = make_precipitation_pass(t->gl, params({k + ".particles=0", k + ".spectral_opacity=1", k + ".regions=1"}), rain);
    t->gl.glClearColor(0, 0, 0, 1);
    t->gl.glClear(GL_COLOR_BUFFER_BIT);
    run_pass(*t, *pass, synthetic_view(*t, p, 0, glm::dmat4(1.0)));
    const Image g = window_image(*t);
    auto at = [&](int x, int y) { return double(g.rgba[(size_t(y) * g.width + x) * 4]); };
    double dx = 0, dy = 0;
    for (int y = 0; y + 1 < t->height; ++y)
        for (int x = 0; x + 1 < t->width; ++x) {
            dx += std::pow(at(x + 1, y) - at(x, y), 2.0);
            dy += std::pow(at(x, y + 1) - at(x, y), 2.0);
        }
    return dx / dy;
}

TEST(Precipitation, RainIsVerticalStreaks) {
    const double rain = streak_ratio(true), snow = streak_ratio(false);
    std::printf("horizontal / vertical gradient energy: rain %.2f, snow %.2f\n", rain, snow);
    EXPECT_GT(rain, 3.0);
    EXPECT_LT(snow, 1.5);
    EXPECT_GT(snow, 0.67);
}

TEST(Precipitation, ImageVelocityHasItsFocusOfExpansion) {
    const glm::dmat4 p = glm::frustum(-0.4, 0.4, -0.3, 0.3, 0.5, 100.0);
    const glm::dvec3 u(0.3, -0.2, 2.0);
    glm::dvec2 foe;
    ASSERT_TRUE(focus_of_expansion(p, 640, 480, u, foe));
    EXPECT_LT(glm::length(image_velocity(p, 640, 480, foe, u, 3.0)), 1e-9);
    const glm::dvec2 q = foe + glm::dvec2(100, 50);
    const glm::dvec2 v = image_velocity(p, 640, 480, q, u, 3.0);
    EXPECT_NEAR(v.x / v.y, 2.0, 1e-9);  // radial
    EXPECT_GT(v.x, 0);                  // outwards when the flakes come closer (u_z > 0)
    EXPECT_FALSE(focus_of_expansion(p, 640, 480, glm::dvec3(0, -1, 0), foe));
}

}  // namespace
}  // namespace glcast::slave::effects
