// A slave's subscription to a live master (docs/wall.md; the Clone pattern of the ZeroMQ guide): subscribe
// first, then catch up, replay that, and go on with the live messages after it. Catching up is
// asking a keeper (docs/keeper.md) for a snapshot of the live state and the master's journal for
// the few messages since, or, without a keeper, the journal for every message so far. A gap in
// the sequence numbers (a dropped message, a slave that fell behind) is filled from the journal
// ("SINCE n"); when the journal no longer holds it, the slave starts over from a snapshot.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "protocol/decoder.h"

namespace zmq {
class context_t;
class socket_t;
class message_t;
}  // namespace zmq

namespace glcast::slave {

// A keeper that has received nothing of the stream yet (the journal has it all).
class KeeperNotReady : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Tries to fill one gap before the live message after it (journal answers that bring nothing).
constexpr int kMaxGapTries = 3;
constexpr int kTailCheckSeconds = 3;

class NetworkSource : public MessageSource {
public:
    // A keeper's snapshot: the state messages in order, the master's last message they cover and
    // the frame that follows it.
    struct State {
        std::deque<std::vector<uint8_t>> messages;
        uint64_t sequence = 0, frame = 0;
        uint32_t boundary_crc = 0;  // of master message `sequence`'s payload (0: not known)
    };

    // keeper_frame > 0: ask the keeper for its state at that frame ("SNAPSHOT AT n"), waiting
    // until the program gets there (a recording that starts at a frame). catch_up_bytes: what one
    // catching up may take from the journal and the keeper (0: GLCAST_CATCH_UP_MB's). kept: a
    // state to start from instead of asking a keeper (a keeper's own, kept on disk,
    // keeper/kept_state.h); when the journal no longer holds what follows it, or holds another
    // stream's message where it ends (boundary_crc), it is dropped for the journal's start.
    NetworkSource(std::string endpoint, std::string journal_endpoint, int wait_seconds, std::string keeper_endpoint = "",
                  uint64_t keeper_frame = 0, uint64_t catch_up_bytes = 0, std::optional<State> kept = std::nullopt);
    ~NetworkSource() override;

    bool next(Message& m) override;  // false when the program has ended

    // Called before the snapshot of a recovery is replayed: the replay must start from nothing.
    std::function<void()> on_restart;
    // Called when a gap in the sequence numbers is found, before it is filled (gap() says which).
    std::function<void()> on_gap;
    // Called when a keeper's snapshot was fetched on a recovery, with joined_frame().
    std::function<void(uint64_t frame)> on_joined;
    // Called every `idle_ms` (200 by default) while no live message arrives (a keeper answers
    // requests then, and polls more often).
    std::function<void()> on_idle;
    void set_idle_interval(int ms) { idle_ms_ = ms; }

    bool live() const { return live_; }              // the last message came from the live stream
    // When the last live message was taken from the stream's socket (steady seconds): a slave busy
    // with earlier frames takes it later than the network brought it.
    double arrived() const { return arrived_; }
    bool from_state() const { return from_state_; }  // ... or from a keeper's snapshot (its own sequence)
    // ... or was the last of a snapshot: the newest frame the master has, which a master in
    // lockstep waits for (the live message that showed a gap is in the snapshot, not replayed again)
    bool caught_up() const { return live_ || snapshot_.empty(); }
    // Lockstep: tells the master this slave has replayed frame `frame`.
    void done(uint64_t frame);
    uint64_t recoveries() const { return recoveries_; }
    uint64_t bytes() const { return bytes_; }
    uint64_t master_frame() const { return master_frame_; }  // the newest frame the master sent
    // The master's frame the last snapshot of a keeper begins at (0: none, or a journal replay
    // from the first message): the replay's frame counter starts there.
    uint64_t joined_frame() const { return joined_frame_; }
    // The last catching up: messages and bytes fetched, and how long it took.
    struct JoinCost {
        uint64_t state_messages = 0, journal_messages = 0, bytes = 0;
        double seconds = 0, state_seconds = 0;  // all of it; the keeper's answer alone
    };
    const JoinCost& join_cost() const { return join_cost_; }
    // Asks `endpoint` (a keeper, or anything that answers as one) for a snapshot: the state
    // messages in order, the last master sequence and the frame they stand for. Throws on no
    // answer within `wait_seconds` or a refusal. (glcast record and the tests use it too.)
    State fetch_state(const std::string& endpoint);
    const std::string& gap() const { return gap_; }          // the last gap, for messages
    // The stream ended because another program began publishing on the endpoint (one that did
    // not end its own stream: it crashed or was killed).
    bool replaced() const { return replaced_; }

private:
    void subscribe();
    void synchronize();  // waits for the subscription to be live, then fetches the snapshot
    void fetch_snapshot(bool from_journal = false);
    // Appends the journal's messages from sequence `first` on to snapshot_; false: GONE.
    bool fetch_since(uint64_t first);
    // Whether the journal's messages in snapshot_ after the first `from` hold message `sequence`
    // with a payload of CRC `crc`, or do not reach back to it (the journal answered from a key
    // message after it): false only for another stream's message.
    bool journal_agrees(size_t from, uint64_t sequence, uint32_t crc);
    // Asks the journal `request`; each message part to `take`; false on GONE.
    bool ask_journal(const std::string& request, const std::function<void(zmq::message_t&)>& take);
    // The next live message into `bytes`; false when the stream has ended. Empty `bytes`: none
    // came, but a tail check (below) put messages into snapshot_.
    bool receive_live(std::vector<uint8_t>& bytes);
    // After kTailCheckSeconds without a live message: messages the publisher dropped at the end of
    // a burst (this slave was stopped while the program ran on, and then the program went quiet
    // or ended) are followed by no message that would show the gap. The journal sends what comes
    // after the last one replayed (true), or nothing; when it does not answer, the program is
    // gone, and `ended` is set.
    bool tail_check(bool& ended);
    // Receives a peer's answer, a part at a time, until `take` returns false; throws when the
    // peer is silent for `silence_seconds`, too slow, or sends more than a catching up may hold.
    // keep_live: live messages that arrive meanwhile go to early_.
    void receive_parts(zmq::socket_t& dealer, const std::string& peer, int silence_seconds,
                       const std::function<bool(zmq::message_t&)>& take, bool keep_live = false);
    void keep_live_messages();
    void check_refused();
    zmq::socket_t& control(const std::string& endpoint);  // throws when the master refused this machine's CURVE key

    std::string endpoint_, journal_endpoint_, keeper_endpoint_;
    std::optional<State> kept_;  // taken by the first catching up
    uint64_t keeper_frame_ = 0;
    bool synchronized_ = false;  // the first catching up is over
    int idle_ms_ = 200;
    int wait_seconds_;
    uint64_t catch_up_limit_;      // bytes one catching up may take (GLCAST_CATCH_UP_MB)
    std::unique_ptr<zmq::context_t> context_;
    std::unique_ptr<zmq::socket_t> sub_;
    std::deque<std::vector<uint8_t>> snapshot_;
    uint64_t catch_up_bytes_ = 0;  // taken from peers in the catching up under way
    size_t state_left_ = 0;      // the first messages of snapshot_ are a keeper's state messages
    uint64_t after_state_ = 0;   // the master's sequence that follows them
    uint64_t replay_from_ = 0;   // journal messages before it only advance chain_ (they were asked
                                 // for from a later one: the journal answers from the key before)
    uint64_t joined_frame_ = 0;
    JoinCost join_cost_;
    std::vector<uint8_t> first_live_;  // received before the snapshot was asked for
    std::deque<std::vector<uint8_t>> early_;  // live, while a keeper prepared its snapshot
    uint64_t early_bytes_ = 0;
    static constexpr uint64_t kEarlyLimitBytes = 64u << 20;
    uint64_t expected_ = 0;
    uint64_t gap_live_ = UINT64_MAX;  // the live message of the last gap, and how often it was one
    int gap_tries_ = 0;
    bool live_ = false, from_state_ = false;
    double arrived_ = 0;
    uint64_t recoveries_ = 0, bytes_ = 0, master_frame_ = 0;
    std::string gap_;
    bool replaced_ = false;
    // The master's stream and a keeper's snapshot are each coded against their own previous
    // message (kMsgDelta): one chain each.
    MessageChain chain_, state_chain_;
    std::unique_ptr<zmq::socket_t> done_, monitor_;
};

// Waits until a program publishes on `endpoint` (a message arrives), calling `idle` every 200 ms
// meanwhile; throws when the master refuses this machine's key. A service slave waits here
// between programs (cli/slave.cpp).
void wait_for_stream(const std::string& endpoint, const std::function<void()>& idle);

// A keeper's answer "STATE <sequence> <frame>": decimal digits only, each at most kMaxKeeperCount
// (a peer's 2^64-1 or "-1" would set the slave's frame counter anywhere). False otherwise.
constexpr uint64_t kMaxKeeperCount = uint64_t(1) << 48;
bool parse_keeper_state(const std::string& text, uint64_t& sequence, uint64_t& frame);

}  // namespace glcast::slave
