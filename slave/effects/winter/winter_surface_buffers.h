// The surfaces under each pixel of the tile and its guard band, for the snow cover and icicle
// pass (docs/winter.md, "Normals"): eye-space normal and position, either re-rendered from the
// frame's own geometry (FrameView::redraw with a program of ours) or reconstructed from the
// window's depth buffer when the stream cannot be re-rendered.
#pragma once

#include "slave/effects/frame_view.h"
#include "slave/effects/gl_api.h"
#include "slave/effects/winter/winter_gl.h"
#include "slave/effects/winter/winter_settings.h"

namespace glcast::slave::effects {

class SurfaceBuffers {
public:
    // Builds the programs in the current context (the geometry program only where the
    // compatibility profile offers gl_Vertex and gl_Normal); throws std::runtime_error.
    explicit SurfaceBuffers(const GlApi& gl);
    ~SurfaceBuffers();
    SurfaceBuffers(const SurfaceBuffers&) = delete;
    SurfaceBuffers& operator=(const SurfaceBuffers&) = delete;

    // Fills the buffers for this frame (frame.buffer_width x frame.buffer_height; pixel
    // (guard, guard) is tile pixel (0, 0)). `window_depth` is view.depth_texture(), fetched by
    // the caller before it binds anything. Leaves this object's framebuffer bound.
    void update(const FrameView& view, const WinterFrame& frame, NormalSource requested, GLuint window_depth);

    // RGBA16F: xyz the unit normal facing the camera; w 1 surface, 0 background, -1 unknown
    // (outside the tile when reconstructed from depth).
    GLuint normals() const { return normal_texture_; }
    // RGBA32F: xyz the eye position, w the window depth of that surface.
    GLuint positions() const { return position_texture_; }
    // The source the last update used: Vertex or Faceted (re-rendered) or Depth.
    NormalSource source() const { return source_; }

private:
    void resize(int width, int height);

    const GlApi& gl_;
    GLuint geometry_program_ = 0;  // winter_normals.vert/.frag; 0 in a core-profile context
    GLuint depth_program_ = 0;     // fullscreen.vert + winter_depth_normals.frag
    GLuint empty_vao_ = 0;
    GLuint normal_texture_ = 0, position_texture_ = 0, depth_texture_ = 0, framebuffer_ = 0;
    int width_ = 0, height_ = 0;
    NormalSource source_ = NormalSource::Depth;
};

}  // namespace glcast::slave::effects
