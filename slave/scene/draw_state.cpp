// The draw state as the slave's driver and the tile adapter have it (draw_state.h).
#include "slave/scene/draw_state.h"

#include <cstring>

#include "glcast_gl_api.h"
#include "slave/tile_adapter.h"

namespace glcast::slave {

GLuint DriverDrawState::draw_framebuffer() {
    if (draw_framebuffer_ < 0) {
        GLint bound = 0;
        gl_.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
        draw_framebuffer_ = GLuint(bound);
    }
    return GLuint(draw_framebuffer_);
}

GLuint DriverDrawState::read_framebuffer() {
    GLint bound = 0;
    gl_.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &bound);
    return GLuint(bound);
}

GLuint DriverDrawState::program() {
    if (program_ < 0) {
        GLint current = 0;
        gl_.glGetIntegerv(GL_CURRENT_PROGRAM, &current);
        program_ = GLuint(current);
    }
    return GLuint(program_);
}

bool DriverDrawState::depth_test() {
    if (depth_test_ < 0) depth_test_ = gl_.glIsEnabled(GL_DEPTH_TEST) ? 1 : 0;
    return depth_test_ != 0;
}

bool DriverDrawState::writes_depth() {
    if (writes_depth_ < 0) {
        GLboolean mask = GL_FALSE;
        gl_.glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
        writes_depth_ = mask && depth_test() ? 1 : 0;
    }
    return writes_depth_ != 0;
}

double DriverDrawState::view_model_far() {
    GLdouble range[2] = {0, 1};
    gl_.glGetDoublev(GL_DEPTH_RANGE, range);
    return range[0] == 0 && range[1] > 0 && range[1] < 1 ? range[1] : 0;
}

glm::dmat4 DriverDrawState::projection() { return tile_.program_projection_now(); }

glm::dmat4 DriverDrawState::modelview() {
    GLdouble mv[16];
    gl_.glGetDoublev(GL_MODELVIEW_MATRIX, mv);
    glm::dmat4 m;
    std::memcpy(&m[0][0], mv, sizeof mv);
    return m;
}

GLenum DriverDrawState::matrix_mode() {
    GLint mode = 0;
    gl_.glGetIntegerv(GL_MATRIX_MODE, &mode);
    return GLenum(mode);
}

effects::SceneLight DriverDrawState::light() {
    GLboolean lighting = GL_FALSE;
    gl_.glGetBooleanv(GL_LIGHTING, &lighting);
    for (GLenum light = GL_LIGHT0; lighting && light < GL_LIGHT0 + 8; ++light) {
        GLboolean on = GL_FALSE;
        gl_.glGetBooleanv(light, &on);
        if (!on) continue;
        GLfloat pos[4];
        gl_.glGetLightfv(light, GL_POSITION, pos);
        return effects::SceneLight{true, glm::dvec4(pos[0], pos[1], pos[2], pos[3])};
    }
    return {};
}

CullState DriverDrawState::cull() {
    GLint cull_face = GL_BACK, front_face = GL_CCW;
    gl_.glGetIntegerv(GL_CULL_FACE_MODE, &cull_face);
    gl_.glGetIntegerv(GL_FRONT_FACE, &front_face);
    return CullState{gl_.glIsEnabled(GL_CULL_FACE) != 0, GLenum(cull_face), GLenum(front_face)};
}

void DriverDrawState::viewport(int32_t out[4]) { tile_.program_viewport(out); }

bool DriverDrawState::camera(GLuint program, ProgramCamera& out) { return tile_.shader_camera(program, out); }

GLenum DriverDrawState::color_attachment_type() {
    GLint type = GL_NONE;
    gl_.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                              GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    return GLenum(type);
}

GLenum DriverDrawState::depth_attachment_type() {
    GLint type = GL_NONE;
    gl_.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                              GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    return GLenum(type);
}

}  // namespace glcast::slave
