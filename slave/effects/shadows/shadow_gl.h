// Internal to the soft-shadow renderer (shadow_renderer.cpp, shadow_steps.cpp): texture units
// of the shaders' inputs and uniform setters that skip inactive uniforms.
#pragma once

#include <chrono>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "slave/effects/gl_api.h"

namespace glcast::slave::effects::shadow_gl {

// Texture units of the shaders' inputs.
enum Unit : GLint {
    kDepthUnit = 0, kShadowMapUnit, kHardUnit, kEdgesUnit, kLinesUnit, kErosionUnit, kVisibilityUnit, kCullUnit
};

inline double now_ms() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline void set_matrix(const GlApi& gl, GLuint program, const char* name, const glm::dmat4& m) {
    const glm::mat4 f(m);
    const GLint at = gl.glGetUniformLocation(program, name);
    if (at >= 0) gl.glUniformMatrix4fv(at, 1, GL_FALSE, glm::value_ptr(f));
}
inline void set_int(const GlApi& gl, GLuint program, const char* name, int v) {
    const GLint at = gl.glGetUniformLocation(program, name);
    if (at >= 0) gl.glUniform1i(at, v);
}
inline void set_float(const GlApi& gl, GLuint program, const char* name, double v) {
    const GLint at = gl.glGetUniformLocation(program, name);
    if (at >= 0) gl.glUniform1f(at, float(v));
}
inline void set_vec2(const GlApi& gl, GLuint program, const char* name, glm::dvec2 v) {
    const GLint at = gl.glGetUniformLocation(program, name);
    if (at >= 0) gl.glUniform2f(at, float(v.x), float(v.y));
}

inline void bind_texture(const GlApi& gl, GLint unit, GLuint texture) {
    gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    gl.glBindTexture(GL_TEXTURE_2D, texture);
}

}  // namespace glcast::slave::effects::shadow_gl
