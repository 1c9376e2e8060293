// A snapshot of live state (docs/keeper.md): the ordinary tuples that recreate, on a slave that
// has seen nothing, everything the messages after a frame boundary can depend on. It is read
// from a keeper: a Replayer that replayed the stream up to that boundary on a headless context
// of its own (no tile, no injected passes), whose objects hold what the master's hold, contents
// made by rendering included. Names are the master's, read through the keeper's name maps, so
// the live messages after the snapshot map exactly as before.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace glcast::slave {
class Replayer;
}  // namespace glcast::slave

namespace glcast::keeper {

class KeptCalls;

struct SnapshotReport {
    uint64_t tuples = 0, bytes = 0;
    uint64_t contexts = 0, objects = 0, lists = 0;
    // What the snapshot could not hold, by name ("context 2: attribute stack depth 1"): state
    // no query reaches. A slave that joins from such a snapshot may draw differently.
    std::vector<std::string> missing;
};

// Receives each tuple of the snapshot in order (Stream::append for a capture).
using TupleOut = std::function<void(const uint8_t* tuple, size_t bytes)>;

// Writes the snapshot of `keeper`'s live state. The keeper's GL state is left as it was.
SnapshotReport write_snapshot(slave::Replayer& keeper, const KeptCalls& kept, const TupleOut& out);

}  // namespace glcast::keeper
