// The frame's scene as the passes saw it, for measurements (scene_report.h).
#include "slave/scene_report.h"

#include <cinttypes>
#include <cstdio>
#include <fstream>

#include "common/image.h"
#include "common/window_readback.h"
#include "slave/effects/gl_util.h"
#include "slave/effects/gl_api.h"

namespace glcast::slave {

namespace {

std::string frame_path(const std::string& dir, uint64_t frame, const char* what) {
    char name[64];
    std::snprintf(name, sizeof name, "/frame-%06" PRIu64 "-%s", frame, what);
    return dir + name;
}

std::string numbers(const glm::dmat4& m) {
    std::string s = "[";
    for (int i = 0; i < 16; ++i) {
        char v[32];
        std::snprintf(v, sizeof v, "%s%.9g", i ? ", " : "", (&m[0][0])[i]);
        s += v;
    }
    return s + "]";
}

}  // namespace

bool write_scene_under_overlays(const GlApi& gl, const std::string& dir, const effects::FrameView& view, GLenum buffer,
                                const char* what, std::string& error) {
    Image image;
    image.width = view.width, image.height = view.height;
    image.rgba = read_window(gl, buffer, view.width, view.height);
    const std::string name = std::string("under-") + what + ".png";
    return write_png(frame_path(dir, view.frame, name.c_str()), image, error);
}

bool write_scene_report(const GlApi& gl, const std::string& dir, const effects::FrameView& view, GLuint kept_fb,
                        std::string& error) {
    const int w = view.width, h = view.height;
    effects::StateGuard guard(gl);  // (pack buffer and pixel store too: kGuardPixelStore)
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    Image kept;
    kept.width = w, kept.height = h;
    kept.rgba.assign(size_t(w) * size_t(h) * 4, 0);
    int64_t kept_pixels = 0;
    if (kept_fb) {
        std::vector<uint8_t> rgba(size_t(w) * size_t(h) * 4);
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, kept_fb);
        gl.glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (!rgba[(size_t(y) * w + x) * 4 + 3]) continue;
                uint8_t* p = &kept.rgba[(size_t(h - 1 - y) * w + x) * 4];  // PNG rows top to bottom
                p[0] = p[1] = p[2] = 255;
                ++kept_pixels;
            }
    }
    for (size_t i = 3; i < kept.rgba.size(); i += 4) kept.rgba[i] = 255;
    if (!write_png(frame_path(dir, view.frame, "kept.png"), kept, error)) return false;
    if (view.view_known && view.depth_texture) {
        std::vector<float> depth(size_t(w) * size_t(h));
        GLuint fb = 0;
        gl.glGenFramebuffers(1, &fb);
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, fb);
        gl.glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, view.depth_texture(), 0);
        gl.glReadBuffer(GL_NONE);
        gl.glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        gl.glDeleteFramebuffers(1, &fb);
        const std::string path = frame_path(dir, view.frame, "depth.f32");
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(depth.data()), std::streamsize(depth.size() * sizeof(float)));
        if (!out) {
            error = "cannot write " + path;
            return false;
        }
    }
    const std::string path = frame_path(dir, view.frame, "scene.json");
    std::ofstream json(path);
    json << "{\"frame\": " << view.frame << ", \"width\": " << w << ", \"height\": " << h
         << ", \"view_known\": " << (view.view_known ? "true" : "false")
         << ", \"eye_from_tile_clip\": " << numbers(view.eye_from_tile_clip)
         << ", \"modelview\": " << numbers(view.modelview) << ", \"kept_pixels\": " << kept_pixels << "}\n";
    if (!json) {
        error = "cannot write " + path;
        return false;
    }
    return true;
}

}  // namespace glcast::slave
