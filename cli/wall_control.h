// What `glcast run` serves to its wall's slaves, local and on other machines (docs/wall.md): the
// swap barrier and the tiles' status reports, on one ROUTER socket (an ipc:// path for a wall on
// this machine, TCP with CURVE for one across machines).
//
// Swap barrier: before presenting frame n a tile says "READY TILE n" and waits for "GO n", sent
// once every tile of the wall still counted waits for frame n or a later one. A tile that says
// nothing (no READY, no report of drawing the program live) for kDropSeconds while others wait is
// no longer counted (said once); it is again as soon as it says READY. A tile joining the program
// holds the others only until the wall's first frame: one that joins later (a restarted slave
// catching up from the keeper) draws none of the frames they wait for.
//
// A tracked viewer (docs/immersive.md): "GO n" carries the head pose for frame n + 1.
//
// Clock: "TIME" is answered "TIME SECONDS" (this machine's clock, since the epoch), for glcast
// doctor's offset.
//
// Status: each slave says "STATUS TILE STATE FRAME MASTER_FRAME FPS MBPS LAG RECOVERIES MACHINE"
// once a second (slave/wall_link.h);
// status() gathers the newest of each tile.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "slave/viewer.h"

namespace glcast::cli {

struct TileStatus {
    std::string machine, state;  // state: idle (no program), joining, live; empty: never reported
    uint64_t frame = 0, master_frame = 0, recoveries = 0;
    double fps = 0, mbps = 0;
    int64_t lag = 0;
    double age_seconds = -1;  // since its last report; < 0: never reported
    bool dropped = false;     // from the barrier
};

// The wall side of the barrier: which tiles may present. Pure (time is given), for tests.
class BarrierState {
public:
    BarrierState(std::vector<std::string> tiles, double drop_seconds, double now);
    struct Release {
        std::string tile;
        uint64_t frame;
    };
    // A tile's READY; unknown tiles are ignored (false).
    bool ready(const std::string& tile, uint64_t frame, double now);
    // A sign of life from a tile drawing the program's frames (a status report saying "live",
    // while it is slow or catches up on a gap): it is not dropped while it keeps saying so.
    void heard(const std::string& tile, double now);
    // Who may present now; tiles dropped or taken back since the last call in `dropped`/`back`.
    std::vector<Release> release(double now, std::vector<std::string>* dropped = nullptr);
    bool counted(const std::string& tile) const;
    // Whether a frame has been released: before, every tile is joining the program together and
    // a joining one holds the others (the wall starts on one frame); after, one that joins again
    // (a restarted slave) does not.
    bool started() const { return started_; }
    std::vector<std::string> back;  // taken back since the last look (cleared by the caller)

private:
    struct Tile {
        bool waiting = false, dropped = false;
        uint64_t frame = 0;
        double last_heard = 0;
    };
    std::map<std::string, Tile> tiles_;
    double drop_seconds_;
    bool started_ = false;
};

// Who speaks for each tile: the first peer that names it (its CURVE key on a wall across
// machines, its connection on a local one); another peer may take the name only once the owner
// has said nothing for `takeover_seconds` (a slave that restarted). Without it any peer on the
// channel could answer READY for a live tile and hold the barrier, or report for it. Pure (time
// is given), for tests.
class TileOwners {
public:
    explicit TileOwners(double takeover_seconds) : takeover_seconds_(takeover_seconds) {}
    // True: `peer` speaks for `tile` (now its owner, or still).
    bool speaks_for(const std::string& tile, const std::string& peer, double now);
    uint64_t refused() const { return refused_; }

private:
    struct Owner {
        std::string peer;
        double last = 0;
    };
    std::map<std::string, Owner> owners_;
    double takeover_seconds_;
    uint64_t refused_ = 0;
};

// The head pose that holds at a frame (a recorded track, a tracker's latest); false: none.
using HeadPoseFor = std::function<bool(uint64_t frame, slave::HeadPose& out)>;

class WallControl {
public:
    static constexpr double kDropSeconds = 2;
    static constexpr double kTakeoverSeconds = 5;  // TileOwners
    // Binds `endpoint` (secured as net/security.h says); throws std::runtime_error. With
    // `head_for`, each "GO n" carries the pose for frame n + 1 as " POSE px py pz qw qx qy qz",
    // asked once per frame, so that every tile of a frame gets the same one.
    WallControl(std::string endpoint, std::vector<std::string> tiles, bool barrier, HeadPoseFor head_for = nullptr);
    ~WallControl();
    std::map<std::string, TileStatus> status() const;

private:
    void serve();
    std::string pose_words(uint64_t frame);
    std::map<uint64_t, std::string> pose_words_;  // by frame, the last 64
    std::string endpoint_;
    std::vector<std::string> tiles_;
    bool barrier_;
    HeadPoseFor head_for_;
    std::atomic<bool> stopping_{false};
    mutable std::mutex mutex_;
    std::map<std::string, TileStatus> status_;
    std::map<std::string, std::chrono::steady_clock::time_point> heard_;
    struct Sockets;
    std::unique_ptr<Sockets> sockets_;
    std::thread thread_;
};

}  // namespace glcast::cli
