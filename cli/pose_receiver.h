// The wall's pose socket (docs/immersive.md): a tracker bridge (VRPN, OpenXR, a motion-capture
// SDK) pushes the viewer's head poses to `glcast run`, which hands each frame's pose to every
// tile with the swap barrier's GO (cli/wall_control.h). A PULL socket, secured as the wall's
// other channels are (net/security.h: CURVE with keys, the bridge's key among the authorized).
//
// A message is one pose as JSON (display_configs/head_poses.h). Nothing malformed is applied:
// a refused pose is counted and the first one said; the newest good pose holds until another
// comes, however long the tracker is silent.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "net/security.h"
#include "slave/viewer.h"

namespace glcast::cli {

class PoseReceiver {
public:
    // Binds `endpoint`; throws std::runtime_error naming it and why.
    explicit PoseReceiver(std::string endpoint, const net::Security& security = net::process_security());
    ~PoseReceiver();
    // The newest accepted pose; false before the first.
    bool latest(slave::HeadPose& out) const;
    uint64_t accepted() const { return accepted_; }
    uint64_t refused() const { return refused_; }  // malformed: not JSON, out of bounds, not a unit quaternion, ...
    uint64_t unauthenticated() const;              // peers the ZAP handler turned away
    const std::string& bound() const { return bound_; }  // the endpoint bound (a port "*" resolved)

private:
    void serve();
    std::string endpoint_, bound_;
    struct Sockets;
    std::unique_ptr<Sockets> sockets_;
    mutable std::mutex mutex_;
    bool has_pose_ = false;
    slave::HeadPose pose_;
    std::atomic<uint64_t> accepted_{0}, refused_{0};
    std::atomic<bool> stopping_{false};
    std::thread thread_;
};

}  // namespace glcast::cli
