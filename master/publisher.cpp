#include "master/publisher.h"

#include "net/security.h"

#include <zmq.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <functional>
#include <map>

#include "protocol/format.h"

namespace glcast {

namespace {

double seconds_now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The zero-copy send's hint: a reference to the journal message, released by libzmq (from its
// I/O thread) once the message is on the wire or dropped.
void release_shared(void*, void* hint) { delete static_cast<std::shared_ptr<const std::vector<uint8_t>>*>(hint); }

}  // namespace

const char* journal_drop_name(JournalDrop d) {
    switch (d) {
    case JournalDrop::none: return "none";
    case JournalDrop::parts: return "parts";
    case JournalDrop::identity: return "identity";
    case JournalDrop::size: return "size";
    case JournalDrop::unknown: return "unknown";
    case JournalDrop::rate: return "rate";
    case JournalDrop::busy: return "busy";
    case JournalDrop::no_lockstep: return "no-lockstep";
    case JournalDrop::window: return "window";
    case JournalDrop::count_: break;
    }
    return "?";
}

JournalRequest classify_journal_request(const std::string_view* parts, size_t count) {
    using namespace journal_limits;
    JournalRequest r;
    if (count != 2) {
        r.drop = JournalDrop::parts;
        return r;
    }
    if (parts[0].empty() || parts[0].size() > kMaxIdentityBytes) {
        r.drop = JournalDrop::identity;
        return r;
    }
    const std::string_view body = parts[1];
    if (body.size() > kMaxRequestBytes) {
        r.drop = JournalDrop::size;
        return r;
    }
    if (body == "SNAPSHOT") {
        r.kind = JournalRequestKind::snapshot;
        return r;
    }
    r.drop = JournalDrop::unknown;
    // "WORD n": n decimal as std::to_string writes it (no sign, no leading zero), at most `max`.
    struct Form {
        std::string_view word;
        JournalRequestKind kind;
        uint64_t max;
    };
    static constexpr Form forms[] = {{"SNAPSHOT AT ", JournalRequestKind::snapshot_at, UINT32_MAX},
                                     {"SINCE ", JournalRequestKind::since, UINT64_MAX},
                                     {"DONE ", JournalRequestKind::done, UINT32_MAX}};
    for (const Form& f : forms) {
        if (body.size() <= f.word.size() || body.substr(0, f.word.size()) != f.word) continue;
        const std::string_view digits = body.substr(f.word.size());
        if (digits.size() > 20 || (digits.size() > 1 && digits[0] == '0')) return r;
        uint64_t n = 0;
        for (char c : digits) {
            if (c < '0' || c > '9') return r;
            if (n > (f.max - uint64_t(c - '0')) / 10) return r;  // past the form's maximum
            n = n * 10 + uint64_t(c - '0');
        }
        r.kind = f.kind;
        r.drop = JournalDrop::none;
        (f.kind == JournalRequestKind::since ? r.sequence : r.frame) = n;
        return r;
    }
    return r;
}

bool JournalAdmission::Bucket::full(double burst, double rate, double now) const {
    return tokens < 0 || tokens + (now - last) * rate >= burst;
}

bool JournalAdmission::Bucket::take(double burst, double rate, double now) {
    if (tokens < 0) {
        tokens = burst;
        last = now;
    }
    if (now > last) tokens = std::min(burst, tokens + (now - last) * rate);
    last = std::max(last, now);  // a clock that goes back refills nothing
    if (tokens < 1) return false;
    tokens -= 1;
    return true;
}

bool JournalAdmission::admit(std::string_view identity, JournalRequestKind kind, double now) {
    using namespace journal_limits;
    if (kind == JournalRequestKind::invalid) return false;
    auto it = peers_.find(std::string(identity));
    if (it == peers_.end()) {
        if (peers_.size() >= kMaxPeers) {
            // A peer whose buckets have refilled is the same as one never seen: forget it.
            for (auto p = peers_.begin(); p != peers_.end();)
                p = p->second.snapshot.full(kSnapshotBurstPerPeer, kSnapshotRatePerPeer, now) &&
                            p->second.done.full(kDoneBurstPerPeer, kDoneRatePerPeer, now)
                        ? peers_.erase(p)
                        : std::next(p);
            if (peers_.size() >= kMaxPeers) return false;
        }
        it = peers_.emplace(std::string(identity), Peer{}).first;
    }
    // The peer's bucket first, so that one peer's flood does not drain everyone's. SINCE
    // sends messages as SNAPSHOT does, and shares its buckets.
    if (kind == JournalRequestKind::snapshot || kind == JournalRequestKind::since ||
        kind == JournalRequestKind::snapshot_at)
        return it->second.snapshot.take(kSnapshotBurstPerPeer, kSnapshotRatePerPeer, now) &&
               snapshot_total_.take(kSnapshotBurstTotal, kSnapshotRateTotal, now);
    return it->second.done.take(kDoneBurstPerPeer, kDoneRatePerPeer, now) &&
           done_total_.take(kDoneBurstTotal, kDoneRateTotal, now);
}


PublisherSink::PublisherSink(PublisherOptions options)
    : options_(std::move(options)), context_(std::make_unique<zmq::context_t>(1)) {
    verbose_ = options_.verbose;
    // With keys (GLCAST_KEYS), peers on TCP are CURVE clients whose public keys this process's
    // ZAP handler knows; it is bound before any socket that asks it (net/security.h).
    authenticator_ = net::authenticator_for(*context_, "the program's stream");
    make_socket();
    // `glcast run` starts its local slaves first and asks the program to wait for them, so that
    // a short program is not over before they listen. Only here, once: never during the run.
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
    if (!options_.snapshot_endpoint.empty()) snapshot_thread_ = std::thread([this] { serve_snapshots(); });
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
    if (h.frame > frame_.load(std::memory_order_relaxed)) frame_.store(h.frame, std::memory_order_relaxed);
    // One copy of the message, shared by the journal and the send: ZeroMQ sends it without a copy
    // of its own and frees it when the last subscriber's queue let go of it.
    Shared kept = std::make_shared<const std::vector<uint8_t>>(message);
    if (!options_.snapshot_endpoint.empty()) {
        std::deque<Shared> gone;  // freed after the lock is released
        bool first_loss = false;
        {
            std::lock_guard lock(journal_mutex_);
            if (journal_.empty()) journal_first_ = h.sequence;
            journal_.push_back(kept);
            journal_bytes_ += message.size();
            // A ring: the oldest go first; the newest message always stays.
            while (journal_bytes_ > options_.journal_limit_bytes && journal_.size() > 1) {
                first_loss |= journal_first_ == 0;
                journal_bytes_ -= journal_.front()->size();
                gone.push_back(std::move(journal_.front()));
                journal_.pop_front();
                journal_first_++;
            }
        }
        if (first_loss && verbose_)
            std::fprintf(stderr, "glcast: the journal passed GLCAST_JOURNAL_MB and keeps only the newest messages; "
                                 "slaves join late through a keeper (glcast keeper) from now on\n");
    }
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
    zmq::message_t body(const_cast<uint8_t*>(kept->data()), kept->size(), release_shared, new Shared(kept));
    if (!pub_->send(body, zmq::send_flags::dontwait)) dropped_++;
    // Lockstep (asked for): the frame this message ends must be replayed by every slave first. A
    // slave silent for kLockstepDropSeconds is no longer waited for; it is again once more slaves
    // than are waited for replay a frame (handle_request).
    if (options_.lockstep > 0 && (h.flags & kMsgFrameEnd)) {
        using journal_limits::kLockstepDropSeconds;
        std::unique_lock lock(done_mutex_);
        auto replayed = [&] {
            auto it = done_.find(h.frame);
            return it == done_.end() ? 0 : int(it->second.size());
        };
        if (!done_changed_.wait_for(lock, std::chrono::duration<double>(kLockstepDropSeconds),
                                    [&] { return replayed() >= lockstep_waited_; })) {
            std::fprintf(stderr, "glcast: lockstep: frame %u replayed by %d of %d slaves within %g s; going on without "
                                 "the rest until they are back\n",
                         h.frame, replayed(), lockstep_waited_, kLockstepDropSeconds);
            lockstep_waited_ = replayed();
        }
        done_.erase(done_.begin(), done_.upper_bound(h.frame));
        done_floor_ = std::max<uint64_t>(done_floor_, uint64_t(h.frame) + 1);
    }
}

// ROUTER side channel. A request is one part "SNAPSHOT"; the answer is every message from the
// first, one part each, then "END". "SINCE n": the messages from sequence n on, then "END". A
// journal that no longer holds the first message asked for answers "GONE". "DONE n" says a slave
// replayed frame n (lockstep). Anything else is dropped and counted; limits in
// master/publisher.h, reasons in docs/security.md.
void PublisherSink::serve_snapshots() {
    using namespace journal_limits;
    zmq::socket_t router(*context_, zmq::socket_type::router);
    try {
        // A peer that never reads fills its queue to the mark; then sends to it fail at once
        // (mandatory: EAGAIN rather than a silent drop) and its session waits, then ends.
        router.set(zmq::sockopt::sndhwm, kSendHwm);
        router.set(zmq::sockopt::router_mandatory, 1);
        router.set(zmq::sockopt::maxmsgsize, int64_t(kMaxFrameBytes));
        router.set(zmq::sockopt::rcvhwm, 1000);
        router.set(zmq::sockopt::linger, 0);
        net::secure_server(router, options_.snapshot_endpoint);
        router.bind(options_.snapshot_endpoint);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast: cannot serve the journal on %s: %s\n", options_.snapshot_endpoint.c_str(), e.what());
        return;
    }
    zmq::message_t parts[kMaxPartsRead];
    while (!stopping_) {
        bool progress = false;
        // A bounded number of requests per turn, so sessions are served during a flood too.
        for (int n = 0; n < 1024; n++) {
            size_t count = 0;
            try {
                if (!router.recv(parts[0], zmq::recv_flags::dontwait)) break;
                count = 1;
                for (zmq::message_t* last = &parts[0]; last->more(); count++) {
                    // Parts past the last slot are read into it and forgotten: a message
                    // with that many parts is dropped anyway. libzmq delivers a message's
                    // parts together, so these never wait.
                    last = &parts[std::min(count, kMaxPartsRead - 1)];
                    if (!router.recv(*last, zmq::recv_flags::dontwait)) break;
                }
            } catch (const zmq::error_t&) {
                break;
            }
            std::string_view views[kMaxPartsRead];
            const size_t kept = std::min(count, kMaxPartsRead);
            for (size_t i = 0; i < kept; i++) views[i] = std::string_view(parts[i].data<char>(), parts[i].size());
            handle_request(views, count, seconds_now());
            progress = true;
        }
        const double now = seconds_now();
        for (auto it = active_.begin(); it != active_.end();) {
            const size_t before = it->next;
            const bool started = it->started;
            const bool finished = serve(router, *it, now);
            progress |= it->next != before || started != it->started || finished;
            it = finished ? active_.erase(it) : std::next(it);
        }
        while (active_.size() < kMaxActiveSnapshots && !pending_.empty()) {
            active_.push_back(std::move(pending_.front()));
            pending_.pop_front();
            active_.back().last_progress = now;
        }
        if (progress) continue;
        zmq::pollitem_t item{router.handle(), 0, ZMQ_POLLIN, 0};
        // Sessions waiting for a full peer queue are looked at again soon; ROUTER's POLLOUT
        // says nothing about one peer.
        zmq::poll(&item, 1, std::chrono::milliseconds(active_.empty() ? 100 : 5));
    }
    if (verbose_) {
        std::string counts;
        for (size_t d = 1; d < size_t(JournalDrop::count_); d++)
            if (drops_[d]) counts += " " + std::string(journal_drop_name(JournalDrop(d))) + "=" + std::to_string(drops_[d]);
        std::fprintf(stderr, "glcast: journal: %llu snapshots served, %llu peers stopped for not reading, dropped requests:%s\n",
                     (unsigned long long)served_, (unsigned long long)stalled_, counts.empty() ? " none" : counts.c_str());
    }
}

void PublisherSink::handle_request(const std::string_view* parts, size_t count, double now) {
    using namespace journal_limits;
    const JournalRequest r = classify_journal_request(parts, count);
    auto drop = [&](JournalDrop why) { drops_[size_t(why)]++; };
    if (r.kind == JournalRequestKind::invalid) return drop(r.drop);
    if (r.kind == JournalRequestKind::snapshot_at) return drop(JournalDrop::unknown);  // a keeper's
    if (r.kind == JournalRequestKind::done && options_.lockstep <= 0) return drop(JournalDrop::no_lockstep);
    if (!admission_.admit(parts[0], r.kind, now)) return drop(JournalDrop::rate);
    if (r.kind == JournalRequestKind::done) {
        const uint64_t current = frame_.load(std::memory_order_relaxed);
        const size_t who = std::hash<std::string_view>{}(parts[0]);
        std::lock_guard lock(done_mutex_);
        const uint64_t low = std::max(done_floor_, current > kDoneWindowFrames ? current - kDoneWindowFrames : 0);
        if (r.frame < low || r.frame > current + 1) return drop(JournalDrop::window);
        auto& slaves = done_[r.frame];
        // Distinct identities, at most the number waited for: one peer cannot stand for all.
        if (int(slaves.size()) < options_.lockstep && std::find(slaves.begin(), slaves.end(), who) == slaves.end())
            slaves.push_back(who);
        if (int(slaves.size()) > lockstep_waited_) {  // a slave is back (or came at last)
            lockstep_waited_ = int(slaves.size());
            if (verbose_) std::fprintf(stderr, "glcast: lockstep: waiting for %d slaves again\n", lockstep_waited_);
        }
        done_changed_.notify_all();
        return;
    }
    auto same = [&](const Session& s) { return s.identity == parts[0]; };
    if (std::any_of(active_.begin(), active_.end(), same) || std::any_of(pending_.begin(), pending_.end(), same) ||
        pending_.size() >= kMaxPendingSnapshots)
        return drop(JournalDrop::busy);
    Session s;
    s.identity = std::string(parts[0]);
    s.whole = r.kind == JournalRequestKind::snapshot;
    s.next = r.sequence;
    s.last_progress = now;
    pending_.push_back(std::move(s));
}

// Sends what the peer's queue takes now, at most 256 messages a turn so that requests (DONE
// for lockstep among them) are read between; never waits. True: finished, or given up.
static bool is_delta(const std::vector<uint8_t>& message) {
    MessageHeader h{};
    if (message.size() >= sizeof h) std::memcpy(&h, message.data(), sizeof h);
    return (h.flags & (kMsgDelta | kMsgXor)) != 0;  // coded against the message before it
}

bool PublisherSink::serve(zmq::socket_t& router, Session& s, double now) {
    using namespace journal_limits;
    if (!s.started) {
        std::lock_guard lock(journal_mutex_);
        if (s.whole) s.next = 0;
        // Up to the newest message: it holds the first live message the slave saw, so the
        // answer covers everything before.
        s.end = journal_first_ + journal_.size();
        // From the key message at or before the one asked for (or before the newest, when the
        // one asked for is yet to come, coded against the newest): a message coded against the
        // one before it (kMsgDelta, kMsgXor) cannot be read without it. The peer unpacks the few
        // before the one it asked for to reach it, and drops them. Without that key: GONE.
        if (!s.whole && s.end > journal_first_ && s.next >= journal_first_) {
            uint64_t at = std::min(s.next, s.end - 1);
            while (at > journal_first_ && is_delta(*journal_[size_t(at - journal_first_)])) at--;
            if (is_delta(*journal_[size_t(at - journal_first_)]))
                s.next = journal_first_ > 0 ? journal_first_ - 1 : s.end + 1;  // the key is gone: GONE
            else
                s.next = std::min(s.next, at);
        }
        s.started = true;
    }
    auto send_part = [&](zmq::message_t& body) -> int {  // 1 sent, 0 queue full, -1 peer gone
        try {
            if (!router.send(zmq::buffer(s.identity), zmq::send_flags::sndmore | zmq::send_flags::dontwait)) return 0;
            router.send(body, zmq::send_flags::dontwait);
            return 1;
        } catch (const zmq::error_t&) {
            return -1;  // EHOSTUNREACH: disconnected
        }
    };
    auto queue_full = [&] {
        if (now - s.last_progress <= kStallSeconds) return false;
        // Said for the first few only: peers that keep doing it could fill the program's stderr.
        stalled_++;
        if (verbose_ && stalled_ <= 8)
            std::fprintf(stderr, "glcast: journal: a peer took nothing for %.0f s; no longer serving it%s\n", kStallSeconds,
                         stalled_ == 8 ? " (further ones are only counted)" : "");
        return true;
    };
    constexpr size_t kBatch = 32;
    for (int turn = 0; turn < 8; turn++) {
        Shared batch[kBatch];
        size_t n = 0;
        bool complete;
        {
            std::lock_guard lock(journal_mutex_);
            // GONE: the journal no longer holds the next message asked for (or never will).
            complete = s.next >= journal_first_ && s.next <= s.end;
            if (complete)
                for (; n < kBatch && s.next + n < s.end; n++) batch[n] = journal_[size_t(s.next + n - journal_first_)];
        }
        if (!complete || n == 0) {
            zmq::message_t last(complete ? std::string_view("END") : std::string_view("GONE"));
            const int r = send_part(last);
            if (r == 0) return queue_full();
            if (r > 0) served_++;
            return true;
        }
        for (size_t i = 0; i < n; i++) {
            const Shared& m = batch[i];
            zmq::message_t body(const_cast<uint8_t*>(m->data()), m->size(), release_shared, new Shared(m));
            const int r = send_part(body);
            if (r < 0) return true;
            if (r == 0) return queue_full();
            s.next++;
            s.last_progress = now;
        }
    }
    return false;
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
    authenticator_.reset();
    context_.reset();
}

}  // namespace glcast
