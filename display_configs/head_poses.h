// Head poses of an immersive wall's viewer (docs/immersive.md): one pose as JSON, as a tracker
// bridge sends it on the wall's pose socket, and a recorded track of them (JSON lines, each
// pose holding from its frame on), as `glcast run --head-poses` and `glcast replay
// --head-poses` play it.
//
//   {"position": [x, y, z], "orientation": [w, x, y, z]}             metres, a unit quaternion
//   {"frame": N, "position": [...], "orientation": [...]}            a line of a track
//   ... "eye_separation": 0.07                                       (optional) the eyes' distance from now on
//
// Nothing malformed is ever applied: a bad pose is refused with what is wrong, a bad track is
// refused whole with its line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "slave/viewer.h"

namespace glcast::slave {

constexpr size_t kMaxPoseBytes = 4096;             // one pose message or line
constexpr size_t kMaxPoseTrackBytes = 64u << 20;   // a track file

// Parses one pose; `frame` (may be null) gets its "frame" when it has one ("frame" is then
// required), `time` (may be null) its optional "time" in seconds. False with `error` set.
bool parse_head_pose(const std::string& text, HeadPose& out, uint64_t* frame, double* time, std::string& error);

class HeadPoseTrack {
public:
    // Reads a JSON-lines file (blank lines and lines starting with # skipped); frames must
    // increase. False with "PATH: line N: what" in `error`, the track left empty.
    bool load(const std::string& path, std::string& error);
    // The pose that holds at `frame`: the last one stamped at or before it; null before the first.
    const HeadPose* at(uint64_t frame) const;
    size_t size() const { return poses_.size(); }

private:
    struct Stamped {
        uint64_t frame;
        HeadPose pose;
    };
    std::vector<Stamped> poses_;
};

}  // namespace glcast::slave
