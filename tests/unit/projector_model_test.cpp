// The projector model of glcast calibrate (display_configs/projector_model.h): surfaces rolled and
// unrolled, a projector's rays and their projection back, its warp and blend. Pure arithmetic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "display_configs/projector_maps.h"
#include "display_configs/projector_model.h"

using namespace glcast::slave;

namespace {

Surface cylinder() {
    Surface s;
    s.kind = Surface::cylinder;
    s.radius = 5, s.azimuth_from = -60, s.azimuth_to = 60, s.height_from = -1.4, s.height_to = 1.4;
    return s;
}

Projector projector(double yaw, double pitch = 0) {
    Projector p;
    p.position = {0, 0.3, 1};
    p.yaw = yaw, p.pitch = pitch;
    p.left = -24, p.right = 24, p.down = -17, p.up = 17;
    return p;
}

}  // namespace

TEST(ProjectorModel, SurfacesRollAndUnrollToTheSameCanvasPosition) {
    Surface dome;
    dome.kind = Surface::dome;
    Surface plane;
    plane.kind = Surface::plane;
    for (const Surface& s : {cylinder(), dome, plane})
        for (double t = 0.05; t < 1; t += 0.1)
            for (double u = 0.05; u < 1; u += 0.1) {
                const auto p = s.roll({u, t});
                if (!p) continue;  // a dome master's corners
                const auto back = s.unroll(*p);
                ASSERT_TRUE(back) << s.kind << " " << u << "," << t;
                EXPECT_NEAR(back->x, u, 1e-9);
                EXPECT_NEAR(back->y, t, 1e-9);
            }
    // Ahead is the canvas's middle column (cylinder) and the dome master's top.
    EXPECT_NEAR(cylinder().unroll({0, 0, -5})->x, 0.5, 1e-12);
    EXPECT_NEAR(dome.unroll({0, 0.0, -5})->y, 0.0, 1e-9);
    EXPECT_FALSE(dome.roll({0.02, 0.02}));  // outside the fisheye's circle
}

TEST(ProjectorModel, ARayHitsTheSurfaceWhereTheProjectorProjectsTheHitBack) {
    const Surface s = cylinder();
    const Projector p = projector(-40, 5);
    for (double y = 0.0625; y < 1; y += 0.125)  // (inside the image: its edges are where project() stops)
        for (double x = 0.0625; x < 1; x += 0.125) {
            const auto hit = s.hit(p.position, p.ray(x, y));
            ASSERT_TRUE(hit);
            EXPECT_NEAR(std::hypot(hit->x, hit->z), s.radius, 1e-9);
            const auto back = p.project(*hit);
            ASSERT_TRUE(back) << x << "," << y;
            EXPECT_NEAR(back->x, x, 1e-9);
            EXPECT_NEAR(back->y, y, 1e-9);
        }
    // Turned right, it lights the right of the canvas; behind it nothing projects.
    EXPECT_GT(s.unroll(*s.hit(projector(40).position, projector(40).ray(0.5, 0.5)))->x, 0.75);
    EXPECT_FALSE(p.project({0, 0, 10}));
}

TEST(ProjectorModel, TheWarpPointsWhereTheLightLandsAndTheBlendsSumToOne) {
    const Surface s = cylinder();
    const std::vector<Projector> all = {projector(-40), projector(0), projector(40)};
    const int cw = 960, ch = 257;
    const CanvasRect r = footprint(s, all[1], cw, ch);
    ASSERT_GT(r.width, 100);
    const WarpMap w = projector_warp(s, all[1], r, cw, ch, 17, 9);
    // The centre node: where the ray through the output's centre lands, in the tile's image.
    const float* uv = &w.uv[(4 * 17 + 8) * 2];
    const auto st = s.unroll(*s.hit(all[1].position, all[1].ray(0.5, 0.5)));
    EXPECT_NEAR(uv[0], (st->x * cw - r.x) / r.width, 1e-5);
    EXPECT_NEAR(uv[1], (st->y * ch - r.y) / r.height, 1e-5);
    // Each point's shares sum to 1: sampled at a point lit by p1 and p2.
    std::vector<BlendMap> b;
    for (size_t i = 0; i < all.size(); i++) b.push_back(projector_blend(s, all, i, 64, 48));
    auto bilinear = [](const BlendMap& m, double x, double y) {  // x, y: 0..1 over the output
        const double px = std::clamp(x * m.width - 0.5, 0.0, m.width - 1.0), py = std::clamp(y * m.height - 0.5, 0.0, m.height - 1.0);
        const int x0 = int(px), y0 = int(py), x1 = std::min(x0 + 1, m.width - 1), y1 = std::min(y0 + 1, m.height - 1);
        auto at = [&](int i, int j) { return double(m.rgb[(size_t(j) * m.width + i) * 3]); };
        const double fx = px - x0, fy = py - y0;
        return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) + (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
    };
    int overlapping = 0;
    for (double u = 0.3; u < 0.7; u += 0.01) {
        const auto point = s.roll({u, 0.5});
        double sum = 0;
        int reaching = 0;
        for (size_t i = 0; i < all.size(); i++)
            if (auto o = all[i].project(*point)) {
                sum += bilinear(b[i], o->x, o->y);
                reaching++;
            }
        overlapping += reaching > 1;
        EXPECT_NEAR(sum, 1.0, 0.02) << u;
    }
    EXPECT_GT(overlapping, 3);
}

TEST(ProjectorMaps, PfmRoundTripsAndItsHeaderIsCheckedFirst) {
    FloatImage f;
    f.width = 3, f.height = 2, f.channels = 3;
    for (int i = 0; i < 18; i++) f.values.push_back(float(i) / 17);
    FloatImage back;
    std::string error;
    ASSERT_TRUE(read_pfm_bytes(pfm_bytes(f), "t.pfm", back, error)) << error;
    EXPECT_EQ(back.values, f.values);  // rows top to bottom in memory, bottom to top in the file
    EXPECT_FALSE(read_pfm_bytes("PF\n3 2\n1.0\n" + std::string(72, '\0'), "t.pfm", back, error));
    EXPECT_NE(error.find("big-endian"), std::string::npos) << error;
    EXPECT_FALSE(read_pfm_bytes("PF\n-3 2\n-1.0\n", "t.pfm", back, error));
    EXPECT_FALSE(read_pfm_bytes("P6\n3 2\n255\n", "t.pfm", back, error));
    EXPECT_NE(error.find("not a PFM"), std::string::npos) << error;
    WarpMap w;
    f.values[0] = std::nanf("");
    EXPECT_TRUE(warp_from_pfm(f, "t.pfm", w, error)) << error;
    EXPECT_TRUE(std::isnan(w.uv[0]));
    f.values[4] = 5000;
    EXPECT_FALSE(warp_from_pfm(f, "t.pfm", w, error));
    EXPECT_NE(error.find("warp node (1, 0) has v = 5000"), std::string::npos) << error;
}
