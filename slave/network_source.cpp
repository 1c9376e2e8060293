#include "slave/network_source.h"

#include <zmq.hpp>

#include <chrono>
#include <cstring>

namespace glcast::slave {

NetworkSource::NetworkSource(std::string endpoint, std::string journal_endpoint, int wait_seconds)
    : endpoint_(std::move(endpoint)),
      journal_endpoint_(std::move(journal_endpoint)),
      wait_seconds_(wait_seconds),
      context_(std::make_unique<zmq::context_t>(1)) {
    sub_ = std::make_unique<zmq::socket_t>(*context_, zmq::socket_type::sub);
    sub_->set(zmq::sockopt::rcvhwm, 0);  // while the snapshot replays, live messages wait here
    sub_->set(zmq::sockopt::subscribe, "");
    try {
        sub_->connect(endpoint_);
    } catch (const zmq::error_t& e) {
        throw std::runtime_error("cannot subscribe to " + endpoint_ + ": " + e.what());
    }
    synchronize();
}

// A subscription becomes live some time after connect: a snapshot asked for before then could
// end before the first message the subscription receives. The first live message proves the
// subscription is live; the snapshot asked for after it covers everything before.
void NetworkSource::synchronize() {
    first_live_.clear();
    if (!journal_endpoint_.empty() && !receive_live(first_live_)) return;
    MessageHeader h{};
    if (first_live_.size() >= sizeof h) std::memcpy(&h, first_live_.data(), sizeof h);
    if (h.magic == kMessageMagic && (h.sequence == 0 || (h.flags & kMsgStreamEnd))) {
        snapshot_.clear();  // there from the first message (or the very end): nothing to catch up
        expected_ = 0;
        return;
    }
    fetch_snapshot();
}

bool NetworkSource::barrier(const std::string& endpoint, uint64_t frame, int timeout_ms) {
    if (!barrier_) {
        barrier_ = std::make_unique<zmq::socket_t>(*context_, zmq::socket_type::dealer);
        barrier_->set(zmq::sockopt::linger, 0);
        barrier_->connect(endpoint);
    }
    const std::string ready = "READY " + std::to_string(frame), go = "GO " + std::to_string(frame);
    barrier_->send(zmq::buffer(ready), zmq::send_flags::none);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (std::chrono::steady_clock::now() < deadline) {
        zmq::pollitem_t item{barrier_->handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(50));
        if (!(item.revents & ZMQ_POLLIN)) continue;
        zmq::message_t answer;
        if (barrier_->recv(answer) && answer.to_string() == go) return true;  // older GOs are skipped
    }
    return false;
}

void NetworkSource::done(uint64_t frame) {
    if (journal_endpoint_.empty()) return;
    if (!done_) {
        done_ = std::make_unique<zmq::socket_t>(*context_, zmq::socket_type::dealer);
        done_->set(zmq::sockopt::linger, 0);
        done_->connect(journal_endpoint_);
    }
    const std::string text = "DONE " + std::to_string(frame);
    done_->send(zmq::buffer(text), zmq::send_flags::dontwait);
}

NetworkSource::~NetworkSource() {
    done_.reset();
    barrier_.reset();
    sub_.reset();
    context_->shutdown();
}

// Asks the journal for every message so far; the live stream continues after the last one.
void NetworkSource::fetch_snapshot() {
    snapshot_.clear();
    if (journal_endpoint_.empty()) return;  // no late join: live messages only, from sequence 0
    zmq::socket_t dealer(*context_, zmq::socket_type::dealer);
    dealer.set(zmq::sockopt::linger, 0);
    dealer.set(zmq::sockopt::rcvhwm, 0);
    dealer.connect(journal_endpoint_);
    dealer.send(zmq::str_buffer("SNAPSHOT"), zmq::send_flags::none);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(wait_seconds_);
    for (;;) {
        zmq::pollitem_t item{dealer.handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(200));
        if (!(item.revents & ZMQ_POLLIN)) {
            if (std::chrono::steady_clock::now() > deadline)
                throw std::runtime_error("the master's journal at " + journal_endpoint_ + " did not answer within " +
                                         std::to_string(wait_seconds_) + " s");
            continue;
        }
        zmq::message_t part;
        if (!dealer.recv(part)) continue;
        const std::string text = part.size() <= 4 ? part.to_string() : std::string();
        if (text == "END") break;
        if (text == "GONE")
            throw std::runtime_error("the master's journal passed GLCAST_JOURNAL_MB: this slave cannot join late");
        snapshot_.emplace_back(part.data<uint8_t>(), part.data<uint8_t>() + part.size());
    }
    expected_ = 0;
    if (!snapshot_.empty()) {
        MessageHeader h;
        std::memcpy(&h, snapshot_.back().data(), sizeof h);
        expected_ = h.sequence + 1;
    }
}

bool NetworkSource::receive_live(std::vector<uint8_t>& bytes) {
    for (int waited_ms = 0;; waited_ms += 200) {
        zmq::pollitem_t item{sub_->handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(200));
        if (item.revents & ZMQ_POLLIN) break;
        if (wait_seconds_ && waited_ms > wait_seconds_ * 1000)
            throw std::runtime_error("no message from " + endpoint_ + " for " + std::to_string(wait_seconds_) + " s");
    }
    zmq::message_t msg;
    if (!sub_->recv(msg)) return false;
    bytes.assign(msg.data<uint8_t>(), msg.data<uint8_t>() + msg.size());
    return true;
}

bool NetworkSource::next(Message& m) {
    std::vector<uint8_t> bytes;
    for (;;) {
        if (!snapshot_.empty()) {
            bytes = std::move(snapshot_.front());
            snapshot_.pop_front();
            live_ = false;
        } else if (!first_live_.empty()) {
            bytes = std::move(first_live_);
            first_live_.clear();
            live_ = true;
        } else {
            if (!receive_live(bytes)) return false;
            live_ = true;
        }
        if (bytes.size() < sizeof(MessageHeader)) throw DecodeError(0, "short message from " + endpoint_);
        MessageHeader h;
        std::memcpy(&h, bytes.data(), sizeof h);
        if (h.magic == kMessageMagic && (h.flags & kMsgStreamEnd)) return false;
        if (live_) {
            master_frame_ = std::max<uint64_t>(master_frame_, h.frame);
            if (h.sequence < expected_) continue;  // already in the snapshot
            if (h.sequence > expected_) {           // lost messages: start over from a snapshot
                if (journal_endpoint_.empty())
                    throw std::runtime_error("messages " + std::to_string(expected_) + " to " +
                                             std::to_string(h.sequence - 1) + " were lost and no journal was given");
                recoveries_++;
                gap_ = "expected message " + std::to_string(expected_) + ", got " + std::to_string(h.sequence);
                if (on_restart) on_restart();
                first_live_ = bytes;  // live, so the snapshot asked for now covers all before it
                fetch_snapshot();
                continue;
            }
        }
        bytes_ += bytes.size();
        decode_message(bytes.data(), bytes.size(), 0, m);
        expected_ = m.header.sequence + 1;
        return true;
    }
}

}  // namespace glcast::slave
