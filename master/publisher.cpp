#include "master/publisher.h"

#include <zmq.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>

#include "protocol/format.h"

namespace glcast {

PublisherSink::PublisherSink(PublisherOptions options)
    : options_(std::move(options)), context_(std::make_unique<zmq::context_t>(1)) {
    try {
        // XPUB: a PUB socket that also reports subscriptions, for the start-up wait below.
        pub_ = std::make_unique<zmq::socket_t>(*context_, zmq::socket_type::xpub);
        pub_->set(zmq::sockopt::sndhwm, options_.send_hwm);
        pub_->set(zmq::sockopt::xpub_verbose, 1);  // every subscription, not only the first of a topic
        // PGM multicast sends at most ZMQ_RATE kbit/s (default 100): a GL stream needs more.
        if (options_.endpoint.rfind("epgm://", 0) == 0 || options_.endpoint.rfind("pgm://", 0) == 0)
            pub_->set(zmq::sockopt::rate, 1000000);
        pub_->set(zmq::sockopt::linger, 1000);
        pub_->bind(options_.endpoint);
    } catch (const zmq::error_t& e) {
        throw std::runtime_error("cannot publish on " + options_.endpoint + ": " + e.what());
    }
    // `glcast run` starts its local slaves first and asks the program to wait for them, so that
    // a short program is not over before they listen. Only here, once: never during the run.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    for (int subscribed = 0; subscribed < options_.wait_subscribers;) {
        zmq::pollitem_t item{pub_->handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(100));
        if (item.revents & ZMQ_POLLIN) {
            zmq::message_t event;
            if (pub_->recv(event, zmq::recv_flags::dontwait) && event.size() && event.data<uint8_t>()[0] == 1)
                subscribed++;
        } else if (std::chrono::steady_clock::now() > deadline) {
            std::fprintf(stderr, "glcast: %d of %d slaves subscribed within 60 s; going on without the rest\n",
                         subscribed, options_.wait_subscribers);
            break;
        }
    }
    if (!options_.snapshot_endpoint.empty()) snapshot_thread_ = std::thread([this] { serve_snapshots(); });
}

PublisherSink::~PublisherSink() { close(); }

void PublisherSink::write(const std::vector<uint8_t>& message) {
    {
        std::lock_guard lock(journal_mutex_);
        if (journal_complete_ && !options_.snapshot_endpoint.empty()) {
            if (journal_bytes_ + message.size() > options_.journal_limit_bytes) {
                journal_complete_ = false;
                journal_.clear();
                journal_.shrink_to_fit();
                std::fprintf(stderr, "glcast: the stream passed GLCAST_JOURNAL_MB; slaves can no longer join late\n");
            } else {
                journal_.push_back(message);
                journal_bytes_ += message.size();
            }
        }
    }
    if (options_.drop_every && ++sent_ % options_.drop_every == 0) {
        dropped_++;  // the test hook: lost on the way
        return;
    }
    // Never wait for a subscriber: a full queue loses the message, the slave sees the gap.
    if (!pub_->send(zmq::buffer(message), zmq::send_flags::dontwait)) dropped_++;
    // Lockstep (asked for): the frame this message ends must be replayed by every slave first.
    MessageHeader h;
    std::memcpy(&h, message.data(), sizeof h);
    if (options_.lockstep > 0 && (h.flags & kMsgFrameEnd)) {
        std::unique_lock lock(done_mutex_);
        if (!done_changed_.wait_for(lock, std::chrono::seconds(10), [&] { return done_[h.frame] >= options_.lockstep; }))
            std::fprintf(stderr, "glcast: lockstep: frame %u not replayed by %d slaves within 10 s; going on\n", h.frame,
                         options_.lockstep);
        done_.erase(done_.begin(), done_.upper_bound(h.frame));
    }
}

// ROUTER side channel. A request is one frame "SNAPSHOT"; the answer is every journaled
// message, one frame each, then "END". A journal that passed its limit answers "GONE".
void PublisherSink::serve_snapshots() {
    zmq::socket_t router(*context_, zmq::socket_type::router);
    router.set(zmq::sockopt::sndhwm, 0);
    router.set(zmq::sockopt::linger, 0);
    try {
        router.bind(options_.snapshot_endpoint);
    } catch (const zmq::error_t& e) {
        std::fprintf(stderr, "glcast: cannot serve snapshots on %s: %s\n", options_.snapshot_endpoint.c_str(), e.what());
        return;
    }
    while (!stopping_) {
        zmq::pollitem_t item{router.handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(100));
        if (!(item.revents & ZMQ_POLLIN)) continue;
        std::vector<zmq::message_t> request;
        zmq::message_t part;
        do {
            if (!router.recv(part)) break;
            request.push_back(std::move(part));
        } while (router.get(zmq::sockopt::rcvmore));
        if (request.size() < 2) continue;
        const std::string identity = request.front().to_string();
        const std::string what = request.back().to_string();
        if (what.rfind("DONE ", 0) == 0) {  // lockstep: a slave has replayed a frame
            std::lock_guard lock(done_mutex_);
            done_[std::strtoull(what.c_str() + 5, nullptr, 10)]++;
            done_changed_.notify_all();
            continue;
        }
        if (what != "SNAPSHOT") continue;
        std::vector<std::vector<uint8_t>> copy;
        bool complete;
        {
            std::lock_guard lock(journal_mutex_);
            copy = journal_;
            complete = journal_complete_;
        }
        if (complete)
            for (const auto& message : copy) {
                router.send(zmq::buffer(identity), zmq::send_flags::sndmore);
                router.send(zmq::buffer(message), zmq::send_flags::none);
            }
        router.send(zmq::buffer(identity), zmq::send_flags::sndmore);
        const std::string answer = complete ? "END" : "GONE";
        router.send(zmq::buffer(answer), zmq::send_flags::none);
    }
}

void PublisherSink::close() {
    if (closed_) return;
    closed_ = true;
    // Tell the slaves the program has ended.
    MessageHeader h{};
    h.magic = kMessageMagic;
    h.flags = kMsgStreamEnd;
    h.sequence = UINT64_MAX;
    std::vector<uint8_t> end(sizeof h);
    std::memcpy(end.data(), &h, sizeof h);
    if (pub_) pub_->send(zmq::buffer(end), zmq::send_flags::dontwait);
    stopping_ = true;
    if (snapshot_thread_.joinable()) snapshot_thread_.join();
    pub_.reset();
    context_.reset();
}

}  // namespace glcast
