// `glcast keeper`: the state server of a wall (docs/keeper.md; the ZeroMQ guide's Clone
// pattern). It subscribes to the master's stream like a slave, replays it on a headless context
// of its own, and answers "SNAPSHOT" on a ROUTER socket at the next frame boundary with the
// snapshot of its live state: "STATE <sequence> <frame>" (the master's last message the
// snapshot covers, and the frame that follows it), one part per message of the snapshot, then
// "END"; "SNAPSHOT AT n", the same at the first boundary at or after frame n (a recording that
// starts at frame n). A slave replays those, then the journal's messages after <sequence>, then the live
// stream. What a join costs depends on the live state, not on how long the program has run; with
// --state, so does what the keeper's own restart costs.
#pragma once

#include <cstdint>
#include <string>

namespace glcast::keeper {

struct KeeperOptions {
    std::string connect;   // the master's stream
    std::string journal;   // the master's journal: the stream's start, and gaps ("SINCE n")
    std::string bind;      // where slaves ask for snapshots
    std::string backend = "egl";
    int wait_seconds = 86400;  // for the master's first message
    bool verbose = false;      // a line per snapshot served
    // Its state kept on disk (keeper/kept_state.h): written every `state_every_seconds` at a frame
    // boundary, started from when it is there, removed when the program ends. Empty: none.
    std::string state_path;
    int state_every_seconds = 10;
};

// Runs until the program ends (0) or the keeper cannot go on (1, said on stderr).
int run_keeper(const KeeperOptions& options);

}  // namespace glcast::keeper
