// Projectors of known pose and lens on a known surface (glcast calibrate, docs/projectors.md):
// what a camera-based calibration system would measure, computed. The wall's canvas is the
// surface unrolled (a cylinder section by azimuth and height, a dome as a dome master: the
// azimuthal equidistant fisheye, a plane as itself); each projector's tile is the canvas
// rectangle its light covers, its warp says where each output pixel's light lands on the canvas,
// its blend fades it where other projectors also reach. Pure arithmetic, for tests.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

#include "display_configs/projector_maps.h"

namespace glcast::slave {

struct Surface {
    enum Kind { cylinder, dome, plane } kind = cylinder;
    double radius = 5;                      // cylinder, dome (metres; the viewer at the centre)
    double azimuth_from = -60, azimuth_to = 60;  // cylinder: degrees, 0 ahead (-z), positive right
    double height_from = -1.5, height_to = 1.5;  // cylinder: metres
    double distance = 3;                    // plane: at z = -distance
    double x_from = -2, x_to = 2, y_from = -1, y_to = 1;  // plane: its extent, metres
    // The canvas position (s right, t down, 0..1) of a surface point; nullopt off the section
    // (with `beyond`, positions past its edges too: a warp node just off the section then
    // samples outside the tile, black per pixel rather than for the node's whole cell).
    std::optional<glm::dvec2> unroll(const glm::dvec3& p, bool beyond = false) const;
    // The surface point of a canvas position; nullopt where the canvas shows no surface (a
    // dome master's corners).
    std::optional<glm::dvec3> roll(const glm::dvec2& st) const;
    // Where a ray from `origin` along `dir` meets the surface first (inside it, going out).
    std::optional<glm::dvec3> hit(const glm::dvec3& origin, const glm::dvec3& dir) const;
    double aspect() const;  // of the canvas: width / height
};

struct Projector {
    std::string name;
    glm::dvec3 position{0.0};
    double yaw = 0, pitch = 0, roll = 0;                  // degrees, as a view tile's
    double left = -20, right = 20, down = -12, up = 12;  // frustum edges, degrees
    // The direction of its light at output position (x right, y down, 0..1 over the output).
    glm::dvec3 ray(double x, double y) const;
    // The output position (0..1) whose light lands on `p`; nullopt behind it or outside its frustum.
    std::optional<glm::dvec2> project(const glm::dvec3& p) const;
};

struct CanvasRect {
    int x = 0, y = 0, width = 0, height = 0;  // canvas pixels, top left origin
};

// The canvas rectangle a projector's light covers on the section (its tile); width 0: none.
CanvasRect footprint(const Surface& s, const Projector& p, int canvas_width, int canvas_height);
// Its warp: nodes of `nodes_x` x `nodes_y` over its output, positions in its tile's image.
WarpMap projector_warp(const Surface& s, const Projector& p, const CanvasRect& tile, int canvas_width, int canvas_height,
                       int nodes_x, int nodes_y);
// MPCDI's 3D simulation profile: the image generator renders, for each projector, the view from
// the viewer's eye (the room's origin) through a frustum that holds every surface point the
// projector lights; the warp says which of those points each output node lights.
struct EyeFrustum {
    double yaw = 0, pitch = 0;                 // degrees, as a view tile's (roll 0)
    double left = 0, right = 0, down = 0, up = 0;  // edges, degrees from its axis
};
// Nullopt when the projector lights nothing, or something at 80 degrees or more from its centre.
std::optional<EyeFrustum> eye_frustum(const Surface& s, const Projector& p);
// Per node of `nodes_x` x `nodes_y` over its output (rows top to bottom), the surface point it
// lights (x, y, z in metres relative to the eye), NaN where its light misses the surface.
std::vector<float> projector_points(const Surface& s, const Projector& p, int nodes_x, int nodes_y);
// Its blend at `width` x `height`: each point's share among the projectors that reach it,
// weighted by the square of its distance to each one's image edge (they sum to 1).
BlendMap projector_blend(const Surface& s, const std::vector<Projector>& all, size_t index, int width, int height);

}  // namespace glcast::slave
