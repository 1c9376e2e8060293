// What `glcast run` serves to its wall's slaves, local and on other machines (docs/wall.md): the
// swap barrier and the tiles' status reports, on one ROUTER socket (an ipc:// path for a wall on
// this machine, TCP with CURVE for one across machines).
//
// Swap barrier: before presenting frame n a tile says "READY TILE n" and waits for "GO n", sent
// once every tile of the wall still counted waits for frame n or a later one. A tile that says
// nothing (no READY, no report of drawing the program live) for kDropSeconds while others wait is
// no longer counted (said once); it is again from its first READY of a frame the wall has not
// released yet. Until then it is behind (a backlog after a stop) and each of its READYs is
// answered at once, holding no one. A tile joining the program
// holds the others only until the wall's first frame: one that joins later (a restarted slave
// catching up from the keeper) draws none of the frames they wait for.
//
// A tracked viewer (docs/immersive.md): "GO n" carries the head pose for frame n + 1, and
// "HEAD TILE n" asks for frame n's (a tile's first frame).
//
// Clock: "TIME" is answered "TIME SECONDS" (this machine's clock, since the epoch), for glcast
// doctor's offset; "CLOCK TILE T0" is answered "CLOCK T0 SECONDS" (this machine's steady clock,
// the one the program's swaps are timed on), for the slaves' offsets (slave/wall_link.h).
// "TIMING TILE OFFSET ERROR" with a second part of lines "FRAME ARRIVED REPLAYED PRESENTED" (on
// this machine's steady clock): when the tile received, replayed and presented frames, for
// --timing (cli/wall_timing.h).
//
// Status: each slave says "STATUS TILE STATE FRAME MASTER_FRAME FPS MBPS LAG RECOVERIES MACHINE
// EFFECTS_VERSION" once a second (slave/wall_link.h); status() gathers the newest of each tile.
// "THUMB TILE FRAME" with a JPEG as a second part: what the tile shows, for the dashboard.
//
// Live effects (slave/live_effects.h): "CTL effects +snow -shadows" or "CTL param NAME=VALUE",
// from the operator (on a keyed wall the master's key or one of operators/*.pub; on ipc:// or
// loopback without keys, anyone who can connect), is answered "OK ..." or "ERROR ...". The
// change holds from a frame no tile has presented yet: with the swap barrier the frame after the
// one every tile waits for (every tile switches at it), without it the newest frame reported
// plus half a second. Every tile gets "EFFECTS ..." at once, and again while its reports name an
// older version (a tile that joins later).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cli/wall_timing.h"
#include "slave/live_effects.h"
#include "slave/viewer.h"

namespace glcast::net {
struct Security;
}

namespace glcast::cli {

struct TileStatus {
    std::string machine, state;  // state: idle (no program), joining, live; empty: never reported
    uint64_t frame = 0, master_frame = 0, recoveries = 0;
    double fps = 0, mbps = 0;
    int64_t lag = 0;
    uint64_t effects_version = 0;  // of the live effects it holds
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
    uint64_t last_released_ = 0;  // the newest frame released to the tiles counted
};

// Who speaks for each tile: the first peer that names it (its CURVE key on a wall across
// machines, its connection on a local one); another peer may take the name only once the owner
// has said nothing for `takeover_seconds` (a slave that restarted). Without it any peer on the
// channel could answer READY for a live tile and hold the barrier, or report for it. Pure (time
// is given), for tests.
//
// On a keyed wall a tile's name belongs to one key, the one the config and the keys give it
// (`tile_keys`): a peer with another key never speaks for it, whoever named it first.
class TileOwners {
public:
    // `keys`: tile -> the only key ("key Z85") that speaks for it; "" for a tile no key may take.
    explicit TileOwners(double takeover_seconds, std::map<std::string, std::string> keys = {})
        : takeover_seconds_(takeover_seconds), keys_(std::move(keys)) {}
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
    std::map<std::string, std::string> keys_;
    uint64_t refused_ = 0;
};

// On a keyed wall, the peer ("key Z85") that speaks for each tile of `tiles` (name, machine): a tile
// of this machine (`here`) this machine's own client key (its local slaves connect with it), a
// tile of another machine the key of authorized/MACHINE.pub. A tile whose machine has no such
// file gets "" (no key may speak for it) and is named in `unbound`. Without keys: empty (a
// local channel; its first peer speaks for a tile).
std::map<std::string, std::string> tile_keys(const std::vector<std::pair<std::string, std::string>>& tiles,
                                             const std::string& here, const net::Security& security,
                                             std::vector<std::string>* unbound = nullptr);

// The head pose that holds at a frame (a recorded track, a tracker's latest); false: none.
using HeadPoseFor = std::function<bool(uint64_t frame, slave::HeadPose& out)>;

class WallControl {
public:
    static constexpr double kDropSeconds = 2;
    static constexpr double kTakeoverSeconds = 5;  // TileOwners
    static constexpr size_t kMaxReplyBytes = 4096;  // what glcast ctl reads of an answer
    // Binds `endpoint` (secured as net/security.h says); throws std::runtime_error. With
    // `head_for`, each "GO n" carries the pose for frame n + 1 as " POSE px py pz qw qx qy qz",
    // asked once per frame, so that every tile of a frame gets the same one; "HEAD TILE n" (a
    // tile's first frame, which no GO precedes) is answered "HEAD n" with the pose of frame n.
    // `keys`: tile_keys' binding of tiles to the keys that speak for them.
    WallControl(std::string endpoint, std::vector<std::string> tiles, bool barrier, HeadPoseFor head_for = nullptr,
                std::map<std::string, std::string> keys = {});
    ~WallControl();
    std::map<std::string, TileStatus> status() const;

    // The wall's passes now, and the change an operator asks for (`glcast ctl`'s words, as
    // LiveEffects::change takes them) from any thread (the dashboard): waits until the control
    // channel has sent it to every tile. `reply` is what CTL answers ("OK ..." or "ERROR ...").
    slave::LiveEffects effects() const;
    bool change_effects(const std::string& request, std::string& reply);
    // The newest thumbnail of a tile (a JPEG) and its frame; false: none yet.
    bool thumbnail(const std::string& tile, std::string& jpeg, uint64_t& frame) const;
    // What the tiles started with: the first state, version 0.
    void set_started_effects(const slave::LiveEffects& e);
    // Where the tiles' frame times go (glcast run --timing), from the serve thread.
    using TimingSink = std::function<void(const std::string& tile, uint64_t frame, const TileFrameTiming& t)>;
    void set_timing_sink(TimingSink sink);

private:
    void serve();
    // In the serve thread: a request checked, scheduled and sent to every tile.
    bool apply_request(const std::string& request, std::string& reply);
    uint64_t switch_frame() const;
    void send_effects(const std::string& identity);
    std::string pose_words(uint64_t frame);
    std::string pose_text(uint64_t frame);
    std::map<uint64_t, std::string> pose_words_;  // by frame, the last 64
    std::string endpoint_;
    std::vector<std::string> tiles_;
    std::map<std::string, std::string> keys_;  // tile_keys
    bool barrier_;
    HeadPoseFor head_for_;
    std::atomic<bool> stopping_{false};
    mutable std::mutex mutex_;
    std::map<std::string, TileStatus> status_;
    std::map<std::string, std::chrono::steady_clock::time_point> heard_;
    struct Thumbnail {
        std::string jpeg;
        uint64_t frame = 0;
    };
    std::map<std::string, Thumbnail> thumbnails_;
    TimingSink timing_sink_;
    slave::LiveEffects effects_;
    uint64_t last_released_ = 0;  // the swap barrier's newest GO
    bool released_any_ = false;
    std::map<std::string, std::string> identity_of_;  // tile -> the ROUTER identity of its owner (serve thread)
    // Requests of other threads for the serve thread, and their replies.
    struct Request {
        std::string words, reply;
        bool done = false, ok = false;
    };
    std::vector<std::shared_ptr<Request>> requests_;
    std::condition_variable requests_done_;
    struct Sockets;
    std::unique_ptr<Sockets> sockets_;
    std::thread thread_;
};

}  // namespace glcast::cli
