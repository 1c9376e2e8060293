// Recording the frame's scene, call by call (scene_recorder.h).
#include "slave/scene/scene_recorder.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

#include "protocol/format.h"
#include "slave/replayer.h"
#include "slave/scene/window_copies.h"
#include "slave/tile_adapter.h"

namespace glcast::slave {

ContextScene& SceneRecorder::scene(const SlaveContext& ctx) {
    auto& s = scenes_[ctx.id];
    if (!s) s = std::make_unique<ContextScene>();
    return *s;
}

void SceneRecorder::follow(SlaveContext& ctx, const Call& c) { scene(ctx).followed.follow(c, ctx.names); }

namespace {

// The rectangle x0, y0, x1, y1 (master window coordinates, either way round) covers the program's
// whole window.
bool covers_window(const SlaveContext& ctx, const int32_t r[4]) {
    return std::min(r[0], r[2]) <= 0 && std::min(r[1], r[3]) <= 0 &&
           std::max(int64_t(r[0]), int64_t(r[2])) >= ctx.master_width &&
           std::max(int64_t(r[1]), int64_t(r[3])) >= ctx.master_height;
}

}  // namespace

ClassifierSettings SceneRecorder::settings(const SlaveContext& ctx) const {
    return ClassifierSettings{core_.options().view.program_fov_y_deg != 0, core_.options().effects.redraws(),
                              ctx.master_width, ctx.master_height};
}

void SceneRecorder::record(SlaveContext& ctx, const Call& c, const uint8_t* tuple, size_t tuple_size) {
    if (c.opcode >= kSynthBase && c.opcode != kSynthClientArrays) return;
    ContextScene& sc = scene(ctx);
    FrameRecord& rec = sc.record;
    SceneFacts& facts = sc.facts;
    const GlApi& gl = core_.api();
    if (sc.loan.placement_pending && !rec.in_begin_end && rec.entries.size() > sc.loan.placement_from)
        lending_.place_borrowed_scene(ctx, sc);  // the draw that shows a borrowed scene has run
    const int mode = c.info ? c.info->sem.primitive_param : -1;
    DriverDrawState state(gl, tile_, sc.followed, mode >= 0 ? GLenum(c.args[mode].bits) : GLenum(GL_TRIANGLES));
    if (sc.loan.complete && !ctx.drawing_to_window && state.draw_framebuffer() == facts.scene_framebuffer)
        sc.next_frame();  // a lent scene is kept until its next
    if (!rec.started) {
        rec.started = true;
        rec.start_program = GLint(state.program());
        rec.start_program_stream = ctx.current_program;
    }
    const RedrawKind kind = c.opcode >= kSynthBase ? RedrawKind::State : c.info->sem.redraw;
    if (kind == RedrawKind::NewList || kind == RedrawKind::EndList) {  // never re-executed
        rec.compiling_list = kind == RedrawKind::NewList;
        return;
    }
    if (kind == RedrawKind::Ignored && !rec.in_begin_end) return;
    if (rec.compiling_list) return;
    const bool to_window = ctx.drawing_to_window;
    if (kind == RedrawKind::Clear) {  // never kept
        if (to_window && !rec.in_begin_end && !facts.main_known && !facts.overlay &&
            clears_whole_colour(gl, GLbitfield(c.args[0].bits)))
            facts.window_cleared = true;
        if (to_window && !rec.in_begin_end && depth_clear_starts_overlays(facts, GLbitfield(c.args[0].bits)) &&
            on_overlays_start)
            on_overlays_start(ctx);
        return;
    }
    if (kind == RedrawKind::Copy && !to_window && facts.main_known && facts.scene_framebuffer &&
        !sc.loan.scene_texture && !sc.presents(core_.frame()))
        lending_.note_resolved_scene(sc, state);
    if ((kind == RedrawKind::Copy || ((kind == RedrawKind::Draw || kind == RedrawKind::Begin) && !rec.in_begin_end)) &&
        !to_window)
        follow_scene_texture(facts, state, kind);  // a scene shown in part of the window, copied on
    // Into a framebuffer object: shader-program and vertex state are kept (the scene may be drawn
    // there), draws only into the one that can hold the scene.
    GLuint framebuffer = 0;
    const bool opens = (kind == RedrawKind::Draw || kind == RedrawKind::Begin) && !rec.in_begin_end;
    if (opens && !to_window && later_scene_target(facts, state, ctx.master_width, ctx.master_height))
        for (RecordEntry& e : rec.entries) e.main = e.main && !e.offscreen;
    if (opens && !to_window && on_scene_depth_shared && scene_depth_overlay_starts(facts, state))
        on_scene_depth_shared(ctx);
    if (!to_window && !rec.in_begin_end &&
        (opens ? !offscreen_scene(facts, state, ctx.master_width, ctx.master_height, framebuffer)
               : kind != RedrawKind::State && kind != RedrawKind::ProgramState))
        return;
    if (opens && !to_window && framebuffer && framebuffer == facts.scene_framebuffer &&
        scene_target_overlays_start(facts, state, kind) && on_target_overlays_start)
        on_target_overlays_start(ctx);
    if (kind == RedrawKind::Copy) {  // a blit to the window shows an offscreen scene there
        const CommandSemantics& sem = c.info->sem;
        if (!facts.scene_framebuffer || facts.overlay) return;
        if (sem.window != WindowMapping::Blit) {  // (its rectangles not annotated)
            if (!facts.in_part) facts.presented = true;
            return;
        }
        int32_t destination[4], source[4];
        for (int k = 0; k < 4; ++k)
            destination[k] = core_.value<GLint>(c, sem.window_params[k]),
            source[k] = core_.value<GLint>(c, sem.window_params[4 + k]);
        const bool shown_before = facts.presented;
        if (window_blit(facts, state, source, destination) == WindowDrawMeaning::ShowsInPart)
            lending_.show_own_scene(ctx, sc, source, destination);
        else if (!shown_before && facts.presented)
            facts.shown_whole = covers_window(ctx, destination);
        return;
    }
    if (sc.loan.borrowed_from && to_window && opens && state.writes_depth()) {
        // A 3D draw to the window: the other context's texture was a picture in this program's
        // own scene (a preview), not its view; the main view is looked for among the window's.
        drop_borrowed(sc);
        facts.overlay = false;
    }
    if (facts.main_known && !facts.overlay && !rec.in_begin_end && to_window) {
        const bool shown_before = facts.presented;
        const WindowDrawMeaning meaning = window_draw(facts, state, kind);
        if (!shown_before && facts.presented && !facts.in_part) {
            int32_t v[4];
            state.viewport(v);
            const int32_t r[4] = {v[0], v[1], int32_t(int64_t(v[0]) + v[2]), int32_t(int64_t(v[1]) + v[3])};
            facts.shown_whole = covers_window(ctx, r);
        }
        switch (meaning) {
        case WindowDrawMeaning::Scene: break;
        case WindowDrawMeaning::StartsOverlays:
            if (on_overlays_start) on_overlays_start(ctx);
            break;
        case WindowDrawMeaning::NotTheScene:
            for (RecordEntry& e : rec.entries) e.main = e.main && !e.offscreen;
            break;
        case WindowDrawMeaning::ShowsInPart: lending_.show_own_scene(ctx, sc); break;
        }
    }
    if (rec.overflow || kind == RedrawKind::Pixels) return;
    if (c.info && c.info->sem.redraw_first_count) {  // e.g. only the targets glPushClientAttrib restores
        const uint64_t first = c.args[0].bits;
        const uint32_t* v = c.info->sem.redraw_first_values;
        if (std::find(v, v + c.info->sem.redraw_first_count, first) == v + c.info->sem.redraw_first_count) return;
    }

    RecordEntry e;
    e.begin = rec.bytes.size(), e.size = tuple_size;
    e.program_state = kind == RedrawKind::ProgramState;
    e.offscreen = !to_window;
    if (opens) {
        if (to_window && !facts.main_known && !facts.overlay) lending_.borrow_scene(ctx, sc, state);
        e.draw = e.opens = true;
        const DrawVerdict verdict = classify_draw(facts, state, framebuffer, settings(ctx));
        if (verdict.found_view) lending_.note_lendable_scene(ctx, sc);
        if ((verdict.marks_start || verdict.keeps_depth || verdict.over_end) && on_over_scene) on_over_scene(ctx, verdict);
        if (verdict.over_end) lending_.note_lendable_scene(ctx, sc);  // (its own depth again, not the kept)
        e.main = verdict.main;
        if (e.main) {
            e.cull = verdict.cull.enabled;
            e.cull_face = uint16_t(verdict.cull.cull_face), e.front_face = uint16_t(verdict.cull.front_face);
            e.alpha_test = verdict.alpha.enabled;
            e.alpha_func = uint16_t(verdict.alpha.func), e.alpha_ref = float(verdict.alpha.ref);
        }
        if (kind == RedrawKind::Begin) rec.in_begin_end = true, rec.begin_is_main = e.main;
    } else if (rec.in_begin_end) {
        e.draw = true;
        e.main = rec.begin_is_main;
        if (kind == RedrawKind::End) rec.in_begin_end = false;
    } else if (!facts.main_known && to_window && c.info && c.info->sem.matrix == MatrixOp::Push) {
        note_push(facts, state);
    }
    if (!rec.append(tuple, tuple_size, e))
        std::fprintf(stderr, "glcast replay: frame %" PRIu64 " records more than %zu MiB of draws: the injected passes "
                     "cannot re-render it\n", core_.frame(), kMaxRecordBytes >> 20);
}

void SceneRecorder::frame_drawn(SlaveContext& ctx) {
    ContextScene& sc = scene(ctx);
    sc.last_present = core_.frame();
    if (sc.loan.placement_pending) lending_.place_borrowed_scene(ctx, sc);
    if (sc.facts.in_part && !sc.loan.borrowed_from) drop_borrowed(sc);  // drawn, never shown
}

void SceneRecorder::frame_decorated(SlaveContext& ctx) {
    for (auto& [id, other] : scenes_) {
        if (id == ctx.id || other->presents(core_.frame()) || other->record.in_begin_end || other->record.compiling_list) continue;
        if (other->facts.main_known && other->loan.scene_texture) other->loan.complete = true;
        else other->next_frame();
    }
}

}  // namespace glcast::slave
