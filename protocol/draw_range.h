// The vertices and instances a draw reads from client-memory vertex arrays, computed the same
// way by the shim, which ships exactly that range before the draw's tuple, and by the slave,
// which refuses a draw that reads outside what was shipped (docs/stream-format.md, "Client
// arrays"). Built from commands.yaml `draws:` by the generated code of both sides.
#pragma once

#include <cstdint>

namespace glcast {

class SizeQueries;

struct DrawRange {
    enum Kind : uint8_t { Arrays, Elements, MultiArrays, MultiElements } kind = Arrays;
    int64_t first = 0, count = 0;        // Arrays
    const void* indices = nullptr;       // Elements: client pointer, or offset into the element buffer
    uint32_t type = 0;
    int64_t basevertex = 0;
    int64_t instances = 1;
    int64_t baseinstance = 0;
    const int32_t* firsts = nullptr;     // MultiArrays
    const int32_t* counts = nullptr;
    int64_t drawcount = 0;
    const void* const* index_arrays = nullptr;  // MultiElements
    const int32_t* basevertices = nullptr;

    static DrawRange arrays(int64_t first, int64_t count, int64_t instances, int64_t baseinstance);
    static DrawRange elements(const void* indices, uint32_t type, int64_t count, int64_t basevertex,
                              int64_t instances, int64_t baseinstance);
    static DrawRange multi_arrays(const int32_t* firsts, const int32_t* counts, int64_t drawcount);
    static DrawRange multi_elements(const void* const* indices, uint32_t type, const int32_t* counts,
                                    int64_t drawcount, const int32_t* basevertices);
};

// [lo, hi] of the per-vertex elements the draw reads; false when it reads none. Indices in an
// element buffer are read back through `sz` (SizeQueries::read_buffer), the primitive-restart
// index honoured; the caller has made sure the indices lie in what it may read.
bool vertex_range(const DrawRange& r, SizeQueries& sz, int64_t& lo, int64_t& hi);

// The element a per-instance array (divisor > 0) is read at for the draw's last instance;
// -1 when it reads none.
int64_t last_instance_element(const DrawRange& r, uint32_t divisor);

// Computes [min, max] of an index array (after base vertex), skipping the primitive-restart
// index; false when no index is drawn. Exposed for tests.
bool index_range(const void* indices, uint32_t type, int64_t count, int64_t basevertex,
                 bool restart, uint32_t restart_index, int64_t& lo, int64_t& hi);

}  // namespace glcast
