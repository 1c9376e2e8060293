// Snow cover (docs/winter.md, "Cover"): which pixels of the tile and its guard band hold snow,
// and the snow shaded over the window. The snow accumulator of docs/winter.md (spread angle around the
// direction opposite to the snowfall, density, seed, uniform or random spread) and its snow by
// texture (the mask image over the canvas).
#pragma once

#include "slave/effects/frame_view.h"
#include "slave/effects/gl_api.h"
#include "slave/effects/winter/winter_gl.h"
#include "slave/effects/winter/winter_settings.h"
#include "slave/effects/winter/winter_surface_buffers.h"

namespace glcast::slave::effects {

class CoverStage {
public:
    CoverStage(const GlApi& gl, const CoverSettings& settings);  // throws std::runtime_error
    ~CoverStage();
    CoverStage(const CoverStage&) = delete;
    CoverStage& operator=(const CoverStage&) = delete;

    // Computes the cover buffer (RGBA16F over the guard-band buffers: r snow amount, g eye
    // distance, a 1 surface / 0 background / -1 unknown). Leaves its framebuffer bound.
    void classify(const FrameView& view, const WinterFrame& frame, const SurfaceBuffers& surfaces,
                  GLuint window_depth);
    // Blends the shaded snow into the window (framebuffer 0; viewport = the tile). It runs
    // before the shadow pass (pipeline.cpp), so shadows darken the snow afterwards.
    void composite(const FrameView& view, const WinterFrame& frame, const SurfaceBuffers& surfaces);

    GLuint cover() const { return cover_texture_; }

private:
    void resize(int width, int height);

    const GlApi& gl_;
    const CoverSettings& settings_;
    GLuint classify_program_ = 0, snow_program_ = 0, empty_vao_ = 0;
    GLuint mask_texture_ = 0;
    GLuint cover_texture_ = 0, framebuffer_ = 0;
    int width_ = 0, height_ = 0;
};

}  // namespace glcast::slave::effects
