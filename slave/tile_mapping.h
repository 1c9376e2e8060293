// Planar tile adaptation (docs/slave.md): the master's window is stretched over the canvas, and
// a tile shows one rectangle of it. Window coordinates of the program (viewport, scissor box,
// window raster positions, blit rectangles) are mapped into the tile's framebuffer, and
// pixel-sized state (line width, point size, pixel zoom) scales with the canvas. This needs
// no knowledge of the program's projection and applies only while the window framebuffer is
// bound; rendering into the program's own framebuffer objects is untouched.
#pragma once

#include <cmath>
#include <cstdint>

namespace glcast::slave {

struct TileMapping {
    bool enabled = false;
    int canvas_width = 0, canvas_height = 0;
    int x = 0, y = 0, width = 0, height = 0;   // the tile on the canvas, GL convention: origin bottom-left
    // Where canvas-indexed effects (slave/effects) place the tile: the tile's rectangle on the
    // canvas for planar tiles; a rotated tile's rectangle in the display config (its x, y, w, h
    // above describe its own window instead).
    int place_x = 0, place_y = 0, place_canvas_width = 0, place_canvas_height = 0;

    // For a master window of window_width x window_height:
    double sx(int window_width) const { return window_width > 0 ? double(canvas_width) / window_width : 1; }
    double sy(int window_height) const { return window_height > 0 ? double(canvas_height) / window_height : 1; }
    // A window x (or y) coordinate in the tile's framebuffer.
    int64_t map_x(double wx, int window_width) const { return std::llround(wx * sx(window_width)) - x; }
    int64_t map_y(double wy, int window_height) const { return std::llround(wy * sy(window_height)) - y; }
    // A window extent (width, height), scaled the same way as the coordinates it spans.
    int64_t map_w(double wx, double ww, int window_width) const {
        return std::llround((wx + ww) * sx(window_width)) - std::llround(wx * sx(window_width));
    }
    int64_t map_h(double wy, double wh, int window_height) const {
        return std::llround((wy + wh) * sy(window_height)) - std::llround(wy * sy(window_height));
    }
};

}  // namespace glcast::slave
