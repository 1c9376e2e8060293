#include "slave/tile_adapter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "common/gl_headers.h"
#include "common/gl_state.h"
#include "slave/program_camera.h"
#include "slave/replayer.h"
#include "slave/scene/scene_classifier.h"

namespace glcast::slave {

// Per context: the program's rectangles as it set them, and the projection-correction state
// of rotated tiles, one entry per GL_PROJECTION stack level: whether the level holds
// M * P_app, whether the program changed it since (relative to M * P_app), and the M it holds.
struct TileAdapter::State {
    double viewport[kViewports][4] = {};
    int32_t scissor[kViewports][4] = {};
    bool indexed = false;  // the program used GL_ARB_viewport_array: all rectangles are applied
    int mapped_for[2] = {0, 0};  // the master's window size the rectangles were last mapped for
    struct Projection {
        bool corrected = false, dirty = false;
        glm::dmat4 m{1.0};
        bool left = false;  // not perspective: shown as the program drew it
    };
    std::vector<Projection> projection = std::vector<Projection>(1);
    uint32_t matrix_mode = GL_MODELVIEW;
    bool in_begin_end = false;  // GL refuses queries between glBegin and glEnd
    uint64_t draw_framebuffer = 0;  // the master's name of the bound draw framebuffer (0: the window)
    // Framebuffer objects (by the master's name) that hold colour and depth: a scene may be drawn
    // there. Asked of the driver at the first draw into each, forgotten when attachments change.
    std::unordered_map<uint64_t, bool> colour_and_depth;
    // Engines draw their other views (a monitor's, a reflection's) first and their scene last
    // before showing it: the last such target drawn before the window in a frame held the
    // scene, unless the window itself got a perspective view (then none did), and from the next
    // frame on only it is turned (until then, every one).
    uint64_t scene_target = 0;  // 0: the window
    bool scene_target_known = false;
    uint64_t frame_scene_target = 0;  // this frame's, so far
    bool window_drawn = false;        // this frame has drawn to the window
    bool window_view = false;         // ... with a perspective view
};

// Per share group: what the shader patch needs to know of shaders and programs.
struct TileAdapter::Shared {
    std::unordered_map<uint64_t, uint32_t> shader_types;  // master shader name -> GL_VERTEX_SHADER, ...
    // glcast_clip's location in each slave program (-1: not patched) and what it holds now.
    struct Clip {
        int32_t location = -1;
        glm::mat4 value{0.0f};
    };
    std::unordered_map<uint32_t, Clip> clip_uniforms;
    explicit Shared(const GlApi& gl) : cameras(gl) {}
    ProgramCameras cameras;  // shader programs' projections, without program_projection
};

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

bool TileAdapter::wants(uint32_t, const CommandInfo* info) const {
    if (!info) return false;
    const CommandSemantics& s = info->sem;
    const bool view = patching();
    return s.window != WindowMapping::Nothing || s.shader_type >= 0 || (s.flags & kSemLinksProgram) ||
           (view && (s.matrix != MatrixOp::Nothing || s.redraw == RedrawKind::Draw || s.redraw == RedrawKind::Begin ||
                     s.redraw == RedrawKind::End || s.writes_ns == Ns::framebuffer || (s.flags & kSemDeletes)));
}

bool TileAdapter::patching() const {
    return core_.options().view.enabled || core_.options().effects.redraws();
}

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
    if (!redrawing_ && !patching()) return;
    if (k != RedrawKind::Draw && k != RedrawKind::Begin && k != RedrawKind::End) return;
    State& s = state();
    if (k == RedrawKind::End) s.in_begin_end = false;
    else if (!s.in_begin_end) correct_projection();
    if (k == RedrawKind::Begin) s.in_begin_end = true;
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
    case WindowMapping::BlitDestination: {
        // Into the window: the destination rectangle is window coordinates. (Reading the window
        // back on a tile would need the other tiles' pixels; that source is left as it is.)
        if (!mapping()) return false;
        const SlaveContext& ctx = core_.current();
        const TileMapping& t = core_.options().tile;
        // The call as the program made it but for the mapped rectangle, replayed as any call is
        // (whatever the command's other parameters are).
        Call mapped = c;
        auto map = [&](int k, bool x) {
            const int64_t v = core_.value<GLint>(c, arg(k));
            const int64_t m = x ? t.map_x(double(v), ctx.master_width) : t.map_y(double(v), ctx.master_height);
            mapped.args[size_t(arg(k))].bits = uint32_t(GLint(m));  // as the decoder holds an i32: its 4 bytes
        };
        map(0, true), map(1, false), map(2, true), map(3, false);
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
    if (sem.writes_ns == Ns::framebuffer || (sem.flags & kSemDeletes)) state().colour_and_depth.clear();
    if (sem.shader_type >= 0) shared().shader_types[c.ret.bits] = uint32_t(c.args[size_t(sem.shader_type)].bits);
    if (sem.flags & kSemLinksProgram) {  // linking resets uniforms, and may change which there are
        shared().clip_uniforms.clear();
        shared().cameras.forget();
    }
    if (sem.matrix != MatrixOp::Nothing && (redrawing_ || core_.options().view.enabled)) track_matrix(c);
}

// --- rotated tiles: the projection correction (slave/view_correction.h) ----------------

void TileAdapter::track_matrix(const Call& c) {
    State& s = state();
    switch (c.info->sem.matrix) {
    case MatrixOp::Mode: s.matrix_mode = uint32_t(c.args[size_t(c.info->sem.subject_params[0])].bits); return;
    case MatrixOp::Push:
        if (s.matrix_mode == GL_PROJECTION) s.projection.push_back(s.projection.back());
        return;
    case MatrixOp::Pop:
        if (s.matrix_mode == GL_PROJECTION && s.projection.size() > 1) s.projection.pop_back();
        return;
    default: break;
    }
    if (s.matrix_mode != GL_PROJECTION) return;
    auto& top = s.projection.back();
    if (c.info->sem.matrix == MatrixOp::Load) top = State::Projection{};  // the program's own matrix again
    else top.dirty = top.corrected || top.left;  // M * P_app * X: M must be redone for P_app * X
}

glm::dmat4 TileAdapter::program_projection_now() {
    GLdouble m[16];
    core_.api().glGetDoublev(GL_PROJECTION_MATRIX, m);
    glm::dmat4 p;
    std::memcpy(&p[0][0], m, sizeof m);
    const auto& top = state().projection.back();
    return top.corrected ? glm::inverse(top.m) * p : p;
}

// A framebuffer object the program draws its 3D view into, to show it in the window later (as
// engines since 2010 do, behind post-processing): colour and depth attached, drawn over at the
// window's shape (window_shaped: the scene classifier's rule too), at its size or another. A rotated
// tile turns what is drawn there as it turns what the window gets; the program's other targets
// (shadow and environment maps, post-processing without depth, thumbnails) are left alone.
bool TileAdapter::draws_scene_target(SlaveContext& ctx) {
    State& s = state();
    if (!window_shaped(s.viewport[0], ctx.master_width, ctx.master_height)) return false;
    auto [known, fresh] = s.colour_and_depth.try_emplace(s.draw_framebuffer, false);
    if (fresh) {
        const GlApi& gl = core_.api();
        GLint colour = GL_NONE, depth = GL_NONE;
        gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                                 GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &colour);
        gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                                 GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &depth);
        known->second = colour != GL_NONE && depth != GL_NONE;
    }
    if (!known->second) return false;
    if (!s.window_drawn) s.frame_scene_target = s.draw_framebuffer;
    return !s.scene_target_known || s.draw_framebuffer == s.scene_target;
}

void TileAdapter::end_frame(SlaveContext& ctx) {
    if (core_.current_or_null() != &ctx) return;
    State& s = state();
    if (s.frame_scene_target || s.window_view) {
        s.scene_target = s.window_view ? 0 : s.frame_scene_target;
        s.scene_target_known = true;
    }
    s.frame_scene_target = 0;
    s.window_drawn = s.window_view = false;
}

// The driver is asked only when the name is no longer mapped (a program deleted while in use
// stays in use).
GLuint TileAdapter::program_in_use() {
    SlaveContext& ctx = core_.current();
    if (!ctx.current_program) return 0;
    uint64_t slave = 0;
    if (ctx.names.map(Ns::program).find(ctx.current_program, slave)) return GLuint(slave);
    GLint program = 0;
    core_.api().glGetIntegerv(GL_CURRENT_PROGRAM, &program);
    return GLuint(program);
}

// Before a draw on the window of a fixed-function program: make GL_PROJECTION hold
// M * P_app for the program's current P_app.
void TileAdapter::correct_projection() {
    SlaveContext& ctx = core_.current();
    const GlApi& gl = core_.api();
    State& s = state();
    redraw_refused_ = false;
    if (ctx.drawing_to_window && !redrawing_) s.window_drawn = true;
    const GLuint program = !redrawing_ || redraw_programs_ ? program_in_use() : 0;
    if (program) {  // a shader program: its patched vertex shader multiplies by glcast_clip
        redraw_refused_ = !correct_shader_program(GLuint(program)) && redrawing_;
        return;
    }
    if (redrawing_) {  // an injected pass re-renders the main view: its correction, always
        const glm::dmat4 corrected = redraw_correction_ * program_projection_now();
        GlStateGuard mode(gl, kGuardMatrixMode);
        gl.glMatrixMode(GL_PROJECTION);
        gl.glLoadMatrixd(&corrected[0][0]);
        s.projection.back() = State::Projection{true, false, redraw_correction_};
        return;
    }
    // The window, and a target the program draws its scene into to show later; its other
    // framebuffer objects are left alone.
    if (!core_.options().view.enabled || !(ctx.drawing_to_window || draws_scene_target(ctx))) return;
    auto& top = s.projection.back();
    if ((top.corrected || top.left) && !top.dirty) return;
    GLdouble current[16];
    gl.glGetDoublev(GL_PROJECTION_MATRIX, current);
    glm::dmat4 p;
    std::memcpy(&p[0][0], current, sizeof current);
    const glm::dmat4 app = top.corrected ? glm::inverse(top.m) * p : p;
    if (ctx.drawing_to_window && is_perspective(app)) s.window_view = true;
    if (!is_perspective(app)) {
        // An orthographic draw (a HUD, the full-window quad that shows a scene drawn offscreen)
        // has no camera to turn: turned as if it had, it would land elsewhere or nowhere.
        if (top.corrected) {
            GlStateGuard mode(gl, kGuardMatrixMode);
            gl.glMatrixMode(GL_PROJECTION);
            gl.glLoadMatrixd(&app[0][0]);
        }
        top = State::Projection{false, false, glm::dmat4(1.0), true};
        return;
    }
    const glm::dmat4 m = core_.options().view.correction(app);
    const glm::dmat4 corrected = m * app;
    GlStateGuard mode(gl, kGuardMatrixMode);
    gl.glMatrixMode(GL_PROJECTION);
    gl.glLoadMatrixd(&corrected[0][0]);
    top = State::Projection{true, false, m};
}

// Shader programs on rotated tiles: glcast_clip holds M while the window is drawn to, the
// identity while one of the program's FBOs is. M is for the display config's program_projection,
// or else for the projection found in the program's matrices at this draw (program_camera.h);
// a draw whose projection is not found is left alone, and the slave says so once. In a redraw
// it holds the redraw's correction; on planar tiles, the identity.
bool TileAdapter::correct_shader_program(uint32_t program) {
    SlaveContext& ctx = core_.current();
    const ViewCorrection& view = core_.options().view;
    const GlApi& gl = core_.api();
    Shared& group = shared();
    auto it = group.clip_uniforms.find(program);
    if (it == group.clip_uniforms.end())
        it = group.clip_uniforms.emplace(program, Shared::Clip{gl.glGetUniformLocation(program, "glcast_clip")}).first;
    if (it->second.location < 0) return false;
    glm::mat4 m(1.0f);
    if (redrawing_) {
        m = glm::mat4(redraw_correction_);
    } else if (view.enabled && (ctx.drawing_to_window || draws_scene_target(ctx))) {
        const double aspect = ctx.master_height ? double(ctx.master_width) / ctx.master_height : 1.0;
        ProgramCamera camera;
        if (view.program_fov_y_deg) {
            m = glm::mat4(view.correction(view.program_projection(aspect)));
            state().window_view |= ctx.drawing_to_window;
        } else if (shader_camera(program, camera)) {
            m = glm::mat4(view.correction(camera.projection));
            state().window_view |= ctx.drawing_to_window;
        } else if (!warned_no_camera_) {
            warned_no_camera_ = true;
            std::fprintf(stderr, "glcast: a shader program draws to the window with no perspective projection among "
                                 "its matrices: such draws are not turned for this tile (program_projection in the "
                                 "display config says what they use)\n");
        }
    }
    if (it->second.value != m) {
        gl.glUniformMatrix4fv(it->second.location, 1, GL_FALSE, &m[0][0]);
        it->second.value = m;
    }
    return true;
}

bool TileAdapter::shader_camera(uint32_t program, ProgramCamera& out) {
    ProgramCameras& cameras = shared().cameras;
    if (cameras.find(program, out)) return true;
    if (!cameras.reads_fixed_function(program)) return false;
    const glm::dmat4 projection = program_projection_now();
    if (!is_perspective(projection)) return false;
    GLdouble modelview[16];
    core_.api().glGetDoublev(GL_MODELVIEW_MATRIX, modelview);
    out.projection = projection;
    std::memcpy(&out.modelview[0][0], modelview, sizeof modelview);
    out.modelview_known = true;
    return true;
}

bool TileAdapter::patches_vertex_shader(uint64_t shader) {
    if (!patching()) return false;
    const auto& types = shared().shader_types;
    const auto type = types.find(shader);
    return type != types.end() && type->second == GL_VERTEX_SHADER;
}

void TileAdapter::begin_redraw(const glm::dmat4& correction, bool programs) {
    saved_ = std::make_unique<State>(state());
    GLint mode = GL_MODELVIEW;
    core_.api().glGetIntegerv(GL_MATRIX_MODE, &mode);
    state().matrix_mode = uint32_t(mode);
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
        saved_.reset();
    }
}

}  // namespace glcast::slave
