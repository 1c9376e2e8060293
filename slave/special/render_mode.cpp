// Selection and feedback: GL keeps the buffer pointer and fills it during later draws, so the
// slave gives it memory of its own that lives as long as the context.
#include "common/gl_headers.h"
#include "slave/call_replay.h"
#include "slave/replay_limits.h"
#include "slave/slave_context.h"

namespace glcast::slave::replay_special {

void glSelectBuffer(CallReplay& r, const Call& c) {
    const GLsizei size = std::clamp(r.value<GLsizei>(c, 0), 0, 1 << 24);
    SlaveContext& ctx = r.current();
    ctx.select_buffer.assign(size_t(size) * sizeof(GLuint), 0);
    r.api().glSelectBuffer(size, reinterpret_cast<GLuint*>(ctx.select_buffer.data()));
}

void glFeedbackBuffer(CallReplay& r, const Call& c) {
    const GLsizei size = std::clamp(r.value<GLsizei>(c, 0), 0, 1 << 24);
    SlaveContext& ctx = r.current();
    ctx.feedback_buffer.assign(size_t(size) * sizeof(GLfloat), 0);
    r.api().glFeedbackBuffer(size, r.value<GLenum>(c, 1),
                                                              reinterpret_cast<GLfloat*>(ctx.feedback_buffer.data()));
}

void glRenderMode(CallReplay& r, const Call& c) {
    r.api().glRenderMode(r.value<GLenum>(c, 0));
}

}  // namespace glcast::slave::replay_special
