// In-process harness of the snow cover and icicle tests: a headless EGL compatibility context
// (the slave's "egl" backend), a fixed-function scene drawn the way a 1990s GL program draws it
// (glBegin/glEnd, matrix stack, GL_LIGHT0), and a FrameView whose redraw() re-renders that
// scene as the replayer re-renders a frame's recorded calls: GL_PROJECTION loaded with
// correction * P_app, the camera and per-object transforms on GL_MODELVIEW.
//
// Surface classes: the scene can also be drawn with each face's class as its red value (no
// lighting), so the tests measure snow per class of surface.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/image.h"
#include "slave/backend.h"
#include "slave/effects/effect_params.h"
#include "slave/effects/frame_view.h"
#include "slave/effects/gl_api.h"

namespace winter_test {

using glcast::slave::Image;

enum SurfaceClass : uint8_t {
    kBackground = 0,
    kGround = 1,
    kTop = 2,     // box tops: horizontal, facing up
    kSide = 3,    // box sides: vertical
    kUnder = 4,   // box bottoms: horizontal, facing down
    kPanel = 5,   // kPanel + i: the i-th tilted panel
};

struct Box {
    glm::dvec3 center, size;
    double yaw_deg = 0;
    glm::dvec3 color{0.55, 0.16, 0.10};
};

// A flat rectangle on the ground, tilted about the world x axis by tilt_deg from horizontal,
// its raised edge away from +z (it faces the +z side, where the cameras stand).
struct Panel {
    glm::dvec3 center;
    double width = 2, depth = 2;
    double tilt_deg = 0;
    glm::dvec3 color{0.15, 0.20, 0.45};
};

// A second ground mesh laid over the ground, as a racing game's track over its terrain: a grid of
// quads of `cell` whose corners lie a seeded pseudo-random height within +-amplitude of the
// ground's plane, so that the two meshes cross and the visible one alternates in thin, irregular
// strips, many a pixel tall, along where they cross.
struct Track {
    double x0 = -4, x1 = 4, z0 = -12, z1 = 5;
    double cell = 1.0, amplitude = 0.05;
    glm::dvec3 color{0.40, 0.26, 0.12};
};

struct Scene {
    bool ground = true;
    std::vector<Track> tracks;  // class kGround
    glm::dvec3 ground_color{0.22, 0.36, 0.16};
    std::vector<Box> boxes;
    std::vector<Panel> panels;
    bool light = true;  // GL_LIGHT0 at light_world (FrameView::light known)
    glm::dvec4 light_world{5, 10, 4, 1};
};

struct Camera {
    glm::dvec3 eye{0, 6, 9}, target{0, 0.5, -1};
    double fov_y_deg = 45;
};

// The canvas's rectangle this tile shows (GL convention: origin bottom left).
struct Tile {
    int x = 0, y = 0, width = 0, height = 0;
};

// Ground, three boxes (one of them raised on nothing: its underside is visible from below).
Scene standard_scene();
Camera high_camera();  // above the boxes, looking down about 25 degrees
Camera low_camera();   // below the raised box, looking up at it

struct RenderOptions {
    std::string effects;                       // "cover", "icicles", "cover,icicles" or "" (none)
    std::vector<std::string> params;           // "name=value"
    uint64_t frame = 10;
    bool redraw = true;                        // false: FrameView::redraw empty (as for shader programs)
    bool redraw_ground = true;                 // false: the redraw leaves the visible ground out
    bool view_known = true;                    // false: FrameView says the frame has no perspective view
    // The program's camera looked this many degrees to the left of `camera` (about its up axis), and
    // this tile is turned to show `camera`'s view, as a cylinder's or a CAVE's side tile shows what
    // lies beside or behind the program's camera: the passes get the program's eye space.
    double program_turn_deg = 0;
};

class Harness {
public:
    // A canvas of canvas_width x canvas_height; fails the calling test (ASSERT) when no EGL.
    Harness(int canvas_width, int canvas_height);
    ~Harness();
    bool ok() const { return ok_; }
    const std::string& error() const { return error_; }

    // The scene on `tile` of the canvas, lit, then the effects. A tile of {} is the whole canvas.
    Image render(const Scene& scene, const Camera& camera, const RenderOptions& options, Tile tile = {});
    // The surface class of every pixel (red channel), same framing.
    Image classes(const Scene& scene, const Camera& camera, Tile tile = {});

    int canvas_width() const { return canvas_width_; }
    int canvas_height() const { return canvas_height_; }

private:
    struct FixedFunction;
    void make_current(int width, int height);
    void draw_scene(const Scene& scene, bool lit, bool class_colors);
    void load_matrices(const glm::dmat4& projection, const glm::dmat4& modelview);
    glcast::slave::effects::FrameView frame_view(const Scene& scene, const Camera& camera, Tile tile,
                                                 const RenderOptions& options);
    Image read_window(int width, int height);

    int canvas_width_, canvas_height_;
    int current_width_ = 0, current_height_ = 0;
    bool ok_ = false;
    std::string error_;
    std::unique_ptr<glcast::slave::Backend> backend_;
    glcast::slave::effects::GlApi gl_;
    std::unique_ptr<FixedFunction> ff_;
    // The window copies FrameView hands out (made lazily, once per render).
    unsigned color_copy_ = 0, depth_copy_ = 0, depth_copy_fb_ = 0;
    int copies_width_ = 0, copies_height_ = 0;
    bool color_copied_ = false, depth_copied_ = false;
};

// ---- measurements ------------------------------------------------------------------------

double luminance(const Image& image, int x, int y);  // 0..1, x/y in GL convention (bottom row 0)
uint8_t class_at(const Image& classes, int x, int y);
// True when the class of every pixel within `margin` of (x, y) is the same (away from edges).
bool interior(const Image& classes, int x, int y, int margin);

// Snow at a pixel: the pass turned it bright and light (what the cover's shading gives over
// the test scene's dark colours).
bool snowy(const Image& before, const Image& after, int x, int y);

struct Fraction {
    long snowy = 0, total = 0;
    double value() const { return total ? double(snowy) / double(total) : 0.0; }
};
// Snowy fraction of the interior pixels of each class (optionally only columns [x0, x1)).
std::map<int, Fraction> snow_by_class(const Image& before, const Image& after, const Image& classes,
                                      int x0 = 0, int x1 = 1 << 30);

// Writes `image` to $GLCAST_TEST_OUT (or the working directory)/name.png for a look.
void save(const std::string& name, const Image& image);

}  // namespace winter_test
