// The wall's transport on the master (docs/wall.md): every message is published on a ZeroMQ
// PUB socket, and kept in a journal that a ROUTER side channel hands to slaves that join late
// or lost messages (the zguide's Clone pattern: a slave subscribes first, asks for the
// snapshot, then drops live messages it already has).
//
// The program is never blocked by a slave: sends do not wait (a subscriber whose queue is full
// loses messages and notices by their sequence numbers), and the journal is served from its
// own thread. The journal channel answers whoever connects, so nothing a peer sends on it may
// crash, block or grow the program (docs/security.md): requests are classified by a pure
// function (fuzzed: tests/fuzz_journal_request.cpp), admitted by rate, and answered from
// shared immutable messages without copies.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <vector>

#include "master/stream.h"

namespace zmq {
class context_t;
class socket_t;
}  // namespace zmq

namespace glcast {
namespace net {
class Authenticator;
}

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
inline constexpr uint64_t kDoneWindowFrames = 64;
inline constexpr double kLockstepDropSeconds = 2;  // a slave that replays nothing this long is not waited for  // lockstep: DONE n only for n in [current - 64, current + 1]
}  // namespace journal_limits

// A subscription longer than this (a slave's is one byte): its peer is disconnected.
inline constexpr size_t kMaxSubscriptionBytes = 256;
// Subscriptions no slave sends, in all, before the publishing socket is made anew to free them.
inline constexpr size_t kMaxForeignSubscriptionBytes = 64 << 10;
inline constexpr int kSubscriptionHwm = 64;              // subscriptions queued per peer (ZMQ_RCVHWM)
inline constexpr size_t kSubscriptionsPerMessage = 1024;  // read at most this many at each message sent

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

struct PublisherOptions {
    std::string endpoint;           // PUB: tcp://*:5555, ipc:///tmp/glcast/stream, epgm://...; several: a,b
    std::string snapshot_endpoint;  // ROUTER for the journal; empty: no late join
    // The journal keeps the newest messages up to this many bytes: all of a short run (late
    // join by replaying it), the recent past of a long one (a keeper's or slave's gap, "SINCE").
    size_t journal_limit_bytes = size_t(64) << 20;
    uint64_t drop_every = 0;        // test hook: do not send every Nth message (it stays in the journal)
    int send_hwm = 1000;            // messages queued per subscriber before they are dropped
    int wait_subscribers = 0;       // at start, wait (up to 60 s) until this many slaves subscribed
    bool verbose = false;           // say when the journal starts losing its start, and its counts at exit
    int lockstep = 0;               // after each frame, wait until this many slaves replayed it (a silent one is
                                    // dropped after kLockstepDropSeconds, and waited for again once it is back)
};

class PublisherSink : public MessageSink {
public:
    explicit PublisherSink(PublisherOptions options);  // binds; throws std::runtime_error
    ~PublisherSink() override;
    void write(const std::vector<uint8_t>& message) override;
    void close() override;

    uint64_t dropped() const { return dropped_; }

private:
    using Shared = std::shared_ptr<const std::vector<uint8_t>>;
    struct Session {
        std::string identity;
        bool whole = true;         // SNAPSHOT: from message 0; else SINCE `next`
        uint64_t next = 0, end = 0;  // sequence numbers still to send
        double last_progress = 0;
        bool started = false;
    };
    // Reads up to `at_most` subscription messages: a subscription to everything is taken (what
    // slaves send), others are dropped. Returns how many were taken.
    int take_subscriptions(size_t at_most);
    void make_socket();  // pub_, bound to every endpoint; throws std::runtime_error
    void serve_snapshots();
    void handle_request(const std::string_view* parts, size_t count, double now);
    bool serve(zmq::socket_t& router, Session& s, double now);  // true: finished or given up

    PublisherOptions options_;
    bool verbose_ = false;
    size_t foreign_subscription_bytes_ = 0;  // subscriptions no slave sends, since pub_ was made
    bool said_foreign_ = false;
    uint64_t remade_sockets_ = 0;
    std::unique_ptr<zmq::context_t> context_;
    std::unique_ptr<net::Authenticator> authenticator_;
    std::unique_ptr<zmq::socket_t> pub_;
    // Held by write() (the program's writer thread) and the serving thread only to append or to
    // take a few shared pointers: never while sending.
    std::mutex journal_mutex_;
    std::deque<Shared> journal_;    // messages journal_first_, journal_first_ + 1, ...
    uint64_t journal_first_ = 0;   // 0 while it holds the whole stream
    size_t journal_bytes_ = 0;
    uint64_t sent_ = 0;
    std::atomic<uint64_t> dropped_{0};
    std::atomic<uint64_t> frame_{0};  // the frame being written: the lockstep window's top
    std::atomic<bool> stopping_{false};
    std::thread snapshot_thread_;
    // Serving thread only.
    JournalAdmission admission_;
    std::deque<Session> active_, pending_;
    uint64_t drops_[size_t(JournalDrop::count_)] = {};
    uint64_t served_ = 0, stalled_ = 0;
    std::mutex done_mutex_;
    std::condition_variable done_changed_;
    std::map<uint64_t, std::vector<size_t>> done_;  // lockstep: frame -> hashes of the identities that replayed it
    uint64_t done_floor_ = 0;                       // frames below were waited for already
    int lockstep_waited_ = options_.lockstep;       // slaves not dropped (see write())
    bool closed_ = false;
};

}  // namespace glcast
