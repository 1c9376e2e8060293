// One context's own objects (vertex arrays, framebuffers) and its state: the generated sections
// of codegen/annotations/snapshot.yaml, then what needs an order or a loop: per-unit state,
// vertex arrays, the matrix stacks (read by popping, restored on the keeper), bindings, the
// client-array copies later draws refer to, and the program's pixel store last.
#include <algorithm>
#include <array>
#include <cstring>

#include "glcast_client_arrays.h"
#include "glcast_encode.h"
#include "glcast_snapshot_state.h"
#include "common/window_readback.h"
#include "glcast_synthetic_encode.h"
#include "keeper/snapshot_writer.h"

namespace glcast::keeper {

namespace {

constexpr GLenum kBufferTargets[][2] = {
    {GL_COPY_READ_BUFFER, GL_COPY_READ_BUFFER_BINDING},   {GL_COPY_WRITE_BUFFER, GL_COPY_WRITE_BUFFER_BINDING},
    {GL_DRAW_INDIRECT_BUFFER, GL_DRAW_INDIRECT_BUFFER_BINDING}, {GL_TEXTURE_BUFFER, GL_TEXTURE_BUFFER_BINDING},
    {GL_UNIFORM_BUFFER, GL_UNIFORM_BUFFER_BINDING},       {GL_SHADER_STORAGE_BUFFER, GL_SHADER_STORAGE_BUFFER_BINDING},
    {GL_PIXEL_PACK_BUFFER, GL_PIXEL_PACK_BUFFER_BINDING}, {GL_ARRAY_BUFFER, GL_ARRAY_BUFFER_BINDING},
};
constexpr GLenum kIndexedBuffers[][4] = {
    {GL_UNIFORM_BUFFER, GL_UNIFORM_BUFFER_BINDING, GL_UNIFORM_BUFFER_START, GL_UNIFORM_BUFFER_SIZE},
    {GL_SHADER_STORAGE_BUFFER, GL_SHADER_STORAGE_BUFFER_BINDING, GL_SHADER_STORAGE_BUFFER_START,
     GL_SHADER_STORAGE_BUFFER_SIZE},
};
constexpr GLenum kUnitTargets[][2] = {
    {GL_TEXTURE_1D, GL_TEXTURE_BINDING_1D},       {GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {GL_TEXTURE_3D, GL_TEXTURE_BINDING_3D},       {GL_TEXTURE_CUBE_MAP, GL_TEXTURE_BINDING_CUBE_MAP},
    {GL_TEXTURE_RECTANGLE, GL_TEXTURE_BINDING_RECTANGLE}, {GL_TEXTURE_1D_ARRAY, GL_TEXTURE_BINDING_1D_ARRAY},
    {GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BINDING_2D_ARRAY}, {GL_TEXTURE_CUBE_MAP_ARRAY, GL_TEXTURE_BINDING_CUBE_MAP_ARRAY},
    {GL_TEXTURE_BUFFER, GL_TEXTURE_BINDING_BUFFER}, {GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_BINDING_2D_MULTISAMPLE},
};
}  // namespace

// --- the window's pixels -------------------------------------------------------------------

// What the window framebuffer holds at the boundary: another context's frame half drawn, or the
// picture of a program that never clears. Written with ordinary calls (a texture of the
// snapshot's own, a framebuffer reading it, a blit into the window, both deleted), so a tile
// maps the blit like any other, in the fresh context before its state is set.
void SnapshotWriter::window_contents(slave::SlaveContext& ctx) {
    if (ctx.width <= 0 || ctx.height <= 0 || !gl_.has(OP_glBlitFramebuffer) || !gl_.has(OP_glBindFramebuffer)) {
        missing("context " + std::to_string(ctx.id) + ": the window's pixels");
        return;
    }
    const std::vector<uint8_t> top_down =
        read_window(gl_, ctx.double_buffered ? GL_BACK : GL_FRONT, ctx.width, ctx.height);
    const size_t row = size_t(ctx.width) * 4;
    std::vector<uint8_t> pixels(top_down.size());
    for (int y = 0; y < ctx.height; ++y)  // GL's rows go up
        std::memcpy(pixels.data() + size_t(y) * row, top_down.data() + size_t(ctx.height - 1 - y) * row, row);
    GLuint texture = kTemporaryNameBase + next_temporary_++, framebuffer = kTemporaryNameBase + next_temporary_++;
    encode_glGenTextures(e_, sz_, 1, &texture);
    encode_glBindTexture(e_, sz_, GL_TEXTURE_2D, texture);
    encode_glTexImage2D(e_, sz_, GL_TEXTURE_2D, 0, GL_RGBA8, ctx.width, ctx.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                        pixels.data());
    encode_glGenFramebuffers(e_, sz_, 1, &framebuffer);
    encode_glBindFramebuffer(e_, sz_, GL_READ_FRAMEBUFFER, framebuffer);
    encode_glFramebufferTexture2D(e_, sz_, GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    encode_glBindFramebuffer(e_, sz_, GL_DRAW_FRAMEBUFFER, 0);
    encode_glBlitFramebuffer(e_, sz_, 0, 0, ctx.width, ctx.height, 0, 0, ctx.width, ctx.height, GL_COLOR_BUFFER_BIT,
                             GL_NEAREST);
    encode_glBindFramebuffer(e_, sz_, GL_READ_FRAMEBUFFER, 0);
    encode_glDeleteFramebuffers(e_, sz_, 1, &framebuffer);
    encode_glBindTexture(e_, sz_, GL_TEXTURE_2D, 0);
    encode_glDeleteTextures(e_, sz_, 1, &texture);
    flush();
}

// --- per-context objects ------------------------------------------------------------------

void SnapshotWriter::context_objects(slave::SlaveContext& ctx) {
    if (gl_.has(OP_glBindVertexArray)) {
        const GLint was = integer(GL_VERTEX_ARRAY_BINDING);
        ctx.names.map(Ns::vertex_array).each([&](uint64_t master, uint64_t slave_name) {
            GLuint name = GLuint(master);
            encode_glGenVertexArrays(e_, sz_, 1, &name);
            report_.objects++;
            if (!gl_.glIsVertexArray(GLuint(slave_name))) return;
            gl_.glBindVertexArray(GLuint(slave_name));
            encode_glBindVertexArray(e_, sz_, GLuint(master));
            vertex_arrays(ctx);
        });
        gl_.glBindVertexArray(GLuint(was));
    }
    if (gl_.has(OP_glBindFramebuffer)) {
        const GLint draw = integer(GL_DRAW_FRAMEBUFFER_BINDING), read = integer(GL_READ_FRAMEBUFFER_BINDING);
        ctx.names.map(Ns::framebuffer).each([&](uint64_t master, uint64_t slave_name) {
            GLuint name = GLuint(master);
            encode_glGenFramebuffers(e_, sz_, 1, &name);
            report_.objects++;
            if (!gl_.glIsFramebuffer(GLuint(slave_name))) return;
            gl_.glBindFramebuffer(GL_FRAMEBUFFER, GLuint(slave_name));
            encode_glBindFramebuffer(e_, sz_, GL_FRAMEBUFFER, GLuint(master));
            framebuffer(ctx);
        });
        gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
        gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
    }
    ctx.names.map(Ns::query).each([&](uint64_t master, uint64_t) {
        GLuint name = GLuint(master);
        encode_glGenQueries(e_, sz_, 1, &name);
    });
    objects_not_held(ctx);
}

// Objects whose state no snapshot here recreates: named so that the keeper refuses to serve the
// snapshot (docs/keeper.md "What a snapshot cannot hold") rather than let a slave draw without them.
void SnapshotWriter::objects_not_held(slave::SlaveContext& ctx) {
    const std::string context = "context " + std::to_string(ctx.id) + ": ";
    ctx.names.map(Ns::transform_feedback).each([&](uint64_t master, uint64_t) {
        missing(context + "transform feedback object " + std::to_string(master));
    });
    ctx.names.map(Ns::program_pipeline).each([&](uint64_t master, uint64_t) {
        missing(context + "program pipeline " + std::to_string(master));
    });
    if (!gl_.has(OP_glGetQueryiv)) return;
    for (GLenum target : {GL_SAMPLES_PASSED, GL_ANY_SAMPLES_PASSED, GL_ANY_SAMPLES_PASSED_CONSERVATIVE,
                          GL_PRIMITIVES_GENERATED, GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, GL_TIME_ELAPSED}) {
        GLint active = 0;
        gl_.glGetQueryiv(target, GL_CURRENT_QUERY, &active);
        if (asked() && active)
            missing(context + "query " + std::to_string(master_name(ctx, Ns::query, GLuint(active))) +
                    " in progress (target " + std::to_string(target) + ")");
    }
}

void SnapshotWriter::framebuffer(slave::SlaveContext& ctx) {
    const GLint colors = std::min(integer(GL_MAX_COLOR_ATTACHMENTS), 16);
    std::vector<GLenum> points;
    for (GLint i = 0; i < colors; ++i) points.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
    points.push_back(GL_DEPTH_ATTACHMENT);
    points.push_back(GL_STENCIL_ATTACHMENT);
    for (GLenum point : points) {
        auto value = [&](GLenum pname) {
            GLint v = 0;
            gl_.glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, point, pname, &v);
            return asked() ? v : 0;
        };
        const GLint type = value(GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE);
        const GLuint object = GLuint(value(GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME));
        if (type == GL_RENDERBUFFER) {
            encode_glFramebufferRenderbuffer(e_, sz_, GL_FRAMEBUFFER, point, GL_RENDERBUFFER,
                                             GLuint(master_name(ctx, Ns::renderbuffer, object)));
        } else if (type == GL_TEXTURE) {
            const GLuint texture = GLuint(master_name(ctx, Ns::texture, object));
            const GLint level = value(GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL);
            const GLint face = value(GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_CUBE_MAP_FACE);
            const GLint layer = value(GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LAYER);
            const GLint layered = value(GL_FRAMEBUFFER_ATTACHMENT_LAYERED);
            auto target = texture_targets_.find({ctx.names.shared.get(), object});
            const GLenum tex_target = target == texture_targets_.end() ? GL_TEXTURE_2D : target->second;
            if (layered) encode_glFramebufferTexture(e_, sz_, GL_FRAMEBUFFER, point, texture, level);
            else if (tex_target == GL_TEXTURE_3D || tex_target == GL_TEXTURE_2D_ARRAY || tex_target == GL_TEXTURE_1D_ARRAY ||
                     tex_target == GL_TEXTURE_CUBE_MAP_ARRAY)
                encode_glFramebufferTextureLayer(e_, sz_, GL_FRAMEBUFFER, point, texture, level, layer);
            else if (tex_target == GL_TEXTURE_1D)
                encode_glFramebufferTexture1D(e_, sz_, GL_FRAMEBUFFER, point, tex_target, texture, level);
            else
                encode_glFramebufferTexture2D(e_, sz_, GL_FRAMEBUFFER, point, face ? GLenum(face) : tex_target, texture,
                                              level);
        }
    }
    const GLint max_draw = std::min(integer(GL_MAX_DRAW_BUFFERS), 16);
    std::vector<GLenum> draw(size_t(std::max(max_draw, 1)), GL_NONE);
    GLint used = 0;
    for (GLint i = 0; i < max_draw; ++i) {
        draw[size_t(i)] = GLenum(integer(GLenum(GL_DRAW_BUFFER0 + i)));
        if (draw[size_t(i)] != GL_NONE) used = i + 1;
    }
    encode_glDrawBuffers(e_, sz_, std::max(used, 1), draw.data());
    encode_glReadBuffer(e_, sz_, GLenum(integer(GL_READ_BUFFER)));
}

// The arrays of the bound vertex array object (0: the context's own). Arrays in client memory
// are left to the glcast.client_arrays tuple of the next draw that uses them.
void SnapshotWriter::vertex_arrays(slave::SlaveContext& ctx) {
    const bool fixed = compatibility();
    const GLint array_buffer = integer(GL_ARRAY_BUFFER_BINDING);
    auto bind_array_buffer = [&](GLuint keeper_name) {
        encode_glBindBuffer(e_, sz_, GL_ARRAY_BUFFER, GLuint(master_name(ctx, Ns::buffer, keeper_name)));
        sz_.set_bound(GL_ARRAY_BUFFER_BINDING, keeper_name != 0);
    };
    sz_.set_array_offsets(true);
    if (fixed) {
        const GLint client_unit = integer(GL_CLIENT_ACTIVE_TEXTURE);
        const GLint units = std::min(integer(GL_MAX_TEXTURE_COORDS), 32);
        for (const FixedClientArray& a : kFixedClientArrays) {
            const int count = a.slot == ClientSlot::TexCoord ? units : 1;
            for (int u = 0; u < count; ++u) {
                if (a.slot == ClientSlot::TexCoord) {
                    gl_.glClientActiveTexture(GLenum(GL_TEXTURE0 + u));
                    encode_glClientActiveTexture(e_, sz_, GLenum(GL_TEXTURE0 + u));
                }
                const bool on = gl_.glIsEnabled(a.cap);
                if (on) encode_glEnableClientState(e_, sz_, a.cap);
                else encode_glDisableClientState(e_, sz_, a.cap);
                const GLint buffer = integer(a.binding);
                if (!buffer) continue;
                const GLint size = a.size_query ? integer(a.size_query) : 0, type = a.type_query ? integer(a.type_query) : 0;
                const GLint stride = integer(a.stride);
                void* pointer = nullptr;
                gl_.glGetPointerv(a.pointer, &pointer);
                bind_array_buffer(GLuint(buffer));
                switch (a.slot) {
                case ClientSlot::Vertex: encode_glVertexPointer(e_, sz_, size, GLenum(type), stride, pointer); break;
                case ClientSlot::Normal: encode_glNormalPointer(e_, sz_, GLenum(type), stride, pointer); break;
                case ClientSlot::Color: encode_glColorPointer(e_, sz_, size, GLenum(type), stride, pointer); break;
                case ClientSlot::SecondaryColor:
                    encode_glSecondaryColorPointer(e_, sz_, size, GLenum(type), stride, pointer);
                    break;
                case ClientSlot::FogCoord: encode_glFogCoordPointer(e_, sz_, GLenum(type), stride, pointer); break;
                case ClientSlot::Index: encode_glIndexPointer(e_, sz_, GLenum(type), stride, pointer); break;
                case ClientSlot::EdgeFlag: encode_glEdgeFlagPointer(e_, sz_, stride, pointer); break;
                case ClientSlot::TexCoord: encode_glTexCoordPointer(e_, sz_, size, GLenum(type), stride, pointer); break;
                case ClientSlot::Attrib: break;
                }
            }
        }
        gl_.glClientActiveTexture(GLenum(client_unit));
        encode_glClientActiveTexture(e_, sz_, GLenum(client_unit));
    }
    if (gl_.has(OP_glGetVertexAttribiv)) {
        const GLint attribs = std::min(integer(GL_MAX_VERTEX_ATTRIBS), 32);
        for (GLint i = 0; i < attribs; ++i) {
            auto value = [&](GLenum pname) {
                GLint v = 0;
                gl_.glGetVertexAttribiv(GLuint(i), pname, &v);
                return v;
            };
            if (value(GL_VERTEX_ATTRIB_ARRAY_ENABLED)) encode_glEnableVertexAttribArray(e_, sz_, GLuint(i));
            else encode_glDisableVertexAttribArray(e_, sz_, GLuint(i));
            const GLint divisor = value(GL_VERTEX_ATTRIB_ARRAY_DIVISOR);
            if (divisor && gl_.has(OP_glVertexAttribDivisor)) encode_glVertexAttribDivisor(e_, sz_, GLuint(i), GLuint(divisor));
            const GLint buffer = value(GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING);
            if (!buffer) continue;
            void* pointer = nullptr;
            gl_.glGetVertexAttribPointerv(GLuint(i), GL_VERTEX_ATTRIB_ARRAY_POINTER, &pointer);
            bind_array_buffer(GLuint(buffer));
            const GLint size = value(GL_VERTEX_ATTRIB_ARRAY_SIZE), type = value(GL_VERTEX_ATTRIB_ARRAY_TYPE);
            const GLint stride = value(GL_VERTEX_ATTRIB_ARRAY_STRIDE);
            if (value(GL_VERTEX_ATTRIB_ARRAY_INTEGER))
                encode_glVertexAttribIPointer(e_, sz_, GLuint(i), size, GLenum(type), stride, pointer);
            else
                encode_glVertexAttribPointer(e_, sz_, GLuint(i), size, GLenum(type),
                                             GLboolean(value(GL_VERTEX_ATTRIB_ARRAY_NORMALIZED)), stride, pointer);
        }
    }
    sz_.set_array_offsets(false);
    bind_array_buffer(GLuint(array_buffer));
    // The element buffer belongs to the vertex array object.
    encode_glBindBuffer(e_, sz_, GL_ELEMENT_ARRAY_BUFFER,
                        GLuint(master_name(ctx, Ns::buffer, GLuint(integer(GL_ELEMENT_ARRAY_BUFFER_BINDING)))));
}

// --- context state -------------------------------------------------------------------------

// A compatibility context: fixed-function state exists. A core profile answers some of its
// queries but refuses every setter.
bool SnapshotWriter::compatibility() {
    GLint mask = 0;
    gl_.glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
    const bool asked_ok = asked();
    return !asked_ok || !(mask & GL_CONTEXT_CORE_PROFILE_BIT);  // before GL 3.2: no profiles, all compatibility
}

void SnapshotWriter::context_state(slave::SlaveContext& ctx) {
    const bool fixed = compatibility();
    client_array_cache(ctx);
    if (gl_.has(OP_glBindVertexArray)) {
        const GLint vao = integer(GL_VERTEX_ARRAY_BINDING);
        gl_.glBindVertexArray(0);
        encode_glBindVertexArray(e_, sz_, 0);
        vertex_arrays(ctx);
        gl_.glBindVertexArray(GLuint(vao));
    } else {
        vertex_arrays(ctx);
    }
    snapshot_values(gl_, e_, sz_);
    snapshot_point_parameters(gl_, e_, sz_);
    if (fixed) snapshot_values_compatibility(gl_, e_, sz_);
    else snapshot_values_core(gl_, e_, sz_);
    if (fixed) {
        // Positions, directions and planes come back in eye coordinates: set under an identity modelview.
        encode_glMatrixMode(e_, sz_, GL_MODELVIEW);
        encode_glLoadIdentity(e_, sz_);
        snapshot_lights(gl_, e_, sz_);
        snapshot_clip_planes(gl_, e_, sz_);
        snapshot_materials(gl_, e_, sz_);
        snapshot_light_model(gl_, e_, sz_);
        snapshot_fog(gl_, e_, sz_);
        snapshot_point_parameters_compatibility(gl_, e_, sz_);
        snapshot_pixel_transfer(gl_, e_, sz_);
        snapshot_current(gl_, e_, sz_);
    }
    const GLint unit = integer(GL_ACTIVE_TEXTURE);
    const GLint units = std::min(std::max(integer(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS), integer(GL_MAX_TEXTURE_UNITS)), 32);
    const GLint fixed_units = fixed ? std::min(integer(GL_MAX_TEXTURE_UNITS), 8) : 0;
    for (GLint u = 0; u < units; ++u) {
        gl_.glActiveTexture(GLenum(GL_TEXTURE0 + u));
        encode_glActiveTexture(e_, sz_, GLenum(GL_TEXTURE0 + u));
        for (const auto& t : kUnitTargets) {
            GLint bound = 0;
            if (!query(t[1], bound)) continue;
            encode_glBindTexture(e_, sz_, t[0], GLuint(master_name(ctx, Ns::texture, GLuint(bound))));
        }
        if (gl_.has(OP_glBindSampler)) {
            const GLint sampler = integer(GL_SAMPLER_BINDING);
            if (sampler) encode_glBindSampler(e_, sz_, GLuint(u), GLuint(master_name(ctx, Ns::sampler, GLuint(sampler))));
        }
        if (u < fixed_units) {
            snapshot_texture_env(gl_, e_, sz_);
            snapshot_texture_lod_bias(gl_, e_, sz_);
            snapshot_texture_gen(gl_, e_, sz_);
            snapshot_enables_per_unit(gl_, e_, sz_);
            GLfloat coords[4] = {0, 0, 0, 1};
            gl_.glGetFloatv(GL_CURRENT_TEXTURE_COORDS, coords);
            encode_glMultiTexCoord4fv(e_, sz_, GLenum(GL_TEXTURE0 + u), coords);
        }
    }
    gl_.glActiveTexture(GLenum(unit));
    if (gl_.has(OP_glGetVertexAttribfv)) {
        const GLint attribs = std::min(integer(GL_MAX_VERTEX_ATTRIBS), 32);
        for (GLint i = fixed ? 1 : 0; i < attribs; ++i) {  // compatibility: attribute 0 is the vertex itself
            GLfloat v[4] = {0, 0, 0, 1};
            gl_.glGetVertexAttribfv(GLuint(i), GL_CURRENT_VERTEX_ATTRIB, v);
            encode_glVertexAttrib4fv(e_, sz_, GLuint(i), v);
        }
    }
    if (fixed) {
        GLint valid = 0;
        gl_.glGetIntegerv(GL_CURRENT_RASTER_POSITION_VALID, &valid);
        GLfloat raster[4] = {};
        gl_.glGetFloatv(GL_CURRENT_RASTER_POSITION, raster);
        if (valid && gl_.has(OP_glWindowPos3f)) encode_glWindowPos3f(e_, sz_, raster[0], raster[1], raster[2]);
        matrices(ctx);
        for (GLenum stack : {GL_ATTRIB_STACK_DEPTH, GL_CLIENT_ATTRIB_STACK_DEPTH}) {
            const GLint depth = integer(stack);
            if (depth > 0)
                missing("context " + std::to_string(ctx.id) + ": " +
                        (stack == GL_ATTRIB_STACK_DEPTH ? "attribute" : "client attribute") + " stack depth " +
                        std::to_string(depth));
        }
    }
    GLint box[4] = {};
    gl_.glGetIntegerv(GL_VIEWPORT, box);
    encode_glViewport(e_, sz_, box[0], box[1], box[2], box[3]);
    gl_.glGetIntegerv(GL_SCISSOR_BOX, box);
    encode_glScissor(e_, sz_, box[0], box[1], box[2], box[3]);
    snapshot_enables_global(gl_, e_, sz_);
    if (fixed) snapshot_enables_compatibility(gl_, e_, sz_);
    bindings(ctx);
    encode_glActiveTexture(e_, sz_, GLenum(unit));
    snapshot_pixel_store(gl_, e_, sz_);
    if (gl_.has(OP_glBindBuffer))
        encode_glBindBuffer(e_, sz_, GL_PIXEL_UNPACK_BUFFER,
                            GLuint(master_name(ctx, Ns::buffer, GLuint(integer(GL_PIXEL_UNPACK_BUFFER_BINDING)))));
    flush();
}

// Each stack from the bottom up; the keeper's stacks are popped to be read and pushed back.
void SnapshotWriter::matrices(slave::SlaveContext& ctx) {
    const GLint mode = integer(GL_MATRIX_MODE);
    const GLint unit = integer(GL_ACTIVE_TEXTURE);
    struct Stack {
        GLenum mode, depth, matrix;
        GLint unit;
    };
    std::vector<Stack> stacks = {{GL_PROJECTION, GL_PROJECTION_STACK_DEPTH, GL_PROJECTION_MATRIX, -1},
                                 {GL_MODELVIEW, GL_MODELVIEW_STACK_DEPTH, GL_MODELVIEW_MATRIX, -1}};
    const GLint units = std::min(integer(GL_MAX_TEXTURE_COORDS), 8);
    for (GLint u = 0; u < units; ++u) stacks.push_back({GL_TEXTURE, GL_TEXTURE_STACK_DEPTH, GL_TEXTURE_MATRIX, u});
    for (const Stack& s : stacks) {
        if (s.unit >= 0) {
            gl_.glActiveTexture(GLenum(GL_TEXTURE0 + s.unit));
            encode_glActiveTexture(e_, sz_, GLenum(GL_TEXTURE0 + s.unit));
        }
        gl_.glMatrixMode(s.mode);
        encode_glMatrixMode(e_, sz_, s.mode);
        const GLint depth = std::max(integer(s.depth), 1);
        // The calls that built each entry, where the stream says: the same numbers, and the same
        // kind of matrix for a driver that multiplies by kind (Mesa's flags). Nothing is popped.
        if (const std::vector<MatrixRecipe>* recipes = kept_.matrices(ctx.id, s.mode);
            recipes && recipes->size() == size_t(depth) &&
            std::all_of(recipes->begin(), recipes->end(), [](const MatrixRecipe& r) { return r.known; })) {
            for (size_t i = 0; i < recipes->size(); ++i) {
                if (i > 0) encode_glPushMatrix(e_, sz_);
                encode_glLoadIdentity(e_, sz_);
                raw((*recipes)[i].calls, ctx.id);
            }
            continue;
        }
        std::vector<std::array<GLdouble, 16>> entries;
        entries.resize(size_t(depth));
        for (GLint i = depth - 1; i >= 0; --i) {
            gl_.glGetDoublev(s.matrix, entries[size_t(i)].data());
            if (i > 0) gl_.glPopMatrix();
        }
        for (GLint i = 0; i < depth; ++i) {
            if (i > 0) {
                gl_.glPushMatrix();
                encode_glPushMatrix(e_, sz_);
            }
            // An identity is loaded as one: GL (Mesa) keeps what kind of matrix it holds, and an
            // identity loaded as numbers is not known as one.
            const std::array<GLdouble, 16>& m = entries[size_t(i)];
            const bool identity = m == std::array<GLdouble, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
            if (identity) {
                gl_.glLoadIdentity();
                encode_glLoadIdentity(e_, sz_);
            } else {
                gl_.glLoadMatrixd(m.data());
                encode_glLoadMatrixd(e_, sz_, m.data());
            }
        }
    }
    gl_.glActiveTexture(GLenum(unit));
    gl_.glMatrixMode(GLenum(mode));
    encode_glMatrixMode(e_, sz_, GLenum(mode));
}

void SnapshotWriter::bindings(slave::SlaveContext& ctx) {
    auto buffer = [&](GLint keeper_name) { return GLuint(master_name(ctx, Ns::buffer, GLuint(keeper_name))); };
    if (gl_.has(OP_glBindBuffer)) {
        for (const auto& t : kBufferTargets) {
            GLint bound = 0;
            if (query(t[1], bound)) encode_glBindBuffer(e_, sz_, t[0], buffer(bound));
        }
        for (const auto& t : kIndexedBuffers) {
            GLint count = 0;
            if (!query(t[0] == GL_UNIFORM_BUFFER ? GL_MAX_UNIFORM_BUFFER_BINDINGS : GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS,
                       count))
                continue;
            for (GLint i = 0; i < std::min(count, 96); ++i) {
                GLint name = 0;
                GLint64 start = 0, size = 0;
                gl_.glGetIntegeri_v(t[1], GLuint(i), &name);
                if (!name) continue;
                gl_.glGetInteger64i_v(t[2], GLuint(i), &start);
                gl_.glGetInteger64i_v(t[3], GLuint(i), &size);
                if (size > 0) encode_glBindBufferRange(e_, sz_, t[0], GLuint(i), buffer(name), GLintptr(start), GLsizeiptr(size));
                else encode_glBindBufferBase(e_, sz_, t[0], GLuint(i), buffer(name));
            }
            // glBindBufferRange also binds the general point: set it again.
            encode_glBindBuffer(e_, sz_, t[0], buffer(integer(t[1])));
        }
    }
    if (gl_.has(OP_glBindRenderbuffer))
        encode_glBindRenderbuffer(e_, sz_, GL_RENDERBUFFER,
                                  GLuint(master_name(ctx, Ns::renderbuffer, GLuint(integer(GL_RENDERBUFFER_BINDING)))));
    if (gl_.has(OP_glBindFramebuffer)) {
        // The window's draw and read buffers, then the program's framebuffers.
        const GLint draw = integer(GL_DRAW_FRAMEBUFFER_BINDING), read = integer(GL_READ_FRAMEBUFFER_BINDING);
        gl_.glBindFramebuffer(GL_FRAMEBUFFER, 0);
        encode_glBindFramebuffer(e_, sz_, GL_FRAMEBUFFER, 0);
        encode_glDrawBuffer(e_, sz_, GLenum(integer(GL_DRAW_BUFFER)));
        encode_glReadBuffer(e_, sz_, GLenum(integer(GL_READ_BUFFER)));
        gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
        gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
        encode_glBindFramebuffer(e_, sz_, GL_DRAW_FRAMEBUFFER, GLuint(master_name(ctx, Ns::framebuffer, GLuint(draw))));
        encode_glBindFramebuffer(e_, sz_, GL_READ_FRAMEBUFFER, GLuint(master_name(ctx, Ns::framebuffer, GLuint(read))));
    } else {
        encode_glDrawBuffer(e_, sz_, GLenum(integer(GL_DRAW_BUFFER)));
        encode_glReadBuffer(e_, sz_, GLenum(integer(GL_READ_BUFFER)));
    }
    if (gl_.has(OP_glUseProgram))
        encode_glUseProgram(e_, sz_, GLuint(master_name(ctx, Ns::program, GLuint(integer(GL_CURRENT_PROGRAM)))));
    if (gl_.has(OP_glBindVertexArray))
        encode_glBindVertexArray(e_, sz_, GLuint(master_name(ctx, Ns::vertex_array, GLuint(integer(GL_VERTEX_ARRAY_BINDING)))));
}

// The slave's copies of client arrays that later glcast.client_arrays tuples may name as
// cached: each sent once, then an empty tuple so that no draw range is left pending.
void SnapshotWriter::client_array_cache(slave::SlaveContext& ctx) {
    for (const auto& [handle, copy] : ctx.client_arrays) {
        e_.begin(kSynthClientArrays);
        encode_synth_client_arrays(e_, 1);
        // A vertex array of 2 shorts (4 bytes), the form glVertexPointer takes for any bytes.
        encode_synth_client_arrays_item(e_, uint8_t(ClientSlot::Vertex), 0, 2, GL_SHORT, 4, 0, 0, handle, 0, 0,
                                        copy.data(), int64_t(copy.size()));
        e_.end();
        flush();
    }
    if (!ctx.client_arrays.empty()) {
        e_.begin(kSynthClientArrays);
        encode_synth_client_arrays(e_, 0);
        e_.end();
    }
}

}  // namespace glcast::keeper
