// The GL steps of the soft-shadow renderer (shadow_renderer.h); set-up, targets and the order
// of the steps are in shadow_renderer.cpp.
#include <algorithm>

#include "slave/effects/gl_util.h"
#include "slave/effects/shadows/shadow_gl.h"
#include "slave/effects/shadows/shadow_renderer.h"

namespace glcast::slave::effects {

using namespace shadow_gl;

void ShadowRenderer::clear(const Target& target, float red) const {
    gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer);
    gl_.glClearColor(red, 0, 0, 0);
    gl_.glClear(GL_COLOR_BUFFER_BIT);
}

void ShadowRenderer::draw_into(const Target& target, GLuint p) const {
    gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer);
    gl_.glViewport(0, 0, target.width, target.height);
    gl_.glDisable(GL_DEPTH_TEST);
    gl_.glDisable(GL_BLEND);
    gl_.glUseProgram(p);
    draw_fullscreen(gl_, empty_vao_);
}

void ShadowRenderer::draw_blocks(const Target& target, GLuint p, GLuint cull, int reach, bool by_width) const {
    bind_texture(gl_, kCullUnit, cull);
    gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer);
    gl_.glViewport(0, 0, target.width, target.height);
    gl_.glDisable(GL_DEPTH_TEST);
    gl_.glDisable(GL_BLEND);
    gl_.glUseProgram(p);
    set_int(gl_, p, "u_cull_level", block_level_);
    set_int(gl_, p, "u_cull_reach", reach);
    set_int(gl_, p, "u_block_size", 1 << block_level_);
    set_int(gl_, p, "u_blocks_x", blocks_.x);
    set_int(gl_, p, "u_cull_by_width", by_width ? 1 : 0);
    gl_.glBindVertexArray(empty_vao_);
    gl_.glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, blocks_.x * blocks_.y);
}

void ShadowRenderer::reduce(const Target& target, int levels, GLuint p) {
    bind_texture(gl_, kEdgesUnit, target.texture);
    set_common_uniforms(p);
    gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer);
    gl_.glDisable(GL_DEPTH_TEST);
    gl_.glDisable(GL_BLEND);
    for (int level = 1; level <= levels; ++level) {
        // Sample only the level above while writing this one (no feedback loop).
        gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, level - 1);
        gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, level - 1);
        gl_.glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target.texture, level);
        gl_.glViewport(0, 0, std::max(1, target.width >> level), std::max(1, target.height >> level));
        draw_fullscreen(gl_, empty_vao_);
    }
    gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels);
    gl_.glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target.texture, 0);
}

void ShadowRenderer::step_done(double ShadowStepTimes::*step) {
    if (!profiling_) return;
    gl_.glFinish();
    const double t = now_ms();
    times_.*step += t - step_start_;
    step_start_ = t;
}

void ShadowRenderer::render_shadow_map(const FrameView& view, const LightFrame& frame) {
    gl_.glBindFramebuffer(GL_FRAMEBUFFER, shadow_map_.framebuffer);
    gl_.glViewport(0, 0, shadow_map_.width, shadow_map_.height);
    gl_.glDisable(GL_BLEND);
    gl_.glEnable(GL_DEPTH_TEST);
    gl_.glDepthFunc(GL_LEQUAL);
    gl_.glDepthMask(GL_TRUE);
    gl_.glClearDepth(1.0);
    gl_.glClear(GL_DEPTH_BUFFER_BIT);
    gl_.glEnable(GL_POLYGON_OFFSET_FILL);
    gl_.glPolygonOffset(float(settings_.offset_factor), float(settings_.offset_units));
    // Casters between the light and the map's near plane still cast (flattened onto it).
    gl_.glEnable(GL_DEPTH_CLAMP);
    gl_.glUseProgram(0);  // the program's own fixed-function draws
    view.redraw(frame.clip_from_eye() * glm::inverse(view.projection));
    gl_.glDisable(GL_DEPTH_CLAMP);
    gl_.glDisable(GL_POLYGON_OFFSET_FILL);
}

void ShadowRenderer::render_camera_depth(const FrameView& view, const glm::dmat4& correction) {
    gl_.glBindFramebuffer(GL_FRAMEBUFFER, camera_depth_.framebuffer);
    gl_.glViewport(0, 0, camera_depth_.width, camera_depth_.height);
    gl_.glDisable(GL_BLEND);
    gl_.glEnable(GL_DEPTH_TEST);
    gl_.glDepthFunc(GL_LEQUAL);
    gl_.glDepthMask(GL_TRUE);
    gl_.glClearDepth(1.0);
    gl_.glClear(GL_DEPTH_BUFFER_BIT);
    gl_.glUseProgram(0);
    view.redraw(correction);
}

void ShadowRenderer::hard_shadows(const Programs& p) {
    bind_texture(gl_, kDepthUnit, camera_depth_texture_);
    bind_texture(gl_, kShadowMapUnit, shadow_map_.texture);
    set_common_uniforms(p.hard);
    // Both outputs: the hard-shadow buffer and the visibility's start.
    gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, hard_.framebuffer);
    gl_.glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, visibility_.texture, 0);
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl_.glDrawBuffers(2, both);
    draw_into(hard_, p.hard);
    gl_.glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, 0, 0);
    gl_.glDrawBuffers(1, both);
}

void ShadowRenderer::detect_edges(const Programs& p) {
    bind_texture(gl_, kDepthUnit, camera_depth_texture_);
    bind_texture(gl_, kShadowMapUnit, shadow_map_.texture);
    bind_texture(gl_, kHardUnit, hard_.texture);
    set_common_uniforms(p.candidates);
    draw_into(candidates_, p.candidates);
    reduce(candidates_, block_level_, p.minmax);
    clear(edges_, 1.0f);
    set_common_uniforms(p.edges);
    set_int(gl_, p.edges, "u_silhouette_check", settings_.silhouette_check ? 1 : 0);
    draw_blocks(edges_, p.edges, candidates_.texture, 0, false);
    if (!p.lines || !settings_.line_fit) return;
    bind_texture(gl_, kEdgesUnit, edges_.texture);
    set_common_uniforms(p.lines);
    clear(lines_, 0.0f);
    draw_blocks(lines_, p.lines, candidates_.texture, 0, false);
}

void ShadowRenderer::build_min_max(const Programs& p) { reduce(edges_, levels_, p.minmax); }

void ShadowRenderer::erode(const Programs& p) {
    bind_texture(gl_, kHardUnit, hard_.texture);
    bind_texture(gl_, kEdgesUnit, edges_.texture);
    bind_texture(gl_, kLinesUnit, lines_.texture);
    set_common_uniforms(p.erode);
    set_int(gl_, p.erode, "u_levels", levels_);
    set_int(gl_, p.erode, "u_line_fit", settings_.line_fit ? 1 : 0);
    set_int(gl_, p.erode, "u_disk_profile", settings_.direct_disk_profile ? 1 : 0);
    // Pixels far from every edge keep: no region (PCF), the hard shadow (direct).
    const bool direct = settings_.method == ShadowMethod::ErosionDirect;
    if (!direct) clear(erosion_, 0.0f);
    draw_blocks(direct ? visibility_ : erosion_, p.erode, edges_.texture, block_reach_, true);
}

void ShadowRenderer::shade(const Programs& p) {
    bind_texture(gl_, kDepthUnit, camera_depth_texture_);
    bind_texture(gl_, kShadowMapUnit, shadow_map_.texture);
    bind_texture(gl_, kHardUnit, hard_.texture);
    bind_texture(gl_, kErosionUnit, erosion_.texture);
    set_common_uniforms(p.shade);
    set_int(gl_, p.shade, "u_pcf_samples", settings_.pcf_samples);
    set_int(gl_, p.shade, "u_blocker_samples", pcss_blocker_samples(settings_.method));
    if (settings_.method != ShadowMethod::ErosionPcf) {
        draw_into(visibility_, p.shade);
        return;
    }
    // Penumbra regions lie within the search radius of an edge; elsewhere the hard shadow that
    // shadow_hard.frag wrote.
    draw_blocks(visibility_, p.shade, edges_.texture, block_reach_, true);
}

void ShadowRenderer::reference(const FrameView& view, const Programs& p) {
    gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, visibility_.framebuffer);
    gl_.glClearColor(0, 0, 0, 0);
    gl_.glClear(GL_COLOR_BUFFER_BIT);
    const int n = settings_.reference_samples;
    const auto samples = area_light_samples(light_, frame_, settings_.light_size, settings_.light_angle_deg, n);
    for (const ShadowLight& sample : samples) {
        const LightFrame frame = fit_light_frame(sample, corners_, settings_.max_light_fov_deg);
        render_shadow_map(view, frame);
        step_done(&ShadowStepTimes::shadow_map);
        bind_texture(gl_, kDepthUnit, camera_depth_texture_);
        bind_texture(gl_, kShadowMapUnit, shadow_map_.texture);
        set_common_uniforms(p.reference);
        set_light_uniforms(p.reference, sample, frame);
        set_float(gl_, p.reference, "u_weight", 1.0 / n);
        gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, visibility_.framebuffer);
        gl_.glViewport(0, 0, visibility_.width, visibility_.height);
        gl_.glDisable(GL_DEPTH_TEST);
        gl_.glEnable(GL_BLEND);
        gl_.glBlendEquation(GL_FUNC_ADD);
        gl_.glBlendFunc(GL_ONE, GL_ONE);
        draw_fullscreen(gl_, empty_vao_);
        gl_.glDisable(GL_BLEND);
        step_done(&ShadowStepTimes::shading);
    }
}

void ShadowRenderer::march_screen_space(const Programs& p) {
    bind_texture(gl_, kDepthUnit, camera_depth_texture_);
    set_common_uniforms(p.screen_space);
    set_matrix(gl_, p.screen_space, "u_eye_from_clip", eye_from_work_clip_);
    set_matrix(gl_, p.screen_space, "u_clip_from_eye", glm::inverse(eye_from_work_clip_));
    const glm::dvec4 light = light_.directional ? glm::dvec4(light_.direction, 0.0) : glm::dvec4(light_.position, 1.0);
    const GLint at = gl_.glGetUniformLocation(p.screen_space, "u_light_eye");
    if (at >= 0) gl_.glUniform4f(at, float(light.x), float(light.y), float(light.z), float(light.w));
    set_int(gl_, p.screen_space, "u_steps", settings_.screen_steps);
    set_float(gl_, p.screen_space, "u_reach_px", settings_.screen_reach * tile_size_.y);
    set_float(gl_, p.screen_space, "u_max_reach", reach_);
    set_float(gl_, p.screen_space, "u_thickness", settings_.screen_thickness);
    draw_into(hard_, p.screen_space);
}

void ShadowRenderer::soften_screen_space(const Programs& p) {
    bind_texture(gl_, kHardUnit, hard_.texture);
    set_common_uniforms(p.screen_filter);
    set_int(gl_, p.screen_filter, "u_search_samples", 16);
    set_int(gl_, p.screen_filter, "u_samples", settings_.pcf_samples);
    draw_into(visibility_, p.screen_filter);
}

void ShadowRenderer::composite(const FrameView& view) {
    const GLuint p = programs_[int(settings_.method)].composite;
    bind_texture(gl_, kVisibilityUnit, visibility_.texture);
    gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(target_framebuffer_));
    gl_.glViewport(0, 0, view.width, view.height);
    gl_.glDisable(GL_DEPTH_TEST);
    gl_.glDepthMask(GL_FALSE);
    gl_.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl_.glEnable(GL_BLEND);
    gl_.glBlendEquation(GL_FUNC_ADD);
    gl_.glBlendFuncSeparate(GL_ZERO, GL_SRC_COLOR, GL_ZERO, GL_ONE);
    gl_.glUseProgram(p);
    set_vec2(gl_, p, "u_tile_offset", glm::dvec2(tile_offset_));
    set_float(gl_, p, "u_strength", settings_.strength);
    set_int(gl_, p, "u_visibility", kVisibilityUnit);
    draw_fullscreen(gl_, empty_vao_);
    gl_.glDisable(GL_BLEND);
    step_done(&ShadowStepTimes::shading);
}

}  // namespace glcast::slave::effects
