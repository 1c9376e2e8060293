// Client-memory vertex arrays and mapped-buffer writes, as the master shipped them
// (protocol/format.h: kSynthClientArrays, kSynthBufferWrite).
#include "common/gl_headers.h"
#include "protocol/format.h"
#include "slave/replayer.h"

namespace glcast::slave {

// Points the array at the slave's copy. The pointer calls must see no GL_ARRAY_BUFFER, or
// they would take the address for a buffer offset; texture-coordinate arrays need their
// client-active unit. Both are restored.
void Replayer::client_arrays(const Call& c) {
    SlaveContext& ctx = current();
    SynthClientArrays t;
    read_synthetic(c, t);
    GLint array_buffer = 0;
    api_.glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer);
    auto bind = [this](GLenum target, GLuint buffer) { api_.glBindBuffer(target, buffer); };
    bind(GL_ARRAY_BUFFER, 0);
    for (const SynthClientArrays::Item& a : t.arrays) {
        const auto slot = ClientSlot(a.slot);
        const uint32_t index = a.index, handle = a.handle, first_byte = a.first_byte;
        const int32_t size = a.size, stride = a.stride;
        const GLenum type = a.type;
        const uint8_t normalized = a.normalized, integer = a.integer;
        std::vector<uint8_t>& copy = ctx.client_arrays[handle];
        if (a.cached) {
            if (copy.empty()) {
                bind(GL_ARRAY_BUFFER, GLuint(array_buffer));
                throw ReplayError("a draw uses client array " + std::to_string(handle) + ", which was never sent");
            }
        } else {
            copy.assign(a.data, a.data + a.data_bytes);
            if (copy.empty()) copy.push_back(0);
        }
        // GL adds first * stride itself: hand it the address the master's range started from.
        const void* p = copy.data() - first_byte;
        switch (slot) {
        case ClientSlot::Vertex: api_.glVertexPointer(size, type, stride, p); break;
        case ClientSlot::Normal: api_.glNormalPointer(type, stride, p); break;
        case ClientSlot::Color: api_.glColorPointer(size, type, stride, p); break;
        case ClientSlot::SecondaryColor:
            api_.glSecondaryColorPointer(size, type, stride, p);
            break;
        case ClientSlot::FogCoord: api_.glFogCoordPointer(type, stride, p); break;
        case ClientSlot::Index: api_.glIndexPointer(type, stride, p); break;
        case ClientSlot::EdgeFlag: api_.glEdgeFlagPointer(stride, p); break;
        case ClientSlot::TexCoord: {
            GLint active = GL_TEXTURE0;
            api_.glGetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &active);
            auto client_active = [this](GLenum unit) { api_.glClientActiveTexture(unit); };
            client_active(GL_TEXTURE0 + index);
            api_.glTexCoordPointer(size, type, stride, p);
            client_active(GLenum(active));
            break;
        }
        case ClientSlot::Attrib:
            if (integer)
                api_.glVertexAttribIPointer(index, size, type, stride, p);
            else
                api_.glVertexAttribPointer(index, size, type, normalized, stride, p);
            break;
        }
    }
    bind(GL_ARRAY_BUFFER, GLuint(array_buffer));
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
