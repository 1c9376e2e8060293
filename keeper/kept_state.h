// A keeper's state kept on disk (glcast keeper --state FILE, docs/keeper.md): its newest snapshot,
// written every few seconds at a frame boundary. A keeper started again (killed, crashed, its
// service restarted) comes back from it and the journal's messages since, instead of replaying
// the stream from its start: that took longer the longer the program had ran, and became
// impossible once the journal no longer held the start.
//
// The file is untrusted input when read: a regular file of this user that no one else may write,
// at most `max_bytes`, every message framed and bounded, its count, total and checksum as its
// header says; anything else is refused with the file and what is wrong named.
#pragma once

#include <cstdint>
#include <string>

#include "slave/network_source.h"

namespace glcast::keeper {

// Writes `state` to `path` whole or not at all (a temporary beside it, synced, renamed over it).
bool save_kept_state(const std::string& path, const slave::NetworkSource::State& state, std::string& error);

// Reads what save_kept_state wrote. False with `error` when the file is missing (error empty) or
// refused.
bool load_kept_state(const std::string& path, uint64_t max_bytes, slave::NetworkSource::State& state,
                     std::string& error);

}  // namespace glcast::keeper
