// The wall's transport on the master (docs/wall.md): every message is published on a ZeroMQ
// PUB socket, and kept in a journal that a ROUTER side channel hands to slaves that join late
// or lost messages (the zguide's Clone pattern: a slave subscribes first, asks for the
// snapshot, then drops live messages it already has).
//
// The program is never blocked by a slave: sends do not wait (a subscriber whose queue is full
// loses messages and notices by their sequence numbers), and the journal is served from its
// own thread.
#pragma once

#include <atomic>
#include <condition_variable>
#include <map>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "master/stream.h"

namespace zmq {
class context_t;
class socket_t;
}  // namespace zmq

namespace glcast {

struct PublisherOptions {
    std::string endpoint;           // PUB: tcp://*:5555, ipc:///tmp/glcast/stream, epgm://...
    std::string snapshot_endpoint;  // ROUTER for the journal; empty: no late join
    size_t journal_limit_bytes = size_t(1) << 30;
    uint64_t drop_every = 0;        // test hook: do not send every Nth message (it stays in the journal)
    int send_hwm = 1000;            // messages queued per subscriber before they are dropped
    int wait_subscribers = 0;       // at start, wait (up to 60 s) until this many slaves subscribed
    int lockstep = 0;               // after each frame, wait (up to 10 s) until this many slaves replayed it
};

class PublisherSink : public MessageSink {
public:
    explicit PublisherSink(PublisherOptions options);  // binds; throws std::runtime_error
    ~PublisherSink() override;
    void write(const std::vector<uint8_t>& message) override;
    void close() override;

    uint64_t dropped() const { return dropped_; }

private:
    void serve_snapshots();

    PublisherOptions options_;
    std::unique_ptr<zmq::context_t> context_;
    std::unique_ptr<zmq::socket_t> pub_;
    std::mutex journal_mutex_;
    std::vector<std::vector<uint8_t>> journal_;
    size_t journal_bytes_ = 0;
    bool journal_complete_ = true;  // false once the limit was passed: late join refused
    uint64_t sent_ = 0;
    std::atomic<uint64_t> dropped_{0};
    std::atomic<bool> stopping_{false};
    std::thread snapshot_thread_;
    std::mutex done_mutex_;
    std::condition_variable done_changed_;
    std::map<uint64_t, int> done_;  // lockstep: frame -> slaves that replayed it
    bool closed_ = false;
};

}  // namespace glcast
