// Small GL helpers shared by the injected passes: shader programs from the GLSL files beside
// each pass (embedded at build time), render targets, and the guard that hands the program its
// GL state back untouched (Magnum's resetState discipline: a pass sets what it needs, the guard
// restores what the program had).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/gl_state.h"
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
// destruction (common/gl_state.h, kGuardPass: framebuffers, viewport, raster state, program,
// vertex array, pixel store, texture units). In compatibility contexts it also turns off, and
// later restores, the fixed-function state that still acts on a shader's output or its
// sampling: Mesa samples nothing from a unit whose enabled fixed-function target differs from
// the shader's sampler type.
class StateGuard : public GlStateGuard {
public:
    explicit StateGuard(const GlApi& gl) : GlStateGuard(gl, kGuardPass) {}
};

}  // namespace glcast::slave::effects
