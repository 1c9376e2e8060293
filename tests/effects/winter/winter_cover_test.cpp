// Snow cover (docs/winter.md, "Cover"): measured fractions of snow per class of surface of the
// harness scene (winter_harness.h), with the thresholds each test states.
//
//   build: cmake --build <build> --target winter_tests
//   run:   <build>/tests/effects/winter/winter_tests --gtest_filter='Cover*'
#include <gtest/gtest.h>

#include <cstdio>

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

TEST(Cover, UpFacingSurfacesHoldSnowVerticalAndUndersidesStayClear) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    for (const Camera& camera : {high_camera(), low_camera()}) {
        const bool high = camera.eye.y > 3;
        const Image before = h.render(scene, camera, {});
        const Image after = h.render(scene, camera, {"cover"});
        const Image ids = h.classes(scene, camera);
        save(high ? "cover_high_before" : "cover_low_before", before);
        save(high ? "cover_high_after" : "cover_low_after", after);
        const auto f = snow_by_class(before, after, ids);
        print(high ? "high camera" : "low camera", f);
        EXPECT_GE(f.at(kGround).value(), 0.80);
        EXPECT_LE(f.at(kSide).value(), 0.03);
        if (high) {
            EXPECT_GE(f.at(kTop).value(), 0.80);
        } else {
            ASSERT_GT(f.at(kUnder).total, 500) << "the low camera must see the raised box's underside";
            EXPECT_LE(f.at(kUnder).value(), 0.01);
        }
    }
}

}  // namespace
}  // namespace winter_test
