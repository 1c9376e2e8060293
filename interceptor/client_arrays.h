// Client-memory vertex arrays: GL reads them at the draw, so the shim ships them then, over
// exactly the range the draw uses, and only when they changed since the last time (the
// shadow-copy array cache of docs/stream-format.md). Buffer-object arrays travel with the buffer data.
#pragma once

#include <cstdint>

#include "protocol/draw_range.h"

namespace glcast {

class CallScope;


// Called by the encoder of a vertex-pointer command that got client memory.
void note_client_pointer(uint32_t opcode);
uint32_t thread_state_opcode();

// glLockArraysEXT / glUnlockArraysEXT: locked elements are read even if the draw does not.
void lock_client_arrays(int64_t first, int64_t count);
void unlock_client_arrays();

}  // namespace glcast
