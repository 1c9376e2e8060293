// The replayer's side of the injected passes (design.md 6, slave/effects_frame.h): recording
// what a frame draws, re-rendering it for a pass, and describing the frame to the passes.
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <string>

#include "common/gl_headers.h"
#include "protocol/format.h"
#include "slave/effects/gl_util.h"
#include "slave/replayer.h"
#include "slave/effects_frame.h"

namespace glcast::slave {

namespace {

// What a recorded call is to redraw.
enum class RedrawKind : uint8_t { Ignored, State, Draw, Begin, End, NewList, EndList };

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// Names without an ARB/EXT/NV suffix, so that extension aliases classify like their core twin.
std::string core_name(std::string name) {
    for (const char* suffix : {"ARB", "EXT", "NV", "OES"}) {
        const size_t n = std::strlen(suffix);
        if (name.size() > n && name.compare(name.size() - n, n, suffix) == 0) return name.substr(0, name.size() - n);
    }
    return name;
}

// Which calls redraw re-executes: those that only draw, or set matrix, current-attribute and
// vertex-array state (restored after the redraw). Never object creation, uploads, deletion,
// framebuffer or viewport changes: the program's resources stay untouched.
std::vector<RedrawKind> build_redraw_kinds() {
    static const char* const kState[] = {
        "glMatrixMode", "glPushMatrix", "glPopMatrix", "glLoadIdentity", "glLoadMatrixf", "glLoadMatrixd",
        "glMultMatrixf", "glMultMatrixd", "glLoadTransposeMatrixf", "glLoadTransposeMatrixd",
        "glMultTransposeMatrixf", "glMultTransposeMatrixd", "glRotatef", "glRotated", "glTranslatef",
        "glTranslated", "glScalef", "glScaled", "glFrustum", "glOrtho", "glListBase", "glVertexPointer",
        "glNormalPointer", "glColorPointer", "glTexCoordPointer", "glSecondaryColorPointer", "glFogCoordPointer",
        "glEdgeFlagPointer", "glIndexPointer", "glInterleavedArrays", "glEnableClientState",
        "glDisableClientState", "glClientActiveTexture", "glBindBuffer", "glBindVertexArray",
        "glVertexAttribPointer", "glVertexAttribIPointer", "glEnableVertexAttribArray",
        "glDisableVertexAttribArray", "glLockArrays", "glUnlockArrays", "glPrimitiveRestartIndex"};
    static const char* const kCurrentPrefixes[] = {"glNormal3", "glColor3", "glColor4", "glTexCoord", "glMultiTexCoord",
                                                   "glSecondaryColor3", "glFogCoord", "glEdgeFlag"};
    std::vector<RedrawKind> kinds(kOpcodeCount, RedrawKind::Ignored);
    for (uint32_t op = 0; op < kOpcodeCount; ++op) {
        const CommandInfo* info = command_info(op);
        if (!info) continue;
        const std::string name = core_name(info->name);
        RedrawKind& k = kinds[op];
        if (info->flags & kDraw) k = RedrawKind::Draw;
        else if (name == "glCallList" || name == "glCallLists" || starts_with(name, "glRect")) k = RedrawKind::Draw;
        else if (name == "glBegin") k = RedrawKind::Begin;
        else if (name == "glEnd") k = RedrawKind::End;
        else if (name == "glNewList") k = RedrawKind::NewList;
        else if (name == "glEndList") k = RedrawKind::EndList;
        else if (name.find("Pointer") == std::string::npos && starts_with(name, "glVertexAttrib")) k = RedrawKind::State;
        else {
            for (const char* s : kState)
                if (name == s) k = RedrawKind::State;
            for (const char* p : kCurrentPrefixes)
                if (starts_with(name, p) && name.find("Pointer") == std::string::npos) k = RedrawKind::State;
        }
    }
    return kinds;
}

const std::vector<RedrawKind>& redraw_kinds() {
    static const std::vector<RedrawKind> kinds = build_redraw_kinds();
    return kinds;
}

bool is_perspective(const glm::dmat4& p) { return p[2][3] != 0 && p[3][3] == 0; }

}  // namespace

SlaveContext::SlaveContext() = default;
SlaveContext::~SlaveContext() = default;

void FrameRecord::clear() {
    bytes.clear();
    entries.clear();
    in_begin_end = begin_is_main = compiling_list = overflow = shader_draws = main_known = pushed = false;
    light = effects::SceneLight{};
}

// The program's own projection now: GL_PROJECTION without the correction a rotated tile (or a
// redraw) premultiplied into it.
glm::dmat4 Replayer::program_projection_now() {
    GLdouble m[16];
    gl<decltype(&::glGetDoublev)>(OP_glGetDoublev)(GL_PROJECTION_MATRIX, m);
    glm::dmat4 p;
    std::memcpy(&p[0][0], m, sizeof m);
    const auto& top = current().projection.back();
    return top.corrected ? glm::inverse(top.m) * p : p;
}

void Replayer::record_for_effects(const Call& c) {
    if (c.opcode >= kSynthBase && c.opcode != kSynthClientArrays) return;
    SlaveContext& ctx = current();
    if (!ctx.effects) ctx.effects = std::make_unique<EffectsState>();
    FrameRecord& rec = ctx.effects->record;
    const RedrawKind kind = c.opcode >= kSynthBase ? RedrawKind::State : redraw_kinds()[c.opcode];
    if (kind == RedrawKind::NewList || kind == RedrawKind::EndList) {  // never re-executed
        rec.compiling_list = kind == RedrawKind::NewList;
        return;
    }
    if (kind == RedrawKind::Ignored && !rec.in_begin_end) return;
    if (rec.compiling_list || !ctx.drawing_to_window || rec.overflow) return;
    if (c.opcode == OP_glBindBuffer || c.opcode == OP_glBindBufferARB) {
        const uint64_t target = c.args[0].bits;  // only the targets glPushClientAttrib restores
        if (target != GL_ARRAY_BUFFER && target != GL_ELEMENT_ARRAY_BUFFER) return;
    }
    const auto get_doubles = gl<decltype(&::glGetDoublev)>(OP_glGetDoublev);
    const auto get_ints = gl<decltype(&::glGetIntegerv)>(OP_glGetIntegerv);

    FrameRecord::Entry e{rec.bytes.size(), tuple_size_, false, false, false};
    if ((kind == RedrawKind::Draw || kind == RedrawKind::Begin) && !rec.in_begin_end) {
        GLint program = 0;
        get_ints(GL_CURRENT_PROGRAM, &program);
        e.draw = e.opens = true;
        if (program) {
            rec.shader_draws = true;
        } else {
            const glm::dmat4 app = program_projection_now();
            if (!rec.main_known && is_perspective(app)) {
                rec.main_known = true;
                rec.projection = app;
                GLdouble mv[16];
                get_doubles(GL_MODELVIEW_MATRIX, mv);
                std::memcpy(&rec.modelview[0][0], mv, sizeof mv);
                if (rec.pushed) rec.modelview = rec.last_push;
                std::memcpy(rec.viewport, ctx.viewport, sizeof rec.viewport);
                GLboolean lighting = GL_FALSE;
                gl<decltype(&::glGetBooleanv)>(OP_glGetBooleanv)(GL_LIGHTING, &lighting);
                for (GLenum light = GL_LIGHT0; lighting && light < GL_LIGHT0 + 8; ++light) {
                    GLboolean on = GL_FALSE;
                    gl<decltype(&::glGetBooleanv)>(OP_glGetBooleanv)(light, &on);
                    if (!on) continue;
                    GLfloat pos[4];
                    gl<decltype(&::glGetLightfv)>(OP_glGetLightfv)(light, GL_POSITION, pos);
                    rec.light = effects::SceneLight{true, glm::dvec4(pos[0], pos[1], pos[2], pos[3])};
                    break;
                }
            }
            e.main = rec.main_known && app == rec.projection;
        }
        if (kind == RedrawKind::Begin) rec.in_begin_end = true, rec.begin_is_main = e.main;
    } else if (rec.in_begin_end) {
        e.draw = true;
        e.main = rec.begin_is_main;
        if (kind == RedrawKind::End) rec.in_begin_end = false;
    } else if (!rec.main_known && c.opcode == OP_glPushMatrix) {
        GLint mode = 0;  // the value a push saves is the one on top before it
        get_ints(GL_MATRIX_MODE, &mode);
        if (mode == GL_MODELVIEW) {
            GLdouble mv[16];
            get_doubles(GL_MODELVIEW_MATRIX, mv);
            std::memcpy(&rec.last_push[0][0], mv, sizeof mv);
            rec.pushed = true;
        }
    }
    if (rec.bytes.size() + tuple_size_ > kMaxRecordBytes) {
        rec.overflow = true;
        std::fprintf(stderr, "glcast replay: frame %" PRIu64 " records more than %zu MiB of draws: the injected passes "
                     "cannot re-render it\n", frame_, kMaxRecordBytes >> 20);
        return;
    }
    rec.bytes.insert(rec.bytes.end(), tuple_bytes_, tuple_bytes_ + tuple_size_);
    rec.entries.push_back(e);
}

// Re-executes the recorded calls of the main view with `correction` premultiplied into the
// program's projection. Everything it changes is put back: attributes and client attributes
// (glPush/PopAttrib), the three matrix stacks (depth and top), and the replayer's trackers.
void Replayer::redraw_main_view(const glm::dmat4& correction) {
    SlaveContext& ctx = current();
    FrameRecord& rec = ctx.effects->record;
    const effects::GlApi& gl = *effects_gl_;
    if (rec.entries.empty() || !gl.glPushAttrib) return;
    const auto saved_projection = ctx.projection;
    const uint32_t saved_matrix_mode = ctx.matrix_mode, saved_list_base = ctx.list_base;
    struct Stack {
        GLenum mode, depth_query, matrix_query;
        GLint depth = 0;
        GLdouble top[16] = {};
    } stacks[] = {{GL_MODELVIEW, GL_MODELVIEW_STACK_DEPTH, GL_MODELVIEW_MATRIX},
                  {GL_PROJECTION, GL_PROJECTION_STACK_DEPTH, GL_PROJECTION_MATRIX},
                  {GL_TEXTURE, GL_TEXTURE_STACK_DEPTH, GL_TEXTURE_MATRIX}};
    GLint mode = GL_MODELVIEW, vao = 0;
    gl.glGetIntegerv(GL_MATRIX_MODE, &mode);
    gl.glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
    for (Stack& s : stacks) {
        gl.glGetIntegerv(s.depth_query, &s.depth);
        gl.glGetDoublev(s.matrix_query, s.top);
    }
    ctx.matrix_mode = uint32_t(mode);
    gl.glPushAttrib(GL_ALL_ATTRIB_BITS);  // GL_TEXTURE_BIT: the pass's texture bindings come back
    gl.glPushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS);
    const EffectsState& st = *ctx.effects;
    gl.glBindVertexArray(GLuint(st.program_vao));
    for (int unit = 0; unit < 8; ++unit) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        gl.glBindTexture(GL_TEXTURE_2D, GLuint(st.program_textures[unit]));
    }
    gl.glActiveTexture(GLenum(st.program_active_texture));
    redrawing_ = true;
    redraw_correction_ = correction;
    Call c;
    for (const FrameRecord::Entry& e : rec.entries) {
        if (e.draw && !e.main) continue;
        ByteReader r(rec.bytes.data() + e.begin, e.size, 0);
        decode_tuple(r, c);
        arena_used_ = 0;
        try {
            if (c.opcode >= kSynthBase) {
                synthetic(c);
                continue;
            }
            track_matrix_call(c);
            if (e.opens) correct_projection();  // never inside glBegin/glEnd, where GL refuses queries
            kReplay[c.opcode](*this, c);
        } catch (const ReplayError&) {
            // reported when the frame was replayed
        }
    }
    redrawing_ = false;
    gl.glPopClientAttrib();
    gl.glPopAttrib();
    gl.glBindVertexArray(GLuint(vao));
    for (const Stack& s : stacks) {
        gl.glMatrixMode(s.mode);
        GLint depth = 0;
        gl.glGetIntegerv(s.depth_query, &depth);
        for (; depth > s.depth; --depth) gl.glPopMatrix();
        for (; depth < s.depth; ++depth) gl.glPushMatrix();
        gl.glLoadMatrixd(s.top);
    }
    gl.glMatrixMode(GLenum(mode));
    ctx.projection = saved_projection;
    ctx.matrix_mode = saved_matrix_mode;
    ctx.list_base = saved_list_base;
}

// A copy of the window framebuffer's color (RGBA8) or depth (DEPTH24_STENCIL8) as it is now.
unsigned Replayer::window_copy(SlaveContext& ctx, bool depth) {
    EffectsState& st = *ctx.effects;
    const effects::GlApi& gl = *effects_gl_;
    if (st.copies_width != ctx.width || st.copies_height != ctx.height) {
        GLuint textures[2] = {st.color_texture, st.depth_texture}, fbs[2] = {st.color_fb, st.depth_fb};
        if (st.color_texture) gl.glDeleteTextures(2, textures), gl.glDeleteFramebuffers(2, fbs);
        st.color_texture = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height);
        st.depth_texture = effects::make_texture(gl, GL_DEPTH24_STENCIL8, ctx.width, ctx.height);
        st.color_fb = effects::make_framebuffer(gl, st.color_texture, 0);
        st.depth_fb = effects::make_framebuffer(gl, 0, st.depth_texture, GL_DEPTH_STENCIL_ATTACHMENT);
        st.copies_width = ctx.width, st.copies_height = ctx.height;
    }
    bool& done = depth ? st.depth_copied : st.color_copied;
    if (!done) {
        effects::StateGuard guard(gl);
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        gl.glReadBuffer(ctx.double_buffered ? GL_BACK : GL_FRONT);
        gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, depth ? st.depth_fb : st.color_fb);
        gl.glBlitFramebuffer(0, 0, ctx.width, ctx.height, 0, 0, ctx.width, ctx.height,
                             depth ? GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT : GL_COLOR_BUFFER_BIT, GL_NEAREST);
        done = true;
    }
    return depth ? st.depth_texture : st.color_texture;
}

void Replayer::frame_view(SlaveContext& ctx, effects::FrameView& v) {
    FrameRecord& rec = ctx.effects->record;
    const TileMapping& t = options_.tile;
    v.frame = frame_;
    v.frame_time = 1.0 / 60;
    v.time = double(frame_) * v.frame_time;
    v.width = ctx.width, v.height = ctx.height;
    v.canvas_x = t.enabled ? t.place_x : 0;
    v.canvas_y = t.enabled ? t.place_y : 0;
    v.canvas_width = t.enabled ? t.place_canvas_width : ctx.width;
    v.canvas_height = t.enabled ? t.place_canvas_height : ctx.height;
    v.light = rec.light;
    v.view_known = rec.main_known;
    if (!rec.main_known && rec.shader_draws && options_.view.program_fov_y_deg) {
        v.view_known = true;  // a shader program: the projection the display config states
        rec.projection = options_.view.program_projection(double(ctx.master_width) / std::max(1, ctx.master_height));
        rec.viewport[0] = rec.viewport[1] = 0;
        rec.viewport[2] = ctx.master_width, rec.viewport[3] = ctx.master_height;
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
        const glm::dmat4 rotated = options_.view.enabled ? options_.view.correction(rec.projection) : glm::dmat4(1.0);
        v.tile_clip_from_app_clip = planar * rotated;
        v.tile_clip_from_eye = v.tile_clip_from_app_clip * v.projection;
        v.eye_from_tile_clip = glm::inverse(v.tile_clip_from_eye);
    }
    EffectsState* st = ctx.effects.get();
    st->color_copied = st->depth_copied = false;
    const effects::GlApi& gl = *effects_gl_;
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
    if (rec.main_known && !rec.shader_draws && !rec.overflow && effects_gl_->glPushAttrib)
        v.redraw = [this](const glm::dmat4& correction) { redraw_main_view(correction); };
}

void Replayer::run_effects() {
    SlaveContext& ctx = current();
    if (!ctx.effects) ctx.effects = std::make_unique<EffectsState>();
    EffectsState& st = *ctx.effects;
    if (ctx.width <= 0 || ctx.height <= 0) {  // nothing shown: nothing to decorate
        st.record.clear();
        return;
    }
    if (!effects_gl_) {
        auto gl = std::make_unique<effects::GlApi>();
        std::string error;
        if (!gl->load([this](const char* name) { return backend_->proc_address(name); }, error))
            throw EffectsError("effects: " + error);
        effects_gl_ = std::move(gl);
    }
    try {
        if (!st.pipeline) st.pipeline = std::make_unique<effects::Pipeline>(*effects_gl_, options_.effects);
        effects::FrameView view;
        frame_view(ctx, view);
        st.pipeline->run(view);
        if (after_effects) after_effects(view);
    } catch (const std::runtime_error& e) {
        throw EffectsError(std::string("effects: ") + e.what());
    }
    st.record.clear();
}

}  // namespace glcast::slave
