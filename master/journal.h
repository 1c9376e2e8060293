// The journal: the newest messages of the stream, up to a size, shared between the program's
// writer thread (which appends) and the journal server (which hands runs of them to slaves that
// join late or lost messages). Messages are immutable and shared, so a send never copies one and
// the lock is held only to append or to take a few pointers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

namespace glcast {

class Journal {
public:
    using Shared = std::shared_ptr<const std::vector<uint8_t>>;

    explicit Journal(size_t limit_bytes) : limit_bytes_(limit_bytes) {}

    // Appends message `sequence` (the next one); the oldest go while the journal is over its
    // limit, the newest always stays. True when this was the first time the stream's start went.
    bool append(Shared message, uint64_t sequence);

    // Where an answer from message `wanted` on, up to `end`, must start: at the key message at or
    // before it (one coded against its predecessor cannot be read alone; the peer unpacks the
    // few before the one it asked for and drops them). A number before first() when that key is
    // no longer held. `end` is end_now() of when the answer started.
    uint64_t start_for(uint64_t wanted, uint64_t end) const;
    uint64_t end_now() const;  // one past the newest message

    // Up to `at_most` messages from `next` on, before `end`, into `out`; their count. False in
    // `held` when `next` is no longer (or never will be) held.
    size_t take(uint64_t next, uint64_t end, Shared* out, size_t at_most, bool& held) const;

private:
    const size_t limit_bytes_;
    mutable std::mutex mutex_;
    std::deque<Shared> messages_;  // first_, first_ + 1, ...
    uint64_t first_ = 0;           // 0 while it holds the whole stream
    size_t bytes_ = 0;
};

}  // namespace glcast
