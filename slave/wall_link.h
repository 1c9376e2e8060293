// A slave's side of `glcast run`'s control channel (cli/wall_control.h): the swap barrier and
// the status reports that make run's one status line for the whole wall.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "slave/live_effects.h"
#include "slave/viewer.h"

namespace zmq {
class context_t;
class socket_t;
}  // namespace zmq

namespace glcast::slave {

struct TileReport {
    std::string state = "idle";  // idle (no program), joining, live
    uint64_t frame = 0, master_frame = 0, recoveries = 0;
    double fps = 0, mbps = 0;
    int64_t lag = 0;
    uint64_t effects_version = 0;  // of the live effects it holds (slave/live_effects.h)
};

// This machine's steady clock against the wall run's (NTP's way over the control channel): a
// sample asks "CLOCK TILE t0" at t0 and hears "CLOCK t0 T" at t2; the run's clock read T somewhere
// between, so run = here + T - (t0 + t2) / 2 within (t2 - t0) / 2. Of the last kSamples the one
// with the shortest round trip is used: queueing only lengthens a trip, and the bound stays true.
class ClockOffset {
public:
    static constexpr size_t kSamples = 16;
    void sample(double t0, double run_time, double t2);
    bool known() const { return !samples_.empty(); }
    double offset() const { return best().offset; }  // add to this machine's seconds: the run's
    double error() const { return best().round_trip / 2; }
    size_t samples() const { return samples_.size(); }

private:
    struct Sample {
        double offset, round_trip;
    };
    Sample best() const;
    std::deque<Sample> samples_;
};

// When one frame reached a tile, was replayed and was presented (steady seconds of this machine).
struct FrameTiming {
    uint64_t frame = 0;
    double arrived = 0, replayed = 0, presented = 0;
};

// Seconds of this machine's steady clock (CLOCK_MONOTONIC: the shim's swap log's clock too).
double steady_seconds();

class WallLink {
public:
    // Connects (secured as net/security.h says; throws std::runtime_error when refused).
    WallLink(std::string endpoint, std::string tile, std::string machine);
    ~WallLink();
    // "READY TILE n", then waits at most timeout_ms for "GO n". False on a timeout. A GO may
    // carry the viewer's head pose for frame n + 1 (docs/immersive.md): then `next_head` holds it
    // and `has_head` is true; a pose that is not finite, not within 10 km or not a unit
    // quaternion is not taken.
    bool barrier(uint64_t frame, int timeout_ms, HeadPose* next_head = nullptr, bool* has_head = nullptr);
    // The head pose of the first frame a tile draws, which no GO before it carried: "HEAD TILE n",
    // then at most timeout_ms for "HEAD n" with the pose as a GO carries it. False: no pose (none
    // known, refused as a GO's would be, or no answer in time).
    bool first_head(uint64_t frame, int timeout_ms, HeadPose& head);
    void report(const TileReport& r);  // never waits; a report may be lost
    // A frame's times, sent to the run on its clock (with the offset and its bound) in batches
    // of at most a tenth of a second; held until the clock is known (at most kMaxHeldTimings).
    // Never waits; a batch may be lost.
    void timing(const FrameTiming& t);
    // One clock sample when due (the first kQuickSamples at once, then one a second, and 5 s
    // after one unanswered): waits at most kClockWaitMs. Call where a wait matters least (after
    // a present).
    void sync_clock();
    void flush_timings();  // what is held, now (a program's last frames)
    const ClockOffset& clock() const { return clock_; }
    static constexpr size_t kQuickSamples = 8, kMaxHeldTimings = 4096;
    static constexpr int kClockWaitMs = 100;
    // A small JPEG of what the tile shows, for the dashboard (about once a second); never waits.
    void thumbnail(uint64_t frame, const std::string& jpeg);
    // The newest live effects the wall's run sent (read without waiting, and while barrier()
    // waits); false: none since the last call.
    bool take_effects(LiveEffects& out);
    static constexpr size_t kMaxThumbnailBytes = 64 * 1024;

private:
    // Sends `request` and waits at most timeout_ms for an answer that starts with `answer` and
    // that `accept` takes (given the whole answer).
    bool ask(const std::string& request, const std::string& answer, int timeout_ms,
             const std::function<bool(const std::string&)>& accept);
    void send_timings();
    void heard(const std::string& text);  // a message that is not the answer waited for
    std::string endpoint_, tile_, machine_;
    bool has_effects_ = false;
    LiveEffects effects_;
    ClockOffset clock_;
    double next_sample_ = 0;  // steady seconds
    std::vector<FrameTiming> timings_;  // not yet sent
    double timings_sent_ = 0;
    std::unique_ptr<zmq::context_t> context_;
    std::unique_ptr<zmq::socket_t> socket_;
};

// This machine's name on a wall: GLCAST_MACHINE, else the host name.
std::string machine_name();

}  // namespace glcast::slave
