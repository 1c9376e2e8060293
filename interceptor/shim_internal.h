// State private to the shim: per-thread recording state and stream lifetime hooks.
#pragma once

#include <cstdint>
#include <vector>

#include "interceptor/driver_size_queries.h"
#include "master/encoder.h"

namespace glcast {

class Stream;

struct ThreadState {
    int depth = 0;                  // > 0 while inside one of our entry points
    uint32_t opcode = 0;            // the outermost call being recorded
    uint32_t context_id = 0;        // this thread's current context (0: none)
    int es_version = 0;             // its OpenGL ES version times 10 (30: ES 3.0), 0 for desktop GL
    ByteVector scratch;             // the tuple being encoded
    Encoder encoder{scratch};
    ByteVector synthetic;           // a synthetic tuple, encoded while `scratch` is in use
    Encoder synthetic_encoder{synthetic};
    DriverSizeQueries sizes;
};

Stream* stream();          // nullptr when no consumer could be opened
void on_frame_end();       // after a swap's tuple: ends the frame, applies GLCAST_FRAMES
void drain_stream();   // writes what the stream holds so far (interceptor/lifetime.h)
void finish_stream();

}  // namespace glcast
