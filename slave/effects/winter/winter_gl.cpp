#include "slave/effects/winter/winter_gl.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/type_ptr.hpp>

#include "slave/effects/gl_util.h"

namespace glcast::slave::effects {

WinterFrame winter_frame(const FrameView& view, const WinterSettings& settings, bool icicles, const glm::dvec3& up) {
    WinterFrame f;
    f.canvas_width = view.canvas_width > 0 ? view.canvas_width : view.width;
    f.canvas_height = view.canvas_height > 0 ? view.canvas_height : view.height;

    const CoverSettings& c = settings.cover;
    const glm::dvec3 up_through_view = glm::dmat3(view.modelview) * up;
    if (c.up_in_world && view.view_known && glm::length(up_through_view) > 1e-9 &&
        std::abs(glm::determinant(view.modelview)) > 1e-12) {
        f.up_eye = glm::normalize(up_through_view);
        f.world_from_eye = glm::inverse(view.modelview);
    } else {  // eye space asked for, or a view transform that flattens the scene
        f.up_eye = up;
    }
    if (view.light.known) {
        f.light_eye = view.light.eye_position;
    } else {
        // Light from above and a little towards the camera, so that lit snow reads as snow.
        f.light_eye = glm::dvec4(glm::normalize(f.up_eye + glm::dvec3(0.25, 0.0, 0.6)), 0.0);
    }
    const double h = f.canvas_height;
    f.cover_fraction = c.build_frames > 0 ? std::clamp(double(view.frame) / c.build_frames, 0.0, 1.0) : 1.0;

    const IcicleSettings& i = settings.icicles;
    f.spacing_px = std::max(1.0, i.spacing * h);
    f.radius_min_px = i.radius_min * h;
    f.radius_max_px = i.radius_max * h;
    f.length_max_px = i.length_max * h;
    f.edge_cos = std::cos(glm::radians(c.edge_angle_deg));
    f.lip_px = c.lip * h;
    f.lip_rows = int(std::ceil(1.5 * f.lip_px));
    f.lip_seed = c.seed;
    double reach = f.lip_rows;
    if (icicles) reach += std::max(f.length_max_px, 2.0 * f.radius_max_px + f.spacing_px);
    f.guard = int(std::ceil(reach)) + 2;
    f.buffer_width = view.width + 2 * f.guard;
    f.buffer_height = view.height + 2 * f.guard;
    return f;
}

GLuint build_winter_program(const GlApi& gl, const std::string& vertex_file, const std::string& fragment_file,
                            const std::vector<std::string>& libraries) {
    std::string prefix = shader_source("winter_noise.glsl") + "\n";
    for (const std::string& library : libraries) prefix += shader_source(library) + "\n";
    return build_program(gl, vertex_file, fragment_file, prefix);
}

void set_edge_uniforms(const GlApi& gl, GLuint program, const WinterFrame& frame) {
    set_uniform(gl, program, "edge_cos", frame.edge_cos);
    set_uniform(gl, program, "lip_px", frame.lip_px);
    set_seed_uniform(gl, program, "lip_seed_bits", frame.lip_seed);
}

void set_uniform(const GlApi& gl, GLuint program, const char* name, int value) {
    gl.glUniform1i(uniform(gl, program, name), value);
}
void set_uniform(const GlApi& gl, GLuint program, const char* name, double value) {
    gl.glUniform1f(uniform(gl, program, name), float(value));
}
void set_uniform(const GlApi& gl, GLuint program, const char* name, const glm::dvec2& value) {
    gl.glUniform2f(uniform(gl, program, name), float(value.x), float(value.y));
}
void set_uniform(const GlApi& gl, GLuint program, const char* name, const glm::dvec3& value) {
    gl.glUniform3f(uniform(gl, program, name), float(value.x), float(value.y), float(value.z));
}
void set_uniform(const GlApi& gl, GLuint program, const char* name, const glm::dvec4& value) {
    gl.glUniform4f(uniform(gl, program, name), float(value.x), float(value.y), float(value.z), float(value.w));
}
void set_uniform(const GlApi& gl, GLuint program, const char* name, const glm::dmat4& value) {
    const glm::mat4 m(value);
    gl.glUniformMatrix4fv(uniform(gl, program, name), 1, GL_FALSE, glm::value_ptr(m));
}
void set_seed_uniform(const GlApi& gl, GLuint program, const char* name, unsigned value) {
    int bits = 0;
    static_assert(sizeof bits == sizeof value);
    std::memcpy(&bits, &value, sizeof bits);
    gl.glUniform1i(uniform(gl, program, name), bits);
}
void copy_window(const GlApi& gl, GLuint& texture, glm::ivec2& size, int width, int height) {
    GLint window_buffer = GL_BACK;
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl.glGetIntegerv(GL_DRAW_BUFFER, &window_buffer);
    if (size != glm::ivec2(width, height)) {
        if (texture) gl.glDeleteTextures(1, &texture);
        texture = make_texture(gl, GL_RGBA8, width, height);
        size = {width, height};
    }
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl.glReadBuffer(GLenum(window_buffer));
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glBindTexture(GL_TEXTURE_2D, texture);
    gl.glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, 0, width, height);
}

void bind_sampler(const GlApi& gl, GLuint program, const char* name, int unit, GLuint texture) {
    gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    gl.glBindTexture(GL_TEXTURE_2D, texture);
    gl.glUniform1i(uniform(gl, program, name), unit);
}

}  // namespace glcast::slave::effects
