#include "tests/effects/shadows/shadow_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "slave/effects/gl_util.h"

namespace shadow_test {

using glcast::slave::Image;
using glcast::slave::effects::FrameView;

glm::dmat4 Scene::view() const { return glm::lookAt(eye, target, glm::dvec3(0, 1, 0)); }

glm::dmat4 Scene::projection(double aspect) const {
    return glm::perspective(glm::radians(fov_y_deg), aspect, near, far);
}

bool Scene::occluded(const glm::dvec3& p) const {
    const bool directional = light.w == 0;
    const glm::dvec3 towards = directional ? glm::dvec3(light) : glm::dvec3(light) / light.w - p;
    const double t_end = directional ? std::numeric_limits<double>::max() : 1.0;
    for (const glm::dmat4& model : boxes) {
        const glm::dmat4 inv = glm::inverse(model);
        const glm::dvec3 o = glm::dvec3(inv * glm::dvec4(p, 1.0));
        const glm::dvec3 d = glm::dvec3(inv * glm::dvec4(towards, 0.0));
        double t0 = 1e-9, t1 = t_end;
        for (int axis = 0; axis < 3 && t0 <= t1; ++axis) {
            if (std::abs(d[axis]) < 1e-15) {
                if (o[axis] < -1 || o[axis] > 1) t0 = 2, t1 = 1;
                continue;
            }
            double a = (-1 - o[axis]) / d[axis], b = (1 - o[axis]) / d[axis];
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
        }
        if (t0 <= t1) return true;
    }
    return false;
}

glm::dmat4 box(const glm::dvec3& center, const glm::dvec3& half, double yaw_deg, double roll_deg) {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), center);
    m = glm::rotate(m, glm::radians(yaw_deg), glm::dvec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(roll_deg), glm::dvec3(0, 0, 1));
    return glm::scale(m, half);
}

Scene blocks_scene() {
    Scene s;
    s.name = "blocks";
    s.boxes = {box({-2.0, 0.6, 0.2}, {0.6, 0.6, 0.6}, 20),   // standing on the ground
               box({-0.5, 1.0, -2.0}, {0.25, 1.0, 0.25}),     // pillar
               box({0.6, 1.0, 0.6}, {0.7, 0.05, 0.5}, -10),   // plate at 1.0
               box({2.2, 2.2, -0.8}, {0.4, 0.4, 0.4}, 35)};   // cube at 2.2
    s.light = {2.0, 7.0, 1.5, 1.0};
    s.light_size = 0.8;
    return s;
}

Scene fence_scene() {
    Scene s;
    s.name = "fence";
    s.eye = {0.5, 5.0, 7.5};
    s.target = {0.0, 0.4, 0.0};
    for (double x : {-1.5, 1.5})
        for (double z : {-1.0, 1.0}) s.boxes.push_back(box({x, 0.75, z}, {0.06, 0.75, 0.06}));
    for (int i = 0; i < 11; ++i) s.boxes.push_back(box({0.0, 1.53, -1.1 + 0.22 * i}, {1.65, 0.03, 0.04}));
    for (double x : {-1.4, 1.4}) s.boxes.push_back(box({x, 1.47, 0.0}, {0.05, 0.03, 1.2}));
    s.light = glm::dvec4(glm::normalize(glm::dvec3(0.35, 1.0, 0.45)), 0.0);
    s.light_angle_deg = 3.0;
    return s;
}

Scene ramp_scene() {
    Scene s;
    s.name = "ramp";
    s.eye = {3.0, 4.5, 7.0};
    s.target = {0.0, 0.4, 0.0};
    const double rise = 1.6, run = 4.0;
    const double roll = glm::degrees(std::atan2(rise, run)), half_length = 0.5 * std::hypot(rise, run);
    // The plank's lower end touches the ground at x = -2 (its bottom edge at y = 0 there).
    s.boxes = {box({0.0, 0.5 * rise + 0.04, 0.0}, {half_length, 0.04, 0.5}, 0, roll),
               box({1.8, 0.5, -1.6}, {0.2, 0.5, 0.2}), box({-1.0, 0.7, -1.8}, {0.15, 0.7, 0.15}),
               box({-2.2, 1.8, -0.6}, {0.3, 0.3, 0.3}, 25)};
    s.light = {-1.0, 6.0, 2.0, 1.0};
    s.light_size = 1.0;
    return s;
}

Scene plates_scene() {
    Scene s;
    s.name = "plates";
    s.eye = {0.0, 8.0, 1.5};
    s.target = {0.0, 0.0, 0.0};
    s.boxes = {box({-2.4, 0.5, 0.0}, {0.45, 0.02, 0.6}), box({-0.8, 1.0, 0.0}, {0.45, 0.02, 0.6}),
               box({0.8, 1.8, 0.0}, {0.45, 0.02, 0.6}), box({2.8, 0.08, 0.0}, {0.45, 0.02, 0.6})};
    s.light = {0.0, 5.0, 0.0, 1.0};
    s.light_size = 1.0;
    return s;
}

SceneContext::SceneContext() {
    std::string error;
    backend_ = glcast::slave::make_backend("egl", error);
    if (!backend_) throw std::runtime_error("egl backend: " + error);
    if (!backend_->create_context(1, 0, {}, error) || !backend_->make_current(1, 64, 64, error))
        throw std::runtime_error("egl context: " + error);
    auto resolve = [this](const char* name) { return backend_->proc_address(name); };
    if (!gl_.load(resolve, error)) throw std::runtime_error(error);
    if (!gl_.has(glcast::OP_glMatrixMode) || !gl_.has(glcast::OP_glLoadMatrixd)) throw std::runtime_error("no compatibility profile");
#define SHADOW_TEST_LOAD(name)                                                          \
    compat_.name = reinterpret_cast<decltype(compat_.name)>(backend_->proc_address(#name)); \
    if (!compat_.name) throw std::runtime_error("missing " #name);
    SHADOW_TEST_COMPAT_GL(SHADOW_TEST_LOAD)
#undef SHADOW_TEST_LOAD
}

SceneContext::~SceneContext() {
    if (window_depth_copy_) gl_.glDeleteTextures(1, &window_depth_copy_);
    if (window_depth_fb_) gl_.glDeleteFramebuffers(1, &window_depth_fb_);
}

glm::dmat4 SceneContext::tile_from_canvas_clip(const Tile& t) const {
    glm::dmat4 m(1.0);
    m[0][0] = double(t.canvas_width) / t.width;
    m[3][0] = double(t.canvas_width - 2 * t.x) / t.width - 1;
    m[1][1] = double(t.canvas_height) / t.height;
    m[3][1] = double(t.canvas_height - 2 * t.y) / t.height - 1;
    return m;
}

VisibilityError visibility_error(const std::vector<float>& method, const std::vector<float>& reference, int width,
                                 int height, int margin) {
    // The shadow mask, dilated by a separable max over `margin` pixels.
    std::vector<uint8_t> mask(reference.size()), wide(reference.size());
    for (size_t i = 0; i < reference.size(); ++i) mask[i] = reference[i] < 0.999f;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            uint8_t m = 0;
            for (int k = std::max(0, x - margin); k <= std::min(width - 1, x + margin) && !m; ++k) m = mask[size_t(y) * width + k];
            wide[size_t(y) * width + x] = m;
        }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            uint8_t m = 0;
            for (int k = std::max(0, y - margin); k <= std::min(height - 1, y + margin) && !m; ++k) m = wide[size_t(k) * width + x];
            mask[size_t(y) * width + x] = m;
        }
    VisibilityError e;
    double all = 0, shadows = 0;
    for (size_t i = 0; i < reference.size(); ++i) {
        const double d = double(method[i]) - reference[i];
        all += d * d;
        if (mask[i]) shadows += d * d, ++e.shadow_pixels;
    }
    e.all = std::sqrt(all / std::max<size_t>(reference.size(), 1));
    e.shadows = std::sqrt(shadows / std::max<size_t>(e.shadow_pixels, 1));
    return e;
}

glm::dvec2 project_to_tile(const Scene& scene, const Tile& t, const glm::dvec3& world) {
    const glm::dvec4 c = scene.projection(double(t.canvas_width) / t.canvas_height) * scene.view() * glm::dvec4(world, 1.0);
    const glm::dvec2 ndc = glm::dvec2(c) / c.w;
    return (ndc * 0.5 + 0.5) * glm::dvec2(t.canvas_width, t.canvas_height) - glm::dvec2(t.x, t.y);
}

void SceneContext::draw_geometry(const Scene& scene) const {
    const CompatGl& c = compat_;
    // Ground: 1 x 1 quads, so per-vertex lighting varies over it.
    c.glColor3f(0.8f, 0.8f, 0.75f);
    c.glBegin(GL_QUADS);
    const int n = int(2 * scene.ground_half);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = -scene.ground_half + i, z = -scene.ground_half + j;
            c.glNormal3d(0, 1, 0);
            c.glVertex3d(x, 0, z + 1);
            c.glVertex3d(x + 1, 0, z + 1);
            c.glVertex3d(x + 1, 0, z);
            c.glVertex3d(x, 0, z);
        }
    c.glEnd();
    static const double kFaces[6][3][3] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
        {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
    };
    static const double kCorner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    c.glColor3f(0.85f, 0.45f, 0.25f);
    for (const glm::dmat4& model : scene.boxes) {
        gl_.glPushMatrix();
        c.glMultMatrixd(&model[0][0]);
        c.glBegin(GL_QUADS);
        for (const auto& f : kFaces) {
            c.glNormal3d(f[0][0], f[0][1], f[0][2]);
            for (const auto& k : kCorner)
                c.glVertex3d(f[0][0] + k[0] * f[1][0] + k[1] * f[2][0], f[0][1] + k[0] * f[1][1] + k[1] * f[2][1],
                             f[0][2] + k[0] * f[1][2] + k[1] * f[2][2]);
        }
        c.glEnd();
        gl_.glPopMatrix();
    }
}

void SceneContext::draw_frame(const Scene& scene, const Tile& tile) {
    std::string error;
    if (!backend_->make_current(1, tile.width, tile.height, error)) throw std::runtime_error(error);
    const auto& gl = gl_;
    gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.glViewport(0, 0, tile.width, tile.height);
    gl.glClearColor(0.55f, 0.72f, 0.92f, 1.0f);
    gl.glClearDepth(1.0);
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_LESS);
    gl.glDepthMask(GL_TRUE);
    gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.glEnable(GL_LIGHTING);
    gl.glEnable(GL_LIGHT0);
    gl.glEnable(GL_NORMALIZE);
    gl.glEnable(GL_COLOR_MATERIAL);
    compat_.glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    compat_.glShadeModel(GL_SMOOTH);
    const GLfloat ambient[4] = {0.35f, 0.35f, 0.38f, 1.0f};
    compat_.glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
    gl.glMatrixMode(GL_PROJECTION);
    const glm::dmat4 p = tile_from_canvas_clip(tile) * scene.projection(double(tile.canvas_width) / tile.canvas_height);
    gl.glLoadMatrixd(&p[0][0]);
    gl.glMatrixMode(GL_MODELVIEW);
    const glm::dmat4 v = scene.view();
    gl.glLoadMatrixd(&v[0][0]);
    const GLfloat light[4] = {float(scene.light.x), float(scene.light.y), float(scene.light.z), float(scene.light.w)};
    compat_.glLightfv(GL_LIGHT0, GL_POSITION, light);
    draw_geometry(scene);
    gl.glFinish();
}

FrameView SceneContext::frame_view(const Scene& scene, const Tile& tile) {
    FrameView v;
    v.width = tile.width;
    v.height = tile.height;
    v.canvas_x = tile.x;
    v.canvas_y = tile.y;
    v.canvas_width = tile.canvas_width;
    v.canvas_height = tile.canvas_height;
    v.view_known = true;
    v.projection = scene.projection(double(tile.canvas_width) / tile.canvas_height);
    v.modelview = scene.view();
    v.tile_clip_from_app_clip = tile_from_canvas_clip(tile);
    v.tile_clip_from_eye = v.tile_clip_from_app_clip * v.projection;
    v.eye_from_tile_clip = glm::inverse(v.tile_clip_from_eye);
    v.light.known = true;
    v.light.eye_position = v.modelview * scene.light;
    const glm::dmat4 projection = v.projection, modelview = v.modelview;
    v.redraw = [this, scene, projection, modelview](const glm::dmat4& correction) {
        gl_.glMatrixMode(GL_PROJECTION);
        const glm::dmat4 p = correction * projection;
        gl_.glLoadMatrixd(&p[0][0]);
        gl_.glMatrixMode(GL_MODELVIEW);
        gl_.glLoadMatrixd(&modelview[0][0]);
        draw_geometry(scene);
    };
    v.depth_texture = [this, tile] {
        namespace fx = glcast::slave::effects;
        if (copy_width_ != tile.width || copy_height_ != tile.height) {
            if (window_depth_copy_) gl_.glDeleteTextures(1, &window_depth_copy_), gl_.glDeleteFramebuffers(1, &window_depth_fb_);
            window_depth_copy_ = fx::make_texture(gl_, GL_DEPTH24_STENCIL8, tile.width, tile.height);
            window_depth_fb_ = fx::make_framebuffer(gl_, 0, window_depth_copy_, GL_DEPTH_STENCIL_ATTACHMENT);
            copy_width_ = tile.width, copy_height_ = tile.height;
        }
        fx::StateGuard guard(gl_);
        gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, window_depth_fb_);
        gl_.glBlitFramebuffer(0, 0, tile.width, tile.height, 0, 0, tile.width, tile.height,
                              GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
        return window_depth_copy_;
    };
    return v;
}

Image SceneContext::read_color(const Tile& tile) const {
    Image img;
    img.width = tile.width;
    img.height = tile.height;
    img.rgba.resize(size_t(tile.width) * tile.height * 4);
    gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl_.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl_.glReadPixels(0, 0, tile.width, tile.height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
    return glcast::slave::flip_rows(img);
}

std::vector<float> SceneContext::read_depth(const Tile& tile) const {
    std::vector<float> depth(size_t(tile.width) * tile.height);
    gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl_.glReadPixels(0, 0, tile.width, tile.height, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    return depth;
}

}  // namespace shadow_test
