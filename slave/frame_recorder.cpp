// Recording what a frame draws, re-rendering it for a pass, and describing the frame to the
// passes (slave/frame_recorder.h).
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "common/gl_headers.h"
#include "protocol/format.h"
#include "slave/effects/gl_util.h"
#include "slave/frame_recorder.h"
#include "slave/program_camera.h"
#include "slave/replayer.h"
#include "slave/tile_adapter.h"

namespace glcast::slave {

namespace {

bool is_perspective(const glm::dmat4& p) { return p[2][3] != 0 && p[3][3] == 0; }

// A view turned inside out (glScalef(1, -1, 1)): a game's planar reflection, drawn below its
// floor before the scene (neverball). No camera is: it is not the main view.
bool mirrored(const glm::dmat4& modelview) { return glm::determinant(glm::dmat3(modelview)) < 0; }

bool writes_depth(const GlApi& gl) {
    GLboolean mask = GL_FALSE;
    gl.glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    return mask && gl.glIsEnabled(GL_DEPTH_TEST);
}

// glDepthRange(0, f) with f < 1: a draw kept in front of the world (a view model), or 0.
double view_model_depth_range(const GlApi& gl) {
    GLdouble range[2] = {0, 1};
    gl.glGetDoublev(GL_DEPTH_RANGE, range);
    return range[0] == 0 && range[1] > 0 && range[1] < 1 ? range[1] : 0;
}

void set_enabled(const GlApi& gl, GLenum cap, bool on) {
    if (on) gl.glEnable(cap);
    else gl.glDisable(cap);
}

// The depth format of a framebuffer attachment, from what GL says of it: a depth blit needs the
// same format on both sides. 0 when it has no depth.
GLenum depth_format(const GlApi& gl, GLenum target) {
    GLint type = GL_NONE, name = 0, stencil_type = GL_NONE, stencil_name = 0, bits = 0, component = GL_NONE;
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type == GL_NONE) return 0;
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &bits);
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE,
                                             &component);
    gl.glGetFramebufferAttachmentParameteriv(target, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE,
                                             &stencil_type);
    if (stencil_type != GL_NONE)
        gl.glGetFramebufferAttachmentParameteriv(target, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME,
                                                 &stencil_name);
    const bool packed = stencil_type == type && stencil_name == name;  // one depth-stencil image
    if (component == GL_FLOAT) return packed ? GL_DEPTH32F_STENCIL8 : GL_DEPTH_COMPONENT32F;
    if (bits <= 16) return GL_DEPTH_COMPONENT16;
    if (bits <= 24) return packed ? GL_DEPTH24_STENCIL8 : GL_DEPTH_COMPONENT24;
    return GL_DEPTH_COMPONENT32;
}



// The pending client-array ranges of a context (slave/replayer.h), put back when a redraw ends:
// a glcast.client_arrays tuple whose draw the redraw leaves out would otherwise stay pending and
// be checked against the program's next draw.
class PendingClientArrays {
public:
    explicit PendingClientArrays(SlaveContext& ctx)
        : ctx_(ctx), pending_(ctx.client_range_pending), refused_(ctx.client_arrays_refused), first_(ctx.client_first),
          end_(ctx.client_end), instances_(ctx.client_instances) {}
    ~PendingClientArrays() {
        ctx_.client_range_pending = pending_, ctx_.client_arrays_refused = refused_;
        ctx_.client_first = first_, ctx_.client_end = end_;
        ctx_.client_instances = std::move(instances_);
    }
    PendingClientArrays(const PendingClientArrays&) = delete;
    PendingClientArrays& operator=(const PendingClientArrays&) = delete;

private:
    SlaveContext& ctx_;
    bool pending_, refused_;
    int64_t first_, end_;
    std::vector<ClientInstanceRange> instances_;
};

}  // namespace

FrameRecorder::~FrameRecorder() = default;

EffectsState& FrameRecorder::state(const SlaveContext& ctx) {
    auto& st = states_[ctx.id];
    if (!st) st = std::make_unique<EffectsState>();
    return *st;
}

// Everything the record may keep (semantics.yaml redraw) and, inside glBegin/glEnd, every call.
bool FrameRecorder::wants(uint32_t opcode, const CommandInfo* info) const {
    return info ? true : opcode == kSynthClientArrays;
}

void FrameRecorder::before_call(const Call& c, const uint8_t* tuple, size_t bytes) {
    if (core_.current_or_null()) record(c, tuple, bytes);
}

void FrameRecord::drop_borrowed() {
    borrowed_from = 0;
    main_known = presented = placement_pending = false;
    scene_framebuffer = 0;
    light = effects::SceneLight{};
}

void FrameRecord::clear() {
    bytes.clear();
    entries.clear();
    in_begin_end = begin_is_main = compiling_list = overflow = shader_draws = main_known = pushed = overlay = false;
    started = presented = false;
    scene_framebuffer = 0;
    camera_probes = 0;
    view_model_far = 0;
    light = effects::SceneLight{};
    scene_texture = scene_depth_name = 0;
    scene_depth_type = GL_NONE, scene_depth_format = 0;
    scene_size[0] = scene_size[1] = 0;
    complete = placement_pending = false;
    borrowed_from = 0;
    placement_from = 0;
    std::fill(placement, placement + 4, 0);
}

void FrameRecorder::record(const Call& c, const uint8_t* tuple, size_t tuple_size) {
    if (c.opcode >= kSynthBase && c.opcode != kSynthClientArrays) return;
    SlaveContext& ctx = core_.current();
    if (c.info && (c.info->sem.flags & kSemLinksProgram))  // which matrices a program has may change
        for (auto& [id, st] : states_)
            if (st->program_cameras) st->program_cameras->forget();
    FrameRecord& rec = state(ctx).record;
    const GlApi& gl = core_.api();
    if (rec.placement_pending && !rec.in_begin_end && rec.entries.size() > rec.placement_from)
        place_borrowed_scene(ctx);  // the draw that shows a borrowed scene has run
    if (rec.complete && !ctx.drawing_to_window) {  // a lent scene is kept until its next
        GLint bound = 0;
        gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
        if (GLuint(bound) == rec.scene_framebuffer) rec.clear();
    }
    if (!rec.started) {
        rec.started = true;
        gl.glGetIntegerv(GL_CURRENT_PROGRAM, &rec.start_program);
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
    if (kind == RedrawKind::Copy && !to_window && rec.main_known && rec.scene_framebuffer && !rec.scene_texture &&
        !state(ctx).presents)
        note_resolved_scene(rec);
    // Into a framebuffer object: shader-program and vertex state are kept (the scene may be drawn
    // there), draws only into the one that can hold the scene.
    GLuint framebuffer = 0;
    const bool opens = (kind == RedrawKind::Draw || kind == RedrawKind::Begin) && !rec.in_begin_end;
    if (!to_window && !rec.in_begin_end &&
        (opens ? !offscreen_scene(ctx, rec, framebuffer) : kind != RedrawKind::State && kind != RedrawKind::ProgramState))
        return;
    if (kind == RedrawKind::Copy) {  // a blit to the window shows an offscreen scene there
        if (rec.scene_framebuffer && !rec.overlay) rec.presented = true;
        return;
    }
    if (rec.borrowed_from && to_window && opens && writes_depth(gl)) {
        // A 3D draw to the window: the other context's texture was a picture in this program's
        // own scene (a preview), not its view; the main view is looked for among the window's.
        rec.drop_borrowed();
        rec.overlay = false;
    }
    if (rec.main_known && !rec.overlay && !rec.in_begin_end && to_window) watch_overlays(ctx, kind);
    if (rec.overflow || kind == RedrawKind::Pixels) return;
    if (c.info && c.info->sem.redraw_first_count) {  // e.g. only the targets glPushClientAttrib restores
        const uint64_t first = c.args[0].bits;
        const uint32_t* v = c.info->sem.redraw_first_values;
        if (std::find(v, v + c.info->sem.redraw_first_count, first) == v + c.info->sem.redraw_first_count) return;
    }

    FrameRecord::Entry e{rec.bytes.size(), tuple_size, false, false, false, kind == RedrawKind::ProgramState,
                         !to_window};
    if (opens) {
        if (to_window && !rec.main_known && !rec.overlay) borrow_scene(ctx, rec);
        GLint program = 0;
        gl.glGetIntegerv(GL_CURRENT_PROGRAM, &program);
        e.draw = e.opens = true;
        if (const double far = view_model_depth_range(gl)) {
            // Neither the main view nor a part of it: its pixels go back as the program drew them.
            if (rec.main_known && !rec.overlay) rec.view_model_far = std::max(rec.view_model_far, far);
            if (program) rec.shader_draws = true;
        } else if (program) {
            rec.shader_draws = true;
            e.main = shader_draw_is_main(ctx, rec, GLuint(program), framebuffer);
        } else {
            const glm::dmat4 app = tile_.program_projection_now();
            // A backdrop drawn first without depth writes (neverball's star field) is neither the
            // main view nor, after it, the start of the overlays; the window's depth does not
            // have it, and the redraw leaves it out.
            const bool depth = writes_depth(gl);
            glm::dmat4 modelview(1.0);
            if (!rec.main_known && is_perspective(app) && depth) {
                GLdouble mv[16];
                gl.glGetDoublev(GL_MODELVIEW_MATRIX, mv);
                std::memcpy(&modelview[0][0], mv, sizeof mv);
            }
            if (!rec.main_known && is_perspective(app) && depth && !mirrored(modelview)) {
                rec.main_known = true;
                rec.scene_framebuffer = framebuffer;
                rec.projection = app;
                // (a push made inside a reflection is not the view)
                rec.modelview = rec.pushed && !mirrored(rec.last_push) ? rec.last_push : modelview;
                tile_.program_viewport(rec.viewport);
                note_lendable_scene(ctx, rec);
                GLboolean lighting = GL_FALSE;
                gl.glGetBooleanv(GL_LIGHTING, &lighting);
                for (GLenum light = GL_LIGHT0; lighting && light < GL_LIGHT0 + 8; ++light) {
                    GLboolean on = GL_FALSE;
                    gl.glGetBooleanv(light, &on);
                    if (!on) continue;
                    GLfloat pos[4];
                    gl.glGetLightfv(light, GL_POSITION, pos);
                    rec.light = effects::SceneLight{true, glm::dvec4(pos[0], pos[1], pos[2], pos[3])};
                    break;
                }
            }
            e.main = rec.main_known && app == rec.projection && depth && framebuffer == rec.scene_framebuffer;
        }
        if (e.main) {
            GLint cull_face = GL_BACK, front_face = GL_CCW;
            gl.glGetIntegerv(GL_CULL_FACE_MODE, &cull_face);
            gl.glGetIntegerv(GL_FRONT_FACE, &front_face);
            e.cull = gl.glIsEnabled(GL_CULL_FACE);
            e.cull_face = uint16_t(cull_face), e.front_face = uint16_t(front_face);
        }
        if (kind == RedrawKind::Begin) rec.in_begin_end = true, rec.begin_is_main = e.main;
    } else if (rec.in_begin_end) {
        e.draw = true;
        e.main = rec.begin_is_main;
        if (kind == RedrawKind::End) rec.in_begin_end = false;
    } else if (!rec.main_known && to_window && c.info && c.info->sem.matrix == MatrixOp::Push) {
        GLint mode = 0;  // the value a push saves is the one on top before it
        gl.glGetIntegerv(GL_MATRIX_MODE, &mode);
        if (mode == GL_MODELVIEW) {
            GLdouble mv[16];
            gl.glGetDoublev(GL_MODELVIEW_MATRIX, mv);
            std::memcpy(&rec.last_push[0][0], mv, sizeof mv);
            rec.pushed = true;
        }
    }
    if (rec.bytes.size() + tuple_size > kMaxRecordBytes) {
        rec.overflow = true;
        std::fprintf(stderr, "glcast replay: frame %" PRIu64 " records more than %zu MiB of draws: the injected passes "
                     "cannot re-render it\n", core_.frame(), kMaxRecordBytes >> 20);
        return;
    }
    rec.bytes.insert(rec.bytes.end(), tuple, tuple + tuple_size);
    rec.entries.push_back(e);
}

// A shader program's draw belongs to the main view when its camera (found from its matrices,
// program_camera.h) has the main view's projection, the first such draw making the main view;
// with a program_projection in the display config, every draw before the overlays does. Only
// draws that write depth with the depth test on: a sky drawn without depth is no caster, and
// the window's depth does not have it either.
bool FrameRecorder::shader_draw_is_main(SlaveContext& ctx, FrameRecord& rec, GLuint program, GLuint framebuffer) {
    const GlApi& gl = core_.api();
    const bool configured = core_.options().view.program_fov_y_deg != 0;
    const bool redrawn = core_.options().effects.redraws();
    if (rec.main_known && !redrawn) return false;  // no pass re-renders: the camera is all we need
    if (configured) return redrawn && !rec.overlay && writes_depth(gl) && framebuffer == 0;
    if (!rec.main_known && rec.camera_probes >= kMaxCameraProbes) return false;
    ProgramCamera camera;
    if (!rec.main_known) rec.camera_probes++;
    if (!state(ctx).cameras(gl).find(program, camera)) return false;
    if (!rec.main_known && mirrored(camera.modelview)) return false;  // a reflection's camera
    if (!rec.main_known) {
        rec.main_known = true;
        rec.scene_framebuffer = framebuffer;
        rec.projection = camera.projection;
        rec.modelview = camera.modelview;
        tile_.program_viewport(rec.viewport);
        note_lendable_scene(ctx, rec);
    }
    return !rec.overlay && camera.projection == rec.projection && writes_depth(gl) && framebuffer == rec.scene_framebuffer;
}

bool FrameRecorder::offscreen_scene(SlaveContext& ctx, const FrameRecord& rec, GLuint& framebuffer) {
    const GlApi& gl = core_.api();
    GLint bound = 0;
    gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    framebuffer = GLuint(bound);
    if (rec.main_known) return rec.scene_framebuffer != 0 && framebuffer == rec.scene_framebuffer;
    if (rec.overlay || rec.presented || !framebuffer) return false;
    int32_t viewport[4];
    tile_.program_viewport(viewport);
    if (viewport[0] != 0 || viewport[1] != 0) return false;
    if (viewport[2] != ctx.master_width || viewport[3] != ctx.master_height) {
        // A context that has never presented, beside another of its share group, draws for it
        // (a toolkit's GL widget): its scene target has the widget's size, and a colour texture
        // (or multisampled renderbuffers resolved into one) the other can show. (A program's
        // only context has not presented in its first frame either: its smaller targets are not
        // scenes.)
        if (state(ctx).presents || !shares_with_another(ctx)) return false;
        GLint color = GL_NONE;
        gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                                 GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &color);
        if (color == GL_NONE) return false;
    }
    GLint type = GL_NONE;
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    return type != GL_NONE;
}

// Runs one recorded call again (a redraw): a call the stream got wrong was reported when the
// frame was replayed, and is skipped here.
void FrameRecorder::redispatch_entry(const FrameRecord& rec, const FrameRecord::Entry& e, Call& c) {
    ByteReader r(rec.bytes.data() + e.begin, e.size, 0);
    decode_tuple(r, c);
    try {
        core_.redispatch(c);
    } catch (const ReplayError&) {
    } catch (const GlMissing&) {
    }
}

bool FrameRecorder::shares_with_another(const SlaveContext& ctx) const {
    for (const auto& [id, other] : core_.contexts())
        if (id != ctx.id && other->names.shared == ctx.names.shared) return true;
    return false;
}

void FrameRecorder::note_lendable_scene(SlaveContext& ctx, FrameRecord& rec) {
    if (!rec.scene_framebuffer || state(ctx).presents) return;
    const GlApi& gl = core_.api();
    GLint type = GL_NONE, name = 0;
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    rec.scene_texture = type == GL_TEXTURE ? GLuint(name) : 0;  // else: the texture it is resolved into
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    rec.scene_depth_type = GLenum(type);
    rec.scene_depth_name = GLuint(name);
    rec.scene_depth_format = depth_format(gl, GL_DRAW_FRAMEBUFFER);
    rec.scene_size[0] = rec.viewport[2], rec.scene_size[1] = rec.viewport[3];
}

// A lending context's multisampled scene resolved (glBlitFramebuffer) into a framebuffer object
// whose colour is a texture: that texture shows the scene.
void FrameRecorder::note_resolved_scene(FrameRecord& rec) {
    const GlApi& gl = core_.api();
    GLint read = 0, type = GL_NONE, name = 0;
    gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
    if (GLuint(read) != rec.scene_framebuffer) return;
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_TEXTURE) return;
    gl.glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    rec.scene_texture = GLuint(name);
}

const FrameRecord& FrameRecorder::scene_record(const SlaveContext& ctx) {
    FrameRecord& rec = state(ctx).record;
    if (!rec.borrowed_from) return rec;
    auto it = states_.find(rec.borrowed_from);
    return it != states_.end() ? it->second->record : rec;
}

void FrameRecorder::borrow_scene(SlaveContext& ctx, FrameRecord& rec) {
    const GlApi& gl = core_.api();
    GLint sampled[8] = {}, active = GL_TEXTURE0;
    bool lenders = false;
    for (auto& [id, other] : states_) lenders = lenders || (id != ctx.id && other->record.scene_texture);
    if (!lenders) return;
    gl.glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    for (int unit = 0; unit < 8; ++unit) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &sampled[unit]);
    }
    gl.glActiveTexture(GLenum(active));
    for (auto& [id, other] : states_) {
        const FrameRecord& lent = other->record;
        if (id == ctx.id || other->presents || !lent.main_known || !lent.scene_texture || lent.overflow) continue;
        const SlaveContext* lender = core_.context(id);
        if (!lender || lender->names.shared != ctx.names.shared) continue;  // the same name, another texture
        if (std::find(sampled, sampled + 8, GLint(lent.scene_texture)) == sampled + 8) continue;
        EffectsState& st = state(ctx);
        // Its depth, attached to a framebuffer object of this context.
        GLint read = 0;
        gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
        if (!st.lender_fb) gl.glGenFramebuffers(1, &st.lender_fb);
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, st.lender_fb);
        gl.glFramebufferRenderbuffer(GL_READ_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, 0);
        const bool packed = lent.scene_depth_format == GL_DEPTH24_STENCIL8 || lent.scene_depth_format == GL_DEPTH32F_STENCIL8;
        const GLenum attachment = packed ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT;
        if (lent.scene_depth_type == GL_RENDERBUFFER)
            gl.glFramebufferRenderbuffer(GL_READ_FRAMEBUFFER, attachment, GL_RENDERBUFFER, lent.scene_depth_name);
        else if (lent.scene_depth_type == GL_TEXTURE)
            gl.glFramebufferTexture2D(GL_READ_FRAMEBUFFER, attachment, GL_TEXTURE_2D, lent.scene_depth_name, 0);
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
        rec.borrowed_from = id;
        rec.main_known = rec.presented = true;
        rec.scene_framebuffer = st.lender_fb;
        rec.projection = lent.projection, rec.modelview = lent.modelview, rec.light = lent.light;
        std::copy(lent.viewport, lent.viewport + 4, rec.viewport);
        rec.placement_pending = true;
        rec.placement_from = rec.entries.size();
        return;
    }
}

// The draw that showed a borrowed scene, drawn again in the master's window coordinates (the
// program's viewport, no tile mapping) into a depth-only target with every fragment at depth 0:
// the rectangle it covered is where the scene is, whatever matrix or vertices put it there.
static constexpr int kMaxPlacementSize = 4096;
static constexpr int kPlacementKeptFrames = 30;

bool FrameRecorder::measure_placement(SlaveContext& ctx, size_t end, int32_t out[4]) {
    EffectsState& st = state(ctx);
    FrameRecord& rec = st.record;
    const GlApi& gl = core_.api();
    // At the master's window size, but at most kMaxPlacementSize a side (a stream may claim a
    // window of 16384 squared): the placement is then to a few pixels.
    const int master_w = std::max(1, ctx.master_width), master_h = std::max(1, ctx.master_height);
    const double scale = std::min(1.0, double(kMaxPlacementSize) / std::max(master_w, master_h));
    const int W = std::max(1, int(std::lround(master_w * scale))), H = std::max(1, int(std::lround(master_h * scale)));
    int32_t viewport[4];
    tile_.program_viewport(viewport);  // the program's, for that draw
    const bool compatibility = compatibility_profile(gl);
    std::vector<uint8_t>& depth = st.placement_pixels;
    depth.assign(size_t(W) * size_t(H), 255);
    const PendingClientArrays pending(ctx);
    try {
        GlStateGuard guard(gl, kGuardPass | kGuardPixelPack |
                                   (compatibility ? kGuardMatrixStacks | kGuardMatrixMode : 0));
        if (st.placement_sizes[0] != W || st.placement_sizes[1] != H) {
            if (st.placement_fb) gl.glDeleteFramebuffers(1, &st.placement_fb), gl.glDeleteTextures(1, &st.placement_depth);
            st.placement_depth = effects::make_texture(gl, GL_DEPTH_COMPONENT24, W, H);
            st.placement_fb = effects::make_framebuffer(gl, 0, st.placement_depth);
            st.placement_sizes[0] = W, st.placement_sizes[1] = H;
        }
        GLint program = 0;
        gl.glGetIntegerv(GL_CURRENT_PROGRAM, &program);
        gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st.placement_fb);
        gl.glViewport(GLint(std::lround(viewport[0] * scale)), GLint(std::lround(viewport[1] * scale)),
                      GLsizei(std::lround(viewport[2] * scale)), GLsizei(std::lround(viewport[3] * scale)));
        gl.glEnable(GL_DEPTH_TEST);
        gl.glDepthFunc(GL_ALWAYS);
        gl.glDepthMask(GL_TRUE);
        gl.glClearDepth(1.0);
        gl.glClear(GL_DEPTH_BUFFER_BIT);
        // The depth range and the tile's redraw mode are put back however the redraw ends.
        struct Redrawing {
            const GlApi& gl;
            TileAdapter& tile;
            GLdouble range[2] = {0, 1};
            Redrawing(const GlApi& g, TileAdapter& t, bool programs) : gl(g), tile(t) {
                gl.glGetDoublev(GL_DEPTH_RANGE, range);
                gl.glDepthRange(0, 0);
                tile.begin_redraw(glm::dmat4(1.0), programs);
            }
            ~Redrawing() {
                tile.end_redraw();
                gl.glDepthRange(range[0], range[1]);
            }
        };
        {
            Redrawing redrawing(gl, tile_, program != 0);
            Call c;
            for (size_t i = rec.placement_from; i < end; ++i) redispatch_entry(rec, rec.entries[i], c);
        }
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, st.placement_fb);
        if (gl.has(OP_glBindBuffer)) gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
        gl.glPixelStorei(GL_PACK_ROW_LENGTH, 0);
        gl.glPixelStorei(GL_PACK_SKIP_ROWS, 0);
        gl.glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
        gl.glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_UNSIGNED_BYTE, depth.data());
    } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "glcast: effects: cannot place another context's scene: %s\n", e.what());
    }
    int x0 = W, y0 = H, x1 = 0, y1 = 0;
    for (int y = 0; y < H; ++y) {
        const uint8_t* row = depth.data() + size_t(y) * size_t(W);
        for (int x = 0; x < W; ++x) {
            if (row[x] == 255) continue;
            x0 = std::min(x0, x), x1 = std::max(x1, x + 1), y0 = std::min(y0, y), y1 = std::max(y1, y + 1);
        }
    }
    if (x0 >= x1 || y0 >= y1) return false;
    if (scale < 1) {  // back to the master's pixels
        x0 = int(std::floor(x0 / scale)), y0 = int(std::floor(y0 / scale));
        x1 = std::min(master_w, int(std::ceil(x1 / scale))), y1 = std::min(master_h, int(std::ceil(y1 / scale)));
    }
    out[0] = x0, out[1] = y0, out[2] = x1, out[3] = y1;
    return true;
}

// Where the draw that showed a borrowed scene put it, and the scene's viewport in the window.
// Measuring costs a draw, a clear and a read-back of the master's window size (2.4 ms a frame at
// 800x600 on llvmpipe), so the last frame's rectangle is kept while the frame's calls up to that
// draw are the same bytes, with the same viewport and lender, for at most kPlacementKeptFrames
// frames (a placement moved by a buffer upload, which the record does not hold, is found again
// then).
void FrameRecorder::place_borrowed_scene(SlaveContext& ctx) {
    EffectsState& st = state(ctx);
    FrameRecord& rec = st.record;
    rec.placement_pending = false;
    auto lender = states_.find(rec.borrowed_from);
    if (rec.entries.size() <= rec.placement_from || lender == states_.end()) {  // the draw was not kept
        rec.drop_borrowed();
        return;
    }
    size_t end = rec.placement_from + 1;  // the draw only: its opening call and its block
    while (end < rec.entries.size() && rec.entries[end].draw && !rec.entries[end].opens) end++;
    int32_t viewport[4];
    tile_.program_viewport(viewport);
    const FrameRecord::Entry& last = rec.entries[end - 1];
    uint64_t key = 1469598103934665603ull;  // FNV-1a of what places it
    auto mix = [&key](const void* p, size_t n) {
        for (size_t i = 0; i < n; ++i) key = (key ^ static_cast<const uint8_t*>(p)[i]) * 1099511628211ull;
    };
    mix(rec.bytes.data(), last.begin + last.size);
    mix(viewport, sizeof viewport);
    mix(&rec.borrowed_from, sizeof rec.borrowed_from);
    mix(&ctx.master_width, sizeof ctx.master_width);
    mix(&ctx.master_height, sizeof ctx.master_height);
    int32_t rect[4];
    if (st.placement_known && st.placement_key == key && st.placement_age < kPlacementKeptFrames) {
        std::copy(st.placement_rect, st.placement_rect + 4, rect);
        st.placement_age++;
    } else if (measure_placement(ctx, end, rect)) {
        std::copy(rect, rect + 4, st.placement_rect);
        st.placement_known = true, st.placement_key = key, st.placement_age = 0;
    } else {
        st.placement_known = false;
        rect[0] = rect[2] = 0;
    }
    if (rect[0] >= rect[2]) {  // it drew nothing: the scene is not shown
        rec.drop_borrowed();
        return;
    }
    const FrameRecord& lent = lender->second->record;
    std::copy(rect, rect + 4, rec.placement);
    // The lender's viewport, in its target's pixels, placed and scaled as the window shows them.
    const double sx = double(rect[2] - rect[0]) / std::max(1, lent.scene_size[0]);
    const double sy = double(rect[3] - rect[1]) / std::max(1, lent.scene_size[1]);
    rec.viewport[0] = int32_t(std::lround(rect[0] + lent.viewport[0] * sx));
    rec.viewport[1] = int32_t(std::lround(rect[1] + lent.viewport[1] * sy));
    rec.viewport[2] = int32_t(std::lround(lent.viewport[2] * sx));
    rec.viewport[3] = int32_t(std::lround(lent.viewport[3] * sy));
}

// Where the frame's scene is in this tile's pixels: the whole window, or the rectangle a borrowed
// scene was drawn to.
void FrameRecorder::scene_rect(SlaveContext& ctx, int32_t out[4]) {
    const FrameRecord& rec = state(ctx).record;
    out[0] = out[1] = 0, out[2] = ctx.width, out[3] = ctx.height;
    if (!rec.borrowed_from || rec.placement[2] <= rec.placement[0]) return;
    const TileMapping& t = core_.options().tile;
    const int W = ctx.master_width, H = ctx.master_height;
    const int32_t* p = rec.placement;
    if (!t.enabled) {
        std::copy(p, p + 4, out);
        return;
    }
    out[0] = int32_t(t.map_x(p[0], W)), out[1] = int32_t(t.map_y(p[1], H));
    out[2] = out[0] + int32_t(t.map_w(p[0], p[2] - p[0], W)), out[3] = out[1] + int32_t(t.map_h(p[1], p[3] - p[1], H));
}

// Re-executes the recorded calls of the main view with `correction` premultiplied into the
// program's projection (fixed function) or set as glcast_clip (shader programs, whose vertex
// shaders the slave patched). Everything it changes is put back: attributes and client
// attributes, the three matrix stacks (depth and top), the vertex array, the caller's program,
// the trackers (list base, current program, pending client-array ranges); uniform values and
// uniform buffers end as the frame left them because the
// frame's calls that set them are replayed in its order.
void FrameRecorder::redraw_main_view(SlaveContext& ctx, const glm::dmat4& correction) {
    EffectsState& st = state(ctx);
    const FrameRecord& rec = scene_record(ctx);  // a borrowed scene: the lender's draws
    const bool borrowed = &rec != &st.record;
    const GlApi& gl = core_.api();
    const bool compatibility = compatibility_profile(gl);
    if (rec.entries.empty() || (!compatibility && !rec.shader_draws)) return;
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
    const bool programs = rec.shader_draws;
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
    Call c;
    for (const FrameRecord::Entry& e : rec.entries) {
        if ((e.draw && !e.main) || (e.program_state && !programs)) continue;
        if (e.opens) {
            if (e.cull != cull) set_enabled(gl, GL_CULL_FACE, cull = e.cull);
            if (e.cull_face != cull_face) gl.glCullFace(cull_face = e.cull_face);
            if (e.front_face != front_face) gl.glFrontFace(front_face = e.front_face);
        }
        redispatch_entry(rec, e, c);
    }
    tile_.end_redraw();
    set_enabled(gl, GL_CULL_FACE, caller_cull);
    gl.glCullFace(GLenum(caller_cull_face));
    gl.glFrontFace(GLenum(caller_front_face));
    ctx.list_base = saved_list_base;
    ctx.current_program = saved_program_stream;
    gl.glActiveTexture(GLenum(active_texture));
}

// A copy of the window framebuffer's color (RGBA8) or depth (DEPTH24_STENCIL8) as it is now;
// the depth of a scene drawn offscreen comes from its framebuffer object.
unsigned FrameRecorder::window_copy(SlaveContext& ctx, bool depth) {
    EffectsState& st = state(ctx);
    if (depth && st.record.scene_framebuffer) {
        if (st.depth_copied) return st.scene_depth;
        const unsigned copy = scene_depth_copy(ctx);
        st.depth_copied = true;
        return copy;
    }
    size_copies(ctx);
    bool& done = depth ? st.depth_copied : st.color_copied;
    if (!done) {
        copy_window(ctx, depth ? st.depth_fb : st.color_fb, depth);
        done = true;
    }
    return depth ? st.depth_texture : st.color_texture;
}


unsigned FrameRecorder::scene_depth_copy(SlaveContext& ctx) {
    EffectsState& st = state(ctx);
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, st.record.scene_framebuffer);
    const GLenum format = depth_format(gl, GL_READ_FRAMEBUFFER);
    if (!format) {  // its depth went away since: the window's
        st.record.scene_framebuffer = 0;
        return window_copy(ctx, true);
    }
    const int W = std::max(1, ctx.master_width), H = std::max(1, ctx.master_height);
    const int sizes[4] = {W, H, ctx.width, ctx.height};
    // The scene's target in the master's window: all of it, or where a borrowed scene was drawn.
    const FrameRecord& scene = scene_record(ctx);
    const bool placed = st.record.borrowed_from != 0;
    const int32_t* p = st.record.placement;
    const int from[4] = {0, 0, placed ? scene.scene_size[0] : W, placed ? scene.scene_size[1] : H};
    const int target[4] = {placed ? p[0] : 0, placed ? p[1] : 0, placed ? p[2] : W, placed ? p[3] : H};
    if (format != st.scene_depth_format || !std::equal(sizes, sizes + 4, st.scene_depth_sizes)) {
        if (st.scene_depth_full) {
            const GLuint textures[] = {st.scene_depth_full, st.scene_depth}, fbs[] = {st.scene_depth_full_fb, st.scene_depth_fb};
            gl.glDeleteTextures(2, textures);
            gl.glDeleteFramebuffers(2, fbs);
        }
        const bool packed = format == GL_DEPTH24_STENCIL8 || format == GL_DEPTH32F_STENCIL8;
        st.scene_depth_full = effects::make_texture(gl, format, W, H, /*linear=*/true);
        st.scene_depth_full_fb = effects::make_framebuffer(gl, 0, st.scene_depth_full,
                                                           packed ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT);
        st.scene_depth = effects::make_texture(gl, GL_DEPTH_COMPONENT32F, ctx.width, ctx.height);
        st.scene_depth_fb = effects::make_framebuffer(gl, 0, st.scene_depth, GL_DEPTH_ATTACHMENT);
        st.scene_depth_format = format;
        std::copy(sizes, sizes + 4, st.scene_depth_sizes);
    }
    // Resolved at the program's size (a multisampled source may not be scaled; a depth blit
    // needs the same format on both sides), then this tile's rectangle of the program's window
    // (the canvas stretches it) drawn over the tile's size.
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, st.record.scene_framebuffer);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st.scene_depth_full_fb);
    if (placed) {  // nothing but the scene's rectangle: the far plane around it
        gl.glDepthMask(GL_TRUE);
        gl.glClearDepth(1.0);
        gl.glClear(GL_DEPTH_BUFFER_BIT);
    }
    gl.glBlitFramebuffer(from[0], from[1], from[2], from[3], target[0], target[1], target[2], target[3],
                         GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    const TileMapping& t = core_.options().tile;
    glm::dvec4 source(0, 0, W, H);
    if (t.enabled && !core_.options().view.enabled)
        source = {t.x / t.sx(W), t.y / t.sy(H), (t.x + t.width) / t.sx(W), (t.y + t.height) / t.sy(H)};
    if (!st.scene_depth_program) {
        st.scene_depth_program = effects::build_program(gl, "fullscreen.vert", "scene_depth.frag");
        gl.glGenVertexArrays(1, &st.scene_depth_vao);
    }
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st.scene_depth_fb);
    gl.glViewport(0, 0, ctx.width, ctx.height);
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_ALWAYS);
    gl.glDepthMask(GL_TRUE);
    gl.glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.glUseProgram(st.scene_depth_program);
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glBindTexture(GL_TEXTURE_2D, st.scene_depth_full);
    gl.glUniform1i(effects::uniform(gl, st.scene_depth_program, "scene_depth"), 0);
    gl.glUniform4f(effects::uniform(gl, st.scene_depth_program, "source_rect"), GLfloat(source.x), GLfloat(source.y),
                   GLfloat(source.z), GLfloat(source.w));
    effects::draw_fullscreen(gl, st.scene_depth_vao);
    return st.scene_depth;
}

void FrameRecorder::size_copies(SlaveContext& ctx) {
    EffectsState& st = state(ctx);
    if (st.copies_width == ctx.width && st.copies_height == ctx.height) return;
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);  // making them binds textures and framebuffers: the program's
    GLuint textures[4] = {st.color_texture, st.depth_texture, st.program_image, st.scene_image};
    GLuint fbs[4] = {st.color_fb, st.depth_fb, st.program_image_fb, st.scene_image_fb};
    if (st.color_texture) gl.glDeleteTextures(4, textures), gl.glDeleteFramebuffers(4, fbs);
    st.color_texture = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height);
    st.depth_texture = effects::make_texture(gl, GL_DEPTH24_STENCIL8, ctx.width, ctx.height);
    st.program_image = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height);
    st.scene_image = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height);
    st.color_fb = effects::make_framebuffer(gl, st.color_texture, 0);
    st.depth_fb = effects::make_framebuffer(gl, 0, st.depth_texture, GL_DEPTH_STENCIL_ATTACHMENT);
    st.program_image_fb = effects::make_framebuffer(gl, st.program_image, 0);
    st.scene_image_fb = effects::make_framebuffer(gl, st.scene_image, 0);
    st.copies_width = ctx.width, st.copies_height = ctx.height;
}

// Between the window's colour buffer (the one the program draws to) and one of the copies.
void FrameRecorder::copy_window(SlaveContext& ctx, GLuint copy_fb, bool depth, bool back) {
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    const GLenum window = ctx.double_buffered ? GL_BACK : GL_FRONT;
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, back ? copy_fb : 0);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, back ? 0 : copy_fb);
    // The window's own draw or read buffer is the program's state: set for the blit, then restored.
    GLint program_buffer = 0;
    gl.glGetIntegerv(back ? GL_DRAW_BUFFER : GL_READ_BUFFER, &program_buffer);
    if (back) gl.glDrawBuffer(window);
    else gl.glReadBuffer(window);
    gl.glBlitFramebuffer(0, 0, ctx.width, ctx.height, 0, 0, ctx.width, ctx.height,
                         depth ? GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT : GL_COLOR_BUFFER_BIT, GL_NEAREST);
    if (back) gl.glDrawBuffer(GLenum(program_buffer));
    else gl.glReadBuffer(GLenum(program_buffer));
}

void FrameRecorder::presented(SlaveContext& ctx) {
    EffectsState& st = state(ctx);
    if (!st.program_image_saved) return;
    st.program_image_saved = false;
    if (st.copies_width != ctx.width || st.copies_height != ctx.height) return;  // resized: a new picture anyway
    copy_window(ctx, st.program_image_fb, false, true);
}

void FrameRecorder::frame_view(SlaveContext& ctx, effects::FrameView& v) {
    FrameRecord& rec = state(ctx).record;
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
    v.light = rec.light;
    v.view_known = rec.main_known;
    if (!rec.main_known && rec.shader_draws && options.view.program_fov_y_deg) {
        v.view_known = true;  // a shader program: the projection the display config states
        rec.projection = options.view.program_projection(double(ctx.master_width) / std::max(1, ctx.master_height));
        rec.viewport[0] = rec.viewport[1] = 0;
        rec.viewport[2] = ctx.master_width, rec.viewport[3] = ctx.master_height;
    }
    if (!v.view_known && rec.shader_draws && !warned_no_camera_) {
        warned_no_camera_ = true;
        std::fprintf(stderr, "glcast: effects: no draw with a perspective projection among the shader programs' "
                             "matrices in frame %" PRIu64 ": passes that need the scene's view skip such frames "
                             "(program_projection in the display config states it)\n", core_.frame());
    }
    if (v.view_known) {
        v.projection = rec.projection;
        v.modelview = rec.modelview;
        // The program's viewport as this slave applies it, in tile pixels.
        const int32_t* p = rec.viewport;
        const int W = ctx.master_width, H = ctx.master_height;
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
        const glm::dmat4 rotated = options.view.enabled ? options.view.correction(rec.projection) : glm::dmat4(1.0);
        v.tile_clip_from_app_clip = planar * rotated;
        v.tile_clip_from_eye = v.tile_clip_from_app_clip * v.projection;
        v.eye_from_tile_clip = glm::inverse(v.tile_clip_from_eye);
    }
    EffectsState* st = &state(ctx);
    st->color_copied = st->depth_copied = false;
    const GlApi& gl = core_.api();
    gl.glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &st->program_vao);
    gl.glGetIntegerv(GL_ACTIVE_TEXTURE, &st->program_active_texture);
    for (int unit = 0; unit < 8; ++unit) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &st->program_textures[unit]);
    }
    gl.glActiveTexture(GLenum(st->program_active_texture));
    SlaveContext* c = &ctx;
    v.color_texture = [this, c] { return window_copy(*c, false); };
    v.depth_texture = [this, c] { return window_copy(*c, true); };
    // A borrowed scene's shader draws name the lender's vertex-array objects, which this context
    // does not share: only fixed-function scenes are re-rendered from another context.
    const FrameRecord& scene = scene_record(ctx);
    const bool borrowed = &scene != &rec;
    if (rec.main_known && !scene.overflow && !(borrowed && scene.shader_draws) &&
        (scene.shader_draws ? core_.options().effects.redraws() : compatibility_profile(gl))) {
        v.redraw = [this, c](const glm::dmat4& correction) { redraw_main_view(*c, correction); };
        v.redraw_binds_programs = scene.shader_draws;
    }
}

// A draw after the main view that is two-dimensional starts the overlays: the window as the
// scene left it is copied, and run_effects decorates that copy and puts what was drawn over it
// back on top. Programs draw their HUD and text last, with the depth test off or an
// orthographic projection (the games: neverball, openarena, foobillardplus,
// extremetuxracer); a 3D draw after the HUD (a weapon) is an overlay too. A scene drawn
// offscreen is complete when the program shows it in the window (a full-window draw with the
// depth test off, or a blit); whatever the window gets after that is overlay (openarena's HUD,
// its 3D icons included).
void FrameRecorder::watch_overlays(SlaveContext& ctx, RedrawKind kind) {
    if (kind != RedrawKind::Draw && kind != RedrawKind::Begin && kind != RedrawKind::Pixels) return;
    const GlApi& gl = core_.api();
    EffectsState& st = state(ctx);
    FrameRecord& rec = st.record;
    if (rec.scene_framebuffer && !rec.presented) {
        if (kind == RedrawKind::Pixels || !writes_depth(gl)) {
            rec.presented = true;  // the scene's image drawn over the window
            return;
        }
        // A 3D draw to the window: what was drawn offscreen was not the scene. The window's
        // draws find the main view again.
        rec.main_known = false;
        rec.scene_framebuffer = 0;
        rec.light = effects::SceneLight{};
        for (FrameRecord::Entry& e : rec.entries) e.main = e.main && !e.offscreen;
        return;
    }
    if (!rec.scene_framebuffer && !starts_overlays(ctx, kind)) return;
    size_copies(ctx);
    copy_window(ctx, st.scene_image_fb, false);
    rec.overlay = true;
}

// A draw to the window after a main view drawn there that is flat: pixels at the raster
// position, the depth test off, or a fixed-function orthographic projection; a shader program
// drawing with the main view's camera is scene whatever its depth test.
bool FrameRecorder::starts_overlays(SlaveContext& ctx, RedrawKind kind) {
    const GlApi& gl = core_.api();
    EffectsState& st = state(ctx);
    GLint program = 0;
    if (kind != RedrawKind::Pixels) gl.glGetIntegerv(GL_CURRENT_PROGRAM, &program);
    bool flat = kind == RedrawKind::Pixels || !gl.glIsEnabled(GL_DEPTH_TEST);
    if (!flat) flat = !program && !is_perspective(tile_.program_projection_now());
    // A shader program that paints its 3D scene in order with the depth test off (glmark2's
    // ideas) draws it with the main view's camera: scene, not overlay.
    ProgramCamera camera;
    if (flat && program && st.cameras(gl).find(GLuint(program), camera) && camera.projection == st.record.projection)
        flat = false;
    return flat;
}

void FrameRecorder::put_overlays_back(SlaveContext& ctx, bool overlays) {
    EffectsState& st = state(ctx);
    const GlApi& gl = core_.api();
    if (!st.overlay_program) {
        st.overlay_program = effects::build_program(gl, "fullscreen.vert", "overlays.frag");
        gl.glGenVertexArrays(1, &st.overlay_vao);
    }
    effects::StateGuard guard(gl);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl.glViewport(0, 0, ctx.width, ctx.height);
    gl.glDisable(GL_BLEND);
    gl.glDisable(GL_DEPTH_TEST);
    gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.glUseProgram(st.overlay_program);
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glBindTexture(GL_TEXTURE_2D, st.program_image);
    gl.glActiveTexture(GL_TEXTURE1);
    gl.glBindTexture(GL_TEXTURE_2D, st.scene_image);
    gl.glActiveTexture(GL_TEXTURE2);
    gl.glBindTexture(GL_TEXTURE_2D, st.record.view_model_far > 0 ? st.view_model_depth : 0);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "final_image"), 0);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "scene_image"), 1);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "scene_depth"), 2);
    gl.glUniform1i(effects::uniform(gl, st.overlay_program, "overlays"), overlays);
    gl.glUniform1f(effects::uniform(gl, st.overlay_program, "view_model_far"), GLfloat(st.record.view_model_far));
    int32_t rect[4];
    scene_rect(ctx, rect);
    gl.glUniform4f(effects::uniform(gl, st.overlay_program, "scene_rect"), GLfloat(rect[0]), GLfloat(rect[1]),
                   GLfloat(rect[2]), GLfloat(rect[3]));
    effects::draw_fullscreen(gl, st.overlay_vao);
}

void FrameRecorder::end_frame(SlaveContext& ctx) {
    state(ctx).presents = true;
    if (state(ctx).record.placement_pending) place_borrowed_scene(ctx);
    run_effects(ctx);
    // Contexts that never present: a scene they drew is kept for the frames that show it again
    // (until they draw the next), anything else they recorded is let go, so that their records
    // hold at most one frame's calls.
    for (auto& [id, st] : states_) {
        FrameRecord& other = st->record;
        if (id == ctx.id || st->presents || other.in_begin_end || other.compiling_list) continue;
        if (other.main_known && other.scene_texture) other.complete = true;
        else other.clear();
    }
}

void FrameRecorder::run_effects(SlaveContext& ctx) {
    EffectsState& st = state(ctx);
    if (ctx.width <= 0 || ctx.height <= 0) {  // nothing shown: nothing to decorate
        st.record.clear();
        return;
    }
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
        size_copies(ctx);
        copy_window(ctx, st.program_image_fb, false);
        st.program_image_saved = true;
        const bool overlays = st.record.overlay && st.copies_width == ctx.width && st.copies_height == ctx.height;
        if (overlays) copy_window(ctx, st.scene_image_fb, false, /*back=*/true);  // the scene alone
        const bool view_model = st.record.view_model_far > 0 && st.copies_width == ctx.width &&
                                st.copies_height == ctx.height;
        // A borrowed scene covers part of the window: the rest is the program's.
        const bool placed = st.record.borrowed_from != 0 && st.copies_width == ctx.width &&
                            st.copies_height == ctx.height;
        if (view_model) st.view_model_depth = window_copy(ctx, true);  // before any pass draws
        else st.record.view_model_far = 0;
        st.pipeline->run(view);
        if (overlays || view_model || placed) put_overlays_back(ctx, overlays);
        if (core_.after_effects) core_.after_effects(view);
        if (st.record.borrowed_from && !said_borrowed_) {
            said_borrowed_ = true;
            std::fprintf(stderr, "glcast: effects: from frame %" PRIu64 " on, context %u shows the scene context %u draws "
                                 "into a texture (docs/effects.md, \"A scene another context draws\")\n",
                         core_.frame(), ctx.id, st.record.borrowed_from);
        }
    } catch (const std::runtime_error& e) {
        throw EffectsError(std::string("effects: ") + e.what());
    }
    st.record.clear();
}

}  // namespace glcast::slave
