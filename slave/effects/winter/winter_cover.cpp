#include "slave/effects/winter/winter_cover.h"

#include <algorithm>

#include "slave/effects/gl_util.h"

namespace glcast::slave::effects {

CoverStage::CoverStage(const GlApi& gl, const CoverSettings& settings) : gl_(gl), settings_(settings) {
    classify_program_ = build_winter_program(gl, "fullscreen.vert", "winter_cover.frag");
    snow_program_ = build_winter_program(gl, "fullscreen.vert", "winter_snow.frag", {"winter_edges.glsl"});
    gl.glGenVertexArrays(1, &empty_vao_);
    if (!settings.mask_path.empty()) {
        // PNG rows run top to bottom, GL's from the bottom: upload flipped, so that texture
        // coordinates are canvas pixels over the canvas size.
        const Image mask = flip_rows(settings.mask);
        mask_texture_ = make_texture(gl, GL_RGBA8, mask.width, mask.height, true);
        gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        gl.glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, mask.width, mask.height, GL_RGBA, GL_UNSIGNED_BYTE, mask.rgba.data());
        gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    }
}

CoverStage::~CoverStage() {
    gl_.glDeleteProgram(classify_program_);
    gl_.glDeleteProgram(snow_program_);
    gl_.glDeleteVertexArrays(1, &empty_vao_);
    if (mask_texture_) gl_.glDeleteTextures(1, &mask_texture_);
    resize(0, 0);
}

void CoverStage::resize(int width, int height) {
    if (width == width_ && height == height_) return;
    if (framebuffer_) {
        gl_.glDeleteFramebuffers(1, &framebuffer_);
        gl_.glDeleteTextures(1, &cover_texture_);
        framebuffer_ = cover_texture_ = 0;
    }
    width_ = width;
    height_ = height;
    if (width == 0 || height == 0) return;
    cover_texture_ = make_texture(gl_, GL_RGBA16F, width, height);
    framebuffer_ = make_framebuffer(gl_, cover_texture_, 0);
}

void CoverStage::classify(const FrameView& view, const WinterFrame& frame, const SurfaceBuffers& surfaces,
                          GLuint window_depth) {
    const GlApi& gl = gl_;
    const CoverSettings& c = settings_;
    resize(frame.buffer_width, frame.buffer_height);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    gl.glViewport(0, 0, width_, height_);
    gl.glDisable(GL_BLEND);
    gl.glDisable(GL_DEPTH_TEST);

    const GLuint p = classify_program_;
    gl.glUseProgram(p);
    bind_sampler(gl, p, "normals", 0, surfaces.normals());
    bind_sampler(gl, p, "positions", 1, surfaces.positions());
    bind_sampler(gl, p, "window_depth", 2, window_depth);
    bind_sampler(gl, p, "mask", 3, mask_texture_);
    set_uniform(gl, p, "check_visibility", surfaces.source() != NormalSource::Depth ? 1 : 0);
    set_uniform(gl, p, "guard", frame.guard);
    set_uniform(gl, p, "tile_size", glm::dvec2(view.width, view.height));
    set_uniform(gl, p, "eye_from_tile_clip", view.eye_from_tile_clip);
    set_uniform(gl, p, "world_from_eye", frame.world_from_eye);
    set_uniform(gl, p, "up_eye", frame.up_eye);
    set_uniform(gl, p, "spread_deg", c.spread_deg);
    // smoothstep needs two distinct edges.
    set_uniform(gl, p, "softness_deg", std::max(c.softness_deg, 1e-3));
    set_uniform(gl, p, "random_spread", c.random_spread ? 1 : 0);
    set_uniform(gl, p, "random_shape", glm::dvec3(c.random_offset, c.random_stepper, c.random_exponent));
    set_uniform(gl, p, "random_scale", c.random_scale);
    set_uniform(gl, p, "density", c.density * frame.cover_fraction);
    set_uniform(gl, p, "edge", c.edge);
    set_uniform(gl, p, "noise_scale", c.noise_scale);
    set_seed_uniform(gl, p, "seed_bits", c.seed);
    set_uniform(gl, p, "has_mask", mask_texture_ ? 1 : 0);
    set_uniform(gl, p, "canvas_origin", glm::dvec2(view.canvas_x - frame.guard, view.canvas_y - frame.guard));
    set_uniform(gl, p, "canvas_size", glm::dvec2(frame.canvas_width, frame.canvas_height));
    draw_fullscreen(gl, empty_vao_);
}

void CoverStage::composite(const FrameView& view, const WinterFrame& frame, const SurfaceBuffers& surfaces) {
    const GlApi& gl = gl_;
    gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
    const GLuint p = snow_program_;
    gl.glUseProgram(p);
    bind_sampler(gl, p, "cover", 0, cover_texture_);
    bind_sampler(gl, p, "normals", 1, surfaces.normals());
    bind_sampler(gl, p, "positions", 2, surfaces.positions());
    set_uniform(gl, p, "guard", frame.guard);
    set_uniform(gl, p, "canvas_offset", glm::dvec2(view.canvas_x, view.canvas_y));
    set_uniform(gl, p, "world_from_eye", frame.world_from_eye);
    set_uniform(gl, p, "up_eye", frame.up_eye);
    set_uniform(gl, p, "light_eye", frame.light_eye);
    set_uniform(gl, p, "noise_scale", settings_.noise_scale);
    set_uniform(gl, p, "brightness", settings_.brightness);
    set_seed_uniform(gl, p, "seed_bits", settings_.seed);
    set_edge_uniforms(gl, p, frame);
    set_uniform(gl, p, "lip_rows", frame.lip_rows);
    gl.glDisable(GL_DEPTH_TEST);
    gl.glEnable(GL_BLEND);
    // The window's alpha (if it has any) stays the program's.
    gl.glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    gl.glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    draw_fullscreen(gl, empty_vao_);
    gl.glDisable(GL_BLEND);
}

}  // namespace glcast::slave::effects
