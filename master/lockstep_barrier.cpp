#include "master/lockstep_barrier.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace glcast {

void LockstepBarrier::writing(uint32_t frame) {
    if (frame > frame_.load(std::memory_order_relaxed)) frame_.store(frame, std::memory_order_relaxed);
}

void LockstepBarrier::wait_for(uint32_t frame) {
    using journal_limits::kLockstepDropSeconds;
    std::unique_lock lock(mutex_);
    auto replayed = [&] {
        auto it = done_.find(frame);
        return it == done_.end() ? 0 : int(it->second.size());
    };
    if (!changed_.wait_for(lock, std::chrono::duration<double>(kLockstepDropSeconds),
                           [&] { return replayed() >= waited_; })) {
        std::fprintf(stderr, "glcast: lockstep: frame %u replayed by %d of %d slaves within %g s; going on without "
                             "the rest until they are back\n",
                     frame, replayed(), waited_, kLockstepDropSeconds);
        waited_ = replayed();
    }
    done_.erase(done_.begin(), done_.upper_bound(frame));
    floor_ = std::max<uint64_t>(floor_, uint64_t(frame) + 1);
}

JournalDrop LockstepBarrier::replayed(uint64_t frame, size_t who) {
    using journal_limits::kDoneWindowFrames;
    const uint64_t current = frame_.load(std::memory_order_relaxed);
    std::lock_guard lock(mutex_);
    const uint64_t low = std::max(floor_, current > kDoneWindowFrames ? current - kDoneWindowFrames : 0);
    if (frame < low || frame > current + 1) return JournalDrop::window;
    auto& slaves = done_[frame];
    // Distinct identities, at most the number waited for: one peer cannot stand for all.
    if (int(slaves.size()) < slaves_ && std::find(slaves.begin(), slaves.end(), who) == slaves.end())
        slaves.push_back(who);
    if (int(slaves.size()) > waited_) {  // a slave is back (or came at last)
        waited_ = int(slaves.size());
        if (verbose_) std::fprintf(stderr, "glcast: lockstep: waiting for %d slaves again\n", waited_);
    }
    changed_.notify_all();
    return JournalDrop::none;
}

}  // namespace glcast
