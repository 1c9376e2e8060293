// A slave's subscription to a live master (docs/wall.md; the Clone pattern of the ZeroMQ guide): subscribe
// first, then ask the master's journal for every message so far, replay that, and go on with
// the live messages after it. A gap in the sequence numbers (a dropped message, a slave that
// fell behind) makes the slave start over from a fresh snapshot.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "protocol/decoder.h"

namespace zmq {
class context_t;
class socket_t;
}  // namespace zmq

namespace glcast::slave {

class NetworkSource : public MessageSource {
public:
    NetworkSource(std::string endpoint, std::string journal_endpoint, int wait_seconds);
    ~NetworkSource() override;

    bool next(Message& m) override;  // false when the program has ended

    // Called before the snapshot of a recovery is replayed: the replay must start from nothing.
    std::function<void()> on_restart;

    bool live() const { return live_; }              // the last message came from the live stream
    // ... or was the last of a snapshot: the newest frame the master has, which a master in
    // lockstep waits for (the live message that showed a gap is in the snapshot, not replayed again)
    bool caught_up() const { return live_ || snapshot_.empty(); }
    // Swap barrier: tells the master this tile has frame `frame` and waits (at most `timeout_ms`)
    // until every tile has it. False on a timeout.
    bool barrier(const std::string& endpoint, uint64_t frame, int timeout_ms);
    // Lockstep: tells the master this slave has replayed frame `frame`.
    void done(uint64_t frame);
    uint64_t recoveries() const { return recoveries_; }
    uint64_t bytes() const { return bytes_; }
    uint64_t master_frame() const { return master_frame_; }  // the newest frame the master sent
    const std::string& gap() const { return gap_; }          // the last gap, for messages

private:
    void synchronize();  // waits for the subscription to be live, then fetches the snapshot
    void fetch_snapshot();
    bool receive_live(std::vector<uint8_t>& bytes);

    std::string endpoint_, journal_endpoint_;
    int wait_seconds_;
    std::unique_ptr<zmq::context_t> context_;
    std::unique_ptr<zmq::socket_t> sub_;
    std::deque<std::vector<uint8_t>> snapshot_;
    std::vector<uint8_t> first_live_;  // received before the snapshot was asked for
    uint64_t expected_ = 0;
    bool live_ = false;
    uint64_t recoveries_ = 0, bytes_ = 0, master_frame_ = 0;
    std::string gap_;
    std::unique_ptr<zmq::socket_t> barrier_, done_;
};

}  // namespace glcast::slave
