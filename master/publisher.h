// The wall's transport on the master (docs/wall.md): every message is published on a ZeroMQ
// PUB socket, and kept in a journal (master/journal.h) that the journal server
// (master/journal_server.h) hands to slaves that join late or lost messages; with lockstep the
// program waits at each frame for the slaves (master/lockstep_barrier.h).
//
// The program is never blocked by a slave: sends do not wait (a subscriber whose queue is full
// loses messages and notices by their sequence numbers), and the journal is served from its
// own thread. Nothing a peer sends may crash, block or grow the program (docs/security.md):
// subscriptions are bounded here, journal requests in master/journal_requests.h.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "master/journal.h"
#include "master/journal_requests.h"
#include "master/lockstep_barrier.h"
#include "master/stream.h"

namespace zmq {
class context_t;
class socket_t;
}  // namespace zmq

namespace glcast {
namespace net {
class Authenticator;
}
class JournalServer;

// A subscription longer than this (a slave's is one byte): its peer is disconnected.
inline constexpr size_t kMaxSubscriptionBytes = 256;
// Subscriptions no slave sends, in all, before the publishing socket is made anew to free them.
inline constexpr size_t kMaxForeignSubscriptionBytes = 64 << 10;
inline constexpr int kSubscriptionHwm = 64;              // subscriptions queued per peer (ZMQ_RCVHWM)
inline constexpr size_t kSubscriptionsPerMessage = 1024;  // read at most this many at each message sent

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
    // Reads up to `at_most` subscription messages: a subscription to everything is taken (what
    // slaves send), others are dropped. Returns how many were taken.
    int take_subscriptions(size_t at_most);
    void make_socket();  // pub_, bound to every endpoint; throws std::runtime_error
    void wait_for_subscribers();

    PublisherOptions options_;
    size_t foreign_subscription_bytes_ = 0;  // subscriptions no slave sends, since pub_ was made
    bool said_foreign_ = false;
    uint64_t remade_sockets_ = 0;
    std::unique_ptr<zmq::context_t> context_;
    std::unique_ptr<net::Authenticator> authenticator_;
    std::unique_ptr<zmq::socket_t> pub_;
    Journal journal_;
    LockstepBarrier lockstep_;
    std::unique_ptr<JournalServer> journal_server_;
    uint64_t sent_ = 0;
    std::atomic<uint64_t> dropped_{0};
    bool closed_ = false;
};

}  // namespace glcast
