#include "slave/effects/gl_api.h"

#include "protocol/command_info.h"

namespace glcast::slave::effects {

std::string missing_pass_function(const GlApi& gl) {
    static const uint32_t kNeeded[] = {
        OP_glGetError, OP_glGetIntegerv, OP_glGetFloatv, OP_glGetDoublev, OP_glGetBooleanv, OP_glGetString,
        OP_glIsEnabled, OP_glEnable, OP_glDisable, OP_glViewport, OP_glScissor, OP_glClear, OP_glClearColor,
        OP_glClearDepth, OP_glColorMask, OP_glDepthMask, OP_glDepthFunc, OP_glBlendFunc,
        OP_glBlendFuncSeparate, OP_glBlendEquation, OP_glBlendEquationSeparate, OP_glBlendColor,
        OP_glCullFace, OP_glFrontFace, OP_glPolygonMode, OP_glPolygonOffset, OP_glPointSize, OP_glLineWidth,
        OP_glDrawBuffer, OP_glDrawBuffers, OP_glReadBuffer, OP_glPixelStorei, OP_glReadPixels, OP_glFinish,
        OP_glFlush, OP_glStencilMask, OP_glGenTextures, OP_glDeleteTextures, OP_glBindTexture,
        OP_glActiveTexture, OP_glTexImage2D, OP_glTexSubImage2D, OP_glTexParameteri, OP_glTexParameterfv,
        OP_glCopyTexSubImage2D, OP_glGenerateMipmap, OP_glGetTexImage, OP_glBindSampler, OP_glGenFramebuffers,
        OP_glDeleteFramebuffers, OP_glBindFramebuffer, OP_glFramebufferTexture2D, OP_glCheckFramebufferStatus,
        OP_glBlitFramebuffer, OP_glGenRenderbuffers, OP_glDeleteRenderbuffers, OP_glBindRenderbuffer,
        OP_glRenderbufferStorage, OP_glFramebufferRenderbuffer, OP_glGenBuffers, OP_glDeleteBuffers,
        OP_glBindBuffer, OP_glBufferData, OP_glBufferSubData, OP_glGenVertexArrays, OP_glDeleteVertexArrays,
        OP_glBindVertexArray, OP_glVertexAttribPointer, OP_glEnableVertexAttribArray,
        OP_glDisableVertexAttribArray, OP_glVertexAttribDivisor, OP_glDrawArrays, OP_glDrawArraysInstanced,
        OP_glDrawElements, OP_glCreateShader, OP_glShaderSource, OP_glCompileShader, OP_glGetShaderiv,
        OP_glGetShaderInfoLog, OP_glCreateProgram, OP_glAttachShader, OP_glLinkProgram, OP_glGetProgramiv,
        OP_glGetProgramInfoLog, OP_glDeleteShader, OP_glDeleteProgram, OP_glUseProgram,
        OP_glGetUniformLocation, OP_glUniform1i, OP_glUniform1f, OP_glUniform2f, OP_glUniform3f,
        OP_glUniform4f, OP_glUniform1fv, OP_glUniform2fv, OP_glUniform3fv, OP_glUniform4fv,
        OP_glUniformMatrix4fv, OP_glBindAttribLocation, OP_glBindFragDataLocation, OP_glGenQueries,
        OP_glDeleteQueries, OP_glQueryCounter, OP_glGetQueryObjectui64v, OP_glBeginQuery, OP_glEndQuery,
        OP_glTexImage3D, OP_glTexSubImage3D, OP_glUniform1ui,
    };
    for (uint32_t op : kNeeded)
        if (!gl.has(op))
            return std::string("the slave's driver has no ") + command_info(op)->name +
                   ", which the injected passes need (GL 3.3)";
    return "";
}

}  // namespace glcast::slave::effects
