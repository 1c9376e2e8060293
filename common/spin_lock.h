// A lock for a few nanoseconds of work that one thread almost always takes alone: the open batch
// of the master's stream, which every recorded GL call appends to. Taking it is one atomic
// exchange, giving it back a plain store; std::mutex costs two atomic read-modify-writes and two
// calls into libc (a fifth of a recorded call's cost, bench/call_cost.c under perf).
// A waiter spins briefly, then yields, then sleeps: the holder may itself be waiting for the
// writer thread (a full queue), and a waiter that went on spinning would take the core that the
// holder or the writer needs.
#pragma once

#include <sched.h>
#include <time.h>

#include <atomic>

namespace glcast {

class SpinLock {
public:
    void lock() {
        if (!held_.exchange(true, std::memory_order_acquire)) [[likely]] return;
        lock_contended();
    }
    bool try_lock() { return !held_.load(std::memory_order_relaxed) && !held_.exchange(true, std::memory_order_acquire); }
    void unlock() { held_.store(false, std::memory_order_release); }

private:
    static void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#elif defined(__aarch64__)
        asm volatile("yield");
#endif
    }
    void lock_contended() {
        for (unsigned attempt = 0;; ++attempt) {
            if (try_lock()) return;
            if (attempt < 64) {
                cpu_relax();
            } else if (attempt < 128) {
                sched_yield();
            } else {
                const timespec nap{0, 50'000};  // 50 us
                nanosleep(&nap, nullptr);
            }
        }
    }

    std::atomic<bool> held_{false};
};

}  // namespace glcast
