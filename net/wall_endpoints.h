// A wall's four channels and where each is. The master publishes the stream on one endpoint and
// the others follow from it, so that a display config names one address and port: the journal
// (late joins, gaps) on the next port, the keeper (snapshots for slaves that start late) on the
// one after, the control channel (swap barrier, status) on the one after that. Multicast's side
// channels are TCP on the multicast interface's address; ipc:// channels are sibling paths.
#pragma once

#include <string>

namespace glcast::net {

enum class WallChannel { stream = 0, journal = 1, keeper = 2, control = 3 };

struct WallEndpoints {
    std::string stream, journal, keeper, control;
    bool reachable = false;  // TCP or multicast: machines other than this one can reach the wall
};

// The channels of a wall whose stream is `stream` (tcp://HOST:P, epgm://IF;GROUP:P, ipc://PATH).
// Throws std::invalid_argument naming the endpoint when a TCP or multicast one has no port from
// 1 to 65532 (it and the next three are used), or is of no transport glcast serves.
WallEndpoints wall_endpoints(const std::string& stream);
// One channel of it.
std::string wall_channel(const std::string& stream, WallChannel channel);
// The channels of the master at HOST:PORT (a display config's "master").
WallEndpoints wall_endpoints_at(const std::string& host, int port);
// Where a peer on this machine connects to a bound endpoint: tcp://*:5555 -> tcp://127.0.0.1:5555.
std::string connectable(const std::string& bound);

}  // namespace glcast::net
