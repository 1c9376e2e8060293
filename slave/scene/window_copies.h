// Copies of a context's window framebuffer that the injected passes read and the effects runner
// puts back: its colour and depth as the frame left them, the program's own picture (restored
// after present, so that a program that never clears draws over its own image, not over the
// decorated one), the scene before the first overlay, and the depth of a scene drawn offscreen,
// resolved and cut to this tile.
#pragma once

#include <glm/glm.hpp>

#include "common/gl_headers.h"

namespace glcast {
class GlApi;
}

namespace glcast::slave {

class Replayer;
struct SlaveContext;
struct ContextScene;
struct DepthConvention;

// glClear(mask) of the window clears all of its colour: no scissor test, every colour channel
// written. A program that does so draws a new picture every frame.
bool clears_whole_colour(const GlApi& gl, GLbitfield mask);

// The depth format of the bound framebuffer's depth attachment at `target`, from what GL says of
// it (a depth blit needs the same format on both sides); 0 when it has no depth.
GLenum depth_format(const GlApi& gl, GLenum target);
// ... and its size in pixels (a renderbuffer's, or a 2D texture's level); false when it has none.
bool depth_size(const GlApi& gl, GLenum target, int& width, int& height);

class WindowCopies {
public:
    explicit WindowCopies(Replayer& core) : core_(core) {}

    void size(SlaveContext& ctx);  // the copies at the window's size
    bool sized(const SlaveContext& ctx) const;
    // Blits the window's colour (or depth) into the framebuffer `copy_fb`, or back from it.
    void copy(SlaveContext& ctx, GLuint copy_fb, bool depth, bool back = false);
    // The window's colour (RGBA8) or depth (DEPTH24_STENCIL8) as it is now, a texture name made
    // once a frame; the depth of a scene drawn offscreen comes from its framebuffer object
    // (`shown`: the scene whose size it has, a lender's for a borrowed scene).
    GLuint window_copy(SlaveContext& ctx, bool depth, ContextScene& scene, const ContextScene& shown);
    // `program_depth` (a window_copy) in the passes' depth convention (depth_convention.h): a
    // DEPTH_COMPONENT32F texture of the window's size, made once a frame.
    GLuint pass_depth(SlaveContext& ctx, GLuint program_depth, const DepthConvention& convention,
                      const glm::dmat4& pass_clip_from_program_clip);
    // The window's depth now, before the program clears it for a view model or draws over the
    // scene (marks, a translucent draw): window_copy's depth until end_frame (or
    // forget_kept_depth); the first kept stays.
    void keep_depth(SlaveContext& ctx);
    void forget_kept_depth() { depth_kept_ = false; }  // the window's depth is the scene's again
    // A scene drawn offscreen may get the program's HUD in its own target (VTK's text actors): that
    // target's colour (its read buffer) before the first such draw (`final` false) and at the
    // frame's end, each copied at the target's size into scene_target_before / _final.
    void keep_scene_target(const SlaveContext& ctx, const ContextScene& scene, bool final);
    // The depth of a scene drawn offscreen as it is now, at its target's size and format, before an
    // overlay engine draws into it from another target (SceneFacts::scene_depth_kept): the depth
    // window_copy gives for the frame, and the one the scene's loan lends (scene_lending.h).
    void keep_scene_depth(ContextScene& scene);
    // The rectangle of the scene's texels (x0, y0, x1, y1) that this tile shows over its size: of
    // its target (as those copies are), or of a borrowed scene (`shown`: the lender's) where the
    // draw that showed it put it (beyond its texels: outside the scene); a scene shown upside down
    // (SceneFacts::shown_mirrored) has y0 above y1, one mirrored left to right x0 right of x1.
    // `size`: its SW x SH texels.
    glm::dvec4 scene_texels_on_tile(const SlaveContext& ctx, const ContextScene& scene, const ContextScene& shown,
                                    int size[2]) const;
    GLuint scene_target_before = 0, scene_target_final = 0;
    void new_frame() { color_copied_ = depth_copied_ = pass_depth_done_ = false; }
    void end_frame() { depth_kept_ = false; }

    GLuint program_image = 0, program_image_fb = 0;
    bool program_image_saved = false;
    GLuint scene_image = 0, scene_image_fb = 0;

private:
    GLuint scene_depth_copy(SlaveContext& ctx, ContextScene& scene, const ContextScene& shown);
    // The part of a program-window-sized image of SW x SH texels this tile shows: all of it on a
    // rotated tile, this tile's rectangle of the canvas on a planar one.
    glm::dvec4 tile_source(const SlaveContext& ctx, int SW, int SH) const;

    Replayer& core_;
    GLuint color_texture_ = 0, depth_texture_ = 0, color_fb_ = 0, depth_fb_ = 0;
    int width_ = 0, height_ = 0;
    bool color_copied_ = false, depth_copied_ = false, depth_kept_ = false;
    // Resolved at the program's size, then this tile's part of it at the window's size.
    GLuint scene_depth_full_ = 0, scene_depth_full_fb_ = 0, scene_depth_ = 0, scene_depth_fb_ = 0;
    GLuint scene_depth_program_ = 0, scene_depth_vao_ = 0;
    GLenum scene_depth_format_ = 0;
    GLuint kept_scene_depth_ = 0, kept_scene_depth_fb_ = 0;
    GLenum kept_scene_depth_format_ = 0;
    int kept_scene_depth_size_[2] = {0, 0};
    int scene_depth_sizes_[4] = {0, 0, 0, 0};  // full width, height; tile width, height
    GLuint pass_depth_ = 0, pass_depth_fb_ = 0, pass_depth_program_ = 0;
    int pass_depth_size_[2] = {0, 0};
    bool pass_depth_done_ = false;
    GLuint scene_target_fb_[2] = {0, 0};
    int scene_target_size_[2] = {0, 0};
};

}  // namespace glcast::slave
