// The GL functions the injected passes call, resolved from the slave's backend (the slave links
// no GL library). One table per process is enough: every backend context of a slave comes from
// the same driver. A pass calls `gl.glEnable(...)`.
#pragma once

#include <functional>
#include <string>

#include "common/gl_headers.h"

namespace glcast::slave::effects {

// Core 3.3 functions every pass may use.
#define GLCAST_EFFECTS_GL_CORE(X)                                                                        \
    X(glGetError) X(glGetIntegerv) X(glGetFloatv) X(glGetDoublev) X(glGetBooleanv) X(glGetString)           \
    X(glIsEnabled) X(glEnable) X(glDisable) X(glViewport) X(glScissor) X(glClear) X(glClearColor)           \
    X(glClearDepth) X(glColorMask) X(glDepthMask) X(glDepthFunc) X(glBlendFunc) X(glBlendFuncSeparate)      \
    X(glBlendEquation) X(glBlendEquationSeparate) X(glBlendColor) X(glCullFace) X(glFrontFace)              \
    X(glPolygonMode) X(glPolygonOffset) X(glPointSize) X(glLineWidth) X(glDrawBuffer) X(glDrawBuffers)      \
    X(glReadBuffer) X(glPixelStorei) X(glReadPixels) X(glFinish) X(glFlush) X(glStencilMask)               \
    X(glGenTextures) X(glDeleteTextures) X(glBindTexture) X(glActiveTexture) X(glTexImage2D)               \
    X(glTexSubImage2D) X(glTexParameteri) X(glTexParameterfv) X(glCopyTexSubImage2D) X(glGenerateMipmap)   \
    X(glGetTexImage) X(glBindSampler) X(glGenFramebuffers) X(glDeleteFramebuffers) X(glBindFramebuffer)    \
    X(glFramebufferTexture2D) X(glCheckFramebufferStatus) X(glBlitFramebuffer) X(glGenRenderbuffers)       \
    X(glDeleteRenderbuffers) X(glBindRenderbuffer) X(glRenderbufferStorage) X(glFramebufferRenderbuffer)   \
    X(glGenBuffers) X(glDeleteBuffers) X(glBindBuffer) X(glBufferData) X(glBufferSubData)                  \
    X(glGenVertexArrays) X(glDeleteVertexArrays) X(glBindVertexArray) X(glVertexAttribPointer)             \
    X(glEnableVertexAttribArray) X(glDisableVertexAttribArray) X(glVertexAttribDivisor) X(glDrawArrays)     \
    X(glDrawArraysInstanced) X(glDrawElements) X(glCreateShader) X(glShaderSource) X(glCompileShader)      \
    X(glGetShaderiv) X(glGetShaderInfoLog) X(glCreateProgram) X(glAttachShader) X(glLinkProgram)           \
    X(glGetProgramiv) X(glGetProgramInfoLog) X(glDeleteShader) X(glDeleteProgram) X(glUseProgram)          \
    X(glGetUniformLocation) X(glUniform1i) X(glUniform1f) X(glUniform2f) X(glUniform3f) X(glUniform4f)     \
    X(glUniform1fv) X(glUniform2fv) X(glUniform3fv) X(glUniform4fv) X(glUniformMatrix4fv)                  \
    X(glBindAttribLocation) X(glBindFragDataLocation) X(glGenQueries) X(glDeleteQueries)                   \
    X(glQueryCounter) X(glGetQueryObjectui64v) X(glBeginQuery) X(glEndQuery) X(glTexImage3D)                   \
    X(glTexSubImage3D) X(glUniform1ui)

// Compatibility-profile functions: null in core contexts (check before use).
#define GLCAST_EFFECTS_GL_COMPAT(X)                                                                      \
    X(glPushAttrib) X(glPopAttrib) X(glPushClientAttrib) X(glPopClientAttrib) X(glMatrixMode)               \
    X(glLoadMatrixd) X(glPushMatrix) X(glPopMatrix) X(glGetLightfv)

struct GlApi {
#define GLCAST_EFFECTS_MEMBER(name) decltype(&::name) name = nullptr;
    GLCAST_EFFECTS_GL_CORE(GLCAST_EFFECTS_MEMBER)
    GLCAST_EFFECTS_GL_COMPAT(GLCAST_EFFECTS_MEMBER)
#undef GLCAST_EFFECTS_MEMBER

    // Resolves every function with `resolve` (a backend's proc_address). False with `error`
    // naming the first missing core function.
    bool load(const std::function<void*(const char*)>& resolve, std::string& error);
};

}  // namespace glcast::slave::effects
