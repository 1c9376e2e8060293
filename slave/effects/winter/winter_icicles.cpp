#include "slave/effects/winter/winter_icicles.h"

#include <cmath>

#include "slave/effects/gl_util.h"

namespace glcast::slave::effects {

IcicleStage::IcicleStage(const GlApi& gl, const IcicleSettings& settings) : gl_(gl), settings_(settings) {
    const std::vector<std::string> libraries = {"winter_icicle_common.glsl", "winter_edges.glsl"};
    roots_program_ = build_winter_program(gl, "fullscreen.vert", "winter_icicle_roots.frag", libraries);
    icicles_program_ = build_winter_program(gl, "winter_icicles.vert", "winter_icicles.frag", libraries);
    gl.glGenVertexArrays(1, &empty_vao_);
}

IcicleStage::~IcicleStage() {
    gl_.glDeleteProgram(roots_program_);
    gl_.glDeleteProgram(icicles_program_);
    gl_.glDeleteVertexArrays(1, &empty_vao_);
    if (roots_framebuffer_) gl_.glDeleteFramebuffers(1, &roots_framebuffer_);
    const GLuint textures[] = {roots_texture_, scene_texture_};
    gl_.glDeleteTextures(2, textures);
}

void IcicleStage::set_icicle_uniforms(GLuint p, const FrameView& view, const WinterFrame& frame) const {
    const GlApi& gl = gl_;
    set_uniform(gl, p, "icicle_spacing", frame.spacing_px);
    set_seed_uniform(gl, p, "icicle_seed_bits", settings_.seed);
    set_uniform(gl, p, "icicle_density", settings_.density);
    set_uniform(gl, p, "icicle_radius", glm::dvec2(frame.radius_min_px, frame.radius_max_px));
    set_uniform(gl, p, "icicle_length_max", frame.length_max_px);
    set_uniform(gl, p, "icicle_growth_frames", settings_.growth_frames);
    set_uniform(gl, p, "icicle_frame", double(view.frame));
    set_edge_uniforms(gl, p, frame);
}

void IcicleStage::run(const FrameView& view, const WinterFrame& frame, const SurfaceBuffers& surfaces, GLuint cover,
                      GLuint window_depth) {
    const GlApi& gl = gl_;
    // The ice refracts the window as it is now, snow included: copy it before drawing over it.
    copy_window(gl, scene_texture_, scene_size_, view.width, view.height);

    // Candidate columns over the guard-band buffers' canvas range.
    const int canvas_left = view.canvas_x - frame.guard;
    const int first_cell = int(std::floor(canvas_left / frame.spacing_px));
    const int last_cell = int(std::floor((canvas_left + frame.buffer_width - 1) / frame.spacing_px));
    const int cells = last_cell - first_cell + 1;
    if (cells != roots_width_ || frame.buffer_height != roots_height_) {
        if (roots_framebuffer_) {
            gl.glDeleteFramebuffers(1, &roots_framebuffer_);
            gl.glDeleteTextures(1, &roots_texture_);
        }
        roots_texture_ = make_texture(gl, GL_RGBA32F, cells, frame.buffer_height);
        roots_framebuffer_ = make_framebuffer(gl, roots_texture_, 0);
        roots_width_ = cells;
        roots_height_ = frame.buffer_height;
    }
    gl.glBindFramebuffer(GL_FRAMEBUFFER, roots_framebuffer_);
    gl.glViewport(0, 0, roots_width_, roots_height_);
    gl.glDisable(GL_BLEND);
    gl.glDisable(GL_DEPTH_TEST);
    GLuint p = roots_program_;
    gl.glUseProgram(p);
    set_icicle_uniforms(p, view, frame);
    bind_sampler(gl, p, "cover", 0, cover);
    bind_sampler(gl, p, "normals", 1, surfaces.normals());
    set_uniform(gl, p, "buffer_size", glm::dvec2(frame.buffer_width, frame.buffer_height));
    set_uniform(gl, p, "canvas_origin", glm::dvec2(canvas_left, view.canvas_y - frame.guard));
    set_uniform(gl, p, "first_cell", first_cell);
    draw_fullscreen(gl, empty_vao_);

    gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.glViewport(0, 0, view.width, view.height);
    p = icicles_program_;
    gl.glUseProgram(p);
    set_icicle_uniforms(p, view, frame);
    bind_sampler(gl, p, "roots", 0, roots_texture_);
    bind_sampler(gl, p, "scene", 1, scene_texture_);
    bind_sampler(gl, p, "window_depth", 2, window_depth);
    set_uniform(gl, p, "eye_from_tile_clip", view.eye_from_tile_clip);
    set_uniform(gl, p, "tile_size", glm::dvec2(view.width, view.height));
    set_uniform(gl, p, "guard", frame.guard);
    set_uniform(gl, p, "canvas_offset", glm::dvec2(view.canvas_x, view.canvas_y));
    set_uniform(gl, p, "first_cell", first_cell);
    set_uniform(gl, p, "cell_count", cells);
    set_uniform(gl, p, "taper", settings_.taper);
    set_uniform(gl, p, "refraction", settings_.refraction);
    set_uniform(gl, p, "light_eye", frame.light_eye);
    gl.glEnable(GL_BLEND);
    gl.glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    gl.glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    // One quad per roots texel, in (row, cell) order: the same order on every tile, so where
    // two icicles overlap the same one is drawn last everywhere.
    gl.glBindVertexArray(empty_vao_);
    gl.glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, cells * frame.buffer_height);
    gl.glDisable(GL_BLEND);
}

}  // namespace glcast::slave::effects
