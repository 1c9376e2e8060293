// `glcast dump`: one line per call, like `apitrace dump`, and a summary per frame.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "protocol/decoder.h"

namespace glcast {

struct DumpOptions {
    uint64_t first_frame = 0;
    uint64_t last_frame = UINT64_MAX;
    bool calls = true;        // false: frame summaries only
    size_t max_elements = 8;  // array elements shown before "..."
};

struct FrameSummary {
    uint64_t frame = 0, calls = 0, raw_bytes = 0, stored_bytes = 0;
    uint64_t arrays_sent = 0, array_bytes = 0, cache_hits = 0, unserialized = 0, buffer_writes = 0;
};

// Formats one decoded call (without index or newline).
std::string format_call(const Call& call, const DumpOptions& opt);

// Dumps a capture to `out`; throws DecodeError (with the file offset) on bad input.
void dump_capture(CaptureReader& reader, const DumpOptions& opt, FILE* out);

}  // namespace glcast
