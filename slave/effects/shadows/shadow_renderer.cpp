#include "slave/effects/shadows/shadow_renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slave/effects/gl_util.h"
#include "slave/effects/shadows/shadow_gl.h"

namespace glcast::slave::effects {

using namespace shadow_gl;

namespace {

int floor_mod(int a, int b) { return ((a % b) + b) % b; }

// The clip-space map from the tile's clip space to the work area's: the tile's pixels land
// `offset` pixels in, in a framebuffer of `work` pixels (docs/shadows.md: a correction applied
// after the program's projection, like FrameView::guard_band but asymmetric).
glm::dmat4 work_from_tile_clip(glm::ivec2 tile, glm::ivec2 work, glm::ivec2 offset) {
    glm::dmat4 m(1.0);
    m[0][0] = double(tile.x) / work.x;
    m[1][1] = double(tile.y) / work.y;
    m[3][0] = double(tile.x + 2 * offset.x) / work.x - 1;
    m[3][1] = double(tile.y + 2 * offset.y) / work.y - 1;
    return m;
}

}  // namespace

ShadowRenderer::ShadowRenderer(const GlApi& gl, const ShadowSettings& settings) : gl_(gl), settings_(settings) {
    build_programs(settings_.method);
    gl_.glGenVertexArrays(1, &empty_vao_);
}

ShadowRenderer::~ShadowRenderer() {
    release_targets();
    for (auto& [key, program] : program_cache_) gl_.glDeleteProgram(program);
    if (empty_vao_) gl_.glDeleteVertexArrays(1, &empty_vao_);
}

void ShadowRenderer::set_method(ShadowMethod method) {
    build_programs(method);
    settings_.method = method;
}

GLuint ShadowRenderer::program(const std::string& fragment, const std::string& defines, bool common, bool blocks) {
    const std::string key = fragment + "|" + defines + (blocks ? "|blocks" : "");
    auto it = program_cache_.find(key);
    if (it != program_cache_.end()) return it->second;
    const std::string prefix = defines + (common ? shader_source("shadow_common.glsl") : std::string());
    const GLuint p = build_program(gl_, blocks ? "shadow_blocks.vert" : "fullscreen.vert", fragment, prefix);
    program_cache_.emplace(key, p);
    return p;
}

void ShadowRenderer::build_programs(ShadowMethod method) {
    Programs& p = programs_[int(method)];
    if (p.composite) return;
    switch (method) {
    case ShadowMethod::ErosionPcf:
    case ShadowMethod::ErosionDirect: {
        const bool direct = method == ShadowMethod::ErosionDirect;
        const std::string outlines = direct ? "" : "#define OCCLUSION_EDGES\n";
        p.hard = program("shadow_hard.frag", "", true);
        p.candidates = program("shadow_candidates.frag", outlines, true);
        p.edges = program("shadow_edges.frag", outlines, true, true);
        p.minmax = program("shadow_minmax.frag", "", false);
        p.erode = program("shadow_erode.frag", direct ? "#define EROSION_DIRECT\n" : "", true, true);
        if (direct) p.lines = program("shadow_lines.frag", "", true, true);
        else p.shade = program("shadow_shade.frag", "#define EROSION_PCF\n", true, true);
        break;
    }
    case ShadowMethod::Pcss8:
    case ShadowMethod::Pcss32:
    case ShadowMethod::Pcss64: p.shade = program("shadow_shade.frag", "", true); break;
    case ShadowMethod::Reference: p.reference = program("shadow_reference.frag", "", true); break;
    case ShadowMethod::ScreenSpace: break;
    }
    // Every method falls back to it for frames that cannot be re-rendered.
    p.screen_space = program("shadow_screen_space.frag", "", true);
    p.screen_filter = program("shadow_screen_filter.frag", "", true);
    p.composite = program("shadow_composite.frag", "", false);
}

void ShadowRenderer::release_targets() {
    for (Target* t : {&shadow_map_, &camera_depth_, &hard_, &candidates_, &edges_, &lines_, &erosion_, &visibility_}) {
        if (t->framebuffer) gl_.glDeleteFramebuffers(1, &t->framebuffer);
        if (t->texture) gl_.glDeleteTextures(1, &t->texture);
        *t = Target{};
    }
}

void ShadowRenderer::ensure_targets(const FrameView& view, bool rerender_depth) {
    const int search = settings_.max_penumbra_px;
    const int guard = rerender_depth ? search : 0;
    // Levels until a 2x2 block of the coarsest covers the largest search square.
    levels_ = int(std::ceil(std::log2(2.0 * search)));
    const int block = 1 << levels_;
    tile_offset_ = rerender_depth ? glm::ivec2(guard + floor_mod(view.canvas_x - guard, block),
                                               guard + floor_mod(view.canvas_y - guard, block))
                                  : glm::ivec2(0);
    const glm::ivec2 work(view.width + tile_offset_.x + guard, view.height + tile_offset_.y + guard);
    canvas_origin_ = glm::ivec2(view.canvas_x, view.canvas_y) - tile_offset_;
    levels_ = std::min(levels_, int(std::floor(std::log2(double(std::max(work.x, work.y))))));
    // Blocks of 16 pixels for the culled steps (shadow_blocks.vert), fewer levels permitting.
    block_level_ = std::min(4, levels_);
    const int block_size = 1 << block_level_;
    blocks_ = (work + block_size - 1) / block_size;
    block_reach_ = (search + 2 + block_size - 1) / block_size;

    const int map = settings_.map_size;
    if (shadow_map_.width != map) {
        if (shadow_map_.framebuffer) gl_.glDeleteFramebuffers(1, &shadow_map_.framebuffer);
        if (shadow_map_.texture) gl_.glDeleteTextures(1, &shadow_map_.texture);
        shadow_map_.texture = make_texture(gl_, GL_DEPTH_COMPONENT32F, map, map);
        shadow_map_.framebuffer = make_framebuffer(gl_, 0, shadow_map_.texture);
        shadow_map_.width = shadow_map_.height = map;
    }
    if (work == work_size_ && edges_.texture && levels_ == edge_levels_) return;
    work_size_ = work;
    edge_levels_ = levels_;
    const Target keep_map = shadow_map_;
    shadow_map_ = Target{};
    release_targets();
    shadow_map_ = keep_map;
    auto make = [&](Target& t, GLenum format, int mip_levels, bool depth) {
        t.texture = make_texture(gl_, format, work.x, work.y, false, mip_levels);
        t.framebuffer = depth ? make_framebuffer(gl_, 0, t.texture) : make_framebuffer(gl_, t.texture, 0);
        t.width = work.x;
        t.height = work.y;
    };
    make(camera_depth_, GL_DEPTH_COMPONENT32F, 1, true);
    make(hard_, GL_RGBA16F, 1, false);
    make(candidates_, GL_R8, block_level_ + 1, false);
    make(edges_, GL_RGBA16F, levels_ + 1, false);
    make(lines_, GL_RG16F, 1, false);
    make(erosion_, GL_RG16F, 1, false);
    make(visibility_, GL_RG32F, 1, false);
}

void ShadowRenderer::set_light_uniforms(GLuint p, const ShadowLight& light, const LightFrame& frame) const {
    set_matrix(gl_, p, "u_light_view_from_clip", frame.view * eye_from_work_clip_);
    set_matrix(gl_, p, "u_light_clip_from_clip", frame.clip_from_eye() * eye_from_work_clip_);
    const glm::dvec3 camera(frame.view[3]);
    const GLint at = gl_.glGetUniformLocation(p, "u_camera_in_light_view");
    if (at >= 0) gl_.glUniform3f(at, float(camera.x), float(camera.y), float(camera.z));
    set_int(gl_, p, "u_light_ortho", frame.orthographic ? 1 : 0);
    set_float(gl_, p, "u_light_near", frame.near);
    set_float(gl_, p, "u_light_far", frame.far);
    set_vec2(gl_, p, "u_uv_per_unit", frame.uv_per_unit);
    // penumbra_world() in the shaders: the same formula as penumbra_width() here.
    const double spread = light.directional ? penumbra_width(light, 0, settings_.light_angle_deg, 1, 0)
                                            : settings_.light_size;
    set_float(gl_, p, "u_light_spread", spread);
}

void ShadowRenderer::set_common_uniforms(GLuint p) const {
    gl_.glUseProgram(p);
    set_int(gl_, p, "u_depth", kDepthUnit);
    set_int(gl_, p, "u_shadow_map", kShadowMapUnit);
    set_int(gl_, p, "u_hard", kHardUnit);
    set_int(gl_, p, "u_edges", kEdgesUnit);
    set_int(gl_, p, "u_source", kEdgesUnit);
    set_int(gl_, p, "u_lines", kLinesUnit);
    set_int(gl_, p, "u_erosion", kErosionUnit);
    set_int(gl_, p, "u_visibility", kVisibilityUnit);
    set_int(gl_, p, "u_cull", kCullUnit);
    const glm::dvec4 eye_z(eye_from_work_clip_[0][2], eye_from_work_clip_[1][2], eye_from_work_clip_[2][2],
                           eye_from_work_clip_[3][2]);
    const GLint at = gl_.glGetUniformLocation(p, "u_eye_z_row");
    if (at >= 0) gl_.glUniform4f(at, float(eye_z.x), float(eye_z.y), float(eye_z.z), float(eye_z.w));
    set_vec2(gl_, p, "u_work_size", glm::dvec2(work_size_));
    set_vec2(gl_, p, "u_canvas_origin", glm::dvec2(canvas_origin_));
    set_float(gl_, p, "u_focal_px", focal_px_);
    set_float(gl_, p, "u_max_radius_px", settings_.max_penumbra_px);
    set_float(gl_, p, "u_map_size", settings_.map_size);
    set_float(gl_, p, "u_bias_texels", settings_.bias_texels);
    set_light_uniforms(p, light_, frame_);
}

bool ShadowRenderer::render(const FrameView& view, std::string& why) {
    if (!view.view_known) {
        why = "no draw with a perspective projection this frame";
        return false;
    }
    if (!view.redraw && !view.depth_texture) {
        why = "the stream's draws cannot be re-rendered and the window's depth is not at hand";
        return false;
    }
    gl_.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target_framebuffer_);
    screen_space_ = settings_.method == ShadowMethod::ScreenSpace || !view.redraw;
    // Screen-space marching reads what the window shows: no guard band to re-render.
    const bool rerender = view.redraw && (settings_.rerender_depth || !view.depth_texture) && !screen_space_;
    ensure_targets(view, rerender);
    tile_size_ = {view.width, view.height};
    const glm::dmat4 to_work = work_from_tile_clip({view.width, view.height}, work_size_, tile_offset_);
    eye_from_work_clip_ = glm::inverse(to_work * view.tile_clip_from_eye);
    const double fx = std::abs(view.tile_clip_from_eye[0][0]) * 0.5 * view.width;
    const double fy = std::abs(view.tile_clip_from_eye[1][1]) * 0.5 * view.height;
    focal_px_ = std::sqrt(fx * fy);
    light_ = choose_light(view, settings_);
    reach_ = shadow_reach(settings_, view.projection);
    corners_ = view_frustum_corners(view.projection, reach_);
    frame_ = fit_light_frame(light_, corners_, settings_.max_light_fov_deg);

    times_ = ShadowStepTimes{};
    if (profiling_) gl_.glFinish();
    step_start_ = now_ms();
    const ShadowMethod method = screen_space_ ? ShadowMethod::ScreenSpace : settings_.method;
    if (method != ShadowMethod::Reference && method != ShadowMethod::ScreenSpace) {
        render_shadow_map(view, frame_);
        step_done(&ShadowStepTimes::shadow_map);
    }
    if (rerender) {
        render_camera_depth(view, to_work * view.tile_clip_from_app_clip);
        camera_depth_texture_ = camera_depth_.texture;
    } else {
        camera_depth_texture_ = view.depth_texture();
    }
    const Programs& p = programs_[int(settings_.method)];
    switch (method) {
    case ShadowMethod::ScreenSpace:
        march_screen_space(p);
        step_done(&ShadowStepTimes::hard_shadows);
        soften_screen_space(p);
        step_done(&ShadowStepTimes::shading);
        break;
    case ShadowMethod::ErosionPcf:
    case ShadowMethod::ErosionDirect:
        hard_shadows(p);
        step_done(&ShadowStepTimes::hard_shadows);
        detect_edges(p);
        step_done(&ShadowStepTimes::edge_detection);
        build_min_max(p);
        erode(p);
        step_done(&ShadowStepTimes::erosion);
        if (method == ShadowMethod::ErosionPcf) {
            shade(p);
            step_done(&ShadowStepTimes::shading);
        }
        break;
    case ShadowMethod::Pcss8:
    case ShadowMethod::Pcss32:
    case ShadowMethod::Pcss64:
        step_done(&ShadowStepTimes::hard_shadows);
        shade(p);
        step_done(&ShadowStepTimes::shading);
        break;
    case ShadowMethod::Reference:
        step_done(&ShadowStepTimes::hard_shadows);
        reference(view, p);
        break;
    }
    return true;
}

std::vector<float> ShadowRenderer::read_tile(GLuint texture, int channel) const {
    std::vector<float> all(size_t(work_size_.x) * work_size_.y * 4);
    gl_.glActiveTexture(GL_TEXTURE0);
    gl_.glBindTexture(GL_TEXTURE_2D, texture);
    gl_.glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, all.data());
    const int w = tile_size_.x, h = tile_size_.y;
    std::vector<float> tile(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            tile[size_t(y) * w + x] = all[(size_t(y + tile_offset_.y) * work_size_.x + x + tile_offset_.x) * 4 + channel];
    return tile;
}

}  // namespace glcast::slave::effects
