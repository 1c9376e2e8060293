// The vertex range an index array reads: pure arithmetic, used by the shim's client arrays
// (interceptor/client_arrays.cpp) and by tests.
#pragma once

#include <cstdint>

namespace glcast {

// Computes [min, max] of an index array (after base vertex), skipping the primitive-restart
// index; false when no index is drawn. Exposed for tests.
bool index_range(const void* indices, uint32_t type, int64_t count, int64_t basevertex,
                 bool restart, uint32_t restart_index, int64_t& lo, int64_t& hi);

}  // namespace glcast
