// Running the injected passes at the end of each frame (effects_runner.h).
#include "slave/effects_runner.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <string>

#include "common/gl_headers.h"
#include "common/gl_state.h"
#include "protocol/format.h"
#include "slave/effects/gl_util.h"
#include "slave/replayer.h"
#include "slave/scene_report.h"
#include "slave/scene/redraw.h"
#include "slave/tile_adapter.h"

namespace glcast::slave {

namespace {

void set_enabled(const GlApi& gl, GLenum cap, bool on) {
    if (on) gl.glEnable(cap);
    else gl.glDisable(cap);
}

// What the context's state says of the program's depth at the end of its frame.
ProgramDepthState program_depth_state(const GlApi& gl) {
    ProgramDepthState s;
    GLdouble range[2] = {0, 1};
    gl.glGetDoublev(GL_DEPTH_RANGE, range);
    s.range_near = range[0], s.range_far = range[1];
    GLfloat clear = 1;
    gl.glGetFloatv(GL_DEPTH_CLEAR_VALUE, &clear);
    s.clear_depth = clear;
    if (gl.has(OP_glClipControl)) {
        GLint origin = GL_LOWER_LEFT, mode = GL_NEGATIVE_ONE_TO_ONE;
        gl.glGetIntegerv(GL_CLIP_ORIGIN, &origin);
        gl.glGetIntegerv(GL_CLIP_DEPTH_MODE, &mode);
        s.upper_left = origin == GL_UPPER_LEFT;
        s.zero_to_one = mode == GL_ZERO_TO_ONE;
    }
    return s;
}

// The passes draw in GL's default clip convention and depth range; the program's come back after.
void set_depth_state(const GlApi& gl, const ProgramDepthState& s) {
    if (gl.has(OP_glClipControl))
        gl.glClipControl(s.upper_left ? GL_UPPER_LEFT : GL_LOWER_LEFT, s.zero_to_one ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    gl.glDepthRange(s.range_near, s.range_far);
}

}  // namespace

EffectsRunner::EffectsRunner(Replayer& core, TileAdapter& tile) : core_(core), tile_(tile), scenes_(core, tile) {
    // The window as the scene left it, before the first overlay: what the passes decorate, now
    // when the frame is a new picture (the overlays are then drawn over the winter, translucent
    // ones blended with it), else at the frame's end, the overlays' pixels put back after.
    scenes_.on_overlays_start = [this](SlaveContext& ctx) {
        if (decorates_under_overlays(ctx)) {
            decorate(ctx, /*under_overlays=*/true);
            return;
        }
        const SceneFacts& facts = scenes_.scene(ctx).facts;
        if (facts.marks && !facts.scene_framebuffer) return;  // kept before the marks
        WindowCopies& copies = passes(ctx).copies;
        copies.size(ctx);
        copies.copy(ctx, copies.scene_image_fb, false);
        if (facts.depth_cleared) copies.keep_depth(ctx);
    };
    // The scene before the main view's lines and points, which are no part of it, and before a
    // translucent draw that writes depth; a surface after them says they were.
    scenes_.on_over_scene = [this](SlaveContext& ctx, const DrawVerdict& v) {
        ContextScene& scene = scenes_.scene(ctx);
        WindowCopies& copies = passes(ctx).copies;
        if (scene.facts.scene_framebuffer) {  // (ended: the classifier dropped the target's copies)
            if (v.marks_start) copies.keep_scene_target(ctx, scene, /*final=*/false);
            if (v.keeps_depth) copies.keep_scene_depth(scene);
        } else if (v.over_end) {
            copies.forget_kept_depth();
        } else {
            copies.size(ctx);
            if (v.marks_start) copies.copy(ctx, copies.scene_image_fb, false);
            if (v.keeps_depth) copies.keep_depth(ctx);
        }
    };
    // The scene's depth before an overlay engine's target that holds it gets its wire frames.
    scenes_.on_scene_depth_shared = [this](SlaveContext& ctx) {
        passes(ctx).copies.keep_scene_depth(scenes_.scene(ctx));
    };
    // The scene's own target before the program's HUD is drawn into it.
    scenes_.on_target_overlays_start = [this](SlaveContext& ctx) {
        passes(ctx).copies.keep_scene_target(ctx, scenes_.scene(ctx), /*final=*/false);
    };
}

EffectsRunner::~EffectsRunner() = default;

EffectsRunner::ContextPasses& EffectsRunner::passes(const SlaveContext& ctx) {
    auto& p = passes_[ctx.id];
    if (!p) p = std::make_unique<ContextPasses>(core_);
    return *p;
}

// Everything the record may keep (semantics.yaml redraw) and, inside glBegin/glEnd, every call.
bool EffectsRunner::wants(uint32_t opcode, const CommandInfo* info) const {
    return info ? true : opcode == kSynthClientArrays;
}

void EffectsRunner::before_call(const Call& c, const uint8_t* tuple, size_t bytes) {
    if (SlaveContext* ctx = core_.current_or_null()) scenes_.record(*ctx, c, tuple, bytes);
}

void EffectsRunner::after_call(const Call& c) {
    if (SlaveContext* ctx = core_.current_or_null()) scenes_.follow(*ctx, c);
}

void EffectsRunner::reset() {
    scenes_.reset();
    passes_.clear();
}

void EffectsRunner::settings_changed() {
    for (auto& [id, st] : passes_) st->pipeline.reset();  // built again, with the new settings, when next run
}

void EffectsRunner::context_removed(uint32_t id) {
    scenes_.forget(id);
    passes_.erase(id);
}

void EffectsRunner::end_frame(SlaveContext& ctx) {
    scenes_.frame_drawn(ctx);
    run_effects(ctx);
    scenes_.frame_decorated(ctx);
}

void EffectsRunner::presented(SlaveContext& ctx) {
    WindowCopies& copies = passes(ctx).copies;
    if (!copies.program_image_saved) return;
    copies.program_image_saved = false;
    if (!copies.sized(ctx)) return;  // resized: a new picture anyway
    copies.copy(ctx, copies.program_image_fb, false, true);
}

void EffectsRunner::run_effects(SlaveContext& ctx) {
    ContextPasses& st = passes(ctx);
    ContextScene& scene = scenes_.scene(ctx);
    if (st.under_overlays.decorated) {
        report_under_overlays(ctx);
        st.under_overlays = UnderOverlays{};
    } else if (ctx.width > 0 && ctx.height > 0 && core_.options().effects.any()) {
        // (nothing shown, or every pass switched off live: nothing to decorate)
        decorate(ctx, /*under_overlays=*/false);
    }
    st.copies.end_frame();
    scene.next_frame();
    keep_frame_start(ctx);
}

// The vertex array and the textures bound as the next frame's record starts (the passes put back
// what they change): a redraw starts from them. The state when the passes run is another, the
// first overlay's (a vertex-array object of its own), which the frame's calls before their first
// glBindVertexArray would otherwise change (an element buffer bound into the scene's).
void EffectsRunner::keep_frame_start(SlaveContext& ctx) {
    ContextPasses& st = passes(ctx);
    const GlApi& gl = core_.api();
    gl.glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &st.program_vao);
    gl.glGetIntegerv(GL_ACTIVE_TEXTURE, &st.program_active_texture);
    for (int unit = 0; unit < 8; ++unit) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &st.program_textures[unit]);
    }
    gl.glActiveTexture(GLenum(st.program_active_texture));
}

bool EffectsRunner::decorates_under_overlays(SlaveContext& ctx) {
    const ContextScene& scene = scenes_.scene(ctx);
    // (a scene shown in part of the window is placed by the draw that shows it, after the fact)
    const bool new_picture = scene.facts.window_cleared || scene.facts.shown_whole;
    return !passes(ctx).under_overlays.decorated && new_picture && !scene.loan.borrowed_from &&
           !scene.facts.in_part && ctx.width > 0 && ctx.height > 0 && core_.options().effects.any();
}

void EffectsRunner::decorate(SlaveContext& ctx, bool under_overlays) {
    ContextPasses& st = passes(ctx);
    ContextScene& scene = scenes_.scene(ctx);
    const GlApi& gl = core_.api();
    if (!checked_) {
        const std::string missing = effects::missing_pass_function(gl);
        if (!missing.empty()) throw EffectsError("effects: " + missing);
        checked_ = true;
    }
    try {
        if (!st.pipeline) st.pipeline = std::make_unique<effects::Pipeline>(gl, core_.options().effects);
        effects::FrameView view;
        frame_view(ctx, view);
        WindowCopies& copies = st.copies;
        copies.size(ctx);
        const bool sized = copies.sized(ctx);
        // The main view's lines and points in the window: scene_image holds the scene before them
        // (on_over_scene), what differs from it is the program's, as its overlays are.
        const bool window_marks = scene.facts.marks && !scene.facts.scene_framebuffer && sized;
        if (!under_overlays || window_marks) {
            copies.copy(ctx, copies.program_image_fb, false);
            // (a frame decorated under its overlays is a new picture: nothing to give back)
            if (!under_overlays) copies.program_image_saved = true;
        }
        const bool overlays = ((!under_overlays && scene.facts.overlay) || window_marks) && sized;
        if (overlays) copies.copy(ctx, copies.scene_image_fb, false, /*back=*/true);  // the scene alone
        // (a borrowed scene's target is another context's)
        const bool target_overlays = scene.facts.target_overlay && scene.facts.scene_framebuffer &&
                                     !scene.loan.borrowed_from && copies.scene_target_before;
        if (target_overlays) copies.keep_scene_target(ctx, scene, /*final=*/true);
        const bool engine = engine_overlays(ctx) != 0 && sized;
        const bool view_model = scene.facts.view_model_far > 0 && sized;
        // A borrowed scene covers part of the window: the rest is the program's.
        const bool placed = scene.loan.borrowed_from != 0 && sized;
        if (view_model) st.view_model_depth = copies.window_copy(ctx, true, scene, scenes_.scene_shown(ctx));  // before any pass draws
        else scene.facts.view_model_far = 0;
        const ReplayOptions& opt = core_.options();
        const bool report = !opt.scene_report_dir.empty() && view.frame >= opt.first_frame && view.frame <= opt.last_frame;
        std::string error;
        const GLenum window = ctx.double_buffered ? GL_BACK : GL_FRONT;
        if (under_overlays && !window_marks && (view_model || target_overlays || engine)) {
            // The program's pixels to put back over the passes (not to give back after present).
            copies.copy(ctx, copies.program_image_fb, false);
        }
        if (under_overlays && report) {
            if (!write_scene_under_overlays(gl, opt.scene_report_dir, view, window, "plain", error))
                throw std::runtime_error("--scene-report: " + error);
            // The depth the report gives is the scene's, copied now (kept for the frame): the
            // overlays may clear it before the frame's end (a view model's depth-only clear).
            if (view.view_known && view.depth_texture) view.depth_texture();
        }
        if (!st.depth.standard) set_depth_state(gl, ProgramDepthState{});
        st.pipeline->run(view);
        if (!st.depth.standard) set_depth_state(gl, st.depth.program);
        const bool kept = overlays || view_model || placed || target_overlays || engine;
        if (kept) put_overlays_back(ctx, overlays, target_overlays);
        if (under_overlays) {
            // The program draws its overlays over this: for the report, what differs from it at
            // the frame's end is theirs (report_under_overlays).
            if (report) {
                copies.copy(ctx, copies.scene_image_fb, false);
                if (!write_scene_under_overlays(gl, opt.scene_report_dir, view, window, "decorated", error))
                    throw std::runtime_error("--scene-report: " + error);
            }
            st.under_overlays = UnderOverlays{true, report, target_overlays, view};
        } else if (report) {
            report_scene(ctx, view, overlays, target_overlays, kept);
        }
        if (core_.after_effects) core_.after_effects(view);
        if (scene.loan.borrowed_from && !said_borrowed_) {
            said_borrowed_ = true;
            const int32_t* p = scene.loan.placement;
            if (scene.loan.borrowed_from == ctx.id)
                std::fprintf(stderr, "glcast: effects: from frame %" PRIu64 " on, context %u shows its scene in part of "
                                     "the window, x %d..%d, y %d..%d of the program's (docs/effects.md, \"A scene shown "
                                     "in part of the window\")\n",
                             core_.frame(), ctx.id, p[0], p[2], p[1], p[3]);
            else
                std::fprintf(stderr, "glcast: effects: from frame %" PRIu64 " on, context %u shows the scene context %u "
                                     "draws into a texture (docs/effects.md, \"A scene shown in part of the window\")\n",
                             core_.frame(), ctx.id, scene.loan.borrowed_from);
        }
    } catch (const std::runtime_error& e) {
        throw EffectsError(std::string("effects: ") + e.what());
    }
}

void EffectsRunner::report_under_overlays(SlaveContext& ctx) {
    ContextPasses& st = passes(ctx);
    if (!st.under_overlays.report || !st.copies.sized(ctx)) return;
    WindowCopies& copies = st.copies;
    copies.copy(ctx, copies.program_image_fb, false);  // the final picture, overlays and all
    try {
        report_scene(ctx, st.under_overlays.view, /*overlays=*/true, st.under_overlays.target_overlays, /*kept=*/true);
    } catch (const std::runtime_error& e) {
        throw EffectsError(std::string("effects: ") + e.what());
    }
}

void EffectsRunner::frame_view(SlaveContext& ctx, effects::FrameView& v) {
    ContextScene& scene = scenes_.scene(ctx);
    SceneFacts& facts = scene.facts;
    const ReplayOptions& options = core_.options();
    const TileMapping& t = options.tile;
    v.frame = core_.frame();
    v.frame_time = 1.0 / 60;
    v.time = double(v.frame) * v.frame_time;
    v.width = ctx.width, v.height = ctx.height;
    v.canvas_x = t.enabled ? t.place_x : 0;
    v.canvas_y = t.enabled ? t.place_y : 0;
    v.canvas_width = t.enabled ? t.place_canvas_width : ctx.width;
    v.canvas_height = t.enabled ? t.place_canvas_height : ctx.height;
    v.light = facts.light;
    v.view_known = facts.main_known;
    if (!facts.main_known && facts.shader_draws && options.view.program_fov_y_deg) {
        v.view_known = true;  // a shader program: the projection the display config states
        facts.projection = options.view.program_projection(double(ctx.master_width) / std::max(1, ctx.master_height));
        facts.viewport[0] = facts.viewport[1] = 0;
        facts.viewport[2] = ctx.master_width, facts.viewport[3] = ctx.master_height;
    }
    // Said once for all passes, which leave such frames as they are (snow.without_view aside).
    if (!v.view_known && !warned_no_camera_) {
        warned_no_camera_ = true;
        if (facts.shader_draws)
            std::fprintf(stderr, "glcast: effects: no draw with a perspective projection among the shader programs' "
                                 "matrices in frame %" PRIu64 ": the passes leave such frames as the program drew them "
                                 "(a projection computed in a shader is not linear and cannot be found; "
                                 "program_projection in the display config states a linear one)\n", core_.frame());
        else
            std::fprintf(stderr, "glcast: effects: no draw with a perspective projection in frame %" PRIu64 ": the "
                                 "passes leave such frames as the program drew them (a 2D program, a menu)\n",
                         core_.frame());
    }
    if (v.view_known) {
        v.projection = facts.projection;
        v.modelview = facts.modelview;
        if (v.projection[2][3] > 0) {
            // A left-handed eye space (w = +z, Irrlicht's): the passes get it mirrored into GL's,
            // P * F and F * MV (F mirrors z), the same clip coordinates and the same turn.
            glm::dmat4 mirror(1.0);
            mirror[2][2] = -1;
            v.projection = v.projection * mirror;
            v.modelview = mirror * v.modelview;
            v.light.eye_position.z = -v.light.eye_position.z;
        }
        v.light = effects::light_from_the_sky(v.light, v.modelview);
        // The program's viewport as this slave applies it, in tile pixels.
        const int W = ctx.master_width, H = ctx.master_height;
        // A scene drawn at another size is shown stretched over the window.
        const int32_t whole[4] = {0, 0, W, H};
        const int32_t* p = stretched_scene(facts, W, H) ? whole : facts.viewport;
        double vx = p[0], vy = p[1], vw = p[2], vh = p[3];
        if (t.enabled) {
            vx = double(t.map_x(p[0], W)), vy = double(t.map_y(p[1], H));
            vw = double(t.map_w(p[0], p[2], W)), vh = double(t.map_h(p[1], p[3], H));
        }
        // app NDC -> tile NDC through both viewports, as a matrix on clip coordinates.
        glm::dmat4 planar(1.0);
        planar[0][0] = vw / ctx.width;
        planar[3][0] = (2 * vx + vw) / ctx.width - 1;
        planar[1][1] = vh / ctx.height;
        planar[3][1] = (2 * vy + vh) / ctx.height - 1;
        const glm::dmat4 rotated = options.view.enabled ? options.view.correction(v.projection) : glm::dmat4(1.0);
        v.tile_clip_from_app_clip = planar * rotated;
        v.tile_clip_from_eye = v.tile_clip_from_app_clip * v.projection;
        v.eye_from_tile_clip = glm::inverse(v.tile_clip_from_eye);
        convert_depth(ctx, v, planar);
    } else {
        passes(ctx).depth = DepthConvention{};
    }
    ContextPasses* st = &passes(ctx);
    st->copies.new_frame();
    const GlApi& gl = core_.api();
    SlaveContext* c = &ctx;
    ContextScene* sc = &scene;
    v.color_texture = [this, c, st, sc] { return st->copies.window_copy(*c, false, *sc, scenes_.scene_shown(*c)); };
    v.depth_texture = [this, c, st, sc] {
        const GLuint program = st->copies.window_copy(*c, true, *sc, scenes_.scene_shown(*c));
        return st->depth.standard ? program : st->copies.pass_depth(*c, program, st->depth, st->pass_clip_from_program_clip);
    };
    // (a scene drawn into a framebuffer object has its depth there; the window's is another's)
    v.window_depth_matches = st->depth.standard && !facts.scene_framebuffer;
    // A borrowed scene's shader draws name the lender's vertex-array objects, which this context
    // does not share: only fixed-function scenes are re-rendered from another context.
    const ContextScene& shown = scenes_.scene_shown(ctx);
    const bool borrowed = &shown != &scene;
    const bool programs = shown.facts.main_shader_draws;
    if (facts.main_known && !shown.record.overflow && !(borrowed && programs) &&
        (programs ? core_.options().effects.redraws() : compatibility_profile(gl))) {
        v.redraw = [this, c, st](const glm::dmat4& correction) {
            redraw_main_view(*c, st->depth.standard ? correction : correction * st->depth.pass_from_program);
        };
        v.redraw_binds_programs = programs;
    }
    st->painter_depth_done = false;
    if (v.redraw && shown.facts.painter_draws && v.view_known) {
        // (snow then tests its flakes against this depth, not the window's)
        v.window_depth_matches = false;
        const glm::dmat4 correction = v.tile_clip_from_eye * glm::inverse(v.projection);
        v.depth_texture = [this, c, st, base = v.depth_texture, redraw = v.redraw,
                           programs = v.redraw_binds_programs, correction] {
            const GLuint depth = base();
            if (!st->painter_depth_done) complete_painter_depth(*c, redraw, programs, depth, correction);
            st->painter_depth_done = true;
            return depth;
        };
    }
}

void EffectsRunner::complete_painter_depth(SlaveContext& ctx, const std::function<void(const glm::dmat4&)>& redraw,
                                           bool binds_programs, GLuint depth, const glm::dmat4& correction) {
    ContextPasses& st = passes(ctx);
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    if (!st.painter_depth_fb) gl.glGenFramebuffers(1, &st.painter_depth_fb);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, st.painter_depth_fb);
    gl.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
    gl.glDrawBuffer(GL_NONE);
    gl.glReadBuffer(GL_NONE);
    if (gl.glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return;
    gl.glViewport(0, 0, ctx.width, ctx.height);
    gl.glDisable(GL_BLEND);
    gl.glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_LEQUAL);
    gl.glDepthMask(GL_TRUE);
    if (!binds_programs) gl.glUseProgram(0);  // (fixed function: the program's own transform)
    redraw(correction);
    gl.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, 0, 0);
}

void EffectsRunner::convert_depth(SlaveContext& ctx, effects::FrameView& v, const glm::dmat4& planar) {
    ContextPasses& st = passes(ctx);
    const glm::dmat4 program = v.projection;
    ProgramDepthState state = program_depth_state(core_.api());
    state.shown_mirrored = scenes_.scene(ctx).facts.shown_mirrored;
    state.shown_mirrored_columns = scenes_.scene(ctx).facts.shown_mirrored_columns;
    st.depth = depth_convention(program, state);
    if (st.depth.standard) return;
    if (!said_depth_convention_) {
        said_depth_convention_ = true;
        const ProgramDepthState& s = st.depth.program;
        std::fprintf(stderr, "glcast: effects: the program's depth is its own (%s%s%s%s, depth range %g..%g, cleared to "
                             "%g): the passes read it converted to a standard projection, near %g, far %g "
                             "(docs/effects.md, \"Depth conventions\")\n",
                     s.zero_to_one ? "clip depth 0..1" : "clip depth -1..1",
                     st.depth.reversed ? ", reversed" : "",
                     s.upper_left ? ", origin upper left" : s.shown_mirrored ? ", shown upside down" : "",
                     s.shown_mirrored_columns ? ", shown mirrored left to right" : "",
                     s.range_near, s.range_far, s.clear_depth,
                     st.depth.near, st.depth.far);
    }
    const ReplayOptions& options = core_.options();
    // The program's tile clip space as its window shows it (origin flipped after its turn).
    glm::dmat4 flip(1.0);
    if (st.depth.program.flipped()) flip[1][1] = -1;
    if (st.depth.program.flipped_columns()) flip[0][0] = -1;
    const glm::dmat4 program_turn = options.view.enabled ? options.view.correction(program) : glm::dmat4(1.0);
    const glm::dmat4 pass_turn = options.view.enabled ? options.view.correction(st.depth.pass_projection) : glm::dmat4(1.0);
    v.projection = st.depth.pass_projection;
    v.tile_clip_from_app_clip = planar * pass_turn;
    v.tile_clip_from_eye = v.tile_clip_from_app_clip * v.projection;
    v.eye_from_tile_clip = glm::inverse(v.tile_clip_from_eye);
    st.pass_clip_from_program_clip = v.tile_clip_from_eye * glm::inverse(planar * flip * program_turn * program);
}

// Re-executes the recorded calls of the main view with `correction` premultiplied into the
// program's projection (fixed function) or set as glcast_clip (shader programs, whose vertex
// shaders the slave patched). Everything it changes is put back: attributes and client
// attributes, the three matrix stacks (depth and top), the vertex array, the caller's program,
// the trackers (list base, current program, pending client-array ranges); uniform values and
// uniform buffers end as the frame left them because the frame's calls that set them are
// replayed in its order.
void EffectsRunner::redraw_main_view(SlaveContext& ctx, const glm::dmat4& correction) {
    ContextPasses& st = passes(ctx);
    const ContextScene& shown = scenes_.scene_shown(ctx);  // a borrowed scene: the lender's draws
    const bool borrowed = &shown != &scenes_.scene(ctx);
    const FrameRecord& rec = shown.record;
    const GlApi& gl = core_.api();
    const bool compatibility = compatibility_profile(gl);
    if (rec.entries.empty() || (!compatibility && !shown.facts.main_shader_draws)) return;
    const uint32_t saved_list_base = ctx.list_base;
    const uint64_t saved_program_stream = ctx.current_program;
    const PendingClientArrays pending(ctx);
    GLint active_texture = GL_TEXTURE0;
    gl.glGetIntegerv(GL_ACTIVE_TEXTURE, &active_texture);
    GlStateGuard guard(gl, kGuardProgram | kGuardVertexArray |
                               (compatibility ? kGuardAttribStacks | kGuardMatrixStacks | kGuardMatrixMode : 0));
    // (A borrowed scene's draws start from no vertex-array object and no textures: this
    // context's are not the lender's.)
    gl.glBindVertexArray(borrowed ? 0 : GLuint(st.program_vao));
    for (int unit = 0; unit < 8; ++unit) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.glBindTexture(GL_TEXTURE_2D, borrowed ? 0 : GLuint(st.program_textures[unit]));
    }
    gl.glActiveTexture(GLenum(st.program_active_texture));
    // A frame of fixed-function draws keeps the caller's program (a pass's own shading);
    // shader draws bring theirs, from the one current when the frame began.
    const bool programs = shown.facts.main_shader_draws;
    if (programs) {
        gl.glUseProgram(GLuint(rec.start_program));
        ctx.current_program = rec.start_program_stream;
    }
    tile_.begin_redraw(correction, programs);
    // Face culling is the program's, draw by draw, and the caller's again afterwards.
    const bool caller_cull = gl.glIsEnabled(GL_CULL_FACE);
    GLint caller_cull_face = GL_BACK, caller_front_face = GL_CCW;
    gl.glGetIntegerv(GL_CULL_FACE_MODE, &caller_cull_face);
    gl.glGetIntegerv(GL_FRONT_FACE, &caller_front_face);
    bool cull = caller_cull;
    GLenum cull_face = GLenum(caller_cull_face), front_face = GLenum(caller_front_face);
    // So is the alpha test of shader programs' draws (their fragment shaders write the alpha it
    // tests); the caller's own shading keeps the caller's.
    const bool alpha_tests = programs && compatibility;
    const bool caller_alpha = alpha_tests && gl.glIsEnabled(GL_ALPHA_TEST);
    GLint caller_alpha_func = GL_ALWAYS;
    GLfloat caller_alpha_ref = 0;
    if (alpha_tests) {
        gl.glGetIntegerv(GL_ALPHA_TEST_FUNC, &caller_alpha_func);
        gl.glGetFloatv(GL_ALPHA_TEST_REF, &caller_alpha_ref);
    }
    bool alpha = caller_alpha;
    GLenum alpha_func = GLenum(caller_alpha_func);
    float alpha_ref = caller_alpha_ref;
    Call c;
    for (const RecordEntry& e : rec.entries) {
        if ((e.draw && !e.main) || (e.program_state && !programs)) continue;
        if (e.opens) {
            if (e.cull != cull) set_enabled(gl, GL_CULL_FACE, cull = e.cull);
            if (e.cull_face != cull_face) gl.glCullFace(cull_face = e.cull_face);
            if (e.front_face != front_face) gl.glFrontFace(front_face = e.front_face);
            if (alpha_tests && e.alpha_test != alpha) set_enabled(gl, GL_ALPHA_TEST, alpha = e.alpha_test);
            if (alpha_tests && e.alpha_test && (e.alpha_func != alpha_func || e.alpha_ref != alpha_ref))
                gl.glAlphaFunc(alpha_func = e.alpha_func, alpha_ref = e.alpha_ref);
        }
        redispatch_entry(core_, rec, e, c);
    }
    tile_.end_redraw();
    set_enabled(gl, GL_CULL_FACE, caller_cull);
    gl.glCullFace(GLenum(caller_cull_face));
    gl.glFrontFace(GLenum(caller_front_face));
    if (alpha_tests) {
        set_enabled(gl, GL_ALPHA_TEST, caller_alpha);
        gl.glAlphaFunc(GLenum(caller_alpha_func), caller_alpha_ref);
    }
    ctx.list_base = saved_list_base;
    ctx.current_program = saved_program_stream;
    gl.glActiveTexture(GLenum(active_texture));
}

void EffectsRunner::put_overlays_back(SlaveContext& ctx, bool overlays, bool target_overlays, GLuint target) {
    ContextPasses& st = passes(ctx);
    const ContextScene& scene = scenes_.scene(ctx);
    const GlApi& gl = core_.api();
    if (!st.overlay_program) {
        st.overlay_program = effects::build_program(gl, "fullscreen.vert", "overlays.frag");
        gl.glGenVertexArrays(1, &st.overlay_vao);
    }
    effects::StateGuard guard(gl);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    gl.glViewport(0, 0, ctx.width, ctx.height);
    gl.glDisable(GL_BLEND);
    gl.glDisable(GL_DEPTH_TEST);
    gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.glUseProgram(st.overlay_program);
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glBindTexture(GL_TEXTURE_2D, st.copies.program_image);
    gl.glActiveTexture(GL_TEXTURE1);
    gl.glBindTexture(GL_TEXTURE_2D, st.copies.scene_image);
    gl.glActiveTexture(GL_TEXTURE2);
    gl.glBindTexture(GL_TEXTURE_2D, scene.facts.view_model_far > 0 ? st.view_model_depth : 0);
    gl.glActiveTexture(GL_TEXTURE3);
    gl.glBindTexture(GL_TEXTURE_2D, target_overlays ? st.copies.scene_target_before : 0);
    gl.glActiveTexture(GL_TEXTURE4);
    gl.glBindTexture(GL_TEXTURE_2D, target_overlays ? st.copies.scene_target_final : 0);
    const GLuint mask = tile_.scene_over_tile();
    gl.glActiveTexture(GL_TEXTURE5);
    gl.glBindTexture(GL_TEXTURE_2D, mask);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "scene_mask"), 5);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "masked"), mask != 0);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "target_before"), 3);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "target_final"), 4);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "target_overlays"), target_overlays);
    int scene_size[2];
    const glm::vec4 texels(st.copies.scene_texels_on_tile(ctx, scene, scenes_.scene_shown(ctx), scene_size));
    // (an overlay engine's colour has the scene's texels: its target holds the scene's depth)
    const GLuint engine = engine_overlay_texture(ctx, scene_size);
    gl.glActiveTexture(GL_TEXTURE6);
    gl.glBindTexture(GL_TEXTURE_2D, engine);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "engine_overlay"), 6);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "engine_overlays"), engine != 0);
    gl.glUniform4f(effects::uniform(gl, st.overlay_program, "target_rect"), texels.x, texels.y, texels.z, texels.w);
    gl.glUniform2f(effects::uniform(gl, st.overlay_program, "tile_size"), GLfloat(ctx.width), GLfloat(ctx.height));
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "final_image"), 0);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "scene_image"), 1);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "scene_depth"), 2);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "overlays"), overlays);
    gl.glUniform1f(effects::uniform(gl, st.overlay_program, "view_model_far"), GLfloat(scene.facts.view_model_far));
    int32_t rect[4];
    scene_rect(ctx, rect);
    gl.glUniform4f(effects::uniform(gl, st.overlay_program, "scene_rect"), GLfloat(rect[0]), GLfloat(rect[1]),
                   GLfloat(rect[2]), GLfloat(rect[3]));
    effects::draw_fullscreen(gl, st.overlay_vao);
}

GLuint EffectsRunner::engine_overlays(SlaveContext& ctx) {
    const SceneFacts& shown = scenes_.scene_shown(ctx).facts;
    if (!shown.main_known || !shown.scene_depth_kept || !shown.overlay_texture) return 0;
    return core_.api().glIsTexture(shown.overlay_texture) ? shown.overlay_texture : 0;  // (deleted since)
}

// The engine's colour (attached to st.engine_fb) copied into a 2D texture of `format` at `size`.
GLuint EffectsRunner::copy_engine_overlay(ContextPasses& st, GLenum format, const int size[2]) {
    const GlApi& gl = core_.api();
    if (!st.engine_copy || st.engine_copy_format != GLint(format) || st.engine_copy_size[0] != size[0] ||
        st.engine_copy_size[1] != size[1]) {
        if (st.engine_copy) {
            gl.glDeleteTextures(1, &st.engine_copy);
            gl.glDeleteFramebuffers(1, &st.engine_copy_fb);
        }
        gl.glGenTextures(1, &st.engine_copy);
        gl.glBindTexture(GL_TEXTURE_2D, st.engine_copy);
        gl.glTexStorage2D(GL_TEXTURE_2D, 1, format, size[0], size[1]);
        gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        st.engine_copy_fb = effects::make_framebuffer(gl, st.engine_copy, 0);
        st.engine_copy_format = GLint(format);
        st.engine_copy_size[0] = size[0], st.engine_copy_size[1] = size[1];
    }
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, st.engine_fb);
    gl.glReadBuffer(GL_COLOR_ATTACHMENT0);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st.engine_copy_fb);
    gl.glBlitFramebuffer(0, 0, size[0], size[1], 0, 0, size[0], size[1], GL_COLOR_BUFFER_BIT, GL_NEAREST);
    return st.engine_copy;
}

// The program's texture is never bound by us: what it is (2D, rectangle, multisampled) is not
// something GL before 4.5 answers, and binding it to the wrong target fails and leaves
// GL_INVALID_OPERATION for the program's next glGetError (glcast replay --verify: 1282 where the
// master's said 0). It is attached to a framebuffer of our own instead, which takes any target,
// and copied by a blit: a multisampled one into a texture of its own format (a blit that resolves
// cannot convert), any other into RGBA16F (the put-back reads only where its alpha is above 0).
GLuint EffectsRunner::engine_overlay_texture(SlaveContext& ctx, const int size[2]) {
    const GLuint engine = engine_overlays(ctx);
    if (!engine || size[0] <= 0 || size[1] <= 0 || !core_.api().has(OP_glTexStorage2D)) return 0;
    ContextPasses& st = passes(ctx);
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    if (!st.engine_fb) gl.glGenFramebuffers(1, &st.engine_fb);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st.engine_fb);
    gl.glFramebufferTexture(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, engine, 0);
    GLint samples = 0, layered = GL_FALSE, component = GL_NONE;
    const bool complete = gl.glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    if (complete) {
        gl.glGetIntegerv(GL_SAMPLES, &samples);
        gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                                 GL_FRAMEBUFFER_ATTACHMENT_LAYERED, &layered);
        gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                                 GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE, &component);
    }
    // (an integer colour blits only into an integer one, and a layered one is not one picture)
    const bool copyable = complete && !layered && component != GL_INT && component != GL_UNSIGNED_INT;
    GLuint texture = 0;
    if (copyable && samples == 0) {
        texture = copy_engine_overlay(st, GL_RGBA16F, size);
    } else if (copyable) {
        GLint bound = 0, format = 0;
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D_MULTISAMPLE, &bound);
        gl.glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, engine);
        gl.glGetTexLevelParameteriv(GL_TEXTURE_2D_MULTISAMPLE, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
        gl.glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, GLuint(bound));
        if (format != 0) texture = copy_engine_overlay(st, GLenum(format), size);
    }
    // (let go of the program's texture: a framebuffer of ours holding it would outlive its deletion)
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st.engine_fb);
    gl.glFramebufferTexture(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0);
    return texture;
}

// The same pixels put back into a mask, then the frame's depth and view, for measurements.
void EffectsRunner::report_scene(SlaveContext& ctx, const effects::FrameView& view, bool overlays,
                                 bool target_overlays, bool kept) {
    ContextPasses& st = passes(ctx);
    const GlApi& gl = core_.api();
    if (st.report_size[0] != ctx.width || st.report_size[1] != ctx.height) {
        effects::StateGuard guard(gl);
        if (st.report_mask) {
            gl.glDeleteTextures(1, &st.report_mask);
            gl.glDeleteFramebuffers(1, &st.report_mask_fb);
        }
        st.report_mask = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height);
        st.report_mask_fb = effects::make_framebuffer(gl, st.report_mask, 0);
        st.report_size[0] = ctx.width, st.report_size[1] = ctx.height;
    }
    {
        effects::StateGuard guard(gl);
        gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st.report_mask_fb);
        gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        gl.glDisable(GL_SCISSOR_TEST);
        gl.glClearColor(0, 0, 0, 0);
        gl.glClear(GL_COLOR_BUFFER_BIT);
    }
    if (kept) put_overlays_back(ctx, overlays, target_overlays, st.report_mask_fb);
    std::string error;
    if (!write_scene_report(gl, core_.options().scene_report_dir, view, st.report_mask_fb, error))
        throw EffectsError("effects: --scene-report: " + error);
}

// Where the frame's scene is in this tile's pixels: the whole window, or the rectangle a borrowed
// scene was drawn to.
void EffectsRunner::scene_rect(SlaveContext& ctx, int32_t out[4]) {
    const SceneLoan& loan = scenes_.scene(ctx).loan;
    out[0] = out[1] = 0, out[2] = ctx.width, out[3] = ctx.height;
    if (!loan.borrowed_from || loan.placement[2] <= loan.placement[0]) return;
    const TileMapping& t = core_.options().tile;
    const int W = ctx.master_width, H = ctx.master_height;
    const int32_t* p = loan.placement;
    if (!t.enabled) {
        std::copy(p, p + 4, out);
        return;
    }
    out[0] = int32_t(t.map_x(p[0], W)), out[1] = int32_t(t.map_y(p[1], H));
    out[2] = out[0] + int32_t(t.map_w(p[0], p[2] - p[0], W)), out[3] = out[1] + int32_t(t.map_h(p[1], p[3] - p[1], H));
}

}  // namespace glcast::slave
