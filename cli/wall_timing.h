// `glcast run --timing FILE` (docs/wall.md, "Time on the wall"): when each frame left the program
// and when each tile received, replayed and presented it, on the run's steady clock, as one JSON
// line a frame:
//
//   {"frame": N, "swap": S, "tiles": {"TILE": {"arrived": A, "replayed": R, "presented": P,
//    "clock_offset": O, "clock_error": E}, ...}}
//
// S is the shim's swap log (GLCAST_TEST_SWAP_LOG, the program's CLOCK_MONOTONIC, which is the
// run's: the program runs on its machine); A, R and P are the tile's own clock moved by O, the
// offset its slave measured over the control channel, true within E (slave/wall_link.h). A frame
// is written once every tile reported it and its swap is known, or kWaitSeconds after it was
// first heard of (then without what did not come: "swap": null, a tile left out); frames a tile
// replayed while catching up are not reported.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace glcast::cli {

struct TileFrameTiming {
    double arrived = 0, replayed = 0, presented = 0, clock_offset = 0, clock_error = 0;
};

// The lines of a slave's "TIMING TILE OFFSET ERROR" message: "FRAME ARRIVED REPLAYED PRESENTED"
// each; false (nothing taken) at the first that is not that, or a time that is not finite.
bool parse_timing_lines(const std::string& lines, double offset, double error,
                        std::vector<std::pair<uint64_t, TileFrameTiming>>& out);

class WallTiming {
public:
    static constexpr double kWaitSeconds = 3;
    static constexpr size_t kMaxHeldFrames = 100000;  // beyond: the oldest is written as it is
    // Throws std::runtime_error when `path` cannot be written.
    WallTiming(const std::string& path, std::string swap_log, std::vector<std::string> tiles);
    ~WallTiming();  // writes every frame still held
    void add(const std::string& tile, uint64_t frame, const TileFrameTiming& t);  // from any thread
    uint64_t written() const { return written_; }

private:
    struct Frame {
        double swap = -1, first_heard = 0;
        std::map<std::string, TileFrameTiming> tiles;
    };
    void read_swaps();
    void write_ready(bool all);
    void write(uint64_t frame, const Frame& f);

    FILE* out_ = nullptr;
    std::string swap_log_;
    FILE* swaps_ = nullptr;
    std::string partial_;  // of the swap log's last line, not yet ended
    std::vector<std::string> tiles_;
    std::mutex mutex_;
    std::map<uint64_t, Frame> frames_;
    std::set<uint64_t> done_;  // frames written (the last kMaxHeldFrames): what comes late is dropped
    std::atomic<uint64_t> written_{0};
    std::atomic<bool> stopping_{false};
    std::mutex wake_mutex_;
    std::condition_variable wake_;
    std::thread thread_;
};

}  // namespace glcast::cli
