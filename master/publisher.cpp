#include "master/publisher.h"

#include <zmq.hpp>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

#include "master/journal_server.h"
#include "master/zero_copy.h"
#include "net/security.h"
#include "protocol/format.h"

namespace glcast {

PublisherSink::PublisherSink(PublisherOptions options)
    : options_(std::move(options)),
      context_(std::make_unique<zmq::context_t>(1)),
      journal_(options_.journal_limit_bytes),
      lockstep_(options_.lockstep, options_.verbose) {
    // With keys (GLCAST_KEYS), peers on TCP are CURVE clients whose public keys this process's
    // ZAP handler knows; it is bound before any socket that asks it (net/security.h).
    authenticator_ = net::authenticator_for(*context_, "the program's stream");
    make_socket();
    wait_for_subscribers();
    if (!options_.snapshot_endpoint.empty())
        journal_server_ = std::make_unique<JournalServer>(*context_, options_.snapshot_endpoint, journal_, lockstep_,
                                                          options_.verbose);
}

// `glcast run` starts its local slaves first and asks the program to wait for them, so that a
// short program is not over before they listen. Only here, once: never during the run.
void PublisherSink::wait_for_subscribers() {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    for (int subscribed = 0; pub_ && subscribed < options_.wait_subscribers;) {
        zmq::pollitem_t item{pub_->handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(100));
        if (item.revents & ZMQ_POLLIN) {
            subscribed += take_subscriptions(1);
        } else if (std::chrono::steady_clock::now() > deadline) {
            std::fprintf(stderr, "glcast: %d of %d slaves subscribed within 60 s; going on without the rest\n",
                         subscribed, options_.wait_subscribers);
            break;
        }
    }
}

PublisherSink::~PublisherSink() { close(); }

// Subscriptions are the peers' input to this program, and libzmq keeps every distinct one (a
// trie of some 30 bytes a topic byte, per peer, until the peer goes): a peer sending endless
// distinct topics would grow the program until it died. Slaves subscribe to everything, a
// one-byte message; none may be longer than kMaxSubscriptionBytes, and once the other
// subscriptions since the socket was made pass kMaxForeignSubscriptionBytes the socket is made
// anew, which frees them (its slaves reconnect and subscribe again, and catch up on the gap).
void PublisherSink::make_socket() {
    try {
        // XPUB: a PUB socket that also reports subscriptions, for the start-up wait and the count.
        pub_ = std::make_unique<zmq::socket_t>(*context_, zmq::socket_type::xpub);
        pub_->set(zmq::sockopt::sndhwm, options_.send_hwm);
        pub_->set(zmq::sockopt::xpub_verbose, 1);  // every subscription, not only the first of a topic
        pub_->set(zmq::sockopt::maxmsgsize, int64_t(kMaxSubscriptionBytes));
        pub_->set(zmq::sockopt::rcvhwm, kSubscriptionHwm);  // what libzmq reads of a peer between two calls
        pub_->set(zmq::sockopt::linger, 1000);
    } catch (const zmq::error_t& e) {
        throw std::runtime_error(std::string("cannot make the publishing socket: ") + e.what());
    }
    foreign_subscription_bytes_ = 0;
    // Several endpoints, comma-separated: a multicast group for the wall and an ipc:// path for
    // the program's own machine, which multicast does not loop back to (docs/wall.md).
    for (size_t at = 0; at <= options_.endpoint.size();) {
        size_t comma = options_.endpoint.find(',', at);
        if (comma == std::string::npos) comma = options_.endpoint.size();
        const std::string one = options_.endpoint.substr(at, comma - at);
        at = comma + 1;
        if (one.empty()) continue;
        // A socket made anew finds its TCP port busy until the old one's close has gone through.
        for (int attempt = 0;; ++attempt) {
            try {
                // PGM multicast sends at most ZMQ_RATE kbit/s (default 100): a GL stream needs more.
                if (one.rfind("epgm://", 0) == 0 || one.rfind("pgm://", 0) == 0) pub_->set(zmq::sockopt::rate, 1000000);
                net::secure_server(*pub_, one);
                pub_->bind(one);
                break;
            } catch (const zmq::error_t& e) {
                if (e.num() != EADDRINUSE || attempt >= 50)
                    throw std::runtime_error("cannot publish on " + one + ": " + e.what());
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
            }
        }
    }
}

int PublisherSink::take_subscriptions(size_t at_most) {
    int taken = 0;
    zmq::message_t event;
    for (size_t n = 0; n < at_most && foreign_subscription_bytes_ <= kMaxForeignSubscriptionBytes &&
                       pub_->recv(event, zmq::recv_flags::dontwait);
         ++n) {
        if (event.size() == 1 && event.data<uint8_t>()[0] == 1) {  // 1, then the topic "": a slave
            taken++;
        } else if (event.size() > 0 && event.data<uint8_t>()[0] == 1) {
            foreign_subscription_bytes_ += event.size();
        }
    }
    if (foreign_subscription_bytes_ > kMaxForeignSubscriptionBytes) {
        if (!said_foreign_)
            std::fprintf(stderr, "glcast: a peer of the stream sent more than %zu bytes of subscriptions no slave "
                                 "sends; the stream's socket is made anew to free them (slaves reconnect)\n",
                         kMaxForeignSubscriptionBytes);
        said_foreign_ = true;
        remade_sockets_++;
        pub_->set(zmq::sockopt::linger, 0);
        pub_.reset();
        try {
            make_socket();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "glcast: %s; the program goes on without publishing\n", e.what());
            pub_.reset();
        }
    }
    return taken;
}

void PublisherSink::write(const std::vector<uint8_t>& message) {
    MessageHeader h{};
    if (message.size() >= sizeof h) std::memcpy(&h, message.data(), sizeof h);
    lockstep_.writing(h.frame);
    // One copy of the message, shared by the journal and the send: ZeroMQ sends it without a copy
    // of its own and frees it when the last subscriber's queue let go of it.
    Journal::Shared kept = std::make_shared<const std::vector<uint8_t>>(message);
    if (journal_server_ && journal_.append(kept, h.sequence) && options_.verbose)
        std::fprintf(stderr, "glcast: the journal passed GLCAST_JOURNAL_MB and keeps only the newest messages; "
                             "slaves join late through a keeper (glcast keeper) from now on\n");
    if (options_.drop_every && ++sent_ % options_.drop_every == 0) {
        dropped_++;  // the test hook: lost on the way
        return;
    }
    // Subscriptions that came since the last message: slaves that joined, or a peer's flood.
    if (pub_) take_subscriptions(kSubscriptionsPerMessage);
    if (!pub_) {
        dropped_++;
        return;
    }
    // Never wait for a subscriber: a full queue loses the message, the slave sees the gap.
    zmq::message_t body = zero_copy_message(kept);
    if (!pub_->send(body, zmq::send_flags::dontwait)) dropped_++;
    // Lockstep (asked for): the frame this message ends must be replayed by every slave first.
    if (lockstep_.enabled() && (h.flags & kMsgFrameEnd)) lockstep_.wait_for(h.frame);
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
    journal_server_.reset();
    pub_.reset();
    authenticator_.reset();
    context_.reset();
}

}  // namespace glcast
