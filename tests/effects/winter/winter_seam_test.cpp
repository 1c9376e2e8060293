// Tiles join without seams (docs/effects.md): the canvas rendered as one tile and as 2x2 tiles
// (each with its own FrameView: canvas offset, the wall's stretch, a re-render of its guard
// band) must give the same picture with cover and icicles.
//
// Tolerance: llvmpipe interpolates relative to each framebuffer's origin, so a tile's (and a
// guard band's) re-render puts positions a rounding step off the whole canvas's; a pixel whose
// snow amount sits at a patch border or whose icicle root sits at a threshold can then change.
// The scene alone differs in a handful of pixels (measured below); with cover and icicles the
// test allows 0.1% of the canvas and prints the measured count.
//
//   run: <build>/tests/effects/winter/winter_tests --gtest_filter='Seams*'
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/effects/winter/winter_harness.h"

namespace winter_test {
namespace {

constexpr int kWidth = 480, kHeight = 360;

bool differing(const Image& a, const Image& b, int tolerance, int x, int y) {
    const size_t i = (size_t(y) * a.width + x) * 4;
    for (int c = 0; c < 3; ++c)
        if (std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])) > tolerance) return true;
    return false;
}

// Pixels of `a` and `b` whose channels differ by more than `tolerance`.
long differing(const Image& a, const Image& b, int tolerance) {
    long n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) n += differing(a, b, tolerance, x, y);
    return n;
}

// The 2x2 tiles of the canvas split at (split_x, split_y), pasted together (GL rows: bottom first).
Image quarters(Harness& h, const Scene& scene, const Camera& camera, const RenderOptions& options, int split_x,
               int split_y) {
    Image whole;
    whole.width = kWidth;
    whole.height = kHeight;
    whole.rgba.assign(size_t(kWidth) * kHeight * 4, 0);
    const int xs[3] = {0, split_x, kWidth}, ys[3] = {0, split_y, kHeight};
    for (int ty = 0; ty < 2; ++ty)
        for (int tx = 0; tx < 2; ++tx) {
            const Tile tile{xs[tx], ys[ty], xs[tx + 1] - xs[tx], ys[ty + 1] - ys[ty]};
            const Image part = h.render(scene, camera, options, tile);
            for (int y = 0; y < tile.height; ++y)
                for (int x = 0; x < tile.width; ++x)
                    for (int c = 0; c < 4; ++c)
                        whole.rgba[(size_t(tile.y + y) * kWidth + tile.x + x) * 4 + c] =
                            part.rgba[(size_t(y) * tile.width + x) * 4 + c];
        }
    return whole;
}

// The tile borders go through the row and the column holding the most icicle pixels, so that
// icicles hang across both (a tile that did not see the edges above it in its guard band
// would cut them off).
TEST(Seams, TwoByTwoTilesEqualTheWholeCanvas) {
    static Harness h(kWidth, kHeight);
    ASSERT_TRUE(h.ok()) << h.error();
    const Scene scene = standard_scene();
    for (const Camera& camera : {high_camera(), low_camera()}) {
        const char* name = camera.eye.y > 3 ? "high" : "low";
        const RenderOptions options{"cover,icicles", {}};
        const Image whole = h.render(scene, camera, options);
        const Image cover = h.render(scene, camera, {"cover", {}});
        std::vector<int> rows(kHeight), columns(kWidth);
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                if (differing(whole, cover, 6, x, y)) ++rows[y], ++columns[x];
        const int split_y = int(std::max_element(rows.begin() + 16, rows.end() - 16) - rows.begin());
        const int split_x = int(std::max_element(columns.begin() + 16, columns.end() - 16) - columns.begin());
        ASSERT_GE(rows[split_y], 10) << "no icicles to cut";
        ASSERT_GE(columns[split_x], 5) << "no icicles to cut";

        const long scene_only = differing(h.render(scene, camera, {}), quarters(h, scene, camera, {}, split_x, split_y), 2);
        const Image tiled = quarters(h, scene, camera, options, split_x, split_y);
        const long with_effects = differing(whole, tiled, 2);
        save(std::string("seams_") + name + "_tiled", tiled);
        std::printf("[ seams ] %s camera, 2x2 tiles split at x %d (%d icicle pixels in that column), y %d (%d in that "
                    "row) against the whole %dx%d canvas: scene alone %ld pixels differ by more than 2, with cover and "
                    "icicles %ld (%.4f%%)\n",
                    name, split_x, columns[split_x], split_y, rows[split_y], kWidth, kHeight, scene_only, with_effects,
                    100.0 * with_effects / (kWidth * kHeight));
        EXPECT_LE(with_effects, kWidth * kHeight / 1000);
    }
}

}  // namespace
}  // namespace winter_test
