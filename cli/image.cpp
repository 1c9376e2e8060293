#include "cli/commands.h"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "slave/image.h"

namespace glcast::slave {

const char* kImageUsage =
    "  image mosaic COLSxROWS OUT.png TILE.png...   tiles (row by row, from the top left) side by side\n"
    "  image compare A.png B.png [--crop X,Y,W,H]     differing pixels and the largest channel difference;\n"
    "        exit 1 if they differ (--crop compares a rectangle of A, from the top left, with all of B)\n"
    "  image pixel IMAGE.png X,Y                     the colour at X,Y (from the top left)\n"
    "  image motion A.png B.png [--crop X,Y,W,H] [--radius R] [--without A0.png B0.png]\n"
    "        the shift DX DY (x right, y down) that best carries A (or its rectangle) onto B;\n"
    "        --without first subtracts the frames without an overlay, to measure the overlay's motion\n";

static int fail(const std::string& msg) {
    std::fprintf(stderr, "glcast image: %s\n", msg.c_str());
    return 2;
}

static Image crop(const Image& src, int x, int y, int w, int h) {
    Image out{w, h, std::vector<uint8_t>(size_t(w) * h * 4)};
    for (int row = 0; row < h; ++row)
        std::memcpy(out.rgba.data() + size_t(row) * w * 4, src.rgba.data() + (size_t(y + row) * src.width + x) * 4,
                    size_t(w) * 4);
    return out;
}

int image_main(const std::vector<std::string>& args) {
    std::string error;
    if (args.size() >= 3 && args[0] == "mosaic") {
        int cols = 0, rows = 0;
        if (std::sscanf(args[1].c_str(), "%dx%d", &cols, &rows) != 2 || cols <= 0 || rows <= 0 || cols > 64 || rows > 64)
            return fail("mosaic takes COLSxROWS, got '" + args[1] + "'");
        if (args.size() != size_t(3 + cols * rows))
            return fail("mosaic " + args[1] + " needs " + std::to_string(cols * rows) + " tiles");
        std::vector<Image> tiles(size_t(cols * rows));
        for (size_t i = 0; i < tiles.size(); ++i)
            if (!read_png(args[3 + i], tiles[i], error)) return fail(error);
        std::vector<std::vector<const Image*>> grid(static_cast<size_t>(rows));
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < cols; ++c) grid[size_t(r)].push_back(&tiles[size_t(r * cols + c)]);
        if (!write_png(args[2], mosaic(grid), error)) return fail(error);
        return 0;
    }
    if (args.size() >= 3 && args[0] == "compare") {
        Image a, b;
        if (!read_png(args[1], a, error) || !read_png(args[2], b, error)) return fail(error);
        if (args.size() == 5 && args[3] == "--crop") {
            int x, y, w, h;
            if (std::sscanf(args[4].c_str(), "%d,%d,%d,%d", &x, &y, &w, &h) != 4 || x < 0 || y < 0 || w <= 0 || h <= 0 ||
                x + w > a.width || y + h > a.height)
                return fail("--crop must lie inside " + args[1]);
            a = crop(a, x, y, w, h);
        } else if (args.size() != 3) {
            return fail("compare takes two images and an optional --crop X,Y,W,H");
        }
        const ImageDiff d = compare(a, b);
        if (d.size_mismatch) {
            std::printf("sizes differ: %dx%d and %dx%d\n", a.width, a.height, b.width, b.height);
            return 1;
        }
        std::printf("%" PRId64 " pixels differ, max channel difference %d\n", d.differing_pixels, d.max_channel_diff);
        return d.differing_pixels ? 1 : 0;
    }
    if (args.size() == 3 && args[0] == "pixel") {
        Image a;
        int x, y;
        if (!read_png(args[1], a, error)) return fail(error);
        if (std::sscanf(args[2].c_str(), "%d,%d", &x, &y) != 2 || x < 0 || y < 0 || x >= a.width || y >= a.height)
            return fail("pixel takes X,Y inside the image, got '" + args[2] + "'");
        const uint8_t* p = &a.rgba[(size_t(y) * a.width + x) * 4];
        std::printf("%d %d %d\n", p[0], p[1], p[2]);
        return 0;
    }
    if (args.size() >= 3 && args[0] == "motion") {
        Image a, b;
        if (!read_png(args[1], a, error) || !read_png(args[2], b, error)) return fail(error);
        if (a.width != b.width || a.height != b.height) return fail("motion needs images of one size");
        int x = 0, y = 0, w = a.width, h = a.height, radius = 8;
        for (size_t i = 3; i < args.size(); ++i) {
            if (args[i] == "--crop" && i + 1 < args.size()) {
                if (std::sscanf(args[++i].c_str(), "%d,%d,%d,%d", &x, &y, &w, &h) != 4)
                    return fail("--crop takes X,Y,W,H, got '" + args[i] + "'");
            } else if (args[i] == "--radius" && i + 1 < args.size()) {
                radius = std::atoi(args[++i].c_str());
                if (radius < 1 || radius > 64) return fail("--radius takes 1..64");
            } else if (args[i] == "--without" && i + 2 < args.size()) {
                Image a0, b0;
                if (!read_png(args[i + 1], a0, error) || !read_png(args[i + 2], b0, error)) return fail(error);
                if (a0.width != a.width || a0.height != a.height || b0.width != a.width || b0.height != a.height)
                    return fail("--without needs images of the same size");
                a = difference(a, a0), b = difference(b, b0);
                i += 2;
            } else {
                return fail("motion: unknown argument '" + args[i] + "'");
            }
        }
        if (x - radius < 0 || y - radius < 0 || w <= 0 || h <= 0 || x + w + radius > a.width || y + h + radius > a.height)
            return fail("motion: the rectangle moved by the radius must lie inside the images");
        const Shift s = estimate_shift(a, b, x, y, w, h, radius);
        std::printf("%d %d\n", s.dx, s.dy);
        return 0;
    }
    return fail("usage:\n" + std::string(kImageUsage));
}

}  // namespace glcast::slave
