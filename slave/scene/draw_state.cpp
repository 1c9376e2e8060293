// The draw state as the program's calls set it, the slave's driver and the tile adapter have it
// (draw_state.h).
#include "slave/scene/draw_state.h"

#include <cstring>
#include <utility>

#include "glcast_gl_api.h"
#include "slave/tile_adapter.h"

namespace glcast::slave {

namespace {

GLint integer(const GlApi& gl, GLenum pname) {
    GLint v = 0;
    gl.glGetIntegerv(pname, &v);
    return v;
}

// The followed value, or the driver's answer, kept until a call sets it.
template <class T, class Ask>
T known_or(std::optional<T>& known, Ask&& ask) {
    if (!known) known = ask();
    return *known;
}

}  // namespace

GLuint DriverDrawState::draw_framebuffer() {
    return known_or(known_.draw_framebuffer, [&] { return GLuint(integer(gl_, GL_DRAW_FRAMEBUFFER_BINDING)); });
}

GLuint DriverDrawState::read_framebuffer() {
    return known_or(known_.read_framebuffer, [&] { return GLuint(integer(gl_, GL_READ_FRAMEBUFFER_BINDING)); });
}

GLuint DriverDrawState::program() {
    return tile_.program_in_use();  // the core follows glUseProgram
}

bool DriverDrawState::depth_test() {
    return known_or(known_.depth_test, [&] { return gl_.glIsEnabled(GL_DEPTH_TEST) != 0; });
}

bool DriverDrawState::blends() {
    return known_or(known_.blend, [&] { return gl_.glIsEnabled(GL_BLEND) != 0; });
}

bool DriverDrawState::depth_always() {
    return known_or(known_.depth_func, [&] { return GLenum(integer(gl_, GL_DEPTH_FUNC)); }) == GL_ALWAYS;
}

bool DriverDrawState::writes_depth() {
    return depth_test() && known_or(known_.depth_mask, [&] {
               GLboolean mask = GL_FALSE;
               gl_.glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
               return mask != 0;
           });
}

double DriverDrawState::view_model_far() {
    const auto [near, far] = known_or(known_.depth_range, [&] {
        GLdouble range[2] = {0, 1};
        gl_.glGetDoublev(GL_DEPTH_RANGE, range);
        return std::make_pair(double(range[0]), double(range[1]));
    });
    return near == 0 && far > 0 && far < 1 ? far : 0;
}

glm::dmat4 DriverDrawState::projection() { return tile_.program_projection_now(); }

glm::dmat4 DriverDrawState::modelview() {
    GLdouble mv[16] = {};
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
        GLfloat pos[4] = {0, 0, 1, 0};
        gl_.glGetLightfv(light, GL_POSITION, pos);
        return effects::SceneLight{true, glm::dvec4(pos[0], pos[1], pos[2], pos[3])};
    }
    return {};
}

CullState DriverDrawState::cull() {
    return CullState{known_or(known_.cull_face, [&] { return gl_.glIsEnabled(GL_CULL_FACE) != 0; }),
                     known_or(known_.cull_face_mode, [&] { return GLenum(integer(gl_, GL_CULL_FACE_MODE)); }),
                     known_or(known_.front_face, [&] { return GLenum(integer(gl_, GL_FRONT_FACE)); })};
}

// From the calls alone (GL_ALPHA_TEST does not exist in a core profile, where asking would be an error).
AlphaTest DriverDrawState::alpha_test() { return AlphaTest{known_.alpha_test, known_.alpha_func, known_.alpha_ref}; }

void DriverDrawState::viewport(int32_t out[4]) { tile_.program_viewport(out); }

bool DriverDrawState::camera(GLuint program, ProgramCamera& out) { return tile_.shader_camera(program, out); }

bool DriverDrawState::flat_program(GLuint program) { return tile_.shader_flat(program); }

effects::SceneLight DriverDrawState::program_light(GLuint program, const ProgramCamera& camera) {
    effects::SceneLight light;
    tile_.shader_light(program, camera, light);
    return light;
}

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

namespace {

// The depth attachment of the framebuffer bound at `target`: its object type and name.
std::pair<GLint, GLint> depth_attachment(const GlApi& gl, GLenum target) {
    GLint type = GL_NONE, name = 0;
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_NONE)
        gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME,
                                                 &name);
    return {type, name};
}

}  // namespace

bool DriverDrawState::shares_depth_with(GLuint framebuffer) {
    const GLuint drawn = draw_framebuffer();
    if (!framebuffer || !drawn || drawn == framebuffer) return false;
    const auto here = depth_attachment(gl_, GL_DRAW_FRAMEBUFFER);
    if (here.first == GL_NONE) return false;
    GLint read = 0;
    gl_.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
    gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    const auto there = depth_attachment(gl_, GL_READ_FRAMEBUFFER);
    gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
    return here == there;
}

GLuint DriverDrawState::color_texture() {
    if (color_attachment_type() != GL_TEXTURE) return 0;
    GLint name = 0;
    gl_.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                              GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    return GLuint(name);
}

// (fixed function samples a unit's texture only where GL_TEXTURE_2D is enabled on it: a texture
// stays bound after texturing is switched off)
bool DriverDrawState::samples_texture(GLuint texture) {
    GLint active = GL_TEXTURE0, bound = 0;
    bool found = false;
    const bool fixed_function = program() == 0;
    gl_.glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    for (int unit = 0; unit < 8 && !found; ++unit) {
        gl_.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl_.glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
        found = GLuint(bound) == texture && (!fixed_function || gl_.glIsEnabled(GL_TEXTURE_2D));
    }
    gl_.glActiveTexture(GLenum(active));
    return found;
}

}  // namespace glcast::slave
