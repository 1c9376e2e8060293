#include "common/gles.h"

#include <cstdio>

#include "common/gl_headers.h"

namespace glcast {

int gles_version(const char* gl_version) {
    int major = 0, minor = 0;
    if (gl_version && std::sscanf(gl_version, "OpenGL ES %d.%d", &major, &minor) == 2) return major * 10 + minor;
    return 0;
}

bool gles_lacks(uint32_t pname, int es) {
    if (!es) return false;
    switch (pname) {
    case GL_PACK_IMAGE_HEIGHT: case GL_PACK_SKIP_IMAGES: case GL_PACK_SWAP_BYTES: case GL_PACK_LSB_FIRST:
    case GL_UNPACK_SWAP_BYTES: case GL_UNPACK_LSB_FIRST:
        return true;
    case GL_PACK_ROW_LENGTH: case GL_PACK_SKIP_PIXELS: case GL_PACK_SKIP_ROWS: case GL_UNPACK_ROW_LENGTH:
    case GL_UNPACK_SKIP_PIXELS: case GL_UNPACK_SKIP_ROWS: case GL_UNPACK_IMAGE_HEIGHT: case GL_UNPACK_SKIP_IMAGES:
    case GL_PIXEL_PACK_BUFFER_BINDING: case GL_PIXEL_UNPACK_BUFFER_BINDING: case GL_READ_BUFFER:
        return es < 30;
    default:
        return pname >= GL_PIXEL_MAP_I_TO_I_SIZE && pname <= GL_PIXEL_MAP_A_TO_A_SIZE;
    }
}

bool gles_lacks_tex_level_query(int es) { return es && es < 31; }
bool gles_lacks_buffer_read(int es) { return es != 0; }

}  // namespace glcast
