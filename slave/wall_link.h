// A slave's side of `glcast run`'s control channel (cli/wall_control.h): the swap barrier and
// the status reports that make run's one status line for the whole wall.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

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
    // A small JPEG of what the tile shows, for the dashboard (about once a second); never waits.
    void thumbnail(uint64_t frame, const std::string& jpeg);
    // The newest live effects the wall's run sent (read without waiting, and while barrier()
    // waits); false: none since the last call.
    bool take_effects(LiveEffects& out);
    static constexpr size_t kMaxThumbnailBytes = 64 * 1024;

private:
    bool ask(const std::string& request, const std::string& answer, int timeout_ms, HeadPose* head, bool* has_head);
    void heard(const std::string& text);  // a message that is not the answer waited for
    std::string endpoint_, tile_, machine_;
    bool has_effects_ = false;
    LiveEffects effects_;
    std::unique_ptr<zmq::context_t> context_;
    std::unique_ptr<zmq::socket_t> socket_;
};

// This machine's name on a wall: GLCAST_MACHINE, else the host name.
std::string machine_name();

}  // namespace glcast::slave
