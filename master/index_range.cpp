// The vertex range an index array reads: pure arithmetic, shared by the shim and tests.
#include <algorithm>

#include "common/gl_headers.h"
#include "master/index_range.h"

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

}  // namespace glcast
