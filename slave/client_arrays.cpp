// Client-memory vertex arrays and mapped-buffer writes, as the master shipped them
// (protocol/format.h: kSynthClientArrays, kSynthBufferWrite).
#include <algorithm>
#include <cstdint>

#include "common/gl_headers.h"
#include "protocol/format.h"
#include "slave/replayer.h"

namespace glcast::slave {

// Bytes of one vertex's element of a client array; 0 for a type GL does not take there.
static int64_t client_element_bytes(ClientSlot slot, int32_t size, GLenum type) {
    if (slot == ClientSlot::EdgeFlag) return 1;  // GLboolean, whatever `type` says
    int64_t comps = size == GL_BGRA ? 4 : size;
    switch (slot) {
    case ClientSlot::Normal: comps = 3; break;
    case ClientSlot::FogCoord: case ClientSlot::Index: case ClientSlot::EdgeFlag: comps = 1; break;
    default: break;
    }
    if (comps < 1 || comps > 4) return 0;
    switch (type) {
    case GL_BYTE: case GL_UNSIGNED_BYTE: case GL_BOOL: return comps;
    case GL_SHORT: case GL_UNSIGNED_SHORT: case GL_HALF_FLOAT: return 2 * comps;
    case GL_INT: case GL_UNSIGNED_INT: case GL_FLOAT: case GL_FIXED: return 4 * comps;
    case GL_DOUBLE: return 8 * comps;
    case GL_INT_2_10_10_10_REV: case GL_UNSIGNED_INT_2_10_10_10_REV: case GL_UNSIGNED_INT_10F_11F_11F_REV: return 4;
    default: return 0;
    }
}

// The pointer call of the array's slot, at the slave's copy `p`.
static void point_array(const GlApi& gl, const SynthClientArrays::Item& a, const void* p) {
    const uint32_t index = a.index;
    const int32_t size = a.size, stride = a.stride;
    const GLenum type = a.type;
    const auto slot = ClientSlot(a.slot);
    switch (slot) {
    case ClientSlot::Vertex: gl.glVertexPointer(size, type, stride, p); break;
    case ClientSlot::Normal: gl.glNormalPointer(type, stride, p); break;
    case ClientSlot::Color: gl.glColorPointer(size, type, stride, p); break;
    case ClientSlot::SecondaryColor:
        gl.glSecondaryColorPointer(size, type, stride, p);
        break;
    case ClientSlot::FogCoord: gl.glFogCoordPointer(type, stride, p); break;
    case ClientSlot::Index: gl.glIndexPointer(type, stride, p); break;
    case ClientSlot::EdgeFlag: gl.glEdgeFlagPointer(stride, p); break;
    case ClientSlot::TexCoord: {
        GLint active = GL_TEXTURE0;
        gl.glGetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &active);
        auto client_active = [&gl](GLenum unit) { gl.glClientActiveTexture(unit); };
        client_active(GL_TEXTURE0 + index);
        gl.glTexCoordPointer(size, type, stride, p);
        client_active(GLenum(active));
        break;
    }
    case ClientSlot::Attrib:
        if (a.integer)
            gl.glVertexAttribIPointer(index, size, type, stride, p);
        else
            gl.glVertexAttribPointer(index, size, type, a.normalized, stride, p);
        break;
    }
}

// Points the array at the slave's copy. The pointer calls must see no GL_ARRAY_BUFFER, or
// they would take the address for a buffer offset; texture-coordinate arrays need their
// client-active unit. Both are restored.
void Replayer::client_arrays(const Call& c) {
    SlaveContext& ctx = current();
    ctx.client_range_pending = false;
    ctx.client_arrays_refused = true;  // until every array is in place
    SynthClientArrays t;
    read_synthetic(c, t);
    GLint array_buffer = 0;
    api_.glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer);
    auto bind = [this](GLenum target, GLuint buffer) { api_.glBindBuffer(target, buffer); };
    // The copies this tuple refers to stay; older ones go when the cache is over its limit
    // (the master then sends them again only if it thinks them current: "never sent").
    uint64_t incoming = 0;
    for (const SynthClientArrays::Item& a : t.arrays) incoming += a.cached ? 0 : a.data_bytes;
    if (incoming > options_.limits.client_array_bytes)
        throw ReplayError("client arrays of " + std::to_string(incoming) + " bytes are over the limit client_array_bytes=" +
                          std::to_string(options_.limits.client_array_bytes));
    if (ctx.client_array_bytes + incoming > options_.limits.client_array_bytes) {
        for (auto it = ctx.client_arrays.begin(); it != ctx.client_arrays.end();) {
            const bool used = std::any_of(t.arrays.begin(), t.arrays.end(),
                                          [&](const SynthClientArrays::Item& a) { return a.handle == it->first; });
            if (used) { ++it; continue; }
            ctx.client_array_bytes -= it->second.size();
            it = ctx.client_arrays.erase(it);
        }
    }
    int64_t range_first = 0, range_end = INT64_MAX;
    ctx.client_instances.clear();
    bind(GL_ARRAY_BUFFER, 0);
    for (const SynthClientArrays::Item& a : t.arrays) {
        const auto slot = ClientSlot(a.slot);
        const uint32_t index = a.index, handle = a.handle, first_byte = a.first_byte;
        const int32_t size = a.size, stride = a.stride;
        const GLenum type = a.type;
        std::vector<uint8_t>& copy = ctx.client_arrays[handle];
        if (a.cached) {
            if (copy.empty()) {
                bind(GL_ARRAY_BUFFER, GLuint(array_buffer));
                throw ReplayError("a draw uses client array " + std::to_string(handle) + ", which was never sent");
            }
        } else {
            ctx.client_array_bytes -= copy.size();
            copy.assign(a.data, a.data + a.data_bytes);
            if (copy.empty()) copy.push_back(0);
            ctx.client_array_bytes += copy.size();
        }
        // The vertices whose elements lie wholly in the copy: e * stride >= first_byte and
        // e * stride + element <= first_byte + copy size.
        const int64_t element = client_element_bytes(slot, size, type);
        if (stride <= 0 || !element) {
            bind(GL_ARRAY_BUFFER, GLuint(array_buffer));
            throw ReplayError("client array " + std::to_string(handle) + " has stride " + std::to_string(stride) +
                              " and element type " + std::to_string(type));
        }
        const int64_t start = int64_t(first_byte), stop = start + int64_t(copy.size());
        const int64_t held_first = (start + stride - 1) / stride, held_end = stop >= element ? (stop - element) / stride + 1 : 0;
        // A per-instance array holds instances, not vertices: its divisor is the slave's own
        // state (the stream replayed glVertexAttribDivisor).
        GLint divisor = 0;
        if (slot == ClientSlot::Attrib && api_.has(OP_glGetVertexAttribiv))
            api_.glGetVertexAttribiv(index, GL_VERTEX_ATTRIB_ARRAY_DIVISOR, &divisor);
        if (divisor > 0) {
            ctx.client_instances.push_back({uint32_t(divisor), held_first, std::max(held_first, held_end)});
        } else {
            range_first = std::max(range_first, held_first);
            range_end = std::min(range_end, held_end);
        }
        // GL adds first * stride itself: hand it the address the master's range started from.
        const void* p = copy.data() - first_byte;
        point_array(api_, a, p);
    }
    bind(GL_ARRAY_BUFFER, GLuint(array_buffer));
    ctx.client_arrays_refused = false;
    ctx.client_range_pending = !t.arrays.empty();
    ctx.client_first = range_first;
    ctx.client_end = std::max(range_first, range_end);
}

// Written through a mapped range on the master. The slave never maps the program's buffers
// itself, so a short map of its own writes the bytes, whatever the buffer's storage flags.
void Replayer::buffer_write(const Call& c) {
    SynthBufferWrite t;
    read_synthetic(c, t);
    if (!t.data_present) throw ReplayError("buffer write without data");
    const uint32_t master = t.buffer, bytes = t.data_bytes;
    const uint64_t offset = t.offset;
    const uint8_t* data = t.data;
    const GLuint buffer = GLuint(map_name(Ns::buffer, master, c));
    GLint saved = 0;
    api_.glGetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &saved);
    auto bind = [this](GLenum target, GLuint buffer) { api_.glBindBuffer(target, buffer); };
    bind(GL_COPY_WRITE_BUFFER, buffer);
    void* p = api_.glMapBufferRange(GL_COPY_WRITE_BUFFER, GLintptr(offset), bytes,
                                                                     GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT);
    if (p) {
        std::memcpy(p, data, bytes);
        api_.glUnmapBuffer(GL_COPY_WRITE_BUFFER);
    }
    bind(GL_COPY_WRITE_BUFFER, GLuint(saved));
    if (!p) throw ReplayError("buffer write: the slave could not map buffer " + std::to_string(master));
}

}  // namespace glcast::slave
