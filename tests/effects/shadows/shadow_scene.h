// Synthetic scenes for the soft-shadow tests and benchmark, drawn the way a fixed-function
// program draws (immediate mode, GL_PROJECTION / GL_MODELVIEW, GL_LIGHT0), in an EGL
// compatibility context of the slave's backend. A FrameView for them carries a redraw that
// does what the replayer's does: the same draws with clip = correction * P * V * M * vertex.
//
// Geometry: a ground quad at y = 0 and boxes (each the unit cube [-1, 1]^3 under a model
// matrix), so the tests can also answer "is this point shadowed by the light's centre?"
// exactly, by ray casting.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/image.h"
#include "slave/backend.h"
#include "slave/effects/frame_view.h"
#include "slave/effects/gl_api.h"

namespace shadow_test {

struct Scene {
    std::string name;
    std::vector<glm::dmat4> boxes;  // model matrices of the unit cube
    double ground_half = 12;        // ground quad [-half, half]^2
    glm::dvec3 eye{0, 6, 9}, target{0, 0.5, 0};
    double fov_y_deg = 45, near = 0.5, far = 100;
    glm::dvec4 light{2, 7, 1, 1};   // world GL_POSITION (w = 0: direction towards the light)
    double light_size = 0.8;        // positional: disk diameter (world units)
    double light_angle_deg = 3;     // directional: angular diameter

    glm::dmat4 view() const;
    glm::dmat4 projection(double aspect) const;
    // Whether the segment from `p` to the light's centre (or the ray towards it) hits a box.
    bool occluded(const glm::dvec3& p) const;
};

glm::dmat4 box(const glm::dvec3& center, const glm::dvec3& half, double yaw_deg = 0, double roll_deg = 0);

Scene blocks_scene();  // a cube on the ground, a pillar, a plate and a cube floating: positional light
Scene fence_scene();   // a pergola of thin slats on four posts: fine structure, directional light
Scene ramp_scene();    // a plank resting on the ground at one end, columns, a floating block
Scene plates_scene();  // four plates at heights 0.08, 0.5, 1.0, 1.8 under a light straight above

// A rectangle of the canvas the program's window is stretched over (canvas pixels, GL origin
// bottom left); the whole canvas when x = y = 0 and the sizes are equal.
struct Tile {
    int x = 0, y = 0, width = 0, height = 0;
    int canvas_width = 0, canvas_height = 0;
};

// The compatibility-profile calls the scenes need, beside GlApi's.
#define SHADOW_TEST_COMPAT_GL(X)                                                                        \
    X(glBegin) X(glEnd) X(glVertex3d) X(glNormal3d) X(glColor3f) X(glLightfv) X(glLightModelfv)           \
    X(glColorMaterial) X(glShadeModel) X(glMultMatrixd)

struct CompatGl {
#define SHADOW_TEST_MEMBER(name) decltype(&::name) name = nullptr;
    SHADOW_TEST_COMPAT_GL(SHADOW_TEST_MEMBER)
#undef SHADOW_TEST_MEMBER
};

// An EGL context with a window framebuffer of the tile's size, the scene's frame drawn into it.
class SceneContext {
public:
    // Throws std::runtime_error when EGL or a GL function is missing.
    SceneContext();
    ~SceneContext();
    const glcast::slave::effects::GlApi& gl() const { return gl_; }

    // Resizes the window framebuffer to the tile and draws the scene's frame into it (the
    // "program's" image, lit by GL_LIGHT0 at the scene's light).
    void draw_frame(const Scene& scene, const Tile& tile);
    // The FrameView of that frame, as the replayer would fill it (light known, redraw set).
    glcast::slave::effects::FrameView frame_view(const Scene& scene, const Tile& tile);
    // The window framebuffer now: RGBA, rows top down; and its depth, rows bottom up.
    glcast::slave::Image read_color(const Tile& tile) const;
    std::vector<float> read_depth(const Tile& tile) const;

private:
    void draw_geometry(const Scene& scene) const;
    glm::dmat4 tile_from_canvas_clip(const Tile& tile) const;

    std::unique_ptr<glcast::slave::Backend> backend_;
    glcast::slave::effects::GlApi gl_;
    CompatGl compat_;
    GLuint window_depth_copy_ = 0, window_depth_fb_ = 0;
    int copy_width_ = 0, copy_height_ = 0;
};

// Root-mean-square difference of two visibility images (tile pixels): over all pixels, and over
// the pixels within `margin` pixels of a place where `reference` is below 0.999 (the shadows).
struct VisibilityError {
    double all = 0, shadows = 0;
    size_t shadow_pixels = 0;
};
VisibilityError visibility_error(const std::vector<float>& method, const std::vector<float>& reference, int width,
                                 int height, int margin = 8);

// Tile pixel (fractional, GL origin) of a world point.
glm::dvec2 project_to_tile(const Scene& scene, const Tile& tile, const glm::dvec3& world);

}  // namespace shadow_test
