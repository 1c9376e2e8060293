// What the scene classifier needs to know of the GL state at one call, asked through one
// interface so that the decisions (scene_classifier.h) run and are tested without a driver:
// DriverDrawState asks the slave's driver and the tile adapter, each value at most once a
// call and only when a decision needs it; a unit test answers from a struct.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "common/gl_headers.h"
#include "slave/effects/frame_view.h"
#include "slave/program_camera.h"

namespace glcast {
class GlApi;
}

namespace glcast::slave {

class TileAdapter;

struct CullState {
    bool enabled = false;
    GLenum cull_face = GL_BACK, front_face = GL_CCW;
};

class DrawState {
public:
    virtual ~DrawState() = default;
    virtual GLuint draw_framebuffer() = 0;  // the slave's name; 0: the window
    virtual GLuint read_framebuffer() = 0;
    virtual GLuint program() = 0;           // the slave's name of the current program; 0: none
    virtual bool depth_test() = 0;
    virtual bool writes_depth() = 0;        // the depth test on and depth writes enabled
    // glDepthRange(0, f) with f < 1, a draw kept in front of the world (a view model); else 0.
    virtual double view_model_far() = 0;
    virtual glm::dmat4 projection() = 0;    // the program's own fixed-function projection now
    virtual glm::dmat4 modelview() = 0;
    virtual GLenum matrix_mode() = 0;
    virtual effects::SceneLight light() = 0;  // the first enabled fixed-function light, if lighting
    virtual CullState cull() = 0;
    virtual void viewport(int32_t out[4]) = 0;  // the program's viewport 0, master window coordinates
    // The camera of a shader program's draw (TileAdapter::shader_camera); false: none.
    virtual bool camera(GLuint program, ProgramCamera& out) = 0;
    // The attachments of the bound draw framebuffer object: GL_NONE, GL_TEXTURE or GL_RENDERBUFFER.
    virtual GLenum color_attachment_type() = 0;
    virtual GLenum depth_attachment_type() = 0;
};

// The slave's driver and the tile adapter's tracking, asked lazily and at most once per value.
// Lives for one call.
class DriverDrawState final : public DrawState {
public:
    DriverDrawState(const GlApi& gl, TileAdapter& tile) : gl_(gl), tile_(tile) {}
    GLuint draw_framebuffer() override;
    GLuint read_framebuffer() override;
    GLuint program() override;
    bool depth_test() override;
    bool writes_depth() override;
    double view_model_far() override;
    glm::dmat4 projection() override;
    glm::dmat4 modelview() override;
    GLenum matrix_mode() override;
    effects::SceneLight light() override;
    CullState cull() override;
    void viewport(int32_t out[4]) override;
    bool camera(GLuint program, ProgramCamera& out) override;
    GLenum color_attachment_type() override;
    GLenum depth_attachment_type() override;

private:
    const GlApi& gl_;
    TileAdapter& tile_;
    // -1: not asked yet this call
    int64_t draw_framebuffer_ = -1, program_ = -1, depth_test_ = -1, writes_depth_ = -1;
};

}  // namespace glcast::slave
