// What the scene classifier needs to know of the GL state at one call, asked through one
// interface so that the decisions (scene_classifier.h) run and are tested without a driver:
// DriverDrawState answers from the state followed from the program's calls (followed_state.h)
// and the tile adapter's tracking, and asks the slave's driver only what no call said (the
// fixed-function matrices and lights, framebuffer attachments, a value after glPopAttrib), each
// only when a decision needs it; a unit test answers from a struct.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "common/gl_headers.h"
#include "slave/effects/frame_view.h"
#include "slave/program_camera.h"
#include "slave/scene/followed_state.h"

namespace glcast {
class GlApi;
}

namespace glcast::slave {

class TileAdapter;

struct CullState {
    bool enabled = false;
    GLenum cull_face = GL_BACK, front_face = GL_CCW;
};

// The fixed-function alpha test, which a compatibility context applies to shader programs' output
// too: foliage drawn as alpha-tested quads (a voxel game's plants) casts the shadow of its leaves.
struct AlphaTest {
    bool enabled = false;
    GLenum func = GL_ALWAYS;
    double ref = 0;
};

class DrawState {
public:
    virtual ~DrawState() = default;
    virtual GLuint draw_framebuffer() = 0;  // the slave's name; 0: the window
    virtual GLuint read_framebuffer() = 0;
    virtual GLuint program() = 0;           // the slave's name of the current program; 0: none
    virtual bool depth_test() = 0;
    virtual bool writes_depth() = 0;        // the depth test on and depth writes enabled
    virtual bool depth_always() = 0;        // the depth function passes everything (GL_ALWAYS)
    virtual bool blends() = 0;              // GL_BLEND is on: the draw is translucent
    // glDepthRange(0, f) with f < 1, a draw kept in front of the world (a view model); else 0.
    virtual double view_model_far() = 0;
    virtual glm::dmat4 projection() = 0;    // the program's own fixed-function projection now
    virtual glm::dmat4 modelview() = 0;
    virtual GLenum matrix_mode() = 0;
    virtual effects::SceneLight light() = 0;  // the first enabled fixed-function light, if lighting
    virtual CullState cull() = 0;
    virtual AlphaTest alpha_test() = 0;
    virtual void viewport(int32_t out[4]) = 0;  // the program's viewport 0, master window coordinates
    // The camera of a shader program's draw (TileAdapter::shader_camera); false: none.
    virtual bool camera(GLuint program, ProgramCamera& out) = 0;
    // It draws flat now (TileAdapter::shader_flat).
    virtual bool flat_program(GLuint program) = 0;
    // Its sun (ProgramCameras::light): unknown when it has none.
    virtual effects::SceneLight program_light(GLuint program, const ProgramCamera& camera) = 0;
    // The attachments of the bound draw framebuffer object: GL_NONE, GL_TEXTURE or GL_RENDERBUFFER.
    virtual GLenum color_attachment_type() = 0;
    virtual GLenum depth_attachment_type() = 0;
    // Its first colour attachment's texture (the slave's name); 0 when it is none or a renderbuffer.
    virtual GLuint color_texture() = 0;
    // It is not `framebuffer` (a framebuffer object) but holds the same depth attachment, the same
    // texture or renderbuffer: an overlay engine's target over the scene's depth.
    virtual bool shares_depth_with(GLuint framebuffer) = 0;
    // The draw about to run samples `texture`: it is bound as GL_TEXTURE_2D on one of units 0-7
    // (and, for fixed function, GL_TEXTURE_2D is enabled there).
    virtual bool samples_texture(GLuint texture) = 0;
    // The draw's primitive mode (the call's argument: GL_LINES, GL_POINTS...); GL_TRIANGLES for a
    // call that names none (a display list, a rectangle).
    virtual GLenum primitive() = 0;
};

// The followed state, the tile adapter's tracking and the slave's driver, asked lazily. Lives for
// one call; what it asks the driver of the followed values it keeps in `known`.
class DriverDrawState final : public DrawState {
public:
    DriverDrawState(const GlApi& gl, TileAdapter& tile, FollowedState& known, GLenum primitive = GL_TRIANGLES)
        : gl_(gl), tile_(tile), known_(known), primitive_(primitive) {}
    GLuint draw_framebuffer() override;
    GLuint read_framebuffer() override;
    GLuint program() override;
    bool depth_test() override;
    bool writes_depth() override;
    bool depth_always() override;
    bool blends() override;
    double view_model_far() override;
    glm::dmat4 projection() override;
    glm::dmat4 modelview() override;
    GLenum matrix_mode() override;
    effects::SceneLight light() override;
    CullState cull() override;
    AlphaTest alpha_test() override;
    void viewport(int32_t out[4]) override;
    bool camera(GLuint program, ProgramCamera& out) override;
    bool flat_program(GLuint program) override;
    effects::SceneLight program_light(GLuint program, const ProgramCamera& camera) override;
    GLenum color_attachment_type() override;
    GLenum depth_attachment_type() override;
    GLuint color_texture() override;
    bool shares_depth_with(GLuint framebuffer) override;
    bool samples_texture(GLuint texture) override;
    GLenum primitive() override { return primitive_; }

private:
    const GlApi& gl_;
    TileAdapter& tile_;
    FollowedState& known_;
    GLenum primitive_;
};

}  // namespace glcast::slave
