// A scaled blit from a multisampled framebuffer (scaled_blit.h).
#include "slave/scaled_blit.h"

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace glcast::slave {

bool ScaledBlit::needed(const GlApi& gl, const int32_t source[4], const int32_t destination[4]) {
    if (std::abs(int64_t(source[2]) - source[0]) == std::abs(int64_t(destination[2]) - destination[0]) &&
        std::abs(int64_t(source[3]) - source[1]) == std::abs(int64_t(destination[3]) - destination[1]))
        return false;
    // GL_SAMPLES is the draw framebuffer's: the read one is bound there for the question.
    GLint draw = 0, read = 0, samples = 0;
    gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
    gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
    if (read == 0) return false;  // (the window's, on a tile, is single-sampled)
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(read));
    gl.glGetIntegerv(GL_SAMPLES, &samples);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
    return samples > 0;
}

GLenum ScaledBlit::read_format(const GlApi& gl) {
    GLint buffer = GL_NONE, type = GL_NONE, name = 0, format = 0;
    gl.glGetIntegerv(GL_READ_BUFFER, &buffer);
    if (buffer == GL_NONE) return 0;
    gl.glGetFramebufferAttachmentParameteriv(GL_READ_FRAMEBUFFER, GLenum(buffer), GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE,
                                             &type);
    gl.glGetFramebufferAttachmentParameteriv(GL_READ_FRAMEBUFFER, GLenum(buffer), GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME,
                                             &name);
    if (type == GL_RENDERBUFFER) {
        GLint bound = 0;
        gl.glGetIntegerv(GL_RENDERBUFFER_BINDING, &bound);
        gl.glBindRenderbuffer(GL_RENDERBUFFER, GLuint(name));
        gl.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_INTERNAL_FORMAT, &format);
        gl.glBindRenderbuffer(GL_RENDERBUFFER, GLuint(bound));
    } else if (type == GL_TEXTURE) {  // a multisampled texture (arrays' layers are not read here)
        GLint bound = 0;
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D_MULTISAMPLE, &bound);
        gl.glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, GLuint(name));
        gl.glGetTexLevelParameteriv(GL_TEXTURE_2D_MULTISAMPLE, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
        gl.glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, GLuint(bound));
    }
    return GLenum(format);
}

void ScaledBlit::fit(const GlApi& gl, GLenum format, int width, int height) {
    if (framebuffer_ && format_ == format && size_[0] == width && size_[1] == height) return;
    GLint bound = 0;
    gl.glGetIntegerv(GL_RENDERBUFFER_BINDING, &bound);
    if (!renderbuffer_) gl.glGenRenderbuffers(1, &renderbuffer_);
    if (!framebuffer_) gl.glGenFramebuffers(1, &framebuffer_);
    gl.glBindRenderbuffer(GL_RENDERBUFFER, renderbuffer_);
    gl.glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
    gl.glBindRenderbuffer(GL_RENDERBUFFER, GLuint(bound));
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_);
    gl.glFramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, renderbuffer_);
    format_ = 0;
    if (gl.glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("a single-sampled target of format 0x" + std::to_string(format) + " and " +
                                 std::to_string(width) + "x" + std::to_string(height) + " is not complete");
    format_ = format, size_[0] = width, size_[1] = height;
}

void ScaledBlit::blit(const GlApi& gl, const int32_t source[4], const int32_t destination[4], GLbitfield mask,
                      GLenum filter) {
    if (!(mask & GL_COLOR_BUFFER_BIT)) return;
    GLint draw = 0, read = 0;
    gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
    gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
    const GLenum format = read_format(gl);
    if (!format) throw std::runtime_error("the multisampled read buffer's format is not known");
    // (the rectangle is the stream's: its size is checked before a target of that size is made)
    const int64_t x = std::min(source[0], source[2]), y = std::min(source[1], source[3]);
    const int64_t w = std::llabs(int64_t(source[2]) - source[0]), h = std::llabs(int64_t(source[3]) - source[1]);
    GLint most = 0;
    gl.glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &most);
    if (w < 1 || h < 1 || w > most || h > most || x + w > INT32_MAX || y + h > INT32_MAX)
        throw std::runtime_error("a source rectangle of " + std::to_string(w) + "x" + std::to_string(h) + " at " +
                                 std::to_string(x) + "," + std::to_string(y) +
                                 " is beyond the driver's largest renderbuffer (" + std::to_string(most) + ")");
    const GLboolean scissor = gl.glIsEnabled(GL_SCISSOR_TEST);
    try {
        fit(gl, format, int(w), int(h));
    } catch (...) {
        gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
        throw;
    }
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_);  // (fit binds it only when it makes it)
    gl.glDisable(GL_SCISSOR_TEST);  // (the program's box is the destination's)
    gl.glBlitFramebuffer(GLint(x), GLint(y), GLint(x + w), GLint(y + h), 0, 0, GLint(w), GLint(h), GL_COLOR_BUFFER_BIT,
                         GL_NEAREST);
    if (scissor) gl.glEnable(GL_SCISSOR_TEST);
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
    // (the source's direction kept: a mirrored blit stays mirrored)
    gl.glBlitFramebuffer(GLint(source[0] - x), GLint(source[1] - y), GLint(source[2] - x), GLint(source[3] - y),
                         destination[0], destination[1], destination[2], destination[3], GL_COLOR_BUFFER_BIT, filter);
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
}

}  // namespace glcast::slave
