// Snow cover (docs/winter.md, "Cover"): measured fractions of snow per class of surface of the
// harness scene (winter_harness.h), with the thresholds each test states.
//
//   build: cmake --build <build> --target winter_tests
//   run:   <build>/tests/effects/winter/winter_tests --gtest_filter='Cover*'
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "slave/effects/winter/winter_gl.h"

#include "tests/effects/winter/winter_harness.h"

namespace winter_test {
namespace {

constexpr int kWidth = 480, kHeight = 360;

Harness& harness() {
    static Harness h(kWidth, kHeight);
    return h;
}

void print(const char* label, const std::map<int, Fraction>& f) {
    std::printf("[ cover ] %s:", label);
    for (const auto& [cls, fr] : f) std::printf(" class %d %.3f (%ld px)", cls, fr.value(), fr.total);
    std::printf("\n");
}

// Default parameters (density 0.9), seeds 1 to 4: the noise patches are a few per box top, so
// a top's fraction varies with the seed; the thresholds hold for each seed.
TEST(Cover, UpFacingSurfacesHoldSnowVerticalAndUndersidesStayClear) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    for (const Camera& camera : {high_camera(), low_camera()}) {
        const bool high = camera.eye.y > 3;
        const Image before = h.render(scene, camera, {});
        const Image ids = h.classes(scene, camera);
        save(high ? "cover_high_before" : "cover_low_before", before);
        for (int seed = 1; seed <= 4; ++seed) {
            const Image after = h.render(scene, camera, {"cover", {"cover.seed=" + std::to_string(seed)}});
            if (seed == 1) save(high ? "cover_high_after" : "cover_low_after", after);
            const auto f = snow_by_class(before, after, ids);
            print((std::string(high ? "high camera" : "low camera") + ", seed " + std::to_string(seed)).c_str(), f);
            EXPECT_GE(f.at(kGround).value(), 0.85);
            EXPECT_LE(f.at(kSide).value(), 0.03);
            if (high) {
                EXPECT_GE(f.at(kTop).value(), 0.75);
            } else {
                ASSERT_GT(f.at(kUnder).total, 500) << "the low camera must see the raised box's underside";
                EXPECT_LE(f.at(kUnder).value(), 0.01);
            }
        }
    }
}

// Two panels on the ground tilted towards the camera, 5 degrees inside and outside the spread.
Scene panel_scene(double spread) {
    Scene scene;
    for (double tilt : {spread - 5, spread + 5}) {
        Panel p;
        p.tilt_deg = tilt;
        p.width = p.depth = 2.6;
        p.center = {scene.panels.empty() ? -2.2 : 2.2, 1.3 * std::sin(glm::radians(tilt)) + 0.01, 2.0};
        scene.panels.push_back(p);
    }
    return scene;
}

TEST(Cover, SpreadAngleSeparatesTiltedPanels) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    for (double spread : {25.0, 40.0, 60.0}) {
        const Scene scene = panel_scene(spread);
        const std::string param = "cover.spread=" + std::to_string(spread);
        const Image before = h.render(scene, high_camera(), {});
        const Image after = h.render(scene, high_camera(), {"cover", {param, "cover.density=1"}});
        const Image ids = h.classes(scene, high_camera());
        if (spread == 40.0) save("cover_spread40", after);
        const auto f = snow_by_class(before, after, ids);
        std::printf("[ cover ] spread %.0f: panel at %.0f deg %.3f, panel at %.0f deg %.3f, ground %.3f\n", spread,
                    spread - 5, f.at(kPanel).value(), spread + 5, f.at(kPanel + 1).value(), f.at(kGround).value());
        EXPECT_GE(f.at(kPanel).value(), 0.97) << "inside the spread angle";
        EXPECT_LE(f.at(kPanel + 1).value(), 0.01) << "outside the spread angle";
        EXPECT_GE(f.at(kGround).value(), 0.97);
    }
}

// The random spread (docs/winter.md): the spread angle times ((r + offset) stepper)^exponent with r a
// seeded value noise in [0, 1); 40 degrees times 0.5..1.5 is 20..60 degrees, so both panels
// (35 and 45 degrees) are partly covered, the ground (0 degrees) fully.
TEST(Cover, RandomSpreadVariesTheAnglePerLocation) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = panel_scene(40);
    const Image before = h.render(scene, high_camera(), {});
    const Image after = h.render(scene, high_camera(),
                                 {"cover", {"cover.spread_mode=random", "cover.random_scale=0.4", "cover.density=1"}});
    const Image ids = h.classes(scene, high_camera());
    save("cover_random_spread", after);
    const auto f = snow_by_class(before, after, ids);
    std::printf("[ cover ] random spread 40 x (0.5..1.5): panel at 35 deg %.3f, panel at 45 deg %.3f, ground %.3f\n",
                f.at(kPanel).value(), f.at(kPanel + 1).value(), f.at(kGround).value());
    EXPECT_GT(f.at(kPanel).value(), 0.40);
    EXPECT_LT(f.at(kPanel).value(), 0.95);
    EXPECT_GT(f.at(kPanel + 1).value(), 0.05);
    EXPECT_LT(f.at(kPanel + 1).value(), 0.60);
    EXPECT_GT(f.at(kPanel).value(), f.at(kPanel + 1).value()) << "the steeper panel holds less";
    EXPECT_GE(f.at(kGround).value(), 0.97);
}

// The covered fraction of the ground follows cover.density (the noise is mapped through its
// measured distribution to be close to uniform; see docs/winter.md).
TEST(Cover, DensityIsTheCoveredFraction) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    const Image before = h.render(scene, high_camera(), {});
    const Image ids = h.classes(scene, high_camera());
    for (double density : {0.0, 0.25, 0.5, 0.75, 1.0}) {
        const Image after = h.render(scene, high_camera(), {"cover", {"cover.density=" + std::to_string(density)}});
        if (density == 0.5) save("cover_density_half", after);
        const double f = snow_by_class(before, after, ids).at(kGround).value();
        std::printf("[ cover ] density %.2f: ground covered %.3f\n", density, f);
        if (density == 0.0) EXPECT_EQ(f, 0.0);
        else if (density == 1.0) EXPECT_GE(f, 0.99);
        else EXPECT_NEAR(f, density, 0.08);
    }
}

// Snow by texture (docs/winter.md): a mask image stretched over the canvas. Three bands: white
// opaque (snow), black opaque (none), white transparent (none); at a resolution other than the
// canvas's.
TEST(Cover, MaskImageDecidesWhereSnowMayLie) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    Image mask;
    mask.width = 90;
    mask.height = 40;
    mask.rgba.assign(size_t(mask.width) * mask.height * 4, 0);
    for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x) {
            uint8_t* p = &mask.rgba[(size_t(y) * mask.width + x) * 4];
            const int band = x * 3 / mask.width;
            const uint8_t value = band == 1 ? 0 : 255;
            p[0] = p[1] = p[2] = value;
            p[3] = band == 2 ? 0 : 255;
        }
    const char* dir = std::getenv("GLCAST_TEST_OUT");
    const std::string path = std::string(dir && *dir ? dir : ".") + "/cover_mask_bands.png";
    std::string error;
    ASSERT_TRUE(glcast::slave::write_png(path, mask, error)) << error;

    const Scene scene = standard_scene();
    const Image before = h.render(scene, high_camera(), {});
    const Image after = h.render(scene, high_camera(), {"cover", {"cover.mask=" + path, "cover.density=1"}});
    const Image ids = h.classes(scene, high_camera());
    save("cover_mask", after);
    const int third = kWidth / 3, margin = 4;
    const double left = snow_by_class(before, after, ids, 0, third - margin).at(kGround).value();
    const double middle = snow_by_class(before, after, ids, third + margin, 2 * third - margin).at(kGround).value();
    const double right = snow_by_class(before, after, ids, 2 * third + margin, kWidth).at(kGround).value();
    std::printf("[ cover ] mask bands: white %.3f, black %.3f, transparent %.3f of the ground covered\n", left, middle,
                right);
    EXPECT_GE(left, 0.97);
    EXPECT_EQ(middle, 0.0);
    EXPECT_EQ(right, 0.0);

    RenderOptions missing{"cover", {"cover.mask=" + path + ".missing"}};
    try {
        h.render(scene, high_camera(), missing);
        ADD_FAILURE() << "a missing mask file was accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("cover.mask"), std::string::npos) << e.what();
    }
}

// Without a re-render (shader programs) the normals come from the depth buffer; without
// vertex normals to trust (an unlit program) from the re-rendered triangles' planes.
TEST(Cover, NormalsFromDepthOrFacetsClassifyAlike) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    Scene lit = standard_scene(), unlit = standard_scene();
    unlit.light = false;
    struct Case {
        const char* name;
        const Scene* scene;
        RenderOptions options;
    };
    const Case cases[] = {
        {"no re-render (depth)", &lit, {"cover", {}, 10, false}},
        {"cover.normals=depth", &lit, {"cover", {"cover.normals=depth"}}},
        {"unlit program (faceted)", &unlit, {"cover", {}}},
        {"cover.normals=faceted", &lit, {"cover", {"cover.normals=faceted"}}},
    };
    for (const Case& c : cases) {
        const Image before = h.render(*c.scene, high_camera(), {});
        const Image after = h.render(*c.scene, high_camera(), c.options);
        const Image ids = h.classes(*c.scene, high_camera());
        const auto f = snow_by_class(before, after, ids);
        std::printf("[ cover ] %s: ground %.3f, tops %.3f, sides %.3f\n", c.name, f.at(kGround).value(),
                    f.at(kTop).value(), f.at(kSide).value());
        EXPECT_GE(f.at(kGround).value(), 0.85) << c.name;
        EXPECT_GE(f.at(kTop).value(), 0.85) << c.name;
        EXPECT_LE(f.at(kSide).value(), 0.03) << c.name;
    }
    save("cover_from_depth", h.render(lit, high_camera(), {"cover", {}, 10, false}));
}

// "Up" in world space goes through the main view's modelview: with up = +z (snow blown
// horizontally towards -z) the box faces turned towards +z, which the camera sees, hold the
// snow, the ground and the tops none.
TEST(Cover, UpDirectionIsInWorldSpace) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    const Image before = h.render(scene, high_camera(), {});
    const Image after = h.render(scene, high_camera(), {"cover", {"cover.up_z=1", "cover.up_y=0", "cover.density=1"}});
    const Image ids = h.classes(scene, high_camera());
    save("cover_up_z", after);
    const auto f = snow_by_class(before, after, ids);
    std::printf("[ cover ] up = +z: ground %.3f, tops %.3f, sides %.3f\n", f.at(kGround).value(), f.at(kTop).value(),
                f.at(kSide).value());
    EXPECT_EQ(f.at(kGround).value(), 0.0);
    EXPECT_EQ(f.at(kTop).value(), 0.0);
    EXPECT_GT(f.at(kSide).value(), 0.25);
}

TEST(Cover, BuildsUpOverFramesAndRerunsIdentically) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    const Image before = h.render(scene, high_camera(), {});
    const Image ids = h.classes(scene, high_camera());
    const Image complete = h.render(scene, high_camera(), {"cover", {}});
    EXPECT_EQ(glcast::slave::compare(complete, h.render(scene, high_camera(), {"cover", {}})).differing_pixels, 0)
        << "a rerun differs";
    for (uint64_t frame : {0, 10, 20, 40}) {
        const Image image = h.render(scene, high_camera(), {"cover", {"cover.build_frames=20"}, frame});
        const double f = snow_by_class(before, image, ids).at(kGround).value();
        std::printf("[ cover ] building over 20 frames: frame %llu, ground covered %.3f\n",
                    static_cast<unsigned long long>(frame), f);
        if (frame == 0) {
            EXPECT_EQ(f, 0.0);
        } else if (frame == 10) {
            EXPECT_NEAR(f, 0.45, 0.1);
        } else if (frame >= 20) {
            EXPECT_EQ(glcast::slave::compare(image, complete).differing_pixels, 0);
        }
    }
}

TEST(Cover, BadParametersAndFramesWithoutAViewAreHandled) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    const std::pair<const char*, const char*> bad[] = {
        {"cover.spread_mode=sideways", "cover.spread_mode"},
        {"cover.up_space=moon", "cover.up_space"},
        {"cover.normals=guess", "cover.normals"},
        {"icicles.radius_min=0.05", "icicles.radius_min"},
    };
    for (const auto& [param, name] : bad) {
        try {
            h.render(scene, high_camera(), {"cover,icicles", {param}});
            ADD_FAILURE() << param << " was accepted";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    }
    RenderOptions no_view{"cover,icicles", {}};
    no_view.view_known = false;
    EXPECT_EQ(glcast::slave::compare(h.render(scene, high_camera(), {}), h.render(scene, high_camera(), no_view))
                  .differing_pixels,
              0);
}

// A visible surface the redraw leaves out (neverball's level in its menu frames: drawn, in the
// window's depth, but not re-rendered) gets its normal from the depth, and holds snow as the
// re-rendered ground does. Before, the re-rendered normals were all there was: none on it.
TEST(Cover, SurfacesTheRedrawLeavesOutTakeTheirNormalsFromDepth) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    const Image before = h.render(scene, high_camera(), {});
    const Image ids = h.classes(scene, high_camera());
    RenderOptions options{"cover", {}};
    options.redraw_ground = false;
    const Image after = h.render(scene, high_camera(), options);
    save("cover_ground_not_redrawn", after);
    const auto f = snow_by_class(before, after, ids);
    print("ground left out of the redraw", f);
    EXPECT_GE(f.at(kGround).value(), 0.85);
    EXPECT_GE(f.at(kTop).value(), 0.75);
    EXPECT_LE(f.at(kSide).value(), 0.03);
}

// cover.up_space=auto (the default): the world axis the first view sees as up. Y-up and Z-up
// worlds (openarena's is Z-up: with up fixed at +Y, its cover held no snow), cameras looking
// down or up by less than 45 degrees, and one rolled upside down.
TEST(Cover, UpIsTheWorldAxisTheViewSeesAsUp) {
    using glcast::slave::effects::world_up_seen;
    const auto view = [](glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up) { return glm::lookAt(eye, target, up); };
    EXPECT_EQ(world_up_seen(view({0, 6.5, 9.5}, {0, 0.8, -1.5}, {0, 1, 0})), glm::dvec3(0, 1, 0));   // 27 degrees down
    EXPECT_EQ(world_up_seen(view({0, 1.2, 7}, {0, 4, -3}, {0, 1, 0})), glm::dvec3(0, 1, 0));         // 16 degrees up
    EXPECT_EQ(world_up_seen(view({3, -10, 4}, {0, 0, 1}, {0, 0, 1})), glm::dvec3(0, 0, 1));          // Z-up, 16 down
    EXPECT_EQ(world_up_seen(view({-5, 8, 1}, {4, -2, 6}, {0, 0, 1})), glm::dvec3(0, 0, 1));          // Z-up, 20 up
    EXPECT_EQ(world_up_seen(view({0, 2, 9}, {0, 0, 0}, {0, -1, 0})), glm::dvec3(0, -1, 0));          // upside down
    // A camera 60 degrees down on a Y-up world is one 30 degrees up on a world whose up is the
    // horizontal axis it looks along: the nearer to level wins.
    EXPECT_EQ(world_up_seen(view({0, 8.66, 5}, {0, 0, 0}, {0, 1, 0})), glm::dvec3(0, 0, -1));
}

}  // namespace
}  // namespace winter_test
