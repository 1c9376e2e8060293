// The vertex range a draw reads (protocol/draw_range.h): the shim and the slave share it.
#include "protocol/draw_range.h"

#include <algorithm>
#include <vector>

#include "common/gl_headers.h"
#include "protocol/size_queries.h"

namespace glcast {
namespace {

template <class T>
void scan(const T* idx, int64_t count, int64_t basevertex, bool restart, uint32_t restart_index, int64_t& lo,
          int64_t& hi, bool& any) {
    for (int64_t i = 0; i < count; ++i) {
        if (restart && idx[i] == T(restart_index)) continue;
        const int64_t v = int64_t(idx[i]) + basevertex;
        lo = any ? std::min(lo, v) : v;
        hi = any ? std::max(hi, v) : v;
        any = true;
    }
}

int index_bytes(uint32_t type) {
    return type == GL_UNSIGNED_BYTE ? 1 : type == GL_UNSIGNED_SHORT ? 2 : type == GL_UNSIGNED_INT ? 4 : 0;
}

}  // namespace

bool index_range(const void* indices, uint32_t type, int64_t count, int64_t basevertex, bool restart,
                 uint32_t restart_index, int64_t& lo, int64_t& hi) {
    bool any = false;
    switch (type) {
    case GL_UNSIGNED_BYTE: scan(static_cast<const uint8_t*>(indices), count, basevertex, restart, restart_index, lo, hi, any); break;
    case GL_UNSIGNED_SHORT: scan(static_cast<const uint16_t*>(indices), count, basevertex, restart, restart_index, lo, hi, any); break;
    case GL_UNSIGNED_INT: scan(static_cast<const uint32_t*>(indices), count, basevertex, restart, restart_index, lo, hi, any); break;
    default: return false;
    }
    return any;
}

DrawRange DrawRange::arrays(int64_t first, int64_t count, int64_t instances, int64_t baseinstance) {
    DrawRange r;
    r.kind = Arrays;
    r.first = first;
    r.count = count;
    r.instances = instances;
    r.baseinstance = baseinstance;
    return r;
}

DrawRange DrawRange::elements(const void* indices, uint32_t type, int64_t count, int64_t basevertex,
                              int64_t instances, int64_t baseinstance) {
    DrawRange r;
    r.kind = Elements;
    r.indices = indices;
    r.type = type;
    r.count = count;
    r.basevertex = basevertex;
    r.instances = instances;
    r.baseinstance = baseinstance;
    return r;
}

DrawRange DrawRange::multi_arrays(const int32_t* firsts, const int32_t* counts, int64_t drawcount) {
    DrawRange r;
    r.kind = MultiArrays;
    r.firsts = firsts;
    r.counts = counts;
    r.drawcount = drawcount;
    return r;
}

DrawRange DrawRange::multi_elements(const void* const* indices, uint32_t type, const int32_t* counts,
                                    int64_t drawcount, const int32_t* basevertices) {
    DrawRange r;
    r.kind = MultiElements;
    r.index_arrays = indices;
    r.type = type;
    r.counts = counts;
    r.drawcount = drawcount;
    r.basevertices = basevertices;
    return r;
}

bool vertex_range(const DrawRange& r, SizeQueries& sz, int64_t& lo, int64_t& hi) {
    switch (r.kind) {
    case DrawRange::Arrays:
        if (r.count <= 0 || r.instances <= 0) return false;
        lo = r.first;
        hi = r.first + r.count - 1;
        return true;
    case DrawRange::MultiArrays: {
        bool any = false;
        for (int64_t i = 0; r.firsts && r.counts && i < r.drawcount; ++i) {
            if (r.counts[i] <= 0) continue;
            lo = any ? std::min<int64_t>(lo, r.firsts[i]) : r.firsts[i];
            hi = any ? std::max<int64_t>(hi, int64_t(r.firsts[i]) + r.counts[i] - 1) : int64_t(r.firsts[i]) + r.counts[i] - 1;
            any = true;
        }
        return any;
    }
    case DrawRange::MultiElements: {
        bool any = false;
        for (int64_t i = 0; r.index_arrays && r.counts && i < r.drawcount; ++i) {
            int64_t l = 0, h = -1;
            const DrawRange one = DrawRange::elements(r.index_arrays[i], r.type, r.counts[i],
                                                      r.basevertices ? r.basevertices[i] : 0, 1, 0);
            if (!vertex_range(one, sz, l, h)) continue;
            lo = any ? std::min(lo, l) : l;
            hi = any ? std::max(hi, h) : h;
            any = true;
        }
        return any;
    }
    case DrawRange::Elements: {
        const int bytes = index_bytes(r.type);
        if (r.count <= 0 || r.instances <= 0 || !bytes) return false;
        bool restart = false;
        uint32_t restart_index = 0;
        if (sz.enabled(GL_PRIMITIVE_RESTART_FIXED_INDEX)) {
            restart = true;
            restart_index = bytes == 1 ? 0xFFu : bytes == 2 ? 0xFFFFu : 0xFFFFFFFFu;
        } else if (sz.enabled(GL_PRIMITIVE_RESTART)) {
            restart = true;
            restart_index = uint32_t(sz.driver_count(GL_PRIMITIVE_RESTART_INDEX));
        }
        if (!sz.bound(GL_ELEMENT_ARRAY_BUFFER_BINDING))
            return r.indices && index_range(r.indices, r.type, r.count, r.basevertex, restart, restart_index, lo, hi);
        // Indices in a buffer object, vertices in client memory: read the indices back.
        std::vector<uint8_t> tmp(size_t(r.count) * size_t(bytes));
        if (!sz.read_buffer(GL_ELEMENT_ARRAY_BUFFER, int64_t(reinterpret_cast<uintptr_t>(r.indices)), int64_t(tmp.size()),
                            tmp.data()))
            return false;
        return index_range(tmp.data(), r.type, r.count, r.basevertex, restart, restart_index, lo, hi);
    }
    }
    return false;
}

int64_t last_instance_element(const DrawRange& r, uint32_t divisor) {
    if (!divisor) return -1;
    int64_t instances = 0;
    switch (r.kind) {
    case DrawRange::Arrays: instances = r.count > 0 ? r.instances : 0; break;
    case DrawRange::Elements: instances = r.count > 0 ? r.instances : 0; break;
    default: instances = 1; break;
    }
    if (instances <= 0) return -1;
    return (instances - 1) / divisor + std::max<int64_t>(r.baseinstance, 0);
}

}  // namespace glcast
