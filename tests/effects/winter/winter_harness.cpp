#include "tests/effects/winter/winter_harness.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "slave/effects/gl_util.h"
#include "slave/effects/pipeline.h"

namespace winter_test {

using glcast::slave::effects::EffectsSettings;
using glcast::slave::effects::FrameView;
using glcast::slave::effects::Pipeline;

// The fixed-function entry points a 1990s program uses, which the passes' GlApi does not list.
#define WINTER_TEST_FF(X)                                                                                   \
    X(glBegin) X(glEnd) X(glVertex3d) X(glNormal3d) X(glColor3d) X(glColor3ub) X(glMatrixMode)             \
    X(glLoadMatrixd) X(glMultMatrixd) X(glPushMatrix) X(glPopMatrix) X(glLightfv) X(glMaterialfv)           \
    X(glColorMaterial) X(glLightModelfv) X(glShadeModel)

struct Harness::FixedFunction {
#define WINTER_TEST_MEMBER(name) decltype(&::name) name = nullptr;
    WINTER_TEST_FF(WINTER_TEST_MEMBER)
#undef WINTER_TEST_MEMBER
};

Scene standard_scene() {
    Scene s;
    s.boxes.push_back({{-2.4, 0.75, -1.0}, {1.5, 1.5, 1.5}, 25, {0.55, 0.16, 0.10}});
    s.boxes.push_back({{1.9, 0.5, 0.8}, {2.2, 1.0, 1.3}, -30, {0.50, 0.30, 0.08}});
    // Raised on nothing, as the rim of a roof: its underside shows from below.
    s.boxes.push_back({{0.2, 3.0, -3.5}, {2.6, 0.4, 1.6}, 10, {0.40, 0.12, 0.30}});
    return s;
}

Camera high_camera() { return Camera{{0, 6.5, 9.5}, {0, 0.8, -1.5}, 45}; }
Camera low_camera() { return Camera{{0, 1.2, 7.0}, {0, 2.2, -3.0}, 45}; }

Harness::Harness(int canvas_width, int canvas_height)
    : canvas_width_(canvas_width), canvas_height_(canvas_height), ff_(std::make_unique<FixedFunction>()) {
    backend_ = glcast::slave::make_backend("egl", error_);
    if (!backend_) return;
    if (!backend_->create_context(1, 0, glcast::slave::ContextRequest{}, error_)) return;
    if (!backend_->make_current(1, canvas_width, canvas_height, error_)) return;
    current_width_ = canvas_width;
    current_height_ = canvas_height;
    auto resolve = [this](const char* name) { return backend_->proc_address(name); };
    if (!gl_.load(resolve, error_)) return;
#define WINTER_TEST_LOAD(name)                                                        \
    ff_->name = reinterpret_cast<decltype(ff_->name)>(backend_->proc_address(#name)); \
    if (!ff_->name) {                                                                 \
        error_ = "no " #name;                                                         \
        return;                                                                       \
    }
    WINTER_TEST_FF(WINTER_TEST_LOAD)
#undef WINTER_TEST_LOAD
    ok_ = true;
}

Harness::~Harness() {
    if (!ok_) return;
    const GLuint textures[] = {color_copy_, depth_copy_};
    gl_.glDeleteTextures(2, textures);
    if (depth_copy_fb_) gl_.glDeleteFramebuffers(1, &depth_copy_fb_);
    std::string error;
    backend_->make_current(0, 0, 0, error);
    backend_->destroy_context(1);
}

void Harness::make_current(int width, int height) {
    if (width == current_width_ && height == current_height_) return;
    std::string error;
    if (!backend_->make_current(1, width, height, error)) throw std::runtime_error("make_current: " + error);
    current_width_ = width;
    current_height_ = height;
}

void Harness::load_matrices(const glm::dmat4& projection, const glm::dmat4& modelview) {
    ff_->glMatrixMode(GL_PROJECTION);
    ff_->glLoadMatrixd(glm::value_ptr(projection));
    ff_->glMatrixMode(GL_MODELVIEW);
    ff_->glLoadMatrixd(glm::value_ptr(modelview));
}

namespace {

// Unit cube faces: normal, two edge directions (u x v = n), class.
struct Face {
    glm::dvec3 n, u, v;
    SurfaceClass cls;
};
const Face kCubeFaces[6] = {
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, kSide},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}, kSide},
    {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}, kTop},   {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}, kUnder},
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, kSide},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}, kSide},
};

}  // namespace

void Harness::draw_scene(const Scene& scene, bool lit, bool class_colors) {
    FixedFunction& f = *ff_;
    auto color = [&](const glm::dvec3& c, int cls) {
        if (class_colors) f.glColor3ub(GLubyte(cls), 0, 0);
        else f.glColor3d(c.x, c.y, c.z);
    };
    if (lit) {
        gl_.glEnable(GL_LIGHTING);
        gl_.glEnable(GL_LIGHT0);
        gl_.glEnable(GL_NORMALIZE);
        gl_.glEnable(GL_COLOR_MATERIAL);
        f.glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
        const GLfloat ambient[4] = {0.3f, 0.3f, 0.32f, 1}, diffuse[4] = {0.85f, 0.85f, 0.8f, 1};
        f.glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
        f.glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
    }
    if (scene.ground) {
        // A grid of quads, as ff_scene draws its ground (lighting per vertex needs vertices).
        color(scene.ground_color, kGround);
        f.glBegin(GL_QUADS);
        const double half = 30, step = 3;
        for (double z = -half; z < half - 1e-9; z += step)
            for (double x = -half; x < half - 1e-9; x += step) {
                f.glNormal3d(0, 1, 0);
                f.glVertex3d(x, 0, z + step);
                f.glVertex3d(x + step, 0, z + step);
                f.glVertex3d(x + step, 0, z);
                f.glVertex3d(x, 0, z);
            }
        f.glEnd();
    }
    for (const Track& t : scene.tracks) {
        color(t.color, kGround);
        // A hash of the corner's grid index: the same heights on every render and tile.
        auto height = [&](int i, int k) {
            uint32_t h = uint32_t(i) * 73856093u ^ uint32_t(k) * 19349663u;
            h ^= h >> 13;
            h *= 0x5bd1e995u;
            h ^= h >> 15;
            return t.amplitude * (2.0 * double(h & 0xffffu) / 65535.0 - 1.0);
        };
        const int nx = int(std::lround((t.x1 - t.x0) / t.cell)), nz = int(std::lround((t.z1 - t.z0) / t.cell));
        f.glBegin(GL_QUADS);
        f.glNormal3d(0, 1, 0);
        for (int k = 0; k < nz; ++k)
            for (int i = 0; i < nx; ++i) {
                const int ci[4] = {i, i + 1, i + 1, i}, ck[4] = {k + 1, k + 1, k, k};
                for (int c = 0; c < 4; ++c)
                    f.glVertex3d(t.x0 + ci[c] * t.cell, height(ci[c], ck[c]), t.z0 + ck[c] * t.cell);
            }
        f.glEnd();
    }
    for (const Box& b : scene.boxes) {
        f.glPushMatrix();
        const glm::dmat4 m = glm::scale(glm::rotate(glm::translate(glm::dmat4(1.0), b.center), glm::radians(b.yaw_deg),
                                                    glm::dvec3(0, 1, 0)),
                                        b.size);
        f.glMultMatrixd(glm::value_ptr(m));
        for (const Face& face : kCubeFaces) {
            color(b.color, face.cls);
            f.glBegin(GL_QUADS);
            f.glNormal3d(face.n.x, face.n.y, face.n.z);
            const double cu[4] = {-1, 1, 1, -1}, cv[4] = {-1, -1, 1, 1};
            for (int k = 0; k < 4; ++k) {
                const glm::dvec3 p = 0.5 * (face.n + cu[k] * face.u + cv[k] * face.v);
                f.glVertex3d(p.x, p.y, p.z);
            }
            f.glEnd();
        }
        f.glPopMatrix();
    }
    for (size_t i = 0; i < scene.panels.size(); ++i) {
        const Panel& p = scene.panels[i];
        f.glPushMatrix();
        const glm::dmat4 m = glm::rotate(glm::translate(glm::dmat4(1.0), p.center), glm::radians(p.tilt_deg),
                                         glm::dvec3(1, 0, 0));
        f.glMultMatrixd(glm::value_ptr(m));
        color(p.color, int(kPanel + i));
        f.glBegin(GL_QUADS);
        f.glNormal3d(0, 1, 0);
        const double w = p.width / 2, d = p.depth / 2;
        f.glVertex3d(-w, 0, d);
        f.glVertex3d(w, 0, d);
        f.glVertex3d(w, 0, -d);
        f.glVertex3d(-w, 0, -d);
        f.glEnd();
        f.glPopMatrix();
    }
    if (lit) {
        gl_.glDisable(GL_LIGHTING);
        gl_.glDisable(GL_COLOR_MATERIAL);
    }
}

namespace {

glm::dmat4 projection_of(const Camera& camera, int canvas_width, int canvas_height) {
    return glm::perspective(glm::radians(camera.fov_y_deg), double(canvas_width) / canvas_height, 0.5, 100.0);
}

glm::dmat4 view_of(const Camera& camera) { return glm::lookAt(camera.eye, camera.target, glm::dvec3(0, 1, 0)); }

// The wall's stretch: canvas clip space to the clip space of `tile` (the planar stretch T of docs/effects.md's FrameView).
glm::dmat4 tile_stretch(Tile t, int canvas_width, int canvas_height) {
    glm::dmat4 m(1.0);
    m[0][0] = double(canvas_width) / t.width;
    m[1][1] = double(canvas_height) / t.height;
    m[3][0] = double(canvas_width - 2 * t.x) / t.width - 1.0;
    m[3][1] = double(canvas_height - 2 * t.y) / t.height - 1.0;
    return m;
}

}  // namespace

FrameView Harness::frame_view(const Scene& scene, const Camera& camera, Tile tile, const RenderOptions& options) {
    FrameView v;
    v.frame = options.frame;
    v.time = double(options.frame) / 60;
    v.width = tile.width;
    v.height = tile.height;
    v.canvas_x = tile.x;
    v.canvas_y = tile.y;
    v.canvas_width = canvas_width_;
    v.canvas_height = canvas_height_;
    v.view_known = options.view_known;
    v.projection = projection_of(camera, canvas_width_, canvas_height_);
    v.modelview = view_of(camera);
    v.tile_clip_from_app_clip = tile_stretch(tile, canvas_width_, canvas_height_);
    if (options.program_turn_deg != 0) {
        // program eye = turn * this tile's eye: the program's view is turn * the camera's, and the
        // tile's correction takes the program's clip space back through the turn
        const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), glm::radians(options.program_turn_deg), glm::dvec3(0, 1, 0));
        v.modelview = turn * v.modelview;
        v.tile_clip_from_app_clip = v.tile_clip_from_app_clip * v.projection * glm::inverse(turn) * glm::inverse(v.projection);
    }
    v.tile_clip_from_eye = v.tile_clip_from_app_clip * v.projection;
    v.eye_from_tile_clip = glm::inverse(v.tile_clip_from_eye);
    v.light.known = scene.light;
    v.light.eye_position = v.modelview * scene.light_world;

    if (copies_width_ != tile.width || copies_height_ != tile.height) {
        const GLuint textures[] = {color_copy_, depth_copy_};
        if (color_copy_) gl_.glDeleteTextures(2, textures);
        if (depth_copy_fb_) gl_.glDeleteFramebuffers(1, &depth_copy_fb_);
        color_copy_ = glcast::slave::effects::make_texture(gl_, GL_RGBA8, tile.width, tile.height);
        depth_copy_ = glcast::slave::effects::make_texture(gl_, GL_DEPTH24_STENCIL8, tile.width, tile.height);
        depth_copy_fb_ = glcast::slave::effects::make_framebuffer(gl_, 0, depth_copy_, GL_DEPTH_STENCIL_ATTACHMENT);
        gl_.glBindFramebuffer(GL_FRAMEBUFFER, 0);
        copies_width_ = tile.width;
        copies_height_ = tile.height;
    }
    color_copied_ = depth_copied_ = false;
    const int w = tile.width, h = tile.height;
    // As the replayer's copies: made on first use, leaving the caller's bindings as they were.
    v.color_texture = [this, w, h]() -> GLuint {
        if (!color_copied_) {
            GLint read_fb = 0, texture = 0;
            gl_.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb);
            gl_.glGetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
            gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
            gl_.glBindTexture(GL_TEXTURE_2D, color_copy_);
            gl_.glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, 0, w, h);
            gl_.glBindTexture(GL_TEXTURE_2D, GLuint(texture));
            gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fb));
            color_copied_ = true;
        }
        return color_copy_;
    };
    v.depth_texture = [this, w, h]() -> GLuint {
        if (!depth_copied_) {
            GLint read_fb = 0, draw_fb = 0;
            gl_.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb);
            gl_.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fb);
            gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
            gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, depth_copy_fb_);
            gl_.glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
            gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fb));
            gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_fb));
            depth_copied_ = true;
        }
        return depth_copy_;
    };
    if (options.redraw) {
        const glm::dmat4 projection = v.projection, modelview = v.modelview;
        Scene redrawn = scene;
        redrawn.ground = scene.ground && options.redraw_ground;
        v.redraw = [this, redrawn, projection, modelview](const glm::dmat4& correction) {
            load_matrices(correction * projection, modelview);
            draw_scene(redrawn, false, false);
        };
    }
    return v;
}

Image Harness::read_window(int width, int height) {
    Image image;
    image.width = width;
    image.height = height;
    image.rgba.resize(size_t(width) * height * 4);
    gl_.glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl_.glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    return image;  // rows bottom to top, as GL
}

Image Harness::render(const Scene& scene, const Camera& camera, const RenderOptions& options, Tile tile) {
    if (tile.width == 0) tile = {0, 0, canvas_width_, canvas_height_};
    make_current(tile.width, tile.height);
    const glm::dmat4 projection = tile_stretch(tile, canvas_width_, canvas_height_) *
                                  projection_of(camera, canvas_width_, canvas_height_);
    const glm::dmat4 modelview = view_of(camera);
    gl_.glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_.glViewport(0, 0, tile.width, tile.height);
    gl_.glClearColor(0.55f, 0.70f, 0.90f, 1);
    gl_.glClearDepth(1);
    gl_.glEnable(GL_DEPTH_TEST);
    gl_.glDepthFunc(GL_LESS);
    gl_.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    load_matrices(projection, modelview);
    if (scene.light) {
        const GLfloat position[4] = {float(scene.light_world.x), float(scene.light_world.y),
                                     float(scene.light_world.z), float(scene.light_world.w)};
        ff_->glLightfv(GL_LIGHT0, GL_POSITION, position);
    }
    draw_scene(scene, scene.light, false);

    if (!options.effects.empty()) {
        EffectsSettings settings;
        std::string error;
        if (!settings.enable(options.effects, error)) throw std::runtime_error(error);
        for (const std::string& p : options.params)
            if (!settings.params.set_assignment(p, error)) throw std::runtime_error(error);
        Pipeline pipeline(gl_, settings);
        const FrameView view = frame_view(scene, camera, tile, options);
        pipeline.run(view);
    }
    const GLenum e = gl_.glGetError();
    if (e != GL_NO_ERROR) throw std::runtime_error("GL error 0x" + std::to_string(e) + " in the frame");
    return read_window(tile.width, tile.height);
}

Image Harness::classes(const Scene& scene, const Camera& camera, Tile tile) {
    if (tile.width == 0) tile = {0, 0, canvas_width_, canvas_height_};
    make_current(tile.width, tile.height);
    gl_.glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_.glViewport(0, 0, tile.width, tile.height);
    gl_.glClearColor(0, 0, 0, 1);
    gl_.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl_.glEnable(GL_DEPTH_TEST);
    gl_.glDisable(GL_DITHER);
    load_matrices(tile_stretch(tile, canvas_width_, canvas_height_) * projection_of(camera, canvas_width_, canvas_height_),
                  view_of(camera));
    draw_scene(scene, false, true);
    gl_.glEnable(GL_DITHER);
    return read_window(tile.width, tile.height);
}

// ---- measurements ------------------------------------------------------------------------

double luminance(const Image& image, int x, int y) {
    const uint8_t* p = &image.rgba[(size_t(y) * image.width + x) * 4];
    return (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) / 255.0;
}

uint8_t class_at(const Image& classes, int x, int y) { return classes.rgba[(size_t(y) * classes.width + x) * 4]; }

bool interior(const Image& classes, int x, int y, int margin) {
    if (x < margin || y < margin || x >= classes.width - margin || y >= classes.height - margin) return false;
    const uint8_t c = class_at(classes, x, y);
    for (int dy = -margin; dy <= margin; ++dy)
        for (int dx = -margin; dx <= margin; ++dx)
            if (class_at(classes, x + dx, y + dy) != c) return false;
    return true;
}

bool snowy(const Image& before, const Image& after, int x, int y) {
    const double a = luminance(after, x, y), b = luminance(before, x, y);
    return a > 0.55 && a > b + 0.15;
}

std::map<int, Fraction> snow_by_class(const Image& before, const Image& after, const Image& classes, int x0, int x1) {
    std::map<int, Fraction> result;
    for (int y = 0; y < classes.height; ++y)
        for (int x = std::max(x0, 0); x < std::min(x1, classes.width); ++x) {
            if (!interior(classes, x, y, 2)) continue;
            Fraction& f = result[class_at(classes, x, y)];
            ++f.total;
            if (snowy(before, after, x, y)) ++f.snowy;
        }
    return result;
}

void save(const std::string& name, const Image& image) {
    const char* dir = std::getenv("GLCAST_TEST_OUT");
    const std::string path = std::string(dir && *dir ? dir : ".") + "/" + name + ".png";
    std::string error;
    if (!glcast::slave::write_png(path, glcast::slave::flip_rows(image), error))
        std::fprintf(stderr, "cannot save %s: %s\n", path.c_str(), error.c_str());
}

}  // namespace winter_test
