// What a call's values say the driver will read, checked against what the stream shipped,
// for the commands whose array sizes need the driver's state (the generated replay checks
// the rest: Replayer::need). The stream is not trusted: a texture upload whose width says
// 1 GiB with 768 bytes shipped would have the driver read past the slave's scratch memory.
#include <algorithm>
#include <cstring>
#include <string>

#include "common/gl_headers.h"
#include "slave/replayer.h"

namespace glcast::slave {

namespace {

enum Kind : uint8_t {
    kNone,
    kImage,          // a pixel transfer from client memory (unpack state)
    kBufferSize,     // a buffer's data store of `size` bytes
    kDrawArrays,     // first, count over client arrays
    kMultiDrawArrays,
    kDrawElements,   // count indices of type
    kMultiDrawElements,
};

// Parameter positions; -1: none.
struct Family {
    const char* name;
    Kind kind;
    int8_t width, height, depth, format, type, data;  // kImage; kBufferSize: size in `width`
    // kDraw*: first (or start) in `width`, count in `height`, type in `type`, indices in `data`,
    // base vertex in `depth`, drawcount in `format`
};

constexpr Family kFamilies[] = {
    {"glTexImage1D", kImage, 3, -1, -1, 5, 6, 7},
    {"glTexImage2D", kImage, 3, 4, -1, 6, 7, 8},
    {"glTexImage3D", kImage, 3, 4, 5, 7, 8, 9},
    {"glTexSubImage1D", kImage, 3, -1, -1, 4, 5, 6},
    {"glTexSubImage2D", kImage, 4, 5, -1, 6, 7, 8},
    {"glTexSubImage3D", kImage, 5, 6, 7, 8, 9, 10},
    {"glTextureSubImage1D", kImage, 3, -1, -1, 4, 5, 6},
    {"glTextureSubImage2D", kImage, 4, 5, -1, 6, 7, 8},
    {"glTextureSubImage3D", kImage, 5, 6, 7, 8, 9, 10},
    {"glDrawPixels", kImage, 0, 1, -1, 2, 3, 4},
    {"glBufferData", kBufferSize, 1, -1, -1, -1, -1, -1},
    {"glBufferStorage", kBufferSize, 1, -1, -1, -1, -1, -1},
    {"glNamedBufferData", kBufferSize, 1, -1, -1, -1, -1, -1},
    {"glNamedBufferStorage", kBufferSize, 1, -1, -1, -1, -1, -1},
    {"glDrawArrays", kDrawArrays, 1, 2, -1, -1, -1, -1},
    {"glDrawArraysInstanced", kDrawArrays, 1, 2, -1, -1, -1, -1},
    {"glDrawArraysInstancedBaseInstance", kDrawArrays, 1, 2, -1, -1, -1, -1},
    {"glMultiDrawArrays", kMultiDrawArrays, 1, 2, -1, 3, -1, -1},
    {"glDrawElements", kDrawElements, -1, 1, -1, -1, 2, 3},
    {"glDrawElementsInstanced", kDrawElements, -1, 1, -1, -1, 2, 3},
    {"glDrawElementsBaseVertex", kDrawElements, -1, 1, 4, -1, 2, 3},
    {"glDrawElementsInstancedBaseVertex", kDrawElements, -1, 1, 5, -1, 2, 3},
    {"glDrawRangeElements", kDrawElements, -1, 3, -1, -1, 4, 5},
    {"glDrawRangeElementsBaseVertex", kDrawElements, -1, 3, 6, -1, 4, 5},
    {"glMultiDrawElements", kMultiDrawElements, -1, 1, -1, 4, 2, 3},
    {"glMultiDrawElementsBaseVertex", kMultiDrawElements, -1, 1, 5, 4, 2, 3},
};

int components(uint32_t format) {
    switch (format) {
    case GL_RED: case GL_GREEN: case GL_BLUE: case GL_ALPHA: case GL_LUMINANCE: case GL_INTENSITY:
    case GL_DEPTH_COMPONENT: case GL_STENCIL_INDEX: case GL_COLOR_INDEX: case GL_RED_INTEGER:
    case GL_GREEN_INTEGER: case GL_BLUE_INTEGER: case GL_ALPHA_INTEGER: return 1;
    case GL_RG: case GL_RG_INTEGER: case GL_LUMINANCE_ALPHA: case GL_DEPTH_STENCIL: return 2;
    case GL_RGB: case GL_BGR: case GL_RGB_INTEGER: case GL_BGR_INTEGER: return 3;
    case GL_RGBA: case GL_BGRA: case GL_RGBA_INTEGER: case GL_BGRA_INTEGER: case GL_ABGR_EXT: return 4;
    default: return 0;
    }
}

// Bytes of one component, or of one pixel for packed types (which count as one component).
int type_bytes(uint32_t type, bool& packed) {
    packed = false;
    switch (type) {
    case GL_UNSIGNED_BYTE: case GL_BYTE: return 1;
    case GL_UNSIGNED_BYTE_3_3_2: case GL_UNSIGNED_BYTE_2_3_3_REV: packed = true; return 1;
    case GL_UNSIGNED_SHORT: case GL_SHORT: case GL_HALF_FLOAT: return 2;
    case GL_UNSIGNED_SHORT_5_6_5: case GL_UNSIGNED_SHORT_5_6_5_REV: case GL_UNSIGNED_SHORT_4_4_4_4:
    case GL_UNSIGNED_SHORT_4_4_4_4_REV: case GL_UNSIGNED_SHORT_5_5_5_1: case GL_UNSIGNED_SHORT_1_5_5_5_REV:
        packed = true; return 2;
    case GL_UNSIGNED_INT: case GL_INT: case GL_FLOAT: case GL_FIXED: return 4;
    case GL_UNSIGNED_INT_8_8_8_8: case GL_UNSIGNED_INT_8_8_8_8_REV: case GL_UNSIGNED_INT_10_10_10_2:
    case GL_UNSIGNED_INT_2_10_10_10_REV: case GL_UNSIGNED_INT_24_8: case GL_UNSIGNED_INT_10F_11F_11F_REV:
    case GL_UNSIGNED_INT_5_9_9_9_REV: packed = true; return 4;
    case GL_DOUBLE: return 8;
    case GL_FLOAT_32_UNSIGNED_INT_24_8_REV: packed = true; return 8;
    default: return 0;
    }
}

int index_bytes(uint32_t type) {
    switch (type) {
    case GL_UNSIGNED_BYTE: return 1;
    case GL_UNSIGNED_SHORT: return 2;
    case GL_UNSIGNED_INT: return 4;
    default: return 0;
    }
}

std::string str(int64_t v) { return std::to_string(v); }

}  // namespace

void Replayer::build_bounds_table() {
    bounds_.assign(kOpcodeCount, 0);
    for (uint8_t k = 0; k < sizeof kFamilies / sizeof kFamilies[0]; ++k) {
        const int op = opcode_by_name(kFamilies[k].name);
        if (op >= 0) bounds_[size_t(op)] = uint8_t(k + 1);
    }
    // Twins (ARB/EXT names of the same command) with the core command's parameters.
    for (uint32_t op = 0; op < kOpcodeCount; ++op) {
        const CommandInfo* info = command_info(op);
        if (!info || bounds_[op] || info->sem.twin == op || info->sem.twin >= kOpcodeCount) continue;
        const CommandInfo* core = command_info(info->sem.twin);
        if (core && core->param_count == info->param_count) bounds_[op] = bounds_[info->sem.twin];
    }
    // Per-instance client arrays hold instances, not vertices (their divisor is not in the
    // stream): instanced draws are not checked against the vertex range.
    for (uint32_t op = 0; op < kOpcodeCount; ++op)
        if (bounds_[op] && std::strstr(command_info(op)->name, "Instanced")) bounds_[op] |= 0x80;
}

void Replayer::check_bounds(const Call& c) {
    const Family& f = kFamilies[(bounds_[c.opcode] & 0x7f) - 1];
    const ReplayLimits& lim = options_.limits;
    auto value = [&c](int i) { return i < 0 ? int64_t(1) : int64_t(int32_t(uint32_t(c.args[size_t(i)].bits))); };
    switch (f.kind) {
    case kImage: {
        const int64_t w = value(f.width), h = value(f.height), d = value(f.depth);
        if (uint64_t(std::max({w, h, d})) > lim.texture_dimension)
            throw ReplayError("image of " + str(w) + "x" + str(h) + "x" + str(d) + " is over the limit texture_dimension=" +
                              str(int64_t(lim.texture_dimension)));
        const PtrRecord& r = c.args[size_t(f.data)].ptr;
        if (r.tag != PtrTag::Data || w <= 0 || h <= 0 || d <= 0) return;  // offsets: Replayer::in
        const auto format = uint32_t(c.args[size_t(f.format)].bits), type = uint32_t(c.args[size_t(f.type)].bits);
        // The slave's unpack state is the master's: the stream replays it.
        GLint alignment = 4, row_length = 0, image_height = 0, skip_pixels = 0, skip_rows = 0, skip_images = 0;
        api_.glGetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
        api_.glGetIntegerv(GL_UNPACK_ROW_LENGTH, &row_length);
        api_.glGetIntegerv(GL_UNPACK_SKIP_PIXELS, &skip_pixels);
        api_.glGetIntegerv(GL_UNPACK_SKIP_ROWS, &skip_rows);
        if (f.depth >= 0) {
            api_.glGetIntegerv(GL_UNPACK_IMAGE_HEIGHT, &image_height);
            api_.glGetIntegerv(GL_UNPACK_SKIP_IMAGES, &skip_images);
        }
        const int64_t align = alignment > 0 ? alignment : 1;
        const int64_t row_pixels = row_length > 0 ? row_length : w;
        const int64_t image_rows = image_height > 0 ? image_height : h;
        const int64_t sp = std::max<int64_t>(skip_pixels, 0), sr = std::max<int64_t>(skip_rows, 0);
        const int64_t si = d > 1 ? std::max<int64_t>(skip_images, 0) : 0;
        int64_t bytes;
        if (type == GL_BITMAP) {
            const int64_t row_bytes = ((row_pixels + 7) / 8 + align - 1) / align * align;
            bytes = (si + d - 1) * image_rows * row_bytes + (sr + h - 1) * row_bytes + (sp + w + 7) / 8;
        } else {
            bool packed = false;
            const int64_t size = type_bytes(type, packed), comps = packed ? 1 : components(format);
            if (!size || !comps) return;  // the driver refuses the format itself
            const int64_t group = comps * size;
            int64_t row_bytes = group * row_pixels;
            if (size < align) row_bytes = (row_bytes + align - 1) / align * align;
            bytes = (si + d - 1) * image_rows * row_bytes + (sr + h - 1) * row_bytes + (sp + w) * group;
        }
        if (bytes > int64_t(r.count))
            throw ReplayError("image of " + str(w) + "x" + str(h) + "x" + str(d) + " reads " + str(bytes) +
                              " bytes, the stream has " + str(r.count));
        return;
    }
    case kBufferSize: {
        const int64_t size = int64_t(c.args[size_t(f.width)].bits);
        if (size < 0 || uint64_t(size) > lim.buffer_bytes)
            throw ReplayError("buffer of " + str(size) + " bytes is over the limit buffer_bytes=" +
                              str(int64_t(lim.buffer_bytes)));
        return;  // the data it reads: Replayer::need (commands.yaml len "size")
    }
    case kDrawArrays:
    case kMultiDrawArrays:
    case kDrawElements:
    case kMultiDrawElements: check_client_draw(c); return;
    case kNone: return;
    }
}

// A draw reads its client arrays over the vertices it names: the range shipped just before it
// must hold them. Indices shipped with the draw are scanned for the largest.
void Replayer::check_client_draw(const Call& c) {
    const Family& f = kFamilies[(bounds_[c.opcode] & 0x7f) - 1];
    SlaveContext* ctx = current_;
    const bool client = ctx && ctx->client_range_pending && !(bounds_[c.opcode] & 0x80);
    if (ctx && ctx->client_arrays_refused) {
        ctx->client_arrays_refused = false;
        throw ReplayError("the client arrays of the draw were refused");
    }
    if (ctx) ctx->client_range_pending = false;
    auto i32 = [&c](int i) { return int64_t(int32_t(uint32_t(c.args[size_t(i)].bits))); };
    auto in_range = [&](int64_t first, int64_t end) {
        if (client && end > first && (first < ctx->client_first || end > ctx->client_end))
            throw ReplayError("the draw reads vertices " + str(first) + ".." + str(end - 1) +
                              ", the client arrays shipped hold " + str(ctx->client_first) + ".." +
                              str(ctx->client_end - 1));
    };
    // Indices shipped as data: enough of them, and their vertices within the client arrays.
    auto indices = [&](const PtrRecord& r, int64_t count, uint32_t type, int64_t base) {
        if (r.tag != PtrTag::Data || count <= 0) return;
        const int bytes = index_bytes(type);
        if (!bytes) return;  // GL_INVALID_ENUM
        if (count * bytes > int64_t(r.count))
            throw ReplayError("the draw reads " + str(count) + " indices, the stream has " + str(r.count / bytes));
        if (!client) return;
        int64_t lo = INT64_MAX, hi = -1;
        const uint64_t restart = (uint64_t(1) << (8 * bytes)) - 1;
        for (int64_t k = 0; k < count; ++k) {
            uint64_t v = 0;
            std::memcpy(&v, r.data + k * bytes, size_t(bytes));
            if (v == restart) continue;  // the fixed primitive-restart index
            lo = std::min(lo, int64_t(v)), hi = std::max(hi, int64_t(v));
        }
        if (hi < 0) return;
        if (lo + base >= ctx->client_first && hi + base < ctx->client_end) return;
        // A program's own restart index may lie outside the arrays.
        if (api_.glIsEnabled(GL_PRIMITIVE_RESTART)) {
            GLint own = 0;
            api_.glGetIntegerv(GL_PRIMITIVE_RESTART_INDEX, &own);
            lo = INT64_MAX, hi = -1;
            for (int64_t k = 0; k < count; ++k) {
                uint64_t v = 0;
                std::memcpy(&v, r.data + k * bytes, size_t(bytes));
                if (v == restart || v == uint64_t(uint32_t(own))) continue;
                lo = std::min(lo, int64_t(v)), hi = std::max(hi, int64_t(v));
            }
            if (hi < 0) return;
        }
        in_range(lo + base, hi + base + 1);
    };
    switch (f.kind) {
    case kDrawArrays: in_range(i32(f.width), i32(f.width) + i32(f.height)); return;
    case kMultiDrawArrays: {
        const PtrRecord &first = c.args[size_t(f.width)].ptr, &count = c.args[size_t(f.height)].ptr;
        const int64_t n = i32(f.format);
        if (first.tag != PtrTag::Data || count.tag != PtrTag::Data) return;
        for (int64_t k = 0; k < n && k < int64_t(first.count) && k < int64_t(count.count); ++k) {
            int32_t a, b;
            std::memcpy(&a, first.data + 4 * k, 4);
            std::memcpy(&b, count.data + 4 * k, 4);
            in_range(a, int64_t(a) + b);
        }
        return;
    }
    case kDrawElements:
        indices(c.args[size_t(f.data)].ptr, i32(f.height), uint32_t(c.args[size_t(f.type)].bits),
                f.depth >= 0 ? i32(f.depth) : 0);
        return;
    case kMultiDrawElements: {
        const PtrRecord& count = c.args[size_t(f.height)].ptr;
        const auto& lists = c.args[size_t(f.data)].strings;
        const PtrRecord& base = f.depth >= 0 ? c.args[size_t(f.depth)].ptr : PtrRecord{};
        const int64_t n = i32(f.format);
        if (n <= 0) return;
        if (count.tag != PtrTag::Data || n > int64_t(count.count) || n > int64_t(lists.size()) ||
            (base.tag == PtrTag::Data && n > int64_t(base.count)))
            throw ReplayError("drawcount " + str(n) + " is more than the stream's counts and index arrays");
        for (int64_t k = 0; k < n; ++k) {
            int32_t m, b = 0;
            std::memcpy(&m, count.data + 4 * k, 4);
            if (base.tag == PtrTag::Data) std::memcpy(&b, base.data + 4 * k, 4);
            indices(lists[size_t(k)], m, uint32_t(c.args[size_t(f.type)].bits), b);
        }
        return;
    }
    default: return;
    }
}

}  // namespace glcast::slave
