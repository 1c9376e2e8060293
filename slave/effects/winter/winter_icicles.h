// Icicles (docs/winter.md, "Icicles"): the icicle generator of docs/winter.md in screen space. They hang
// below the lower edges of the snow cover (CoverStage::cover), in seeded canvas columns, with
// seeded radii and lengths proportional to radius^(4/3), shaded as translucent ice.
#pragma once

#include "slave/effects/frame_view.h"
#include "slave/effects/gl_api.h"
#include "slave/effects/winter/winter_gl.h"
#include "slave/effects/winter/winter_settings.h"
#include "slave/effects/winter/winter_surface_buffers.h"

namespace glcast::slave::effects {

class IcicleStage {
public:
    IcicleStage(const GlApi& gl, const IcicleSettings& settings);  // throws std::runtime_error
    ~IcicleStage();
    IcicleStage(const IcicleStage&) = delete;
    IcicleStage& operator=(const IcicleStage&) = delete;

    // Draws the icicles into the window (framebuffer 0, whose draw buffer is read for the ice's
    // background). `cover` is CoverStage::cover() of this frame.
    void run(const FrameView& view, const WinterFrame& frame, const SurfaceBuffers& surfaces, GLuint cover,
             GLuint window_depth);

private:
    void set_icicle_uniforms(GLuint program, const FrameView& view, const WinterFrame& frame) const;

    const GlApi& gl_;
    const IcicleSettings& settings_;
    GLuint roots_program_ = 0, icicles_program_ = 0, empty_vao_ = 0;
    GLuint roots_texture_ = 0, roots_framebuffer_ = 0;
    int roots_width_ = 0, roots_height_ = 0;
    GLuint scene_texture_ = 0;
    glm::ivec2 scene_size_{0, 0};
};

}  // namespace glcast::slave::effects
