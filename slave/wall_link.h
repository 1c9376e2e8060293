// A slave's side of `glcast run`'s control channel (cli/wall_control.h): the swap barrier and
// the status reports that make run's one status line for the whole wall.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

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
};

class WallLink {
public:
    // Connects (secured as net/security.h says; throws std::runtime_error when refused).
    WallLink(std::string endpoint, std::string tile, std::string machine);
    ~WallLink();
    // "READY TILE n", then waits at most timeout_ms for "GO n". False on a timeout.
    bool barrier(uint64_t frame, int timeout_ms);
    void report(const TileReport& r);  // never waits; a report may be lost

private:
    std::string endpoint_, tile_, machine_;
    std::unique_ptr<zmq::context_t> context_;
    std::unique_ptr<zmq::socket_t> socket_;
};

// This machine's name on a wall: GLCAST_MACHINE, else the host name.
std::string machine_name();

}  // namespace glcast::slave
