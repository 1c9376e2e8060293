#include "slave/replay_sizes.h"

#include "common/gl_headers.h"

namespace glcast::slave {

int64_t ReplaySizeQueries::driver_count(uint32_t pname) {
    GLint v = 0;
    if (gles_lacks(pname, es_)) return 0;
    api_.glGetIntegerv(pname, &v);
    return v;
}

int64_t ReplaySizeQueries::tex_level(uint32_t target, int32_t level, uint32_t pname) {
    GLint v = 0;
    if (gles_lacks_tex_level_query(es_)) return 0;
    api_.glGetTexLevelParameteriv(target, level, pname, &v);
    return v;
}

bool ReplaySizeQueries::client_pointer(const void*) { return bound(GL_ARRAY_BUFFER_BINDING); }

bool ReplaySizeQueries::enabled(uint32_t cap) { return api_.glIsEnabled(cap); }

// The caller has checked that [offset, offset + bytes) lies in the buffer (Replayer::need).
bool ReplaySizeQueries::read_buffer(uint32_t target, int64_t offset, int64_t bytes, void* out) {
    if (gles_lacks_buffer_read(es_)) return false;
    api_.glGetBufferSubData(target, GLintptr(offset), GLsizeiptr(bytes), out);
    return true;
}

namespace {

struct BufferBinding {
    uint32_t target, binding;
};

constexpr BufferBinding kBufferBindings[] = {
    {GL_ARRAY_BUFFER, GL_ARRAY_BUFFER_BINDING},
    {GL_ELEMENT_ARRAY_BUFFER, GL_ELEMENT_ARRAY_BUFFER_BINDING},
    {GL_PIXEL_PACK_BUFFER, GL_PIXEL_PACK_BUFFER_BINDING},
    {GL_PIXEL_UNPACK_BUFFER, GL_PIXEL_UNPACK_BUFFER_BINDING},
    {GL_DRAW_INDIRECT_BUFFER, GL_DRAW_INDIRECT_BUFFER_BINDING},
    {GL_DISPATCH_INDIRECT_BUFFER, GL_DISPATCH_INDIRECT_BUFFER_BINDING},
    {GL_PARAMETER_BUFFER, GL_PARAMETER_BUFFER_BINDING},
    {GL_QUERY_BUFFER, GL_QUERY_BUFFER_BINDING},
    {GL_COPY_READ_BUFFER, GL_COPY_READ_BUFFER_BINDING},
    {GL_COPY_WRITE_BUFFER, GL_COPY_WRITE_BUFFER_BINDING},
    {GL_TEXTURE_BUFFER, GL_TEXTURE_BUFFER_BINDING},
    {GL_UNIFORM_BUFFER, GL_UNIFORM_BUFFER_BINDING},
    {GL_SHADER_STORAGE_BUFFER, GL_SHADER_STORAGE_BUFFER_BINDING},
    {GL_TRANSFORM_FEEDBACK_BUFFER, GL_TRANSFORM_FEEDBACK_BUFFER_BINDING},
    {GL_ATOMIC_COUNTER_BUFFER, GL_ATOMIC_COUNTER_BUFFER_BINDING},
};

}  // namespace

uint32_t binding_target(uint32_t binding) {
    for (const BufferBinding& b : kBufferBindings)
        if (b.binding == binding) return b.target;
    return 0;
}

uint32_t buffer_binding(uint32_t target) {
    for (const BufferBinding& b : kBufferBindings)
        if (b.target == target) return b.binding;
    return 0;
}

}  // namespace glcast::slave
