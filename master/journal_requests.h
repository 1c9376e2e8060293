// What a peer may ask the master's journal channel (master/journal_server.h), decided without
// sockets so that it is tested and fuzzed alone (tests/fuzz_journal_request.cpp): the request
// forms, why one is dropped, and admission by rate. The channel answers whoever connects, so
// these limits are what stands between a peer and the program; docs/security.md gives the
// reason for each value.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>

namespace glcast {

// The limits of the journal channel; docs/security.md gives the reasons for each value.
namespace journal_limits {
inline constexpr size_t kMaxRequestBytes = 32;     // "SNAPSHOT", "SINCE 18446744073709551615": anything longer is not a request
inline constexpr size_t kMaxFrameBytes = 64;       // ZMQ_MAXMSGSIZE: libzmq disconnects a peer sending more
inline constexpr size_t kMaxIdentityBytes = 255;   // ZMTP's own limit for a routing id
inline constexpr size_t kMaxPartsRead = 8;         // parts drained per message before it is dropped unread
inline constexpr double kSnapshotBurstPerPeer = 4, kSnapshotRatePerPeer = 1;    // requests, per second
inline constexpr double kSnapshotBurstTotal = 32, kSnapshotRateTotal = 16;
inline constexpr double kDoneBurstPerPeer = 256, kDoneRatePerPeer = 2000;
inline constexpr double kDoneBurstTotal = 4096, kDoneRateTotal = 32000;
inline constexpr size_t kMaxPeers = 256;           // identities with rate state at once
inline constexpr size_t kMaxActiveSnapshots = 16;  // journals being sent at once (one per identity)
inline constexpr size_t kMaxPendingSnapshots = 64; // admitted requests waiting for a free slot
inline constexpr int kSendHwm = 64;                // journal messages queued per peer (ZMQ_SNDHWM)
inline constexpr double kStallSeconds = 10;        // a peer that takes nothing this long is no longer served
inline constexpr uint64_t kDoneWindowFrames = 64;  // lockstep: DONE n only for n in [current - 64, current + 1]
inline constexpr double kLockstepDropSeconds = 2;  // a slave that replays nothing this long is not waited for
}  // namespace journal_limits

// snapshot_at ("SNAPSHOT AT n") is a keeper's request (keeper/keeper_service.h): the journal
// drops it.
enum class JournalRequestKind : uint8_t { snapshot, snapshot_at, since, done, invalid };

// Why a request was not acted on; counted, and printed at exit with GLCAST_VERBOSE=1.
enum class JournalDrop : uint8_t {
    none,
    parts,        // not exactly identity + one body part
    identity,     // empty or longer than ZMTP allows
    size,         // body longer than kMaxRequestBytes
    unknown,      // not one of the documented forms
    rate,         // past the peer's or the total token bucket, or too many peers
    busy,         // that identity has a snapshot under way, or every slot and the queue are taken
    no_lockstep,  // DONE without GLCAST_LOCKSTEP: ignored
    window,       // DONE for a frame outside the lockstep window
    count_
};
const char* journal_drop_name(JournalDrop d);

struct JournalRequest {
    JournalRequestKind kind = JournalRequestKind::invalid;
    JournalDrop drop = JournalDrop::none;  // why invalid
    uint64_t frame = 0;                    // DONE n, SNAPSHOT AT n: n
    uint64_t sequence = 0;                 // SINCE n: n
};

// The documented forms, as the ROUTER delivers them: parts[0] the peer's identity, parts[1]
// exactly "SNAPSHOT", "SINCE n" (n a message sequence number, decimal as std::to_string writes
// it) or "DONE n" (at most 2^32-1, a frame number of protocol/format.h). Looks at no byte past a part's size, and at no body
// longer than kMaxRequestBytes.
JournalRequest classify_journal_request(const std::string_view* parts, size_t count);

// Admission by token buckets, per identity and in total, separately for SNAPSHOT and DONE.
// Pure (the time is given) so that it is tested and fuzzed without sockets; its memory is
// bounded by kMaxPeers identities.
class JournalAdmission {
public:
    // now: seconds on a monotonic clock. True: serve it.
    bool admit(std::string_view identity, JournalRequestKind kind, double now);
    size_t peers() const { return peers_.size(); }

private:
    struct Bucket {
        double tokens = -1, last = 0;  // tokens < 0: not started (full)
        bool take(double burst, double rate, double now);
        bool full(double burst, double rate, double now) const;
    };
    struct Peer {
        Bucket snapshot, done;
    };
    Bucket snapshot_total_, done_total_;
    std::unordered_map<std::string, Peer> peers_;
};

}  // namespace glcast
