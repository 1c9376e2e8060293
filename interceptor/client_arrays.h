// Client-memory vertex arrays: GL reads them at the draw, so the shim ships them then, over
// exactly the range the draw uses, and only when they changed since the last time (the
// shadow-copy array cache of docs/stream-format.md). Buffer-object arrays travel with the buffer data.
#pragma once

#include <cstdint>

namespace glcast {

class CallScope;

struct DrawRange {
    enum Kind : uint8_t { Arrays, Elements, MultiArrays, MultiElements } kind = Arrays;
    int64_t first = 0, count = 0;        // Arrays
    const void* indices = nullptr;       // Elements: client pointer or buffer offset
    uint32_t type = 0;
    int64_t basevertex = 0;
    int64_t instances = 1;
    const int32_t* firsts = nullptr;     // MultiArrays
    const int32_t* counts = nullptr;
    int64_t drawcount = 0;
    const void* const* index_arrays = nullptr;  // MultiElements
    const int32_t* basevertices = nullptr;

    static DrawRange arrays(int64_t first, int64_t count, int64_t instances);
    static DrawRange elements(const void* indices, uint32_t type, int64_t count, int64_t basevertex,
                              int64_t instances);
    static DrawRange multi_arrays(const int32_t* firsts, const int32_t* counts, int64_t drawcount);
    static DrawRange multi_elements(const void* const* indices, uint32_t type, const int32_t* counts,
                                    int64_t drawcount, const int32_t* basevertices);
};

// Called by the encoder of a vertex-pointer command that got client memory.
void note_client_pointer(uint32_t opcode);
uint32_t thread_state_opcode();

// glLockArraysEXT / glUnlockArraysEXT: locked elements are read even if the draw does not.
void lock_client_arrays(int64_t first, int64_t count);
void unlock_client_arrays();

}  // namespace glcast
