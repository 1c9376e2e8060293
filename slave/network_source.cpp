#include "slave/network_source.h"

#include "common/environment.h"
#include "net/security.h"

#include <algorithm>
#include <zlib.h>
#include <zmq.hpp>

#include <chrono>
#include <cerrno>
#include <cstdio>
#include <optional>
#include <cstdlib>
#include <cstring>

namespace glcast::slave {

namespace {

// What one catching up may take from its peers, a journal or a keeper that answers forever being
// no better than one that never answers: GLCAST_CATCH_UP_MB in all (common/environment.h), and
// after the first `wait_seconds` at least 1 MiB a second on average.
constexpr double kCatchUpMinBytesPerSecond = 1 << 20;
// The master's journal answers from the program's memory at once: this long a silence means it
// is gone (the program ended while a slave was catching up), however long --wait is.
constexpr int kJournalSilenceSeconds = 10;
// A keeper answers a plain SNAPSHOT at its live edge, from memory; one that says nothing for this
// long is rebuilding its state (restarted) or gone: the journal instead.
constexpr int kKeeperSilenceSeconds = 10;

// A peer that said nothing for the time it was given.
class PeerSilent : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace

NetworkSource::NetworkSource(std::string endpoint, std::string journal_endpoint, int wait_seconds,
                             std::string keeper_endpoint, uint64_t keeper_frame, uint64_t catch_up_bytes,
                             std::optional<State> kept)
    : endpoint_(std::move(endpoint)),
      journal_endpoint_(std::move(journal_endpoint)),
      keeper_endpoint_(std::move(keeper_endpoint)),
      kept_(std::move(kept)),
      keeper_frame_(keeper_frame),
      wait_seconds_(wait_seconds),
      catch_up_limit_(catch_up_bytes ? catch_up_bytes : environment().catch_up_bytes),
      context_(std::make_unique<zmq::context_t>(1)) {
    sub_ = std::make_unique<zmq::socket_t>(*context_, zmq::socket_type::sub);
    sub_->set(zmq::sockopt::rcvhwm, 0);  // while the snapshot replays, live messages wait here
    sub_->set(zmq::sockopt::subscribe, "");
    subscribe();
    synchronize();
}

namespace {

// With CURVE, a master that does not know this machine's key closes every handshake: a monitor
// of the subscription turns that into an error that says so instead of a wait that ends in
// silence. Null without CURVE.
std::unique_ptr<zmq::socket_t> secure_subscription(zmq::context_t& context, zmq::socket_t& sub, const std::string& endpoint) {
    const bool curve = net::check_endpoint(endpoint, net::process_security(), false);
    net::secure_client(sub, endpoint);
    if (!curve) return nullptr;
    const std::string address = "inproc://glcast-subscription-" + std::to_string(uintptr_t(&sub));
    if (zmq_socket_monitor(sub.handle(), address.c_str(), ZMQ_EVENT_HANDSHAKE_FAILED_AUTH) != 0) return nullptr;
    auto monitor = std::make_unique<zmq::socket_t>(context, zmq::socket_type::pair);
    monitor->set(zmq::sockopt::linger, 0);
    monitor->connect(address);
    return monitor;
}

void throw_if_refused(zmq::socket_t* monitor, const std::string& endpoint) {
    if (!monitor) return;
    zmq::message_t event, address;
    if (!monitor->recv(event, zmq::recv_flags::dontwait)) return;
    if (monitor->get(zmq::sockopt::rcvmore)) (void)monitor->recv(address);
    const net::Security& s = net::process_security();
    throw std::runtime_error("the master at " + endpoint + " refused this machine's key " + s.client.public_key +
                             ": put " + s.dir + "/" + (s.has_master_pair ? "master" : "slave") +
                             ".pub into the master's authorized/ folder (docs/security.md)");
}

}  // namespace

void wait_for_stream(const std::string& endpoint, const std::function<void()>& idle) {
    zmq::context_t context(1);
    zmq::socket_t sub(context, zmq::socket_type::sub);
    sub.set(zmq::sockopt::linger, 0);
    sub.set(zmq::sockopt::subscribe, "");
    std::unique_ptr<zmq::socket_t> monitor = secure_subscription(context, sub, endpoint);
    sub.connect(endpoint);
    for (;;) {
        zmq::pollitem_t item{sub.handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(200));
        if (item.revents & ZMQ_POLLIN) break;
        throw_if_refused(monitor.get(), endpoint);
        if (idle) idle();
    }
    if (monitor) zmq_socket_monitor(sub.handle(), nullptr, 0);
}

void NetworkSource::subscribe() {
    if (!monitor_) monitor_ = secure_subscription(*context_, *sub_, endpoint_);
    try {
        sub_->connect(endpoint_);
    } catch (const zmq::error_t& e) {
        throw std::runtime_error("cannot subscribe to " + endpoint_ + ": " + e.what());
    }
}

void NetworkSource::check_refused() { throw_if_refused(monitor_.get(), endpoint_); }

// A subscription becomes live some time after connect: a snapshot asked for before then could
// end before the first message the subscription receives. The first live message proves the
// subscription is live; the snapshot asked for after it covers everything before.
void NetworkSource::synchronize() {
    first_live_.clear();
    struct Done {  // from here on a keeper's refusal falls back to the journal inside fetch_snapshot
        bool& flag;
        ~Done() { flag = true; }
    } done{synchronized_};
    // From a keeper, no live message is waited for: the journal's answer after the snapshot
    // reaches some message n, and a first live message after n + 1 is a gap, filled from the
    // journal like any other.
    if (!keeper_endpoint_.empty() || kept_) {
        try {
            fetch_snapshot();
            return;
        } catch (const KeeperNotReady& e) {
            // It has received nothing yet (the master's journal holds everything), or its
            // snapshot cannot hold the program's state: the journal, never a wrong picture.
            std::fprintf(stderr, "glcast: %s; catching up from the journal instead\n", e.what());
        }
    }
    if (!journal_endpoint_.empty() && !receive_live(first_live_)) return;
    MessageHeader h{};
    if (first_live_.size() >= sizeof h) std::memcpy(&h, first_live_.data(), sizeof h);
    if (h.magic == kMessageMagic && (h.sequence == 0 || (h.flags & kMsgStreamEnd))) {
        snapshot_.clear();  // there from the first message (or the very end): nothing to catch up
        expected_ = 0;
        return;
    }
    fetch_snapshot(/*from_journal=*/true);
}

void NetworkSource::done(uint64_t frame) {
    if (journal_endpoint_.empty()) return;
    if (!done_) {
        done_ = std::make_unique<zmq::socket_t>(*context_, zmq::socket_type::dealer);
        done_->set(zmq::sockopt::linger, 0);
        net::secure_client(*done_, journal_endpoint_);
        done_->connect(journal_endpoint_);
    }
    const std::string text = "DONE " + std::to_string(frame);
    done_->send(zmq::buffer(text), zmq::send_flags::dontwait);
}

NetworkSource::~NetworkSource() {
    if (monitor_) zmq_socket_monitor(sub_->handle(), nullptr, 0);
    monitor_.reset();
    done_.reset();
    sub_.reset();
    context_->shutdown();
}

namespace {

uint64_t sequence_of(const std::vector<uint8_t>& message) {
    MessageHeader h{};
    if (message.size() >= sizeof h) std::memcpy(&h, message.data(), sizeof h);
    return h.sequence;
}

}  // namespace

// A part of an answer that is neither a control word nor long enough to hold a message header:
// refused at once (endless empty parts cost memory but no bytes against the catch-up limit).
static void refuse_no_message(const zmq::message_t& part, const std::string& peer) {
    if (part.size() < sizeof(MessageHeader))
        throw std::runtime_error(peer + " sent a part of " + std::to_string(part.size()) +
                                 " bytes, which is no message (a message has a " + std::to_string(sizeof(MessageHeader)) +
                                 "-byte header)");
}

void NetworkSource::receive_parts(zmq::socket_t& dealer, const std::string& peer, int silence_seconds,
                                  const std::function<bool(zmq::message_t&)>& take, bool keep_live) {
    const auto start = std::chrono::steady_clock::now();
    auto silent_until = start + std::chrono::seconds(silence_seconds);
    uint64_t received = 0;
    for (;;) {
        zmq::pollitem_t item{dealer.handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(keep_live ? 20 : 200));
        if (keep_live) keep_live_messages();
        const auto now = std::chrono::steady_clock::now();
        if (!(item.revents & ZMQ_POLLIN)) {
            check_refused();  // the stream's handshake fails with the same key as this one's
            if (now > silent_until)
                throw PeerSilent(peer + " did not answer within " + std::to_string(silence_seconds) + " s");
            continue;
        }
        zmq::message_t part;
        if (!dealer.recv(part)) continue;
        // Every answer is single parts: a stream message each, or a control word.
        if (part.more()) throw std::runtime_error(peer + " sent a message of more than one part");
        received += part.size();
        catch_up_bytes_ += part.size();
        if (catch_up_bytes_ > catch_up_limit_)
            throw std::runtime_error(peer + " sent more than " + std::to_string(catch_up_limit_ >> 20) +
                                     " MiB to catch up with (GLCAST_CATCH_UP_MB)");
        const double seconds = std::chrono::duration<double>(now - start).count();
        if (seconds > wait_seconds_ + double(received) / kCatchUpMinBytesPerSecond)
            throw std::runtime_error(peer + " sent " + std::to_string(received) + " bytes in " +
                                     std::to_string(int(seconds)) + " s: slower than 1 MiB a second");
        silent_until = now + std::chrono::seconds(silence_seconds);
        if (!take(part)) return;
    }
}

bool NetworkSource::ask_journal(const std::string& request, const std::function<void(zmq::message_t&)>& take) {
    zmq::socket_t dealer(*context_, zmq::socket_type::dealer);
    dealer.set(zmq::sockopt::linger, 0);
    dealer.set(zmq::sockopt::rcvhwm, 0);
    // No part larger than a message may be: libzmq hangs up before it allocates one.
    dealer.set(zmq::sockopt::maxmsgsize, int64_t(sizeof(MessageHeader)) + kMaxMessageBytes);
    net::secure_client(dealer, journal_endpoint_);
    dealer.connect(journal_endpoint_);
    dealer.send(zmq::buffer(request), zmq::send_flags::none);
    bool held = true;
    const int silence = wait_seconds_ > 0 ? std::min(wait_seconds_, kJournalSilenceSeconds) : kJournalSilenceSeconds;
    receive_parts(dealer, "the master's journal at " + journal_endpoint_, silence, [&](zmq::message_t& part) {
        const std::string text = part.size() <= 4 ? part.to_string() : std::string();
        if (text == "END") return false;
        if (text == "GONE") return held = false;
        refuse_no_message(part, "the master's journal at " + journal_endpoint_);
        take(part);
        return true;
    });
    return held;
}

bool NetworkSource::fetch_since(uint64_t first) {
    std::deque<std::vector<uint8_t>> got;
    const bool held = ask_journal("SINCE " + std::to_string(first), [&](zmq::message_t& part) {
        got.emplace_back(part.data<uint8_t>(), part.data<uint8_t>() + part.size());
    });
    if (!held) return false;
    for (auto& m : got) snapshot_.push_back(std::move(m));
    return true;
}

bool parse_keeper_state(const std::string& text, uint64_t& sequence, uint64_t& frame) {
    auto number = [&text](size_t& at, uint64_t& out) {
        const size_t start = at;
        out = 0;
        while (at < text.size() && text[at] >= '0' && text[at] <= '9' && at - start < 16) {
            out = out * 10 + uint64_t(text[at] - '0');
            at++;
        }
        return at > start && out <= kMaxKeeperCount && (at == text.size() || text[at] == ' ');
    };
    if (text.rfind("STATE ", 0) != 0) return false;
    size_t at = 6;
    if (!number(at, sequence) || at >= text.size() || text[at] != ' ') return false;
    at++;
    return number(at, frame) && at == text.size();
}

bool NetworkSource::journal_agrees(size_t from, uint64_t sequence, uint32_t crc) {
    if (crc == 0) return true;
    MessageChain chain;
    Message m;
    for (size_t i = from; i < snapshot_.size() && sequence_of(snapshot_[i]) <= sequence; ++i) {
        try {
            decode_message(snapshot_[i].data(), snapshot_[i].size(), 0, m, &chain);
        } catch (const DecodeError&) {
            return false;  // (not of one chain: not this stream either)
        }
        if (m.header.sequence == sequence)
            return uint32_t(crc32(0, m.payload.data(), uInt(m.payload.size()))) == crc;
    }
    return true;
}

NetworkSource::State NetworkSource::fetch_state(const std::string& endpoint) {
    zmq::socket_t dealer(*context_, zmq::socket_type::dealer);
    dealer.set(zmq::sockopt::linger, 0);
    dealer.set(zmq::sockopt::rcvhwm, 0);
    // No part larger than a message may be: libzmq hangs up before it allocates one.
    dealer.set(zmq::sockopt::maxmsgsize, int64_t(sizeof(MessageHeader)) + kMaxMessageBytes);
    net::secure_client(dealer, endpoint);
    dealer.connect(endpoint);
    const std::string request = keeper_frame_ ? "SNAPSHOT AT " + std::to_string(keeper_frame_) : "SNAPSHOT";
    dealer.send(zmq::buffer(request), zmq::send_flags::none);
    State state;
    bool header = false;
    early_.clear();
    early_bytes_ = 0;
    // (asked for a later frame it waits for that frame: the whole --wait)
    const int silence = keeper_frame_ || wait_seconds_ <= 0 ? wait_seconds_ : std::min(wait_seconds_, kKeeperSilenceSeconds);
    try {
        receive_parts(dealer, "the keeper at " + endpoint, silence, [&](zmq::message_t& part) {
            if (!header) {  // "STATE <sequence> <frame>", or "NONE <why>"
                const std::string text = part.size() <= 256 ? part.to_string() : std::string();
                if (text.rfind("NONE", 0) == 0) throw KeeperNotReady("the keeper at " + endpoint + ": " + text.substr(5));
                uint64_t sequence = 0, frame = 0;
                if (!parse_keeper_state(text, sequence, frame))
                    throw std::runtime_error("the keeper at " + endpoint + " cannot give a snapshot: " +
                                             (text.empty() ? std::string("an answer glcast does not know")
                                                           : "\"" + text.substr(0, 64) + "\" is no STATE <sequence> <frame> "
                                                             "of at most " + std::to_string(kMaxKeeperCount)));
                state.sequence = sequence;
                state.frame = frame;
                header = true;
                return true;
            }
            if (part.size() == 3 && part.to_string() == "END") return false;
            refuse_no_message(part, "the keeper at " + endpoint);
            state.messages.emplace_back(part.data<uint8_t>(), part.data<uint8_t>() + part.size());
            return true;
        }, /*keep_live=*/true);
    } catch (const PeerSilent& e) {
        if (keeper_frame_ || header) throw;  // (silent in the middle of its answer: a broken keeper)
        throw KeeperNotReady(e.what());
    }
    return state;
}

// While a keeper prepares its snapshot (for a later frame, it may wait long), the live
// messages are kept, the newest kEarlyLimitBytes of them: those after the snapshot's boundary
// then need no journal, which a program that has ended no longer serves.
void NetworkSource::keep_live_messages() {
    for (zmq::message_t msg; sub_->recv(msg, zmq::recv_flags::dontwait);) {
        early_bytes_ += msg.size();
        early_.emplace_back(msg.data<uint8_t>(), msg.data<uint8_t>() + msg.size());
        while (early_bytes_ > kEarlyLimitBytes && early_.size() > 1) {
            early_bytes_ -= early_.front().size();
            early_.pop_front();
        }
    }
}

// Catches up: from a keeper's snapshot and the journal's messages since, or from the journal's
// every message so far. The live stream continues after the last one.
void NetworkSource::fetch_snapshot(bool from_journal) {
    const auto start = std::chrono::steady_clock::now();
    auto measure = [&] {
        join_cost_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        join_cost_.state_messages = state_left_;
        join_cost_.journal_messages = snapshot_.size() - state_left_;
        join_cost_.bytes = 0;
        for (const auto& m : snapshot_) join_cost_.bytes += m.size();
    };
    snapshot_.clear();
    chain_.forget();  // everything comes again, from a key message
    state_chain_.forget();
    catch_up_bytes_ = 0;
    state_left_ = 0;
    joined_frame_ = 0;
    expected_ = 0;
    std::optional<State> from_keeper;
    const bool from_kept = kept_.has_value() && !from_journal;
    if (from_kept) {
        from_keeper = std::move(*kept_);
        kept_.reset();
    } else if (!keeper_endpoint_.empty() && !from_journal) {
        try {
            from_keeper = fetch_state(keeper_endpoint_);
        } catch (const KeeperNotReady& e) {
            // Not there yet, or a snapshot that cannot hold the program's state: the journal,
            // if it still holds the stream's start, never a wrong picture.
            if (!synchronized_) throw;
            std::fprintf(stderr, "glcast: %s; catching up from the journal instead\n", e.what());
        }
    }
    if (from_keeper) {
        State state = std::move(*from_keeper);
        join_cost_.state_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        snapshot_ = std::move(state.messages);
        state_left_ = snapshot_.size();
        after_state_ = expected_ = state.sequence + 1;
        joined_frame_ = state.frame;
        // The messages between the keeper's boundary and the first live one this slave holds.
        // From the journal, which answers from the key message before them (the first may be
        // coded against one this slave never had); without a journal, those kept while the
        // keeper worked.
        replay_from_ = state.sequence + 1;
        if (from_kept) {
            // A state of this keeper's own, kept on disk: of use only while the journal holds what
            // follows it, and only for the stream it was kept from.
            const char* why = !fetch_since(state.sequence + 1) ? "the master's journal no longer holds what follows it"
                              : !journal_agrees(state_left_, state.sequence, state.boundary_crc)
                                  ? "the master's journal holds another stream's message where it ends"
                                  : nullptr;
            if (why) {
                std::fprintf(stderr, "glcast: the kept state of frame %llu: %s; catching up from the journal's start\n",
                             static_cast<unsigned long long>(state.frame), why);
                fetch_snapshot(true);
                return;
            }
        } else if (!journal_endpoint_.empty()) {
            if (!fetch_since(state.sequence + 1))
                throw std::runtime_error("the master's journal no longer holds message " +
                                         std::to_string(state.sequence + 1) +
                                         ", where the keeper's snapshot ends (the keeper is behind)");
        } else if (!early_.empty() && sequence_of(early_.front()) <= state.sequence + 1) {
            for (auto& m : early_)
                if (sequence_of(m) > state.sequence) snapshot_.push_back(std::move(m));
        }
        early_.clear();
        early_bytes_ = 0;
        if (snapshot_.size() > state_left_) expected_ = sequence_of(snapshot_.back()) + 1;
        measure();
        if (on_joined) on_joined(joined_frame_);
        return;
    }
    if (journal_endpoint_.empty()) return;  // no late join: live messages only, from sequence 0
    replay_from_ = 0;
    const bool whole = ask_journal("SNAPSHOT", [&](zmq::message_t& part) {
        snapshot_.emplace_back(part.data<uint8_t>(), part.data<uint8_t>() + part.size());
    });
    if (!whole)
        throw std::runtime_error("the master's journal no longer holds the stream's first messages (GLCAST_JOURNAL_MB): "
                                 "this slave can join only through a keeper (--keeper)");
    if (!snapshot_.empty()) expected_ = sequence_of(snapshot_.back()) + 1;
    measure();
}

bool NetworkSource::tail_check(bool& ended) {
    const size_t before = snapshot_.size();
    catch_up_bytes_ = 0;
    replay_from_ = expected_;  // the journal answers from the key before it
    try {
        if (!fetch_since(expected_)) {  // its key no longer held: the next live message tells whether a gap is there
            snapshot_.resize(before);
            return false;
        }
    } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "glcast: no message for %d s and %s: the program has ended (messages from %llu on, if "
                             "any, were lost)\n",
                     kTailCheckSeconds, e.what(), static_cast<unsigned long long>(expected_));
        ended = true;
        return false;
    }
    const bool newer = std::any_of(snapshot_.begin() + std::ptrdiff_t(before), snapshot_.end(),
                                   [&](const std::vector<uint8_t>& m) { return sequence_of(m) >= expected_; });
    if (!newer) {  // nothing after what this slave replayed: a program that is quiet
        snapshot_.resize(before);
        return false;
    }
    recoveries_++;
    gap_ = "messages from " + std::to_string(expected_) + " on never came live";
    if (on_gap) on_gap();
    return true;
}

bool NetworkSource::receive_live(std::vector<uint8_t>& bytes) {
    int tail_check_at_ms = kTailCheckSeconds * 1000;
    for (int waited_ms = 0;; waited_ms += idle_ms_) {
        zmq::pollitem_t item{sub_->handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(idle_ms_));
        if (item.revents & ZMQ_POLLIN) break;
        check_refused();
        if (on_idle) on_idle();
        if (!journal_endpoint_.empty() && expected_ > 0 && waited_ms >= tail_check_at_ms) {
            tail_check_at_ms = waited_ms + kTailCheckSeconds * 1000;
            bool ended = false;
            if (tail_check(ended)) {
                bytes.clear();
                return true;
            }
            if (ended) return false;
        }
        if (wait_seconds_ && waited_ms > wait_seconds_ * 1000)
            throw std::runtime_error("no message from " + endpoint_ + " for " + std::to_string(wait_seconds_) + " s");
    }
    zmq::message_t msg;
    if (!sub_->recv(msg)) return false;
    arrived_ = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    bytes.assign(msg.data<uint8_t>(), msg.data<uint8_t>() + msg.size());
    return true;
}

bool NetworkSource::next(Message& m) {
    std::vector<uint8_t> bytes;
    for (;;) {
        bool state = false;
        if (!snapshot_.empty()) {
            bytes = std::move(snapshot_.front());
            snapshot_.pop_front();
            live_ = false;
            state = state_left_ > 0;
            if (state) state_left_--;
        } else if (!first_live_.empty()) {
            bytes = std::move(first_live_);
            first_live_.clear();
            live_ = true;
        } else {
            if (!receive_live(bytes)) return false;
            if (bytes.empty()) continue;  // the journal's answer to a tail check is in snapshot_
            live_ = true;
        }
        if (bytes.size() < sizeof(MessageHeader)) throw DecodeError(0, "short message from " + endpoint_);
        MessageHeader h;
        std::memcpy(&h, bytes.data(), sizeof h);
        if (h.magic == kMessageMagic && (h.flags & kMsgStreamEnd)) return false;
        if (live_ && h.sequence == 0 && expected_ > 0) {  // a new program's first message
            replaced_ = true;
            return false;
        }
        if (live_) {
            master_frame_ = std::max<uint64_t>(master_frame_, h.frame);
            if (h.sequence < expected_) continue;  // already in the snapshot
            if (h.sequence > expected_) {  // lost messages: from the journal, or start over from a snapshot
                if (journal_endpoint_.empty())
                    throw std::runtime_error("messages " + std::to_string(expected_) + " to " +
                                             std::to_string(h.sequence - 1) + " were lost and no journal was given");
                // The journal's answer covers everything before the live message it was asked
                // for: a live message still not joined after it was, kMaxGapTries times, means
                // a journal that answers with nothing or a message from nowhere. Given up on.
                gap_tries_ = h.sequence == gap_live_ ? gap_tries_ + 1 : 1;
                gap_live_ = h.sequence;
                if (gap_tries_ > kMaxGapTries)
                    throw std::runtime_error("the master's journal at " + journal_endpoint_ + " answered " +
                                             std::to_string(kMaxGapTries) + " times without message " +
                                             std::to_string(expected_) + " before live message " +
                                             std::to_string(h.sequence) + ": giving up");
                recoveries_++;
                gap_ = "expected message " + std::to_string(expected_) + ", got " + std::to_string(h.sequence);
                first_live_ = bytes;  // live, so what the journal answers now covers all before it
                if (on_gap) on_gap();
                catch_up_bytes_ = 0;
                replay_from_ = expected_;  // the journal answers from the key before it
                if (fetch_since(expected_)) continue;
                if (on_restart) on_restart();
                fetch_snapshot();
                continue;
            }
        }
        if (!live_ && !state && h.sequence < replay_from_) {
            // From a journal's answer, which starts at the key message before the one asked for:
            // unpacked only so that the chain reaches the next one (docs/stream-format.md).
            decode_message(bytes.data(), bytes.size(), 0, m, &chain_);
            continue;
        }
        bytes_ += bytes.size();
        decode_message(bytes.data(), bytes.size(), 0, m, state ? &state_chain_ : &chain_);
        from_state_ = state;
        // A keeper's state messages count on their own; the master's sequence resumes after them.
        if (!state) expected_ = m.header.sequence + 1;
        else if (!state_left_ && expected_ < after_state_) expected_ = after_state_;
        return true;
    }
}

}  // namespace glcast::slave
