// Icicles (docs/winter.md, "Icicles"): where they hang, that they stay put, how they grow, and
// the length-radius law, measured on the harness scene (winter_harness.h).
//
//   run: <build>/tests/effects/winter/winter_tests --gtest_filter='Icicles*'
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/effects/winter/winter_harness.h"

namespace winter_test {
namespace {

constexpr int kWidth = 480, kHeight = 360;

Harness& harness() {
    static Harness h(kWidth, kHeight);
    return h;
}

// Pixels the icicles changed: any channel differs by more than `threshold`.
std::vector<uint8_t> changed(const Image& a, const Image& b, int threshold = 6) {
    std::vector<uint8_t> mask(size_t(a.width) * a.height);
    for (size_t i = 0; i < mask.size(); ++i)
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(a.rgba[i * 4 + c]) - int(b.rgba[i * 4 + c])) > threshold) mask[i] = 1;
    return mask;
}

long count(const std::vector<uint8_t>& mask) { return long(std::count(mask.begin(), mask.end(), 1)); }

TEST(Icicles, HangOnlyBelowLowerEdgesOfCoveredSurfaces) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    const Camera camera = high_camera();
    const Image cover = h.render(scene, camera, {"cover", {}});
    const Image both = h.render(scene, camera, {"cover,icicles", {}});
    const Image ids = h.classes(scene, camera);
    save("icicles_high", both);
    const std::vector<uint8_t> ice = changed(cover, both);

    // Lower edges of box tops: a top pixel whose neighbour below is not a top pixel.
    std::vector<uint8_t> edge(ice.size());
    for (int y = 1; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            edge[size_t(y) * kWidth + x] = class_at(ids, x, y) == kTop && class_at(ids, x, y - 1) != kTop;
    // Default sizes at this canvas: icicles hang below a lip of at most 1.5 * 0.004 * 360 = 2.2 px,
    // length_max 0.09 * 360 = 32.4 px, radius_max 0.010 * 360 = 3.6 px (plus its bend and
    // antialiasing).
    const int reach_down = 37, reach_side = 6;
    long hanging = 0, stray = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            if (!ice[size_t(y) * kWidth + x]) continue;
            bool below_edge = false;
            for (int dy = 1; dy <= reach_down && !below_edge && y + dy < kHeight; ++dy)
                for (int dx = -reach_side; dx <= reach_side && !below_edge; ++dx)
                    if (x + dx >= 0 && x + dx < kWidth && edge[size_t(y + dy) * kWidth + x + dx]) below_edge = true;
            ++(below_edge ? hanging : stray);
        }
    std::printf("[ icicles ] %ld icicle pixels, %ld of them within the reach below a box top's lower edge, %ld "
                "elsewhere\n",
                hanging + stray, hanging, stray);
    EXPECT_GE(hanging, 150) << "too few icicles to tell anything";
    EXPECT_LE(double(stray), 0.01 * double(hanging + stray));
}

// A racing game's track laid over its terrain (SuperTuxKart's): two ground meshes that cross, the
// visible one alternating in strips a pixel or two tall (winter_harness.h's Track). The normals of
// a frame that cannot be re-rendered (a shader program's) come from its depth, and must see one
// ground there, and a strip of the other mesh is no roof's rim: no icicle hangs from the ground.
// Before, the normal of a strip pixel whose neighbours lay on the other mesh turned at random and
// icicles hung along the crossings (299 and 236 pixels of them in the two views below).
TEST(Icicles, NoneHangFromTwoGroundMeshesThatCross) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    Track gentle, rough;  // a few centimetres over cells of a metre
    rough.amplitude = 0.08;
    const struct {
        const char* name;
        Track track;
        Camera camera;
    } views[] = {{"from a kart", gentle, Camera{{0, 2, 9.5}, {0, 0, -1.5}, 45}},
                 {"from higher", rough, Camera{{0, 3.5, 9.5}, {0, 0, -1.5}, 45}}};
    for (const auto& v : views)
        for (const bool redraw : {false, true}) {
            Scene scene;
            scene.tracks.push_back(v.track);
            // Against icicles of density 0 (the same guard band, so the same redraw), not the cover
            // alone: a redraw's own z-fighting between the two meshes moves with the guard band.
            const Image bare = h.render(scene, v.camera, {"cover,icicles", {"icicles.density=0"}, 10, redraw});
            const Image both = h.render(scene, v.camera, {"cover,icicles", {}, 10, redraw});
            save(std::string("icicles_track_") + (v.track.amplitude > 0.05 ? "rough" : "gentle") +
                     (redraw ? "_redrawn" : "_depth"),
                 both);
            const long ice = count(changed(bare, both));
            std::printf("[ icicles ] a track over the ground seen %s, normals %s: %ld icicle pixels\n", v.name,
                        redraw ? "re-rendered" : "from depth", ice);
            EXPECT_EQ(ice, 0) << v.name << (redraw ? ", re-rendered" : ", from depth");
        }
}

TEST(Icicles, HangAlikeOnATileTurnedBesideOrBehindTheProgramsCamera) {
    // A cylinder's or a CAVE's side tile shows what lies beside or behind the program's camera:
    // there the program's eye-space -z is 0 or negative, and the icicles (their lower edges and
    // distance bands, and their highlight, whose normal is built in the tile's screen axes) must
    // come out as on a tile that looks where the program does.
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    const Camera camera = high_camera();
    const Image ahead_image = h.render(scene, camera, {"cover,icicles", {}});
    const std::vector<uint8_t> ahead = changed(h.render(scene, camera, {"cover", {}}), ahead_image);
    const long icicles = count(ahead);
    EXPECT_GE(icicles, 150) << "too few icicles to tell anything";
    for (const double turn : {90.0, 180.0, -120.0}) {
        RenderOptions cover{"cover", {}}, both{"cover,icicles", {}};
        cover.program_turn_deg = both.program_turn_deg = turn;
        const Image image = h.render(scene, camera, both);
        const std::vector<uint8_t> turned = changed(h.render(scene, camera, cover), image);
        long elsewhere = 0, shaded = 0;
        for (size_t i = 0; i < ahead.size(); ++i) {
            elsewhere += ahead[i] != turned[i];
            if (ahead[i] && turned[i])
                for (int c = 0; c < 3; ++c)
                    if (std::abs(int(image.rgba[4 * i + c]) - int(ahead_image.rgba[4 * i + c])) > 2) {
                        ++shaded;
                        break;
                    }
        }
        std::printf("[ icicles ] a tile turned %.0f degrees from the program's camera: %ld icicle pixels, %ld of them "
                    "not where the tile looking where the program does has its %ld, %ld shaded more than 2 levels "
                    "otherwise\n",
                    turn, count(turned), elsewhere, icicles, shaded);
        EXPECT_LE(elsewhere, icicles / 50) << "turned " << turn;
        EXPECT_LE(shaded, icicles / 50) << "turned " << turn;
    }
}

TEST(Icicles, StayPutWhileTheCameraDoes) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    RenderOptions options{"cover,icicles", {}};
    std::vector<Image> frames;
    for (uint64_t frame : {10, 11, 12, 500}) {
        options.frame = frame;
        frames.push_back(h.render(scene, high_camera(), options));
    }
    for (size_t i = 1; i < frames.size(); ++i) {
        const auto d = glcast::slave::compare(frames[0], frames[i]);
        std::printf("[ icicles ] frame 10 vs frame %zu of a still camera: %lld pixels differ\n", i,
                    static_cast<long long>(d.differing_pixels));
        EXPECT_EQ(d.differing_pixels, 0);
    }
}

TEST(Icicles, GrowFromSeededStartsAndThenStay) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    const Camera camera = high_camera();
    const Image cover = h.render(scene, camera, {"cover", {}});
    const Image grown = h.render(scene, camera, {"cover,icicles", {}});
    std::vector<long> pixels;
    for (uint64_t frame : {0, 15, 30, 45, 60, 90}) {
        const Image image = h.render(scene, camera, {"cover,icicles", {"icicles.growth_frames=30"}, frame});
        pixels.push_back(count(changed(cover, image)));
        std::printf("[ icicles ] growth over 30 frames: frame %llu, %ld icicle pixels\n",
                    static_cast<unsigned long long>(frame), pixels.back());
        if (frame >= 60) {
            // Every start is below 30 and growth takes 30 frames: grown by frame 60.
            EXPECT_EQ(glcast::slave::compare(image, grown).differing_pixels, 0) << "frame " << frame;
        }
    }
    EXPECT_EQ(pixels[0], 0) << "nothing has grown at frame 0";
    for (size_t i = 1; i < 5; ++i) EXPECT_GT(pixels[i], pixels[i - 1]) << "growth is not monotone";
}

// Connected regions of a mask (8-neighbours): rows spanned and pixel count.
struct Region {
    int top = -1, bottom = 1 << 30, left = 1 << 30, right = -1;
    long area = 0;
};

std::vector<Region> regions(const std::vector<uint8_t>& mask, int width, int height) {
    std::vector<int> label(mask.size(), -1);
    std::vector<Region> out;
    std::vector<int> stack;
    for (int start = 0; start < width * height; ++start) {
        if (!mask[start] || label[start] >= 0) continue;
        Region r;
        label[start] = int(out.size());
        stack.push_back(start);
        while (!stack.empty()) {
            const int i = stack.back();
            stack.pop_back();
            const int x = i % width, y = i / width;
            ++r.area;
            r.top = std::max(r.top, y);
            r.bottom = std::min(r.bottom, y);
            r.left = std::min(r.left, x);
            r.right = std::max(r.right, x);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
                    const int j = ny * width + nx;
                    if (mask[j] && label[j] < 0) {
                        label[j] = label[start];
                        stack.push_back(j);
                    }
                }
        }
        out.push_back(r);
    }
    return out;
}

// After Short et al. (docs/winter.md): an icicle's length goes as its radius to the 4/3. Large icicles
// under a long ledge seen head-on; for each, the length is the rows it spans and the root
// radius follows from how fast its width shrinks (a cone, taper 1: width 2 r (1 - t)); the
// slope of log L against log r over four seeds' icicles must be 4/3 within 0.12.
TEST(Icicles, LengthGoesAsRadiusToTheFourThirds) {
    Harness& h = harness();
    ASSERT_TRUE(h.ok()) << h.error();
    Scene scene;
    scene.ground = false;
    scene.boxes.push_back({{0, 1.0, 0}, {14, 2, 1}, 0, {0.45, 0.14, 0.10}});
    const Camera camera{{0, 4.0, 9}, {0, 0.3, 0}, 45};
    const std::vector<std::string> sizes = {"icicles.density=1",       "icicles.spacing=0.13", "icicles.radius_min=0.008",
                                            "icicles.radius_max=0.024", "icicles.length_max=0.25", "icicles.taper=1",
                                            "icicles.refraction=0",     "cover.density=1"};
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (int seed = 1; seed <= 4; ++seed) {
        std::vector<std::string> params = sizes;
        params.push_back("icicles.seed=" + std::to_string(seed));
        const Image cover = h.render(scene, camera, {"cover", params});
        const Image both = h.render(scene, camera, {"cover,icicles", params});
        if (seed == 1) save("icicles_law", both);
        const std::vector<uint8_t> ice = changed(cover, both, 10);
        for (const Region& r : regions(ice, kWidth, kHeight)) {
            if (r.area < 20 || r.left == 0 || r.right == kWidth - 1) continue;  // specks, cut by the border
            // Width against depth below the root: 2 r (1 - t) plus the antialiased fringe, a
            // constant the slope does not see. Radius = slope * length / 2.
            const double length = r.top - r.bottom + 1;
            double s1 = 0, sd = 0, sw = 0, sdd = 0, sdw = 0;
            for (int y = r.bottom; y <= r.top; ++y) {
                int width = 0;
                for (int x = r.left; x <= r.right; ++x) width += ice[size_t(y) * kWidth + x];
                const double depth = r.top - y;
                s1 += 1, sd += depth, sw += width, sdd += depth * depth, sdw += depth * width;
            }
            const double narrowing = -(s1 * sdw - sd * sw) / (s1 * sdd - sd * sd);
            const double radius = narrowing * length / 2;
            std::printf("   icicle x %d..%d: length %.0f px, radius %.2f px\n", r.left, r.right, length, radius);
            sx += std::log(radius);
            sy += std::log(length);
            sxx += std::log(radius) * std::log(radius);
            sxy += std::log(radius) * std::log(length);
            ++n;
        }
    }
    ASSERT_GE(n, 20) << "too few icicles measured";
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    std::printf("[ icicles ] %d icicles: log length against log radius has slope %.3f (law: 4/3)\n", n, slope);
    EXPECT_NEAR(slope, 4.0 / 3.0, 0.12);
}

}  // namespace
}  // namespace winter_test
