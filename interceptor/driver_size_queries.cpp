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

// Values an OpenGL ES context of `es` (ES version times 10) does not have: asking would raise
// GL_INVALID_ENUM, which the program's next glGetError would see. Such a value is GL's default
// there (0: no row length, no skipping, no swapping), as the context behaves.
static bool es_lacks(uint32_t pname, int es) {
    switch (pname) {
    case GL_PACK_IMAGE_HEIGHT: case GL_PACK_SKIP_IMAGES: case GL_PACK_SWAP_BYTES: case GL_PACK_LSB_FIRST:
    case GL_UNPACK_SWAP_BYTES: case GL_UNPACK_LSB_FIRST:
        return true;
    case GL_PACK_ROW_LENGTH: case GL_PACK_SKIP_PIXELS: case GL_PACK_SKIP_ROWS: case GL_UNPACK_ROW_LENGTH:
    case GL_UNPACK_SKIP_PIXELS: case GL_UNPACK_SKIP_ROWS: case GL_UNPACK_IMAGE_HEIGHT: case GL_UNPACK_SKIP_IMAGES:
    case GL_PIXEL_PACK_BUFFER_BINDING: case GL_PIXEL_UNPACK_BUFFER_BINDING:
        return es < 30;
    default:
        return pname >= GL_PIXEL_MAP_I_TO_I_SIZE && pname <= GL_PIXEL_MAP_A_TO_A_SIZE;
    }
}

int64_t DriverSizeQueries::driver_count(uint32_t pname) {
    const int es = thread_state().es_version;
    if (es && es_lacks(pname, es)) return 0;
    return real_get_integer(pname);
}

int64_t DriverSizeQueries::tex_level(uint32_t target, int32_t level, uint32_t pname) {
    GLint v = 0;
    if (const int es = thread_state().es_version; es && es < 31) return 0;  // glGetTexLevelParameter is ES 3.1's
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
    if (!real_gl().has(OP_glGetBufferSubData) || thread_state().es_version) return false;  // desktop GL's only
    real_gl().glGetBufferSubData(target, GLintptr(offset), GLsizeiptr(bytes), out);
    return true;
}

}  // namespace glcast
