// Sizes of the arrays a GL call reads or writes, where gl.xml says only COMPSIZE(...): the
// length expressions of codegen/annotations/commands.yaml call these as `sz.`. Both sides
// evaluate the same expressions: the shim to encode what a call read, the slave to check that
// the stream shipped what its own driver will read. The facts only the driver knows
// (pixel-store state, bound buffers, texture level sizes) come from the virtual methods: the
// shim asks the real driver (DriverSizeQueries), the slave its own (ReplaySizeQueries), tests
// give fixed answers. Everything else is pure arithmetic here.
//
// A size that cannot be determined is recorded with fail() and 0 is returned: the shim then
// forwards the call unserialized and counts it, the slave refuses the call.
#pragma once

#include <cstdint>
#include <string>

#include "common/gles.h"
#include "glcast_pnames.h"

namespace glcast {

enum class Dir { In, Out };


struct PixelStore {
    int32_t row_length = 0, image_height = 0, skip_pixels = 0, skip_rows = 0, skip_images = 0;
    int32_t alignment = 4;
};

class SizeQueries {
public:
    virtual ~SizeQueries() = default;

    // -- what the driver knows -------------------------------------------------------
    virtual int64_t driver_count(uint32_t pname) = 0;          // glGetIntegerv(pname)
    // From driver_count unless a test gives them another way.
    virtual PixelStore pixel_store(Dir dir);
    virtual bool bound(uint32_t binding_query) { return driver_count(binding_query) != 0; }
    virtual int64_t tex_level(uint32_t target, int32_t level, uint32_t pname) = 0;
    // A vertex-array pointer call: true when it is an offset into GL_ARRAY_BUFFER; the
    // implementation also notes that client arrays are in use.
    virtual bool client_pointer(const void* pointer) = 0;
    // glIsEnabled(cap), and `bytes` of the buffer bound at `target` from `offset` (false when
    // they cannot be read): the indices of a draw whose vertices are in client memory.
    virtual bool enabled(uint32_t cap) { (void)cap; return false; }
    virtual bool read_buffer(uint32_t target, int64_t offset, int64_t bytes, void* out) {
        (void)target, (void)offset, (void)bytes, (void)out;
        return false;
    }

    // -- derived sizes ---------------------------------------------------------------
    int64_t image(Dir dir, uint32_t format, uint32_t type, int64_t width, int64_t height, int64_t depth);
    int64_t pixel_bytes(uint32_t format, uint32_t type);
    int64_t type_bytes(uint32_t type);
    int64_t call_lists(int64_t n, uint32_t type);
    int64_t tex_image(uint32_t target, int32_t level, uint32_t format, uint32_t type);
    int64_t compressed_tex_image(uint32_t target, int32_t level);
    int64_t map1_points(uint32_t target, int64_t stride, int64_t order);
    int64_t map2_points(uint32_t target, int64_t ustride, int64_t uorder, int64_t vstride, int64_t vorder);
    int64_t pixel_map(uint32_t map);
    int64_t indirect_bytes(int64_t drawcount, int64_t stride, int64_t record_bytes);
    int64_t text_bytes(const char* text, int64_t length);
    int64_t uniform_components(uint32_t program, int32_t location);
    int64_t pname_count(PnameTable table, uint32_t pname);
    int64_t map_query(uint32_t target, uint32_t query);
    int64_t renderer_integer_count(int32_t attribute);  // GLX_MESA_query_renderer
    // Bytes a texture or renderbuffer image of that internal format takes, at most (unknown
    // formats count as 16 bytes a texel, the largest): the slave's object_bytes limit.
    int64_t texture_bytes(uint32_t internalformat, int64_t width, int64_t height, int64_t depth);
    // All `levels` of immutable storage (glTexStorage*): each level halves width and height,
    // and depth for 3D textures; cube maps have six faces.
    int64_t storage_bytes(uint32_t target, uint32_t internalformat, int64_t levels, int64_t width, int64_t height,
                          int64_t depth);

    void fail(const std::string& reason) { if (failure_.empty()) failure_ = reason; }
    const std::string& failure() const { return failure_; }
    void clear_failure() { failure_.clear(); }

private:
    std::string failure_;
};

int format_components(uint32_t format);   // 0 when unknown
int type_bytes_or_zero(uint32_t type);    // bytes per component, or per pixel for packed types
bool is_packed_type(uint32_t type);

}  // namespace glcast
