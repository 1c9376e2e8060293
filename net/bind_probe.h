// Whether this machine can listen where a wall would, before anything of the wall starts: a port
// held by another process is otherwise found by the program's shim (which then publishes nothing,
// and the program runs unseen) or by a slave after its waits.
#pragma once

#include <string>

namespace glcast::net {

// Throws std::runtime_error naming `role` (the stream, the journal, ...), the endpoint and why,
// unless a ZeroMQ socket can bind `endpoint` now (bound and released at once). Only tcp://
// endpoints are probed: an ipc:// path is the caller's own, a multicast group is not bound.
void check_can_bind(const std::string& endpoint, const std::string& role);

}  // namespace glcast::net
