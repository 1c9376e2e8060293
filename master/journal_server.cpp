#include "master/journal_server.h"

#include <pthread.h>
#include <zmq.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>

#include "master/zero_copy.h"
#include "net/security.h"

namespace glcast {

namespace {

double seconds_now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

JournalServer::JournalServer(zmq::context_t& context, std::string endpoint, const Journal& journal,
                             LockstepBarrier& lockstep, bool verbose)
    : context_(context), endpoint_(std::move(endpoint)), journal_(journal), lockstep_(lockstep), verbose_(verbose) {
    thread_ = std::thread([this] {
        pthread_setname_np(pthread_self(), "glcast-journal");  // glcast's own (interceptor/lifetime.h)
        run();
    });
}

JournalServer::~JournalServer() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
}

void JournalServer::run() {
    using namespace journal_limits;
    zmq::socket_t router(context_, zmq::socket_type::router);
    try {
        // A peer that never reads fills its queue to the mark; then sends to it fail at once
        // (mandatory: EAGAIN rather than a silent drop) and its session waits, then ends.
        router.set(zmq::sockopt::sndhwm, kSendHwm);
        router.set(zmq::sockopt::router_mandatory, 1);
        router.set(zmq::sockopt::maxmsgsize, int64_t(kMaxFrameBytes));
        router.set(zmq::sockopt::rcvhwm, 1000);
        router.set(zmq::sockopt::linger, 0);
        net::secure_server(router, endpoint_);
        router.bind(endpoint_);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast: cannot serve the journal on %s: %s\n", endpoint_.c_str(), e.what());
        return;
    }
    while (!stopping_) {
        bool progress = read_requests(router);
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
    if (verbose_) say_counts();
}

// A bounded number of requests per turn, so sessions are served during a flood too.
bool JournalServer::read_requests(zmq::socket_t& router) {
    using journal_limits::kMaxPartsRead;
    zmq::message_t parts[kMaxPartsRead];
    bool any = false;
    for (int n = 0; n < 1024; n++) {
        size_t count = 0;
        try {
            if (!router.recv(parts[0], zmq::recv_flags::dontwait)) break;
            count = 1;
            for (zmq::message_t* last = &parts[0]; last->more(); count++) {
                // Parts past the last slot are read into it and forgotten: a message with that
                // many parts is dropped anyway. libzmq delivers a message's parts together, so
                // these never wait.
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
        any = true;
    }
    return any;
}

void JournalServer::handle_request(const std::string_view* parts, size_t count, double now) {
    using namespace journal_limits;
    const JournalRequest r = classify_journal_request(parts, count);
    auto drop = [&](JournalDrop why) { drops_[size_t(why)]++; };
    if (r.kind == JournalRequestKind::invalid) return drop(r.drop);
    if (r.kind == JournalRequestKind::snapshot_at) return drop(JournalDrop::unknown);  // a keeper's
    if (r.kind == JournalRequestKind::done && !lockstep_.enabled()) return drop(JournalDrop::no_lockstep);
    if (!admission_.admit(parts[0], r.kind, now)) return drop(JournalDrop::rate);
    if (r.kind == JournalRequestKind::done) {
        const JournalDrop why = lockstep_.replayed(r.frame, std::hash<std::string_view>{}(parts[0]));
        if (why != JournalDrop::none) drop(why);
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

bool JournalServer::stalled(const Session& s, double now) {
    using journal_limits::kStallSeconds;
    if (now - s.last_progress <= kStallSeconds) return false;
    // Said for the first few only: peers that keep doing it could fill the program's stderr.
    stalled_++;
    if (verbose_ && stalled_ <= 8)
        std::fprintf(stderr, "glcast: journal: a peer took nothing for %.0f s; no longer serving it%s\n", kStallSeconds,
                     stalled_ == 8 ? " (further ones are only counted)" : "");
    return true;
}

// Sends what the peer's queue takes now, at most 256 messages a turn so that requests (DONE
// for lockstep among them) are read between; never waits.
bool JournalServer::serve(zmq::socket_t& router, Session& s, double now) {
    if (!s.started) {
        // Up to the newest message: it holds the first live message the slave saw, so the answer
        // covers everything before.
        s.end = journal_.end_now();
        s.next = s.whole ? 0 : journal_.start_for(s.next, s.end);
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
    constexpr size_t kBatch = 32;
    for (int turn = 0; turn < 8; turn++) {
        Journal::Shared batch[kBatch];
        bool held = false;
        const size_t n = journal_.take(s.next, s.end, batch, kBatch, held);
        if (!held || n == 0) {  // GONE: the journal no longer holds the next message asked for
            zmq::message_t last(held ? std::string_view("END") : std::string_view("GONE"));
            const int r = send_part(last);
            if (r == 0) return stalled(s, now);
            if (r > 0) served_++;
            return true;
        }
        for (size_t i = 0; i < n; i++) {
            zmq::message_t body = zero_copy_message(batch[i]);
            const int r = send_part(body);
            if (r < 0) return true;
            if (r == 0) return stalled(s, now);
            s.next++;
            s.last_progress = now;
        }
    }
    return false;
}

void JournalServer::say_counts() const {
    std::string counts;
    for (size_t d = 1; d < size_t(JournalDrop::count_); d++)
        if (drops_[d]) counts += " " + std::string(journal_drop_name(JournalDrop(d))) + "=" + std::to_string(drops_[d]);
    std::fprintf(stderr, "glcast: journal: %llu snapshots served, %llu peers stopped for not reading, dropped requests:%s\n",
                 (unsigned long long)served_, (unsigned long long)stalled_, counts.empty() ? " none" : counts.c_str());
}

}  // namespace glcast
