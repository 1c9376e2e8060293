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
    ByteReader r(c.body, c.body_bytes, c.offset + kTupleHeaderBytes);
    const uint32_t n = r.get<uint32_t>();
    GLint array_buffer = 0;
    gl<decltype(&::glGetIntegerv)>(OP_glGetIntegerv)(GL_ARRAY_BUFFER_BINDING, &array_buffer);
    const auto bind = gl<decltype(&::glBindBuffer)>(OP_glBindBuffer);
    bind(GL_ARRAY_BUFFER, 0);
    for (uint32_t i = 0; i < n; ++i) {
        const auto slot = ClientSlot(r.get<uint8_t>());
        const uint32_t index = r.get<uint32_t>();
        const int32_t size = r.get<int32_t>();
        const GLenum type = r.get<uint32_t>();
        const int32_t stride = r.get<int32_t>();
        const uint8_t normalized = r.get<uint8_t>();
        const uint8_t integer = r.get<uint8_t>();
        const uint32_t handle = r.get<uint32_t>();
        const uint32_t first_byte = r.get<uint32_t>();
        const uint8_t cached = r.get<uint8_t>();
        std::vector<uint8_t>& copy = ctx.client_arrays[handle];
        if (cached) {
            if (copy.empty()) {
                bind(GL_ARRAY_BUFFER, GLuint(array_buffer));
                throw ReplayError("a draw uses client array " + std::to_string(handle) + ", which was never sent");
            }
        } else {
            const uint32_t bytes = r.get<uint32_t>();
            const uint8_t* data = r.bytes(bytes, "client array data");
            copy.assign(data, data + bytes);
            if (copy.empty()) copy.push_back(0);
        }
        // GL adds first * stride itself: hand it the address the master's range started from.
        const void* p = copy.data() - first_byte;
        switch (slot) {
        case ClientSlot::Vertex: gl<decltype(&::glVertexPointer)>(OP_glVertexPointer)(size, type, stride, p); break;
        case ClientSlot::Normal: gl<decltype(&::glNormalPointer)>(OP_glNormalPointer)(type, stride, p); break;
        case ClientSlot::Color: gl<decltype(&::glColorPointer)>(OP_glColorPointer)(size, type, stride, p); break;
        case ClientSlot::SecondaryColor:
            gl<decltype(&::glSecondaryColorPointer)>(OP_glSecondaryColorPointer)(size, type, stride, p);
            break;
        case ClientSlot::FogCoord: gl<decltype(&::glFogCoordPointer)>(OP_glFogCoordPointer)(type, stride, p); break;
        case ClientSlot::Index: gl<decltype(&::glIndexPointer)>(OP_glIndexPointer)(type, stride, p); break;
        case ClientSlot::EdgeFlag: gl<decltype(&::glEdgeFlagPointer)>(OP_glEdgeFlagPointer)(stride, p); break;
        case ClientSlot::TexCoord: {
            GLint active = GL_TEXTURE0;
            gl<decltype(&::glGetIntegerv)>(OP_glGetIntegerv)(GL_CLIENT_ACTIVE_TEXTURE, &active);
            const auto client_active = gl<decltype(&::glClientActiveTexture)>(OP_glClientActiveTexture);
            client_active(GL_TEXTURE0 + index);
            gl<decltype(&::glTexCoordPointer)>(OP_glTexCoordPointer)(size, type, stride, p);
            client_active(GLenum(active));
            break;
        }
        case ClientSlot::Attrib:
            if (integer)
                gl<decltype(&::glVertexAttribIPointer)>(OP_glVertexAttribIPointer)(index, size, type, stride, p);
            else
                gl<decltype(&::glVertexAttribPointer)>(OP_glVertexAttribPointer)(index, size, type, normalized, stride, p);
            break;
        }
    }
    bind(GL_ARRAY_BUFFER, GLuint(array_buffer));
}

// Written through a mapped range on the master. The slave never maps the program's buffers
// itself, so a short map of its own writes the bytes, whatever the buffer's storage flags.
void Replayer::buffer_write(const Call& c) {
    ByteReader r(c.body, c.body_bytes, c.offset + kTupleHeaderBytes);
    const uint32_t master = r.get<uint32_t>();
    const uint64_t offset = r.get<uint64_t>();
    if (PtrTag(r.get<uint8_t>()) != PtrTag::Data) throw ReplayError("buffer write without data");
    const uint32_t bytes = r.get<uint32_t>();
    const uint8_t* data = r.bytes(bytes, "buffer write data");
    const GLuint buffer = GLuint(map_name(Ns::buffer, master, c));
    GLint saved = 0;
    gl<decltype(&::glGetIntegerv)>(OP_glGetIntegerv)(GL_COPY_WRITE_BUFFER_BINDING, &saved);
    const auto bind = gl<decltype(&::glBindBuffer)>(OP_glBindBuffer);
    bind(GL_COPY_WRITE_BUFFER, buffer);
    void* p = gl<decltype(&::glMapBufferRange)>(OP_glMapBufferRange)(GL_COPY_WRITE_BUFFER, GLintptr(offset), bytes,
                                                                     GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT);
    if (p) {
        std::memcpy(p, data, bytes);
        gl<decltype(&::glUnmapBuffer)>(OP_glUnmapBuffer)(GL_COPY_WRITE_BUFFER);
    }
    bind(GL_COPY_WRITE_BUFFER, GLuint(saved));
    if (!p) throw ReplayError("buffer write: the slave could not map buffer " + std::to_string(master));
}

}  // namespace glcast::slave
