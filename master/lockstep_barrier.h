// Lockstep (glcast run --lockstep): the program's writer thread holds after each frame until
// every slave said it replayed that frame ("DONE n" on the journal channel). A slave silent for
// kLockstepDropSeconds is no longer waited for, so a dead tile never stops the program; it is
// waited for again once it replays a frame. Memory is bounded by the window of frames a DONE may
// name and the number of slaves.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <vector>

#include "master/journal_requests.h"

namespace glcast {

class LockstepBarrier {
public:
    LockstepBarrier(int slaves, bool verbose) : slaves_(slaves), waited_(slaves), verbose_(verbose) {}

    bool enabled() const { return slaves_ > 0; }
    // The writer thread, at every message: the newest frame written (the window's top).
    void writing(uint32_t frame);
    // The writer thread, after the message that ends `frame`: waits for the slaves.
    void wait_for(uint32_t frame);
    // The journal server: slave `who` (a hash of its identity) replayed `frame`. A drop reason
    // when the frame is outside the window.
    JournalDrop replayed(uint64_t frame, size_t who);

private:
    const int slaves_;
    std::atomic<uint64_t> frame_{0};
    std::mutex mutex_;
    std::condition_variable changed_;
    std::map<uint64_t, std::vector<size_t>> done_;  // frame -> the identities that replayed it
    uint64_t floor_ = 0;                            // frames below were waited for already
    int waited_;                                    // slaves not dropped
    const bool verbose_;
};

}  // namespace glcast
