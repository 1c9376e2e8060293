#include "interceptor/driver_size_queries.h"

#include "common/gl_headers.h"
#include "glcast_commands.h"
#include "glcast_gl_api.h"
#include "interceptor/client_arrays.h"
#include "interceptor/shim.h"
#include "interceptor/shim_internal.h"

namespace glcast {

int32_t real_get_integer(uint32_t pname) {
    GLint v = 0;
    if (real_gl().has(OP_glGetIntegerv)) real_gl().glGetIntegerv(pname, &v);
    return v;
}

int64_t DriverSizeQueries::driver_count(uint32_t pname) {
    if (gles_lacks(pname, thread_state().es_version)) return 0;
    return real_get_integer(pname);
}

int64_t DriverSizeQueries::tex_level(uint32_t target, int32_t level, uint32_t pname) {
    GLint v = 0;
    if (gles_lacks_tex_level_query(thread_state().es_version)) return 0;
    if (real_gl().has(OP_glGetTexLevelParameteriv)) real_gl().glGetTexLevelParameteriv(target, level, pname, &v);
    return v;
}

bool DriverSizeQueries::client_pointer(const void*) {
    const bool in_buffer = real_get_integer(GL_ARRAY_BUFFER_BINDING) != 0;
    if (!in_buffer) note_client_pointer(thread_state_opcode());
    return in_buffer;
}

bool DriverSizeQueries::enabled(uint32_t cap) {
    return real_gl().has(OP_glIsEnabled) && real_gl().glIsEnabled(cap);
}

bool DriverSizeQueries::read_buffer(uint32_t target, int64_t offset, int64_t bytes, void* out) {
    if (!real_gl().has(OP_glGetBufferSubData) || gles_lacks_buffer_read(thread_state().es_version)) return false;
    real_gl().glGetBufferSubData(target, GLintptr(offset), GLsizeiptr(bytes), out);
    return true;
}

}  // namespace glcast
