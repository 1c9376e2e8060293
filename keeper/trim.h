// `glcast trim`: a capture that begins at any frame (docs/keeper.md). The input is replayed on a
// keeper up to frame A, the snapshot of its live state is written, then the input's own messages
// of frames A..B follow unchanged: replayed, the output shows frames A..B of the input, numbered
// from 0.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "keeper/snapshot.h"

namespace glcast {
class MessageSource;
class Stream;
struct Message;
}  // namespace glcast

namespace glcast::slave {
class Backend;
}  // namespace glcast::slave

namespace glcast::keeper {

struct TrimResult {
    uint64_t frames = 0;            // written after the snapshot
    uint64_t replayed_frames = 0;   // replayed by the keeper before it
    uint64_t keeper_errors = 0;     // calls the keeper refused while replaying
    double snapshot_seconds = 0;    // reading the keeper's state back and encoding it
    SnapshotReport snapshot;
};

// Appends each tuple of a decoded message to `out`, and ends the frame there if the message ends
// one (true). Throws DecodeError on a tuple that runs past the payload.
bool append_message(Stream& out, const Message& m);

// Throws DecodeError on a bad input, std::runtime_error when the output cannot be written.
TrimResult trim_capture(MessageSource& in, uint64_t first, uint64_t last, std::unique_ptr<slave::Backend> backend,
                        const std::string& out_path);

}  // namespace glcast::keeper
