#include "protocol/size_queries.h"

#include <cstdio>
#include <cstring>

#include "common/gl_headers.h"

namespace glcast {

int format_components(uint32_t format) {
    switch (format) {
    case GL_RED: case GL_GREEN: case GL_BLUE: case GL_ALPHA: case GL_LUMINANCE: case GL_INTENSITY:
    case GL_DEPTH_COMPONENT: case GL_STENCIL_INDEX: case GL_COLOR_INDEX: case GL_RED_INTEGER:
    case GL_GREEN_INTEGER: case GL_BLUE_INTEGER: case GL_ALPHA_INTEGER:
        return 1;
    case GL_RG: case GL_RG_INTEGER: case GL_LUMINANCE_ALPHA: case GL_DEPTH_STENCIL:
        return 2;
    case GL_RGB: case GL_BGR: case GL_RGB_INTEGER: case GL_BGR_INTEGER:
        return 3;
    case GL_RGBA: case GL_BGRA: case GL_RGBA_INTEGER: case GL_BGRA_INTEGER: case GL_ABGR_EXT:
        return 4;
    default:
        return 0;
    }
}

bool is_packed_type(uint32_t type) {
    switch (type) {
    case GL_UNSIGNED_BYTE_3_3_2: case GL_UNSIGNED_BYTE_2_3_3_REV:
    case GL_UNSIGNED_SHORT_5_6_5: case GL_UNSIGNED_SHORT_5_6_5_REV:
    case GL_UNSIGNED_SHORT_4_4_4_4: case GL_UNSIGNED_SHORT_4_4_4_4_REV:
    case GL_UNSIGNED_SHORT_5_5_5_1: case GL_UNSIGNED_SHORT_1_5_5_5_REV:
    case GL_UNSIGNED_INT_8_8_8_8: case GL_UNSIGNED_INT_8_8_8_8_REV:
    case GL_UNSIGNED_INT_10_10_10_2: case GL_UNSIGNED_INT_2_10_10_10_REV:
    case GL_UNSIGNED_INT_24_8: case GL_UNSIGNED_INT_10F_11F_11F_REV:
    case GL_UNSIGNED_INT_5_9_9_9_REV: case GL_FLOAT_32_UNSIGNED_INT_24_8_REV:
        return true;
    default:
        return false;
    }
}

int type_bytes_or_zero(uint32_t type) {
    switch (type) {
    case GL_UNSIGNED_BYTE: case GL_BYTE: case GL_UNSIGNED_BYTE_3_3_2: case GL_UNSIGNED_BYTE_2_3_3_REV:
        return 1;
    case GL_UNSIGNED_SHORT: case GL_SHORT: case GL_HALF_FLOAT:
    case GL_UNSIGNED_SHORT_5_6_5: case GL_UNSIGNED_SHORT_5_6_5_REV:
    case GL_UNSIGNED_SHORT_4_4_4_4: case GL_UNSIGNED_SHORT_4_4_4_4_REV:
    case GL_UNSIGNED_SHORT_5_5_5_1: case GL_UNSIGNED_SHORT_1_5_5_5_REV:
        return 2;
    case GL_UNSIGNED_INT: case GL_INT: case GL_FLOAT: case GL_FIXED:
    case GL_UNSIGNED_INT_8_8_8_8: case GL_UNSIGNED_INT_8_8_8_8_REV:
    case GL_UNSIGNED_INT_10_10_10_2: case GL_UNSIGNED_INT_2_10_10_10_REV:
    case GL_UNSIGNED_INT_24_8: case GL_UNSIGNED_INT_10F_11F_11F_REV: case GL_UNSIGNED_INT_5_9_9_9_REV:
        return 4;
    case GL_DOUBLE: case GL_FLOAT_32_UNSIGNED_INT_24_8_REV:
        return 8;
    default:
        return 0;
    }
}

PixelStore SizeQueries::pixel_store(Dir dir) {
    const bool in = dir == Dir::In;
    PixelStore ps;
    ps.row_length = int32_t(driver_count(in ? GL_UNPACK_ROW_LENGTH : GL_PACK_ROW_LENGTH));
    ps.image_height = int32_t(driver_count(in ? GL_UNPACK_IMAGE_HEIGHT : GL_PACK_IMAGE_HEIGHT));
    ps.skip_pixels = int32_t(driver_count(in ? GL_UNPACK_SKIP_PIXELS : GL_PACK_SKIP_PIXELS));
    ps.skip_rows = int32_t(driver_count(in ? GL_UNPACK_SKIP_ROWS : GL_PACK_SKIP_ROWS));
    ps.skip_images = int32_t(driver_count(in ? GL_UNPACK_SKIP_IMAGES : GL_PACK_SKIP_IMAGES));
    ps.alignment = int32_t(driver_count(in ? GL_UNPACK_ALIGNMENT : GL_PACK_ALIGNMENT));
    return ps;
}

// The span of client memory a pixel transfer touches (OpenGL 4.6 compatibility, 8.4.4.1).
int64_t SizeQueries::image(Dir dir, uint32_t format, uint32_t type, int64_t width, int64_t height,
                           int64_t depth) {
    if (width <= 0 || height <= 0 || depth <= 0) return 0;
    const PixelStore ps = pixel_store(dir);
    const int64_t alignment = ps.alignment > 0 ? ps.alignment : 1;
    const int64_t row_pixels = ps.row_length > 0 ? ps.row_length : width;
    const int64_t image_rows = ps.image_height > 0 ? ps.image_height : height;
    const int64_t skip_pixels = ps.skip_pixels > 0 ? ps.skip_pixels : 0;
    const int64_t skip_rows = ps.skip_rows > 0 ? ps.skip_rows : 0;
    const int64_t skip_images = depth > 1 && ps.skip_images > 0 ? ps.skip_images : 0;

    if (type == GL_BITMAP) {
        const int64_t row_bytes = ((row_pixels + 7) / 8 + alignment - 1) / alignment * alignment;
        return (skip_images + depth - 1) * image_rows * row_bytes + (skip_rows + height - 1) * row_bytes +
               (skip_pixels + width + 7) / 8;
    }
    const int64_t comps = is_packed_type(type) ? 1 : format_components(format);
    const int64_t size = type_bytes_or_zero(type);
    if (!comps || !size) {
        char why[96];
        std::snprintf(why, sizeof why, "pixel format 0x%04x / type 0x%04x has no known size", format, type);
        fail(why);
        return 0;
    }
    const int64_t group = comps * size;
    int64_t row_bytes = group * row_pixels;
    if (size < alignment) row_bytes = (row_bytes + alignment - 1) / alignment * alignment;
    return (skip_images + depth - 1) * image_rows * row_bytes + (skip_rows + height - 1) * row_bytes +
           (skip_pixels + width) * group;
}

int64_t SizeQueries::pixel_bytes(uint32_t format, uint32_t type) {
    const int64_t comps = is_packed_type(type) ? 1 : format_components(format);
    const int64_t size = type_bytes_or_zero(type);
    if (!comps || !size) { fail("pixel format/type has no known size"); return 0; }
    return comps * size;
}

int64_t SizeQueries::type_bytes(uint32_t type) {
    const int bytes = type_bytes_or_zero(type);
    if (!bytes) {
        char why[64];
        std::snprintf(why, sizeof why, "type 0x%04x has no known size", type);
        fail(why);
    }
    return bytes;
}

int64_t SizeQueries::call_lists(int64_t n, uint32_t type) {
    if (n <= 0) return 0;
    switch (type) {
    case GL_2_BYTES: return 2 * n;
    case GL_3_BYTES: return 3 * n;
    case GL_4_BYTES: return 4 * n;
    default: return n * type_bytes(type);
    }
}

int64_t SizeQueries::tex_image(uint32_t target, int32_t level, uint32_t format, uint32_t type) {
    const int64_t w = tex_level(target, level, GL_TEXTURE_WIDTH);
    const int64_t h = tex_level(target, level, GL_TEXTURE_HEIGHT);
    const int64_t d = tex_level(target, level, GL_TEXTURE_DEPTH);
    return image(Dir::Out, format, type, w, h, d);
}

int64_t SizeQueries::compressed_tex_image(uint32_t target, int32_t level) {
    return tex_level(target, level, GL_TEXTURE_COMPRESSED_IMAGE_SIZE);
}

static int map_components(uint32_t target) {
    switch (target) {
    case GL_MAP1_INDEX: case GL_MAP2_INDEX: case GL_MAP1_TEXTURE_COORD_1: case GL_MAP2_TEXTURE_COORD_1:
        return 1;
    case GL_MAP1_TEXTURE_COORD_2: case GL_MAP2_TEXTURE_COORD_2:
        return 2;
    case GL_MAP1_VERTEX_3: case GL_MAP2_VERTEX_3: case GL_MAP1_NORMAL: case GL_MAP2_NORMAL:
    case GL_MAP1_TEXTURE_COORD_3: case GL_MAP2_TEXTURE_COORD_3:
        return 3;
    case GL_MAP1_VERTEX_4: case GL_MAP2_VERTEX_4: case GL_MAP1_COLOR_4: case GL_MAP2_COLOR_4:
    case GL_MAP1_TEXTURE_COORD_4: case GL_MAP2_TEXTURE_COORD_4:
        return 4;
    default:
        return 0;
    }
}

int64_t SizeQueries::map1_points(uint32_t target, int64_t stride, int64_t order) {
    const int k = map_components(target);
    if (order <= 0 || stride < k || !k) return 0;  // GL_INVALID_*: nothing is read
    return (order - 1) * stride + k;
}

int64_t SizeQueries::map2_points(uint32_t target, int64_t ustride, int64_t uorder, int64_t vstride,
                                 int64_t vorder) {
    const int k = map_components(target);
    if (uorder <= 0 || vorder <= 0 || ustride < k || vstride < k || !k) return 0;
    return (uorder - 1) * ustride + (vorder - 1) * vstride + k;
}

int64_t SizeQueries::pixel_map(uint32_t map) {
    if (map < GL_PIXEL_MAP_I_TO_I || map > GL_PIXEL_MAP_A_TO_A) return 0;
    // GL_PIXEL_MAP_x_SIZE sits 0x40 above GL_PIXEL_MAP_x
    return driver_count(map + (GL_PIXEL_MAP_I_TO_I_SIZE - GL_PIXEL_MAP_I_TO_I));
}

int64_t SizeQueries::indirect_bytes(int64_t drawcount, int64_t stride, int64_t record_bytes) {
    if (drawcount <= 0) return 0;
    return (drawcount - 1) * (stride ? stride : record_bytes) + record_bytes;
}

int64_t SizeQueries::text_bytes(const char* text, int64_t length) {
    if (!text) return 0;
    return length >= 0 ? length : int64_t(std::strlen(text));
}

int64_t SizeQueries::uniform_components(uint32_t, int32_t) {
    fail("glGetUniform*: the uniform's type is not tracked");
    return 0;
}

int64_t SizeQueries::pname_count(PnameTable table, uint32_t pname) {
    const int64_t n = glcast::pname_count(table, pname, *this);
    if (n < 0) {
        char why[96];
        std::snprintf(why, sizeof why, "pname 0x%04x is not in pname table '%s'", pname, pname_table_name(table));
        fail(why);
        return 0;
    }
    return n;
}

int64_t SizeQueries::renderer_integer_count(int32_t attribute) {
    switch (attribute) {
    case GLX_RENDERER_VENDOR_ID_MESA: case GLX_RENDERER_DEVICE_ID_MESA: case GLX_RENDERER_ACCELERATED_MESA:
    case GLX_RENDERER_VIDEO_MEMORY_MESA: case GLX_RENDERER_UNIFIED_MEMORY_ARCHITECTURE_MESA:
    case GLX_RENDERER_PREFERRED_PROFILE_MESA:
        return 1;
    case GLX_RENDERER_OPENGL_CORE_PROFILE_VERSION_MESA: case GLX_RENDERER_OPENGL_COMPATIBILITY_PROFILE_VERSION_MESA:
    case GLX_RENDERER_OPENGL_ES_PROFILE_VERSION_MESA: case GLX_RENDERER_OPENGL_ES2_PROFILE_VERSION_MESA:
        return 2;
    case GLX_RENDERER_VERSION_MESA:
        return 3;
    default:
        fail("GLX renderer attribute " + std::to_string(attribute) + " has no known size");
        return 0;
    }
}

int64_t SizeQueries::map_query(uint32_t target, uint32_t query) {
    const bool two_d = target >= GL_MAP2_COLOR_4 && target <= GL_MAP2_VERTEX_4;
    return pname_count(two_d ? PnameTable::map2_query : PnameTable::map1_query, query);
}

static int64_t texel_bytes(uint32_t internalformat) {
    switch (internalformat) {
    case GL_R8: case GL_R8_SNORM: case GL_R8I: case GL_R8UI: case GL_ALPHA8: case GL_LUMINANCE8: case GL_INTENSITY8:
    case GL_ALPHA: case GL_LUMINANCE: case GL_INTENSITY: case GL_RED: case GL_STENCIL_INDEX8: case 1:
        return 1;
    case GL_RG8: case GL_RG8_SNORM: case GL_RG8I: case GL_RG8UI: case GL_R16: case GL_R16F: case GL_R16I: case GL_R16UI:
    case GL_LUMINANCE8_ALPHA8: case GL_LUMINANCE_ALPHA: case GL_RG: case GL_DEPTH_COMPONENT16: case GL_RGB565:
    case GL_RGB5_A1: case GL_RGBA4: case 2:
        return 2;
    case GL_RGB8: case GL_SRGB8: case GL_RGB: case GL_DEPTH_COMPONENT24: case 3:
        return 4;  // drivers keep RGB8 as RGBX8
    case GL_RGBA8: case GL_SRGB8_ALPHA8: case GL_RGBA: case GL_RGBA8I: case GL_RGBA8UI: case GL_RGB10_A2:
    case GL_RG16: case GL_RG16F: case GL_R32F: case GL_R32I: case GL_R32UI: case GL_R11F_G11F_B10F: case GL_RGB9_E5:
    case GL_DEPTH_COMPONENT32: case GL_DEPTH_COMPONENT32F: case GL_DEPTH24_STENCIL8: case GL_DEPTH_COMPONENT: case GL_DEPTH_STENCIL:
    case 4:
        return 4;
    case GL_RGBA16: case GL_RGBA16F: case GL_RGBA16I: case GL_RGBA16UI: case GL_RGB16F: case GL_RG32F: case GL_RG32I:
    case GL_RG32UI: case GL_DEPTH32F_STENCIL8:
        return 8;
    default:
        return 16;
    }
}

int64_t SizeQueries::texture_bytes(uint32_t internalformat, int64_t width, int64_t height, int64_t depth) {
    if (width <= 0 || height <= 0 || depth <= 0) return 0;
    // Each factor is at most the texture_dimension limit (16384 by default), checked first:
    // the product stays far inside int64_t.
    return texel_bytes(internalformat) * width * height * depth;
}

int64_t SizeQueries::storage_bytes(uint32_t target, uint32_t internalformat, int64_t levels, int64_t width,
                                   int64_t height, int64_t depth) {
    int64_t total = 0;
    const bool halve_depth = target == GL_TEXTURE_3D;
    const int64_t faces = target == GL_TEXTURE_CUBE_MAP ? 6 : 1;
    for (int64_t l = 0; l < levels && l < 32; ++l) {
        total += faces * texture_bytes(internalformat, width, height, depth);
        width = width > 1 ? width / 2 : 1;
        height = height > 1 ? height / 2 : 1;
        if (halve_depth) depth = depth > 1 ? depth / 2 : 1;
    }
    return total;
}

}  // namespace glcast
