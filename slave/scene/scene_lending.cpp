// Scenes lent between contexts (scene_lending.h).
#include "slave/scene/scene_lending.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "common/gl_state.h"
#include "slave/effects/gl_util.h"
#include "slave/replayer.h"
#include "slave/scene/redraw.h"
#include "slave/scene/scene_recorder.h"
#include "slave/scene/window_copies.h"
#include "slave/tile_adapter.h"

namespace glcast::slave {

namespace {

// The rectangle where the draw that showed a borrowed scene put it is kept while what places it is
// unchanged, for at most kPlacementKeptFrames frames (a placement moved by a buffer upload, which
// the record does not hold, is found again then).
constexpr int kPlacementKeptFrames = 30;

}  // namespace

void drop_borrowed(ContextScene& scene) {
    scene.loan.borrowed_from = 0;
    scene.loan.placement_pending = false;
    scene.facts.main_known = scene.facts.presented = false;
    scene.facts.scene_framebuffer = 0;
    scene.facts.in_part = false;
    scene.facts.scene_texture = 0;
    scene.facts.light = effects::SceneLight{};
}

void SceneLending::note_lendable_scene(SlaveContext&, ContextScene& scene) {
    if (!scene.facts.scene_framebuffer || (scene.presents(core_.frame()) && !scene.facts.in_part)) return;
    const GlApi& gl = core_.api();
    SceneLoan& loan = scene.loan;
    GLint type = GL_NONE, name = 0;
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    loan.scene_texture = type == GL_TEXTURE ? GLuint(name) : 0;  // else: the texture it is resolved into
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    loan.scene_depth_type = GLenum(type);
    loan.scene_depth_name = GLuint(name);
    loan.scene_depth_format = depth_format(gl, GL_DRAW_FRAMEBUFFER);
    loan.scene_size[0] = scene.facts.viewport[2], loan.scene_size[1] = scene.facts.viewport[3];
}

void SceneLending::note_resolved_scene(ContextScene& scene, DrawState& state) {
    if (state.read_framebuffer() != scene.facts.scene_framebuffer) return;
    if (state.color_attachment_type() != GL_TEXTURE) return;
    const GlApi& gl = core_.api();
    GLint name = 0;
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    scene.loan.scene_texture = GLuint(name);
}

const ContextScene& SceneLending::scene_of(const ContextScene& scene) const {
    if (!scene.loan.borrowed_from) return scene;
    auto it = scenes_.find(scene.loan.borrowed_from);
    return it != scenes_.end() ? *it->second : scene;
}

void SceneLending::borrow_scene(SlaveContext& ctx, ContextScene& scene, DrawState& state) {
    const GlApi& gl = core_.api();
    for (auto& [id, other] : scenes_) {
        const SceneLoan& lent = other->loan;
        const SceneFacts& lent_facts = other->facts;
        if (id == ctx.id || other->presents(core_.frame()) || !lent_facts.main_known || !lent.scene_texture || other->record.overflow)
            continue;
        const SlaveContext* lender = core_.context(id);
        if (!lender || lender->names.shared != ctx.names.shared) continue;  // the same name, another texture
        // (its target's colour, the texture it was resolved into, or the one a draw of its size
        // copied it into since: Blender's viewport reaches the window through post-processing)
        if (!state.samples_texture(lent.scene_texture) &&
            !(lent_facts.in_part && lent_facts.scene_texture && state.samples_texture(lent_facts.scene_texture)))
            continue;
        BorrowerObjects& objects = scene.borrower;
        // Its depth, attached to a framebuffer object of this context.
        GLint read = 0;
        gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
        if (!objects.lender_fb) gl.glGenFramebuffers(1, &objects.lender_fb);
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, objects.lender_fb);
        gl.glFramebufferRenderbuffer(GL_READ_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, 0);
        const bool packed = lent.scene_depth_format == GL_DEPTH24_STENCIL8 || lent.scene_depth_format == GL_DEPTH32F_STENCIL8;
        const GLenum attachment = packed ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT;
        if (lent.scene_depth_type == GL_RENDERBUFFER)
            gl.glFramebufferRenderbuffer(GL_READ_FRAMEBUFFER, attachment, GL_RENDERBUFFER, lent.scene_depth_name);
        else if (lent.scene_depth_type == GL_TEXTURE)
            gl.glFramebufferTexture2D(GL_READ_FRAMEBUFFER, attachment, GL_TEXTURE_2D, lent.scene_depth_name, 0);
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
        SceneFacts& facts = scene.facts;
        scene.loan.borrowed_from = id;
        facts.main_known = facts.presented = true;
        facts.scene_framebuffer = objects.lender_fb;
        facts.projection = lent_facts.projection, facts.modelview = lent_facts.modelview, facts.light = lent_facts.light;
        std::copy(lent_facts.viewport, lent_facts.viewport + 4, facts.viewport);
        scene.loan.placement_pending = true;
        scene.loan.placement_from = scene.record.entries.size();
        return;
    }
}

void SceneLending::show_own_scene(SlaveContext& ctx, ContextScene& scene) {
    scene.loan.borrowed_from = ctx.id;
    scene.loan.placement_pending = true;
    scene.loan.placement_from = scene.record.entries.size();
}

void SceneLending::show_own_scene(SlaveContext& ctx, ContextScene& scene, const int32_t source[4],
                                  const int32_t destination[4]) {
    show_own_scene(ctx, scene);
    scene.loan.placement_given = true;
    std::copy(destination, destination + 4, scene.loan.placement);
    std::copy(source, source + 4, scene.loan.placement_source);
}

// The draw that showed a borrowed scene, drawn again in the master's window coordinates: its
// footprint is where the scene is.
bool SceneLending::measure_placement(SlaveContext& ctx, ContextScene& scene, size_t end, int32_t out[4]) {
    BorrowerObjects& st = scene.borrower;
    const FrameRecord& rec = scene.record;
    const GlApi& gl = core_.api();
    int32_t viewport[4];
    tile_.program_viewport(viewport);  // the program's, for that draw
    const bool compatibility = compatibility_profile(gl);
    const PendingClientArrays pending(ctx);
    try {
        GlStateGuard guard(gl, kGuardPass | kGuardPixelPack |
                                   (compatibility ? kGuardMatrixStacks | kGuardMatrixMode : 0));
        GLint program = 0;
        gl.glGetIntegerv(GL_CURRENT_PROGRAM, &program);
        GLdouble range[2] = {0, 1};
        gl.glGetDoublev(GL_DEPTH_RANGE, range);
        st.placement.begin(gl, ctx.master_width, ctx.master_height, viewport);
        // The depth range and the tile's redraw mode are put back however the redraw ends.
        struct Redrawing {
            const GlApi& gl;
            TileAdapter& tile;
            const GLdouble* range;
            Redrawing(const GlApi& g, TileAdapter& t, bool programs, const GLdouble* r) : gl(g), tile(t), range(r) {
                tile.begin_redraw(glm::dmat4(1.0), programs);
            }
            ~Redrawing() {
                tile.end_redraw();
                gl.glDepthRange(range[0], range[1]);
            }
        };
        {
            Redrawing redrawing(gl, tile_, program != 0, range);
            Call c;
            for (size_t i = scene.loan.placement_from; i < end; ++i) redispatch_entry(core_, rec, rec.entries[i], c);
        }
        return st.placement.measure(gl, out);
    } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "glcast: effects: cannot place another context's scene: %s\n", e.what());
    }
    return false;
}

// Measuring costs a draw, a clear and a read-back of the master's window size (docs/performance.md),
// so the last frame's rectangle is kept while the frame's calls up to that draw are the same
// bytes, with the same viewport and lender. False: the draw was not kept, or drew nothing.
bool SceneLending::measured_placement(SlaveContext& ctx, ContextScene& scene, int32_t rect[4]) {
    BorrowerObjects& st = scene.borrower;
    const FrameRecord& rec = scene.record;
    const SceneLoan& loan = scene.loan;
    if (rec.entries.size() <= loan.placement_from) return false;
    size_t end = loan.placement_from + 1;  // the draw only: its opening call and its block
    while (end < rec.entries.size() && rec.entries[end].draw && !rec.entries[end].opens) end++;
    int32_t viewport[4];
    tile_.program_viewport(viewport);
    const RecordEntry& last = rec.entries[end - 1];
    uint64_t key = 1469598103934665603ull;  // FNV-1a of what places it
    auto mix = [&key](const void* p, size_t n) {
        for (size_t i = 0; i < n; ++i) key = (key ^ static_cast<const uint8_t*>(p)[i]) * 1099511628211ull;
    };
    mix(rec.bytes.data(), last.begin + last.size);
    mix(viewport, sizeof viewport);
    mix(&loan.borrowed_from, sizeof loan.borrowed_from);
    mix(&ctx.master_width, sizeof ctx.master_width);
    mix(&ctx.master_height, sizeof ctx.master_height);
    if (st.placement_known && st.placement_key == key && st.placement_age < kPlacementKeptFrames) {
        std::copy(st.placement_rect, st.placement_rect + 4, rect);
        st.placement_age++;
    } else if (measure_placement(ctx, scene, end, rect)) {
        std::copy(rect, rect + 4, st.placement_rect);
        st.placement_known = true, st.placement_key = key, st.placement_age = 0;
    } else {
        st.placement_known = false;
        return false;
    }
    return rect[0] < rect[2];
}

void SceneLending::place_borrowed_scene(SlaveContext& ctx, ContextScene& scene) {
    SceneLoan& loan = scene.loan;
    loan.placement_pending = false;
    auto lender = scenes_.find(loan.borrowed_from);
    if (lender == scenes_.end()) {
        drop_borrowed(scene);
        return;
    }
    const SceneLoan& lent = lender->second->loan;
    int32_t rect[4];
    if (tile_.scene_over_tile()) {  // a rotated tile showed the scene, turned, over all of itself
        rect[0] = rect[1] = 0, rect[2] = ctx.master_width, rect[3] = ctx.master_height;
    } else if (loan.placement_given) {  // a blit's: where it put the whole of the scene's target
        const int32_t* d = loan.placement;
        const int32_t* s = loan.placement_source;
        for (int axis = 0; axis < 2; ++axis) {
            // (the stream's rectangles: in doubles, and the result kept to the int32 range)
            const double scale = (double(d[axis + 2]) - d[axis]) / std::max(1.0, double(s[axis + 2]) - s[axis]);
            const auto clamped = [](double v) { return int32_t(std::clamp(v, double(INT32_MIN), double(INT32_MAX))); };
            rect[axis] = clamped(std::round(d[axis] - s[axis] * scale));
            rect[axis + 2] = clamped(std::round(d[axis] + (lent.scene_size[axis] - double(s[axis])) * scale));
        }
    } else if (!measured_placement(ctx, scene, rect)) {
        rect[0] = rect[2] = 0;
    }
    if (rect[0] >= rect[2] || rect[1] >= rect[3]) {  // nothing drawn, or a blit mirrored: not shown
        drop_borrowed(scene);
        return;
    }
    int32_t lent_viewport[4];  // (the scene's own when it is this context's: copied before it is placed)
    std::copy(lender->second->facts.viewport, lender->second->facts.viewport + 4, lent_viewport);
    std::copy(rect, rect + 4, loan.placement);
    // The lender's viewport, in its target's pixels, placed and scaled as the window shows them.
    const double sx = (double(rect[2]) - rect[0]) / std::max(1, lent.scene_size[0]);
    const double sy = (double(rect[3]) - rect[1]) / std::max(1, lent.scene_size[1]);
    int32_t* v = scene.facts.viewport;
    v[0] = int32_t(std::lround(rect[0] + lent_viewport[0] * sx));
    v[1] = int32_t(std::lround(rect[1] + lent_viewport[1] * sy));
    v[2] = int32_t(std::lround(lent_viewport[2] * sx));
    v[3] = int32_t(std::lround(lent_viewport[3] * sy));
}

}  // namespace glcast::slave
