#include "slave/tile_adapter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "common/gl_headers.h"
#include "common/gl_state.h"
#include "slave/program_camera.h"
#include "slave/replayer.h"
#include "slave/tile_adapter_state.h"

namespace glcast::slave {

TileAdapter::TileAdapter(Replayer& core) : core_(core) {}
TileAdapter::~TileAdapter() = default;

TileAdapter::State& TileAdapter::state() {
    auto& s = states_[core_.current().id];
    if (!s) s = std::make_unique<State>();
    return *s;
}

TileAdapter::Shared& TileAdapter::shared() {
    auto& s = shared_[core_.current().names.shared.get()];
    if (!s) s = std::make_unique<Shared>(core_.api());
    return *s;
}

void TileAdapter::reset() {
    states_.clear();
    shared_.clear();
}

// A destroyed context's state goes with it, and a share group's once no live context has it (its
// address may come back for a new group, which must not find the old programs' uniforms).
void TileAdapter::context_removed(uint32_t id) {
    states_.erase(id);
    for (auto it = shared_.begin(); it != shared_.end();) {
        const bool live = std::any_of(core_.contexts().begin(), core_.contexts().end(),
                                      [&](const auto& c) { return c.second->names.shared.get() == it->first; });
        it = live ? std::next(it) : shared_.erase(it);
    }
}

bool TileAdapter::wants(uint32_t, const CommandInfo* info) const {
    if (!info) return false;
    const CommandSemantics& s = info->sem;
    const bool view = patching();
    const bool draw = s.redraw == RedrawKind::Draw || s.redraw == RedrawKind::Begin;
    return s.window != WindowMapping::Nothing || s.shader_type >= 0 || (s.flags & kSemLinksProgram) ||
           (draw && maps_fragments()) || (view && (s.matrix != MatrixOp::Nothing || s.redraw == RedrawKind::Draw || s.redraw == RedrawKind::Begin ||
                     s.redraw == RedrawKind::End || s.writes_ns == Ns::framebuffer || (s.flags & kSemDeletes)));
}

bool TileAdapter::patching() const {
    return core_.options().view.enabled || core_.options().effects.redraws();
}

bool TileAdapter::maps_fragments() const { return core_.options().tile.enabled || patching(); }

bool TileAdapter::mapping() { return core_.options().tile.enabled && core_.current().drawing_to_window; }

double TileAdapter::pixel_scale() {
    const SlaveContext& ctx = core_.current();
    const TileMapping& t = core_.options().tile;
    return 0.5 * (t.sx(ctx.master_width) + t.sy(ctx.master_height));
}

void TileAdapter::made_current(SlaveContext& ctx, bool first) {
    if (!first) {
        // The master's window was resized: the program's rectangles, which it need not set again,
        // map onto the canvas by the new size (a viewport mapped for the old one may miss the tile).
        const State& s = state();
        if (core_.options().tile.enabled && (s.mapped_for[0] != ctx.master_width || s.mapped_for[1] != ctx.master_height))
            apply_window_rects();
        return;
    }
    // GLX starts a context with viewport and scissor box covering the window it is first made
    // current to; backends differ (a 1x1 buffer, a window created at another size).
    const int mw = ctx.master_width ? ctx.master_width : ctx.width;
    const int mh = ctx.master_height ? ctx.master_height : ctx.height;
    if (mw <= 0 || mh <= 0) return;
    State& s = state();
    for (int i = 0; i < kViewports; ++i) {
        const double v[4] = {0, 0, double(mw), double(mh)};
        const int32_t b[4] = {0, 0, mw, mh};
        std::memcpy(s.viewport[i], v, sizeof v);
        std::memcpy(s.scissor[i], b, sizeof b);
    }
    apply_window_rects();
}

void TileAdapter::program_viewport(int32_t out[4]) {
    const State& s = state();
    for (int i = 0; i < 4; ++i) out[i] = int32_t(s.viewport[0][i]);
}

// Re-issues the program's viewports and scissor boxes for the current draw framebuffer.
void TileAdapter::apply_window_rects() {
    const SlaveContext& ctx = core_.current();
    const TileMapping& t = core_.options().tile;
    const GlApi& gl = core_.api();
    State& s = state();
    const bool map = t.enabled && ctx.drawing_to_window;
    const int W = ctx.master_width, H = ctx.master_height;
    if (map) s.mapped_for[0] = W, s.mapped_for[1] = H;
    GLfloat viewports[kViewports][4];
    GLint scissors[kViewports][4];
    for (int i = 0; i < (s.indexed ? kViewports : 1); ++i) {
        const double* v = s.viewport[i];
        const int32_t* b = s.scissor[i];
        if (map) {
            const double mv[4] = {double(t.map_x(v[0], W)), double(t.map_y(v[1], H)), double(t.map_w(v[0], v[2], W)),
                                  double(t.map_h(v[1], v[3], H))};
            for (int k = 0; k < 4; ++k) viewports[i][k] = GLfloat(mv[k]);
            scissors[i][0] = GLint(t.map_x(b[0], W)), scissors[i][1] = GLint(t.map_y(b[1], H));
            scissors[i][2] = GLint(t.map_w(b[0], b[2], W)), scissors[i][3] = GLint(t.map_h(b[1], b[3], H));
        } else {
            for (int k = 0; k < 4; ++k) viewports[i][k] = GLfloat(v[k]), scissors[i][k] = b[k];
        }
    }
    // (line width and point size once the program set them: context state, scaled with the
    // canvas for the window's draws only)
    const double scale = map ? pixel_scale() : 1.0;
    if (s.line_width > 0) gl.glLineWidth(GLfloat(s.line_width * scale));
    if (s.point_size > 0) gl.glPointSize(GLfloat(s.point_size * scale));
    if (s.indexed) {
        gl.glViewportArrayv(0, kViewports, &viewports[0][0]);
        gl.glScissorArrayv(0, kViewports, &scissors[0][0]);
        return;
    }
    gl.glViewport(GLint(viewports[0][0]), GLint(viewports[0][1]), GLsizei(viewports[0][2]), GLsizei(viewports[0][3]));
    gl.glScissor(scissors[0][0], scissors[0][1], scissors[0][2], scissors[0][3]);
}

// Before a call that opens a draw (a draw call outside glBegin/glEnd, or glBegin itself).
void TileAdapter::before_call(const Call& c, const uint8_t*, size_t) {
    redraw_refused_ = false;
    const RedrawKind k = c.info->sem.redraw;
    if (k != RedrawKind::Draw && k != RedrawKind::Begin && k != RedrawKind::End) return;
    State& s = state();
    const bool opens = k != RedrawKind::End && !s.in_begin_end;
    if (redrawing_ || patching()) {
        opening_begin_ = k == RedrawKind::Begin;
        if (k == RedrawKind::End) s.in_begin_end = false;
        else if (opens) correct_projection();
        if (k == RedrawKind::Begin) s.in_begin_end = true;
    }
    // (after the projection's correction, which may redirect the draw: shown_scene.h)
    if (opens && maps_fragments()) correct_fragcoord(program_in_use());
}

// A fragment shader that reads gl_FragCoord (a post-processing pass that samples its input at the
// fragment's window position over the window's size) drawn with another viewport than the
// program's, on a tile of a wall or a canvas, reads where its fragment lies in the program's
// viewport. Into the program's own framebuffer objects the viewport is the program's: the identity.
void TileAdapter::correct_fragcoord(uint32_t program) {
    if (!program) return;
    Shared& group = shared();
    const GlApi& gl = core_.api();
    auto it = group.fragcoord_uniforms.find(program);
    if (it == group.fragcoord_uniforms.end())
        it = group.fragcoord_uniforms.emplace(program, Shared::FragCoord{gl.glGetUniformLocation(program, "glcast_fragcoord")})
                 .first;
    if (it->second.location < 0) return;
    GLint actual[4] = {0, 0, 0, 0};
    gl.glGetIntegerv(GL_VIEWPORT, actual);
    const State& s = state();
    const double drawn[4] = {double(actual[0]), double(actual[1]), double(actual[2]), double(actual[3])};
    float value[4];
    window_fragcoord(s.viewport[0], drawn, value);
    if (std::memcmp(value, it->second.value, sizeof value) == 0) return;
    gl.glUniform4fv(it->second.location, 1, value);
    std::memcpy(it->second.value, value, sizeof value);
}

// Window coordinates of the program in the tile's framebuffer, pixel sizes scaled with the
// canvas. The program's rectangles are kept as it set them and applied mapped while the
// window is the draw framebuffer, as they are while one of its own framebuffer objects is.
bool TileAdapter::replace_call(const Call& c) {
    if (redraw_refused_) return true;  // a redrawn draw that cannot be moved is left out
    const CommandSemantics& sem = c.info->sem;
    const int8_t* p = sem.window_params;
    auto arg = [&](int k) { return p[k]; };
    const bool tile = core_.options().tile.enabled;
    const GlApi& gl = core_.api();
    switch (sem.window) {
    case WindowMapping::Viewport:
    case WindowMapping::Scissor: {
        State& s = state();
        for (int i = 0; i < kViewports; ++i)
            for (int k = 0; k < 4; ++k) {
                if (sem.window == WindowMapping::Viewport) s.viewport[i][k] = core_.value<int32_t>(c, arg(k));
                else s.scissor[i][k] = core_.value<int32_t>(c, arg(k));
            }
        if (!tile) return false;
        apply_window_rects();
        return true;
    }
    case WindowMapping::ViewportIndexed:
    case WindowMapping::ScissorIndexed:
    case WindowMapping::ViewportArray:
    case WindowMapping::ScissorArray: {
        const bool viewport = sem.window == WindowMapping::ViewportIndexed || sem.window == WindowMapping::ViewportArray;
        const bool array = sem.window == WindowMapping::ViewportArray || sem.window == WindowMapping::ScissorArray;
        State& s = state();
        s.indexed = true;
        const int64_t first = core_.value<uint32_t>(c, arg(0));
        const int64_t count = array ? core_.value<int32_t>(c, arg(1)) : 1;
        // One value each (glViewportIndexedf), or an array of `count` rectangles.
        const int values_at = array ? 2 : 1;
        const bool by_value = !array && p[2] >= 0;
        const PtrRecord* rec = by_value ? nullptr : &c.args[size_t(arg(values_at))].ptr;
        for (int64_t i = 0; i < count && first + i < kViewports && first + i >= 0; ++i) {
            for (int k = 0; k < 4; ++k) {
                double v = 0;
                if (by_value) {
                    v = viewport ? core_.value<float>(c, arg(1 + k)) : core_.value<int32_t>(c, arg(1 + k));
                } else if (rec->tag == PtrTag::Data && uint64_t(4 * i + k) < rec->count) {
                    if (viewport) { float f; std::memcpy(&f, rec->data + 4 * (4 * i + k), 4); v = f; }
                    else { int32_t n; std::memcpy(&n, rec->data + 4 * (4 * i + k), 4); v = n; }
                }
                if (viewport) s.viewport[first + i][k] = v;
                else s.scissor[first + i][k] = int32_t(v);
            }
        }
        if (!tile) return false;
        apply_window_rects();
        return true;
    }
    case WindowMapping::LineWidth:
    case WindowMapping::PointSize: {
        // Context state, not the framebuffer's: kept as the program set it, and scaled with the
        // canvas only while the window is bound (apply_window_rects does it again at each switch).
        State& s = state();
        (sem.window == WindowMapping::LineWidth ? s.line_width : s.point_size) = core_.value<GLfloat>(c, arg(0));
        if (!mapping()) return false;
        const GLfloat v = GLfloat(core_.value<GLfloat>(c, arg(0)) * pixel_scale());
        if (sem.window == WindowMapping::LineWidth) gl.glLineWidth(v);
        else gl.glPointSize(v);
        return true;
    }
    case WindowMapping::PixelZoom: {
        if (!mapping()) return false;
        const SlaveContext& ctx = core_.current();
        const TileMapping& t = core_.options().tile;
        gl.glPixelZoom(GLfloat(core_.value<GLfloat>(c, arg(0)) * t.sx(ctx.master_width)),
                       GLfloat(core_.value<GLfloat>(c, arg(1)) * t.sy(ctx.master_height)));
        return true;
    }
    case WindowMapping::Blit: {
        // Into the window: the destination rectangle is window coordinates. (Reading the window
        // back on a tile would need the other tiles' pixels; that source is left as it is.)
        if (!mapping()) return false;
        const SlaveContext& ctx = core_.current();
        const TileMapping& t = core_.options().tile;
        int32_t destination[4], source[4], mapped_rect[4];
        for (int k = 0; k < 4; ++k)
            destination[k] = core_.value<GLint>(c, arg(k)), source[k] = core_.value<GLint>(c, arg(4 + k));
        const auto mask = GLbitfield(core_.value<GLuint>(c, arg(8)));
        if (shows_scene_by_blit(source, destination, mask)) return true;  // (a rotated tile)
        // A blit of the scene's view into the window shows it, as its first flat draw would: what
        // the window gets after it (a HUD) lies on the program's screen.
        if (State& s = state(); core_.options().view.enabled && s.scene_view && (mask & GL_COLOR_BUFFER_BIT))
            s.scene_shown = true;
        // The call as the program made it but for the mapped rectangle, replayed as any call is
        // (whatever the command's other parameters are).
        Call mapped = c;
        for (int k = 0; k < 4; ++k) {
            const double v = destination[k];
            mapped_rect[k] = int32_t(int64_t(k % 2 == 0 ? t.map_x(v, ctx.master_width) : t.map_y(v, ctx.master_height)));
            mapped.args[size_t(arg(k))].bits = uint32_t(mapped_rect[k]);  // as the decoder holds an i32: its 4 bytes
        }
        if (ScaledBlit::needed(gl, source, mapped_rect)) {  // a multisampled source at the tile's scale
            State& s = state();
            try {
                if (!s.scaled_blit) s.scaled_blit = std::make_shared<ScaledBlit>();
                s.scaled_blit->blit(gl, source, mapped_rect, mask, GLenum(core_.value<GLenum>(c, arg(9))));
            } catch (const std::runtime_error& e) {
                std::fprintf(stderr, "glcast: a multisampled blit into the window cannot be scaled to this tile: %s\n",
                             e.what());
            }
            return true;
        }
        if (!kReplay[c.opcode]) return false;
        kReplay[c.opcode](core_, mapped);
        return true;
    }
    case WindowMapping::DrawFramebuffer:
    case WindowMapping::Nothing: return false;
    }
    return false;
}

void TileAdapter::after_call(const Call& c) {
    const CommandSemantics& sem = c.info->sem;
    if (!redrawing_ && (sem.redraw == RedrawKind::Draw || sem.redraw == RedrawKind::End) && core_.current_or_null() &&
        !state().in_begin_end)
        finish_shown_scene(c);  // (a scene shown in part of the window, on a rotated tile)
    if (sem.window == WindowMapping::DrawFramebuffer) {
        const auto target = core_.value<GLenum>(c, sem.window_params[0]);
        if (target == GL_FRAMEBUFFER || target == GL_DRAW_FRAMEBUFFER) {
            SlaveContext& ctx = core_.current();
            state().draw_framebuffer = c.args[size_t(sem.window_params[1])].bits;
            const bool window = c.args[size_t(sem.window_params[1])].bits == 0;
            if (window != ctx.drawing_to_window) {
                ctx.drawing_to_window = window;
                if (core_.options().tile.enabled) apply_window_rects();
            }
        }
    }
    if (sem.writes_ns == Ns::framebuffer || (sem.flags & kSemDeletes)) state().attachments.clear();
    if (sem.shader_type >= 0) shared().shader_types[c.ret.bits] = uint32_t(c.args[size_t(sem.shader_type)].bits);
    if (sem.flags & kSemLinksProgram) {  // linking resets uniforms, and may change which there are
        shared().clip_uniforms.clear();
        shared().fragcoord_uniforms.clear();
        shared().cameras.forget();
        // (what its shaders read, for finding its camera: not read where no tile turns and no pass runs)
        uint64_t program = 0;
        if ((patching() || core_.options().effects.any()) &&
            core_.current().names.map(Ns::program).find(c.args[size_t(sem.subject_params[0])].bits, program))
            shared().cameras.linked(uint32_t(program));
    }
    if (sem.matrix != MatrixOp::Nothing && (redrawing_ || core_.options().view.enabled)) track_matrix(c);
}

void TileAdapter::begin_redraw(const glm::dmat4& correction, bool programs) {
    saved_ = std::make_unique<State>(state());
    saved_opening_begin_ = opening_begin_;
    GLint mode = GL_MODELVIEW;
    core_.api().glGetIntegerv(GL_MATRIX_MODE, &mode);
    state().matrix_mode = uint32_t(mode);
    // A redraw may run just before the program's glBegin that opens its first overlay, which this
    // adapter has already seen: the redraw's own draws open outside any glBegin/glEnd.
    state().in_begin_end = false;
    redrawing_ = true;
    redraw_programs_ = programs;
    redraw_correction_ = correction;
}

void TileAdapter::end_redraw() {
    redrawing_ = redraw_programs_ = redraw_refused_ = false;
    if (saved_) {
        State& s = state();
        s.projection = saved_->projection;
        s.matrix_mode = saved_->matrix_mode;
        s.in_begin_end = saved_->in_begin_end;
        opening_begin_ = saved_opening_begin_;
        saved_.reset();
    }
    if (clips_before_redraw_.empty()) return;
    const GlApi& gl = core_.api();
    GLint program_in_use = 0;
    gl.glGetIntegerv(GL_CURRENT_PROGRAM, &program_in_use);
    Shared& group = shared();
    for (const auto& [program, before] : clips_before_redraw_) {
        auto it = group.clip_uniforms.find(program);
        if (it == group.clip_uniforms.end() || it->second.value == before) continue;
        gl.glUseProgram(program);
        gl.glUniformMatrix4fv(it->second.location, 1, GL_FALSE, &before[0][0]);
        it->second.value = before;
    }
    gl.glUseProgram(GLuint(program_in_use));
    clips_before_redraw_.clear();
}

}  // namespace glcast::slave
