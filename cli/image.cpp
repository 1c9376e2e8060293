// `glcast image mosaic|compare|pixel|motion`: look at tiles together, compare frames, read a
// pixel, measure motion. Every failure but "the images differ" exits 2, as it always has.
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "common/image.h"

namespace glcast::cli {

using namespace glcast::slave;

namespace {

struct ImageArgs {
    CLI::App *mosaic = nullptr, *compare = nullptr, *pixel = nullptr, *motion = nullptr;
    std::string grid, out, a, b, point;
    std::vector<std::string> tiles, without;
    std::vector<int> crop;
    int radius = 8;
};

int fail(const std::string& msg) {
    std::fprintf(stderr, "glcast image: %s\n", msg.c_str());
    return 2;
}

Image crop(const Image& src, int x, int y, int w, int h) {
    Image out{w, h, std::vector<uint8_t>(size_t(w) * h * 4)};
    for (int row = 0; row < h; ++row)
        std::memcpy(out.rgba.data() + size_t(row) * w * 4, src.rgba.data() + (size_t(y + row) * src.width + x) * 4,
                    size_t(w) * 4);
    return out;
}

int mosaic(const ImageArgs& a) {
    int cols = 0, rows = 0;
    std::string error;
    if (!parse_size(a.grid, 64, cols, rows, error)) usage_error("COLSxROWS", error);
    if (a.tiles.size() != size_t(cols * rows))
        usage_error("mosaic " + a.grid, "needs " + std::to_string(cols * rows) + " tiles, got " +
                                            std::to_string(a.tiles.size()));
    std::vector<Image> tiles(size_t(cols * rows));
    for (size_t i = 0; i < tiles.size(); ++i)
        if (!read_png(a.tiles[i], tiles[i], error)) return fail(error);
    std::vector<std::vector<const Image*>> grid(static_cast<size_t>(rows));
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) grid[size_t(r)].push_back(&tiles[size_t(r * cols + c)]);
    if (!write_png(a.out, slave::mosaic(grid), error)) return fail(error);
    return 0;
}

int compare_images(const ImageArgs& args) {
    Image a, b;
    std::string error;
    if (!read_png(args.a, a, error) || !read_png(args.b, b, error)) return fail(error);
    if (!args.crop.empty()) {
        const int x = args.crop[0], y = args.crop[1], w = args.crop[2], h = args.crop[3];
        if (w <= 0 || h <= 0 || x + w > a.width || y + h > a.height) return fail("--crop must lie inside " + args.a);
        a = crop(a, x, y, w, h);
    }
    const ImageDiff d = compare(a, b);
    if (d.size_mismatch) {
        std::printf("sizes differ: %dx%d and %dx%d\n", a.width, a.height, b.width, b.height);
        return 1;
    }
    std::printf("%" PRId64 " pixels differ, max channel difference %d\n", d.differing_pixels, d.max_channel_diff);
    return d.differing_pixels ? 1 : 0;
}

int pixel(const ImageArgs& args) {
    Image a;
    std::string error;
    std::vector<int> xy;
    if (!parse_ints(args.point, 2, 0, 65535, "X,Y", xy, error)) usage_error("POINT", error);
    if (!read_png(args.a, a, error)) return fail(error);
    const int x = xy[0], y = xy[1];
    if (x >= a.width || y >= a.height) return fail("pixel takes X,Y inside the image, got '" + args.point + "'");
    const uint8_t* p = &a.rgba[(size_t(y) * a.width + x) * 4];
    std::printf("%d %d %d\n", p[0], p[1], p[2]);
    return 0;
}

int motion(const ImageArgs& args) {
    Image a, b;
    std::string error;
    if (!read_png(args.a, a, error) || !read_png(args.b, b, error)) return fail(error);
    if (a.width != b.width || a.height != b.height) return fail("motion needs images of one size");
    int x = 0, y = 0, w = a.width, h = a.height;
    if (!args.crop.empty()) x = args.crop[0], y = args.crop[1], w = args.crop[2], h = args.crop[3];
    if (!args.without.empty()) {
        Image a0, b0;
        if (!read_png(args.without[0], a0, error) || !read_png(args.without[1], b0, error)) return fail(error);
        if (a0.width != a.width || a0.height != a.height || b0.width != a.width || b0.height != a.height)
            return fail("--without needs images of the same size");
        a = difference(a, a0), b = difference(b, b0);
    }
    const int radius = args.radius;
    if (x - radius < 0 || y - radius < 0 || w <= 0 || h <= 0 || x + w + radius > a.width || y + h + radius > a.height)
        return fail("motion: the rectangle moved by the radius must lie inside the images");
    const Shift s = estimate_shift(a, b, x, y, w, h, radius);
    std::printf("%d %d\n", s.dx, s.dy);
    return 0;
}

int image(const ImageArgs& a) {
    if (a.mosaic->parsed()) return mosaic(a);
    if (a.compare->parsed()) return compare_images(a);
    if (a.pixel->parsed()) return pixel(a);
    if (a.motion->parsed()) return motion(a);
    throw CLI::ValidationError(std::string("which of mosaic, compare, pixel, motion? (glcast image --help)"));
}

}  // namespace

Command add_image(CLI::App& glcast) {
    auto a = std::make_shared<ImageArgs>();
    CLI::App* app = glcast.add_subcommand("image", "PNG tools: mosaic, compare, pixel, motion (glcast image CMD --help)");
    app->require_subcommand(0, 1);  // none: a usage error of our own, naming the four

    a->mosaic = app->add_subcommand("mosaic", "tiles side by side, row by row from the top left, into one PNG");
    a->mosaic->add_option("COLSxROWS", a->grid, "the grid, e.g. 2x2 (1..64 each)")->required();
    a->mosaic->add_option("OUT", a->out, "the PNG to write")->required();
    a->mosaic->add_option("TILES", a->tiles, "COLS*ROWS PNGs, row by row")->required();

    a->compare = app->add_subcommand(
        "compare", "differing pixels and the largest channel difference; exit 1 if any differ");
    a->compare->add_option("A", a->a, "a PNG")->required();
    a->compare->add_option("B", a->b, "another PNG")->required();
    add_ints(*a->compare, "--crop", 4, 0, 65536, "X,Y,W,H", a->crop,
             "compare this rectangle of A (from the top left) with all of B");

    a->pixel = app->add_subcommand("pixel", "the colour (R G B) of one pixel");
    a->pixel->add_option("IMAGE", a->a, "a PNG")->required();
    a->pixel->add_option("POINT", a->point, "the pixel X,Y, from the top left")->required()->type_name("X,Y");

    a->motion = app->add_subcommand("motion", "the shift DX DY (x right, y down) that best carries A onto B");
    a->motion->add_option("A", a->a, "a PNG")->required();
    a->motion->add_option("B", a->b, "the PNG it moved into")->required();
    add_ints(*a->motion, "--crop", 4, -65536, 65536, "X,Y,W,H", a->crop, "only this rectangle of A (from the top left)");
    add_int(*a->motion, "--radius", a->radius, 1, 64, "the largest shift searched, in pixels (default 8)");
    a->motion->add_option("--without", a->without,
                          "first subtract the frames without an overlay (A0 from A, B0 from B),\n"
                          "to measure the overlay's motion")
        ->expected(2)
        ->type_name("PNG");
    return {app, [a](const std::vector<std::string>&) { return image(*a); }};
}

}  // namespace glcast::cli
