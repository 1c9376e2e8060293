// Small GL helpers shared by the injected passes: shader programs from the GLSL files beside
// each pass (embedded at build time), render targets, and the guard that hands the program its
// GL state back untouched (Magnum's resetState discipline: a pass sets what it needs, the guard
// restores what the program had).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "slave/effects/gl_api.h"

namespace glcast::slave::effects {

// The text of the shader file <file_name> of slave/effects/ or one of its folders (e.g.
// "snow_composite.frag"); throws std::runtime_error for a name that was not embedded.
const std::string& shader_source(const std::string& file_name);

// Compiles and links a program from embedded shader files. Every file gets the line
// "#version 330 core" (or the version its first line names) first. Throws std::runtime_error
// with the file name and the driver's log on failure.
GLuint build_program(const GlApi& gl, const std::string& vertex_file, const std::string& fragment_file,
                     const std::string& defines = "");
GLint uniform(const GlApi& gl, GLuint program, const char* name);  // -1 if inactive

// A 2D texture (storage of one level unless `mip_levels` > 1), clamped, nearest unless
// `linear`. Returns its name; the caller deletes it.
GLuint make_texture(const GlApi& gl, GLenum internal_format, int width, int height, bool linear = false,
                    int mip_levels = 1);
// A framebuffer with the given color (0: none) and depth (0: none) textures; throws
// std::runtime_error if incomplete.
GLuint make_framebuffer(const GlApi& gl, GLuint color, GLuint depth, GLenum depth_attachment = GL_DEPTH_ATTACHMENT);

// Draws one triangle covering the viewport (the vertex shader "fullscreen.vert" needs no
// attributes; an empty VAO is bound).
void draw_fullscreen(const GlApi& gl, GLuint empty_vao);

// Saves, on construction, every piece of GL state a pass may change, and restores it on
// destruction: framebuffer bindings and draw/read buffers, viewport, scissor, the enables
// passes use, blend/depth/stencil/color masks and functions, polygon mode and offset, point
// size, line width, clear values, program, VAO, array and pixel buffers, pixel store, active
// texture and the 2D texture and sampler of units 0..7. In compatibility contexts it also turns
// off, and later restores, the fixed-function state that still acts on a shader's output or
// its sampling: texture-target enables of units 0..7 (Mesa samples nothing from a unit whose
// enabled fixed-function target differs from the shader's sampler type), alpha test, user
// clip planes, polygon and line stipple.
class StateGuard {
public:
    explicit StateGuard(const GlApi& gl);
    ~StateGuard();
    StateGuard(const StateGuard&) = delete;
    StateGuard& operator=(const StateGuard&) = delete;

private:
    const GlApi& gl_;
    GLint draw_fb_, read_fb_, draw_buffer_, read_buffer_, viewport_[4], scissor_[4];
    std::vector<std::pair<GLenum, GLboolean>> enables_;
    GLint blend_src_rgb_, blend_dst_rgb_, blend_src_a_, blend_dst_a_, blend_eq_rgb_, blend_eq_a_;
    GLfloat blend_color_[4], clear_color_[4], clear_depth_, polygon_offset_[2], point_size_, line_width_;
    GLboolean color_mask_[4], depth_mask_;
    GLint depth_func_, stencil_mask_, polygon_mode_[2], cull_face_, front_face_;
    GLint program_, vao_, array_buffer_, pack_buffer_, unpack_buffer_, active_texture_;
    std::vector<std::pair<GLenum, GLint>> pixel_store_;
    GLint textures_[8], samplers_[8];
    bool compatibility_ = false;
    std::vector<std::pair<GLenum, GLboolean>> unit_enables_[8];
};

}  // namespace glcast::slave::effects
