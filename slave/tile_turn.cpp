// Rotated tiles (cylinders, CAVEs): the tile adapter's projection correction
// (slave/view_correction.h) of fixed-function draws, shader programs' glcast_clip, the scene
// target an engine draws into, and the program's screen that its HUD lies on.
#include <algorithm>
#include <cstdio>
#include <cstring>

#include "common/gl_headers.h"
#include "common/gl_state.h"
#include "slave/program_camera.h"
#include "slave/replayer.h"
#include "slave/scene/scene_classifier.h"
#include "slave/tile_adapter.h"
#include "slave/tile_adapter_state.h"

namespace glcast::slave {

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

void TileAdapter::view_changed() {
    for (auto& [id, state] : states_)
        for (State::Projection& level : state->projection)
            if (level.corrected) level.dirty = true;
    if (saved_)
        for (State::Projection& level : saved_->projection)
            if (level.corrected) level.dirty = true;
}

glm::dmat4 TileAdapter::program_projection_now() {
    GLdouble m[16] = {};  // (a driver that answers nothing: no projection, not stack garbage)
    core_.api().glGetDoublev(GL_PROJECTION_MATRIX, m);
    glm::dmat4 p;
    std::memcpy(&p[0][0], m, sizeof m);
    const auto& top = state().projection.back();
    return top.corrected ? glm::inverse(top.m) * p : p;
}

// A framebuffer object the program draws its 3D view into, to show it in the window later (as
// engines since 2010 do, behind post-processing): colour and depth attached, drawn over at the
// window's shape (window_shaped: the scene classifier's rule too), at its size or another; or,
// once found to hold the scene, one of another shape that the window shows in part of itself (a
// content suite's viewport: shown_scene.h). A rotated tile turns what is drawn there as it turns
// what the window gets; the program's other targets (shadow and environment maps,
// post-processing without depth, thumbnails) are left alone.
bool TileAdapter::draws_scene_target(SlaveContext& ctx) {
    State& s = state();
    if (window_shaped(s.viewport[0], ctx.master_width, ctx.master_height))
        return holds_colour_and_depth() &&
               (!s.scene_target_known || s.draw_framebuffer == s.scene_target ||
                std::find(s.scene_targets.begin(), s.scene_targets.end(), s.draw_framebuffer) != s.scene_targets.end());
    // (and the others of its size: Blender's viewport draws its engines' colour and its overlays
    // into targets of the region's size, which the draw that shows it blends; its overlay engine
    // draws the grid and the object centres into one that holds colour only, and tests depth in
    // its shaders against the scene's depth texture)
    if (!s.scene_in_part || s.part_refused || !s.scene_target_known) return false;
    if (s.draw_framebuffer == s.scene_target) return holds_colour_and_depth();
    return (attachments() & kHoldsColour) && int32_t(s.viewport[0][2]) == s.part_viewport[2] &&
           int32_t(s.viewport[0][3]) == s.part_viewport[3];
}

uint8_t TileAdapter::attachments() {
    State& s = state();
    auto [known, fresh] = s.attachments.try_emplace(s.draw_framebuffer, uint8_t(0));
    if (fresh) {
        const GlApi& gl = core_.api();
        GLint colour = GL_NONE, depth = GL_NONE;
        gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                                 GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &colour);
        gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                                 GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &depth);
        known->second = uint8_t((colour != GL_NONE ? kHoldsColour : 0) | (depth != GL_NONE ? kHoldsDepth : 0));
    }
    return known->second;
}

// A context that never presented has no frames of its own (a toolkit's GL widget's, which draws
// into its offscreen surface at will): what it drew there says nothing of the order of its views.
bool TileAdapter::drew_window_this_frame(const State& s) { return s.window_drawn && s.presented; }

// A target of colour and depth not of the window's shape, drawn with a perspective view this
// frame: if no other view is found, the scene is there, shown in part of the window.
bool TileAdapter::part_candidate(SlaveContext& ctx) {
    State& s = state();
    return !ctx.drawing_to_window && !s.part_refused &&
           !window_shaped(s.viewport[0], ctx.master_width, ctx.master_height) && holds_colour_and_depth();
}

void TileAdapter::note_part_view() {
    State& s = state();
    s.frame_part_target = s.draw_framebuffer;
    for (int k = 0; k < 4; ++k) s.part_viewport[k] = int32_t(s.viewport[0][k]);
}

// A perspective view drawn now: the window's, or, before the window is drawn, the scene
// target's. The target is the one that got the frame's last view (a post-processing chain's own
// window-shaped targets, drawn with full-screen quads after it, are not the scene's); one of the
// window's shape before one shown in part of the window.
void TileAdapter::saw_view(SlaveContext& ctx, const glm::dmat4& projection) {
    State& s = state();
    (ctx.drawing_to_window ? s.window_view : s.scene_view) = true;
    (ctx.drawing_to_window ? s.window_projection : s.scene_projection) = projection;
    if (ctx.drawing_to_window) return;
    s.scene_screen = projection;
    for (int axis = 0; axis < 2; ++axis)
        if (projection[axis][axis] < 0)
            for (int c = 0; c < 4; ++c) s.scene_screen[c][axis] = -projection[c][axis];
    if (window_shaped(s.viewport[0], ctx.master_width, ctx.master_height)) {
        if (drew_window_this_frame(s)) return;
        s.frame_scene_target = s.draw_framebuffer;
        s.frame_shaped_view = true;
        auto seen = std::find_if(s.frame_views.begin(), s.frame_views.end(),
                                 [&](const auto& view) { return view.first == s.draw_framebuffer; });
        if (seen != s.frame_views.end()) seen->second = projection;
        else if (s.frame_views.size() < State::kFrameViews) s.frame_views.emplace_back(s.draw_framebuffer, projection);
        return;
    }
    // (shown in part of the window, it may be drawn after other parts were: Blender draws each
    // region into its own target and copies it into the window before drawing the next)
    // (a target of its size with colour only, an overlay's, is drawn over it: not the scene's)
    s.part_turned = true;  // (draws_scene_target turns only the known one)
    for (int k = 0; k < 4; ++k) s.part_viewport[k] = int32_t(s.viewport[0][k]);
    if (!s.frame_shaped_view && holds_colour_and_depth()) s.frame_scene_target = s.draw_framebuffer;
}

void TileAdapter::end_frame(SlaveContext& ctx) {
    if (core_.current_or_null() != &ctx) return;
    State& s = state();
    // A scene turned but not found where the window shows it would show squeezed there: never again.
    auto refuse = [](State& scene) {
        scene.part_refused = true;
        std::fprintf(stderr, "glcast: a scene drawn into a framebuffer object of %dx%d is not found where the window "
                             "shows it (no draw to the window sampled a texture of that size): it is not turned for "
                             "this tile\n",
                     scene.part_viewport[2], scene.part_viewport[3]);
    };
    if (s.part_turned && !s.part_found && !s.part_refused) refuse(s);
    if (State* lender = lender_of(s); lender && lender->part_turned && !s.part_found && !lender->part_refused)
        refuse(*lender);
    if (s.frame_scene_target || s.window_view) {
        s.scene_target = s.window_view ? 0 : s.frame_scene_target;
        s.scene_targets.clear();
        const auto last = std::find_if(s.frame_views.begin(), s.frame_views.end(),
                                       [&](const auto& view) { return view.first == s.scene_target; });
        for (const auto& [target, projection] : s.frame_views)
            if (s.scene_target && last != s.frame_views.end() && target != s.scene_target &&
                same_projection(projection, last->second))
                s.scene_targets.push_back(target);
        s.scene_in_part = s.scene_target && !s.frame_shaped_view;
        s.scene_target_known = true;
    } else if (s.frame_part_target && !s.part_refused) {
        s.scene_target = s.frame_part_target;
        s.scene_in_part = s.scene_target_known = true;
    }
    s.presented = true;
    s.presented_frame = core_.frame();
    s.frame_scene_target = s.frame_part_target = 0;
    s.frame_views.clear();
    s.window_drawn = s.window_view = s.scene_view = s.scene_shown = s.frame_shaped_view = false;
    s.part_turned = s.part_found = false;
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
        // (a built-in gl_ModelViewProjectionMatrix must then hold the program's own projection,
        // not one a fixed-function draw before it left corrected)
        auto& top = s.projection.back();
        if (top.corrected) {
            const glm::dmat4 app = program_projection_now();
            GlStateGuard mode(gl, kGuardMatrixMode);
            gl.glMatrixMode(GL_PROJECTION);
            gl.glLoadMatrixd(&app[0][0]);
            top = State::Projection{};
        }
        // (a redraw with no correction, the placing of a scene shown in part of the window, draws
        // as the program drew: an unpatched program needs none)
        redraw_refused_ = !correct_shader_program(GLuint(program)) && redrawing_ &&
                          redraw_correction_ != glm::dmat4(1.0);
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
    if (!core_.options().view.enabled) return;
    if (!(ctx.drawing_to_window || draws_scene_target(ctx))) {
        if (part_candidate(ctx) && is_perspective(program_projection_now())) note_part_view();
        return;
    }
    auto& top = s.projection.back();
    // (until the draw that shows a scene drawn in part of the window went by, each draw to the
    // window is looked at: it may be that one)
    if ((top.corrected || top.left) && !top.dirty && !awaits_shown_scene(ctx)) return;
    GLdouble current[16] = {};
    gl.glGetDoublev(GL_PROJECTION_MATRIX, current);
    glm::dmat4 p;
    std::memcpy(&p[0][0], current, sizeof current);
    const glm::dmat4 app = top.corrected ? glm::inverse(top.m) * p : p;
    if (is_perspective(app)) saw_view(ctx, app);
    const glm::dmat4* screen = !is_perspective(app) ? screen_of_flat_draw(ctx) : nullptr;
    if (screen) {
        // Drawn over the scene a view showed (a HUD, a game's menu over it): on the program's
        // screen, which lies in the direction that view looks; every tile shows it where it
        // sees that screen, the tiles looking elsewhere not at all.
        const glm::dmat4 m = core_.options().view.correction(*screen);
        const glm::dmat4 corrected = m * app;
        GlStateGuard mode(gl, kGuardMatrixMode);
        gl.glMatrixMode(GL_PROJECTION);
        gl.glLoadMatrixd(&corrected[0][0]);
        top = State::Projection{true, false, m};
        return;
    }
    if (!is_perspective(app)) {
        // An orthographic draw with no view before it (a backdrop, the full-window quad that
        // shows a scene drawn offscreen) has no camera to turn: turned as if it had, it would
        // land elsewhere or nowhere. After the quad that shows the scene, the next draw is
        // looked at again: with the same matrix it may be a HUD.
        if (top.corrected) {
            GlStateGuard mode(gl, kGuardMatrixMode);
            gl.glMatrixMode(GL_PROJECTION);
            gl.glLoadMatrixd(&app[0][0]);
        }
        top = State::Projection{false, ctx.drawing_to_window && s.scene_shown, glm::dmat4(1.0), true};
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
        State& s = state();
        if (view.program_fov_y_deg) {
            m = glm::mat4(view.correction(view.program_projection(aspect)));
            saw_view(ctx, view.program_projection(aspect));
        } else if (shader_camera(program, camera)) {
            m = glm::mat4(view.correction(camera.projection));
            saw_view(ctx, camera.projection);
        } else if (const glm::dmat4* screen = ctx.drawing_to_window || shared().cameras.places_by_matrix(program)
                                                  ? screen_of_flat_draw(ctx)
                                                  : nullptr) {
            // Over a view: on the program's screen. (Into the scene's target, a draw by a program
            // with no matrix at all is a pass over the picture there, a colour grade's or a
            // background's full-target triangle, which stays over the whole target.)
            m = glm::mat4(view.correction(*screen));
        } else if (ctx.drawing_to_window && (s.scene_view || s.window_view || s.scene_shown || s.frame_part_target)) {
            // the quad that shows the scene: as drawn (or a scene in part of the window, not known
            // yet: the frame that finds it is shown as drawn)
        } else if (!warned_no_camera_) {
            warned_no_camera_ = true;
            std::fprintf(stderr, "glcast: a shader program draws to the window with no perspective projection among "
                                 "its matrices: such draws are not turned for this tile (program_projection in the "
                                 "display config says what they use)\n");
        }
    }
    if (!redrawing_ && view.enabled && part_candidate(ctx)) {
        ProgramCamera camera;
        if (view.program_fov_y_deg || shader_camera(program, camera)) note_part_view();
    }
    if (it->second.value != m) {
        if (redrawing_ && std::none_of(clips_before_redraw_.begin(), clips_before_redraw_.end(),
                                       [program](const auto& kept) { return kept.first == program; }))
            clips_before_redraw_.emplace_back(program, it->second.value);
        gl.glUniformMatrix4fv(it->second.location, 1, GL_FALSE, &m[0][0]);
        it->second.value = m;
    }
    return true;
}

const glm::dmat4* TileAdapter::screen_of_flat_draw(const SlaveContext& ctx) {
    State& s = state();
    if (!ctx.drawing_to_window)
        return s.scene_view && s.draw_framebuffer == s.frame_scene_target &&
                       (!drew_window_this_frame(s) || (s.scene_in_part && s.part_turned))
                   ? &s.scene_projection
                   : nullptr;
    if (s.window_view) return &s.window_projection;
    if (const State* scene = scene_in_part(ctx)) {  // a scene shown in part of the window
        if (!s.scene_shown && shows_scene_in_part(ctx, *scene)) {
            s.scene_shown = true;
            return nullptr;
        }
        return s.window_screen_known ? &s.window_screen : nullptr;
    }
    if (!s.scene_view) {
        find_lender(ctx);
        return nullptr;
    }
    if (!s.scene_shown) {  // this draw shows the scene
        s.scene_shown = true;
        return nullptr;
    }
    return &s.scene_screen;
}

bool TileAdapter::awaits_shown_scene(const SlaveContext& ctx) {
    return ctx.drawing_to_window && !state().scene_shown && scene_in_part(ctx);
}

bool TileAdapter::shader_camera(uint32_t program, ProgramCamera& out) {
    ProgramCameras& cameras = shared().cameras;
    if (cameras.find(program, out)) return true;
    if (!cameras.reads_fixed_function(program)) return false;
    const glm::dmat4 projection = program_projection_now();
    if (!is_perspective(projection)) return false;
    GLdouble modelview[16] = {};
    core_.api().glGetDoublev(GL_MODELVIEW_MATRIX, modelview);
    out.projection = projection;
    std::memcpy(&out.modelview[0][0], modelview, sizeof modelview);
    out.modelview_known = true;
    return true;
}

bool TileAdapter::shader_flat(uint32_t program) {
    ProgramCameras& cameras = shared().cameras;
    if (cameras.orthographic(program)) return true;
    return cameras.reads_fixed_function(program) && is_orthographic(program_projection_now());
}

bool TileAdapter::shader_light(uint32_t program, const ProgramCamera& camera, effects::SceneLight& out) {
    return shared().cameras.light(program, camera, out);
}

ShaderPatch TileAdapter::shader_patch(uint64_t shader) {
    const auto& types = shared().shader_types;
    const auto type = types.find(shader);
    if (type == types.end()) return ShaderPatch::Untouched;
    if (type->second == GL_VERTEX_SHADER && patching()) return ShaderPatch::Clip;
    if (type->second == GL_FRAGMENT_SHADER && maps_fragments()) return ShaderPatch::WindowFragCoord;
    return ShaderPatch::Untouched;
}

}  // namespace glcast::slave
