#include "slave/replay_sizes.h"

#include "common/gl_headers.h"

namespace glcast::slave {

int32_t ReplaySizeQueries::integer(uint32_t pname) const {
    GLint v = 0;
    api_.glGetIntegerv(pname, &v);
    return v;
}

PixelStore ReplaySizeQueries::pixel_store(Dir dir) {
    const bool in = dir == Dir::In;
    PixelStore ps;
    ps.row_length = integer(in ? GL_UNPACK_ROW_LENGTH : GL_PACK_ROW_LENGTH);
    ps.image_height = integer(in ? GL_UNPACK_IMAGE_HEIGHT : GL_PACK_IMAGE_HEIGHT);
    ps.skip_pixels = integer(in ? GL_UNPACK_SKIP_PIXELS : GL_PACK_SKIP_PIXELS);
    ps.skip_rows = integer(in ? GL_UNPACK_SKIP_ROWS : GL_PACK_SKIP_ROWS);
    ps.skip_images = integer(in ? GL_UNPACK_SKIP_IMAGES : GL_PACK_SKIP_IMAGES);
    ps.alignment = integer(in ? GL_UNPACK_ALIGNMENT : GL_PACK_ALIGNMENT);
    return ps;
}

bool ReplaySizeQueries::bound(uint32_t binding_query) { return integer(binding_query) != 0; }

int64_t ReplaySizeQueries::driver_count(uint32_t pname) { return integer(pname); }

int64_t ReplaySizeQueries::tex_level(uint32_t target, int32_t level, uint32_t pname) {
    GLint v = 0;
    api_.glGetTexLevelParameteriv(target, level, pname, &v);
    return v;
}

bool ReplaySizeQueries::client_pointer(const void*) { return bound(GL_ARRAY_BUFFER_BINDING); }

bool ReplaySizeQueries::enabled(uint32_t cap) { return api_.glIsEnabled(cap); }

// The caller has checked that [offset, offset + bytes) lies in the buffer (Replayer::need).
bool ReplaySizeQueries::read_buffer(uint32_t target, int64_t offset, int64_t bytes, void* out) {
    api_.glGetBufferSubData(target, GLintptr(offset), GLsizeiptr(bytes), out);
    return true;
}

uint32_t binding_target(uint32_t binding) {
    switch (binding) {
    case GL_ARRAY_BUFFER_BINDING: return GL_ARRAY_BUFFER;
    case GL_ELEMENT_ARRAY_BUFFER_BINDING: return GL_ELEMENT_ARRAY_BUFFER;
    case GL_PIXEL_PACK_BUFFER_BINDING: return GL_PIXEL_PACK_BUFFER;
    case GL_PIXEL_UNPACK_BUFFER_BINDING: return GL_PIXEL_UNPACK_BUFFER;
    case GL_DRAW_INDIRECT_BUFFER_BINDING: return GL_DRAW_INDIRECT_BUFFER;
    case GL_DISPATCH_INDIRECT_BUFFER_BINDING: return GL_DISPATCH_INDIRECT_BUFFER;
    case GL_PARAMETER_BUFFER_BINDING: return GL_PARAMETER_BUFFER;
    case GL_QUERY_BUFFER_BINDING: return GL_QUERY_BUFFER;
    case GL_COPY_READ_BUFFER_BINDING: return GL_COPY_READ_BUFFER;
    case GL_COPY_WRITE_BUFFER_BINDING: return GL_COPY_WRITE_BUFFER;
    case GL_TEXTURE_BUFFER_BINDING: return GL_TEXTURE_BUFFER;
    default: return 0;
    }
}

}  // namespace glcast::slave
