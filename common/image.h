// RGBA8 images for the slave and its tests: PNG files (libpng), pixel comparison, and the
// mosaic of a wall's tiles.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace glcast::slave {

// Rows top to bottom, 4 bytes per pixel (R, G, B, A); rgba.size() == width * height * 4.
struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;
};

// Writes an 8-bit RGBA PNG. False with `error` set (naming the file) on any failure.
bool write_png(const std::string& path, const Image& image, std::string& error);

// Reads an 8-bit gray, gray+alpha, RGB or RGBA PNG (interlaced or not) and converts it to RGBA
// (alpha 255 where the file has none, or from a tRNS chunk). Palette and 1/2/4/16-bit files are
// refused with an error saying so; corrupt or truncated files give an error, never a crash.
// A file is opened only when it is a regular file, without blocking (a FIFO is refused). An
// image of more than `max_pixels` is refused from its header, before its pixels are held.
bool read_png(const std::string& path, Image& image, std::string& error, int64_t max_pixels = int64_t(1) << 28);
// The same from bytes in memory (an entry of an archive); `name` names them in messages.
bool read_png_bytes(const std::string& bytes, const std::string& name, Image& image, std::string& error,
                    int64_t max_pixels = int64_t(1) << 28);

// Each factor x factor block's mean, rounded (a partial block at the right or bottom edge is
// dropped): a thumbnail, or a picture compared at a coarser resolution. factor 1: a copy.
Image scaled_down(const Image& in, int factor);

struct ImageDiff {
    int64_t differing_pixels = 0;  // pixels where any channel differs
    int max_channel_diff = 0;      // largest |a - b| over all channels of all pixels
    bool size_mismatch = false;    // then differing_pixels is the larger pixel count and
                                   // max_channel_diff 255, so "== 0" checks still fail
};
ImageDiff compare(const Image& a, const Image& b);

// The integer shift (dx, dy), |dx|, |dy| <= radius, x right and y down, that best carries the
// rectangle (x, y, w, h) of `a` onto `b` (least squares over grey levels): the motion of the
// content between two frames. The rectangle moved by any shift must lie inside `b`.
struct Shift {
    int dx = 0, dy = 0;
};
Shift estimate_shift(const Image& a, const Image& b, int x, int y, int w, int h, int radius);
// |a - a0| per channel: what a pass added to a frame, given the frame without it.
Image difference(const Image& a, const Image& a0);

// Tiles in a grid: rows[r][c] is the tile at row r (top first), column c (left first). Column c
// is as wide as its widest tile, row r as tall as its tallest; a tile sits at its cell's
// top-left corner, and uncovered pixels (nullptr tiles, smaller tiles, short rows) are opaque
// black.
Image mosaic(const std::vector<std::vector<const Image*>>& rows);

// The same image upside down: glReadPixels returns rows bottom to top.
Image flip_rows(const Image& image);

}  // namespace glcast::slave
