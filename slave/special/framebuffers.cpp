// Buffer names of the window framebuffer (GL_BACK, ...) as the slave's window has them.
#include "common/gl_headers.h"
#include "slave/call_replay.h"
#include "slave/replay_limits.h"
#include "slave/slave_context.h"

namespace glcast::slave::replay_special {
namespace {

// The slave's window framebuffer may be single-buffered (pbuffer, OSMesa buffer) where the
// program's was double-buffered: its back buffer is then the slave's front buffer.
GLenum window_buffer(CallReplay& r, GLenum buf) {
    if (r.current().double_buffered) return buf;
    switch (buf) {
    case GL_BACK: return GL_FRONT;
    case GL_BACK_LEFT: return GL_FRONT_LEFT;
    case GL_BACK_RIGHT: return GL_FRONT_RIGHT;
    default: return buf;
    }
}

bool window_bound(CallReplay& r, GLenum binding) {
    GLint fb = 0;
    r.api().glGetIntegerv(binding, &fb);
    return fb == 0;
}

}  // namespace

void glDrawBuffer(CallReplay& r, const Call& c) {
    GLenum buf = r.value<GLenum>(c, 0);
    if (window_bound(r, GL_DRAW_FRAMEBUFFER_BINDING)) {
        r.current().window_draw_buffer = buf;
        buf = window_buffer(r, buf);
    }
    r.api().glDrawBuffer(buf);
}

void glReadBuffer(CallReplay& r, const Call& c) {
    GLenum buf = r.value<GLenum>(c, 0);
    if (window_bound(r, GL_READ_FRAMEBUFFER_BINDING)) {
        r.current().window_read_buffer = buf;
        buf = window_buffer(r, buf);
    }
    r.api().glReadBuffer(buf);
}

void glDrawBuffers(CallReplay& r, const Call& c) {
    const GLsizei n = r.value<GLsizei>(c, 0);
    r.need(c, 1, n);
    const auto* bufs = static_cast<const GLenum*>(r.in(c, 1));
    if (!bufs && n > 0) throw ReplayError("glDrawBuffers of " + std::to_string(n) + " buffers without the array");
    std::vector<GLenum> mapped(bufs ? bufs : nullptr, bufs ? bufs + std::max(n, 0) : nullptr);
    if (window_bound(r, GL_DRAW_FRAMEBUFFER_BINDING)) {
        if (!mapped.empty()) r.current().window_draw_buffer = mapped[0];
        for (GLenum& b : mapped) b = window_buffer(r, b);
    }
    r.api().glDrawBuffers(n, mapped.data());
}

void glNamedFramebufferDrawBuffer(CallReplay& r, const Call& c) {
    const bool window = c.args[0].bits == 0;
    const GLuint fb = r.name<GLuint>(Ns::framebuffer, c, 0);
    GLenum buf = r.value<GLenum>(c, 1);
    if (window) {
        r.current().window_draw_buffer = buf;
        buf = window_buffer(r, buf);
    }
    r.api().glNamedFramebufferDrawBuffer(fb, buf);
}

void glNamedFramebufferReadBuffer(CallReplay& r, const Call& c) {
    const bool window = c.args[0].bits == 0;
    const GLuint fb = r.name<GLuint>(Ns::framebuffer, c, 0);
    GLenum buf = r.value<GLenum>(c, 1);
    if (window) {
        r.current().window_read_buffer = buf;
        buf = window_buffer(r, buf);
    }
    r.api().glNamedFramebufferReadBuffer(fb, buf);
}

}  // namespace glcast::slave::replay_special
