#include "keeper/keeper_service.h"

#include "net/security.h"

#include <unistd.h>
#include <zlib.h>
#include <zmq.hpp>

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <optional>

#include "common/environment.h"
#include "keeper/kept_calls.h"
#include "keeper/kept_state.h"
#include "keeper/snapshot.h"
#include "master/journal_requests.h"
#include "master/stream.h"
#include "protocol/format.h"
#include "slave/backend.h"
#include "slave/network_source.h"
#include "slave/replayer.h"

namespace glcast::keeper {

namespace {

double seconds_now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Holds the messages of one snapshot as the master's Stream frames and compresses them.
class CollectSink : public MessageSink {
public:
    explicit CollectSink(std::vector<std::vector<uint8_t>>& out) : out_(out) {}
    void write(const std::vector<uint8_t>& message) override { out_.push_back(message); }

private:
    std::vector<std::vector<uint8_t>>& out_;
};

constexpr size_t kMaxWaiting = 64;  // requests answered at one boundary; more wait for the next

// The keeper's stream: the master's messages, and between two of them, when the last one ended
// a frame (or while none arrives), the requests waiting on the ROUTER socket answered.
class KeeperSource : public MessageSource {
public:
    KeeperSource(slave::NetworkSource& live, slave::Replayer& keeper, KeptCalls& kept, zmq::socket_t& router,
                 const KeeperOptions& options)
        : live_(live), keeper_(keeper), kept_(kept), router_(router), verbose_(options.verbose),
          state_path_(options.state_path), state_every_(options.state_every_seconds),
          next_save_(seconds_now() + options.state_every_seconds) {
        live_.on_idle = [this] {
            if (at_boundary_) serve();
        };
        live_.set_idle_interval(5);  // a request waits at most this long while the program is idle
    }

    bool next(Message& m) override {
        if (at_boundary_) serve();
        if (!live_.next(m)) return false;
        if (live_.from_state()) {  // its own kept state, replayed first: numbered as a snapshot, not the stream
            at_boundary_ = false;
            return true;
        }
        last_sequence_ = m.header.sequence;
        at_boundary_ = (m.header.flags & kMsgFrameEnd) != 0;
        started_ = true;
        if (at_boundary_ && !state_path_.empty() && seconds_now() >= next_save_) {
            // What binds the kept state to this stream: the payload of the message it ends at.
            boundary_crc_ = uint32_t(crc32(0, m.payload.data(), uInt(m.payload.size())));
            save_due_ = true;
        }
        return true;
    }

private:
    // The snapshot of the keeper's state now (at a frame boundary), as compressed stream messages.
    // False (with `report.missing`) when some of the state cannot be held.
    bool take_snapshot(std::vector<std::vector<uint8_t>>& messages, SnapshotReport& report) {
        std::vector<std::unique_ptr<MessageSink>> sinks;
        sinks.push_back(std::make_unique<CollectSink>(messages));
        Stream stream(std::move(sinks), 1, 4);
        report = write_snapshot(keeper_, kept_, [&](const uint8_t* t, size_t n) { stream.append(t, n); });
        stream.close();
        return report.missing.empty();
    }

    // Every state_every_ seconds: the state on disk, for a keeper started again after this one.
    // One that cannot be held, or a disk that refuses it, leaves the last one there (older, but
    // still this stream's, and still good while the journal holds what follows it).
    void save_state() {
        save_due_ = false;
        next_save_ = seconds_now() + state_every_;
        const auto start = std::chrono::steady_clock::now();
        std::vector<std::vector<uint8_t>> messages;
        SnapshotReport report;
        if (!take_snapshot(messages, report)) return;
        slave::NetworkSource::State state;
        state.sequence = last_sequence_;
        state.frame = keeper_.frame();
        state.boundary_crc = boundary_crc_;
        for (auto& m : messages) state.messages.push_back(std::move(m));
        std::string error;
        if (!save_kept_state(state_path_, state, error)) {
            if (!save_failed_) std::fprintf(stderr, "glcast keeper: cannot keep its state: %s\n", error.c_str());
            save_failed_ = true;
            return;
        }
        save_failed_ = false;
        if (verbose_)
            std::fprintf(stderr, "glcast keeper: kept the state of frame %" PRIu64 " (%zu messages) in %.1f ms\n",
                         state.frame, state.messages.size(),
                         std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }

    void serve() {
        if (save_due_) save_state();
        std::vector<std::string> waiting;
        const double now = seconds_now();
        // Requests for a later frame wait until the replay gets there.
        for (auto it = later_.begin(); it != later_.end();) {
            if (keeper_.frame() < it->second) {
                ++it;
                continue;
            }
            waiting.push_back(it->first);
            it = later_.erase(it);
        }
        for (size_t n = 0; n < 1024; ++n) {
            zmq::message_t parts[3];
            size_t count = 0;
            try {
                if (!router_.recv(parts[0], zmq::recv_flags::dontwait)) break;
                count = 1;
                while (parts[std::min<size_t>(count - 1, 2)].more() && count < 64) {
                    if (!router_.recv(parts[std::min<size_t>(count, 2)], zmq::recv_flags::dontwait)) break;
                    count++;
                }
            } catch (const zmq::error_t&) {
                break;
            }
            std::string_view views[2] = {std::string_view(parts[0].data<char>(), parts[0].size()),
                                         count > 1 ? std::string_view(parts[1].data<char>(), parts[1].size())
                                                   : std::string_view()};
            const JournalRequest r = classify_journal_request(views, count);
            const bool at = r.kind == JournalRequestKind::snapshot_at;
            if ((r.kind != JournalRequestKind::snapshot && !at) || !admission_.admit(views[0], r.kind, now)) continue;
            if (at && keeper_.frame() < r.frame) {
                if (later_.size() < kMaxWaiting) later_.emplace_back(std::string(views[0]), r.frame);
                continue;
            }
            if (waiting.size() < kMaxWaiting) waiting.emplace_back(views[0]);
        }
        if (waiting.empty()) return;
        if (!started_) {  // nothing replayed yet: the master's journal has it all
            for (const std::string& who : waiting) send(who, "NONE the keeper has not received the stream yet");
            return;
        }
        const auto start = std::chrono::steady_clock::now();
        std::vector<std::vector<uint8_t>> messages;
        SnapshotReport report;
        take_snapshot(messages, report);
        // A snapshot that cannot hold some of the state would show a wrong picture: the slave is
        // told why and falls back to the journal (docs/keeper.md).
        if (!report.missing.empty()) {
            std::string why = "NONE the snapshot cannot hold " + report.missing.front();
            if (report.missing.size() > 1) why += " (and " + std::to_string(report.missing.size() - 1) + " more)";
            for (const std::string& who : waiting) send(who, why);
            for (const std::string& what : report.missing)
                std::fprintf(stderr, "glcast keeper: not in the snapshot: %s\n", what.c_str());
            return;
        }
        const std::string header = "STATE " + std::to_string(last_sequence_) + " " + std::to_string(keeper_.frame());
        size_t bytes = 0;
        for (const auto& m : messages) bytes += m.size();
        for (const std::string& who : waiting) {
            if (!send(who, header)) continue;
            for (const auto& m : messages)
                if (!send(who, std::string_view(reinterpret_cast<const char*>(m.data()), m.size()))) break;
            send(who, "END");
        }
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        if (verbose_ || !report.missing.empty()) {
            std::fprintf(stderr, "glcast keeper: snapshot of frame %" PRIu64 " for %zu slaves: %zu messages, %zu bytes, "
                                 "%.1f ms\n", keeper_.frame(), waiting.size(), messages.size(), bytes, ms);
            for (const std::string& what : report.missing)
                std::fprintf(stderr, "glcast keeper: not in the snapshot: %s\n", what.c_str());
        }
    }

    bool send(const std::string& who, std::string_view body) {
        try {
            if (!router_.send(zmq::buffer(who), zmq::send_flags::sndmore | zmq::send_flags::dontwait)) return false;
            return router_.send(zmq::buffer(body.data(), body.size()), zmq::send_flags::dontwait).has_value();
        } catch (const zmq::error_t&) {
            return false;  // the peer is gone
        }
    }

    slave::NetworkSource& live_;
    slave::Replayer& keeper_;
    KeptCalls& kept_;
    zmq::socket_t& router_;
    bool verbose_;
    std::string state_path_;
    int state_every_;
    double next_save_;
    bool save_due_ = false, save_failed_ = false;
    uint32_t boundary_crc_ = 0;
    bool at_boundary_ = false, started_ = false;
    uint64_t last_sequence_ = 0;
    JournalAdmission admission_;
    std::vector<std::pair<std::string, uint64_t>> later_;  // SNAPSHOT AT n: who, n
};

}  // namespace

int run_keeper(const KeeperOptions& o) {
    std::string error;
    std::unique_ptr<slave::Backend> backend = slave::make_backend(o.backend, error);
    if (!backend) {
        std::fprintf(stderr, "glcast keeper: %s\n", error.c_str());
        return 1;
    }
    zmq::context_t context(1);
    std::unique_ptr<net::Authenticator> authenticator;
    zmq::socket_t router(context, zmq::socket_type::router);
    try {
        authenticator = net::authenticator_for(context, "the keeper");
        // A snapshot is sent whole to each slave that asked (at most kMaxWaiting at a time,
        // admitted by rate as the journal's requests): its queue holds one snapshot.
        router.set(zmq::sockopt::sndhwm, 0);
        router.set(zmq::sockopt::router_mandatory, 1);
        router.set(zmq::sockopt::maxmsgsize, int64_t(journal_limits::kMaxFrameBytes));
        router.set(zmq::sockopt::linger, 0);
        net::secure_server(router, o.bind);
        router.bind(o.bind);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast keeper: cannot serve snapshots on %s: %s\n", o.bind.c_str(), e.what());
        return 1;
    }
    try {
        // A state kept by a keeper before this one: the journal's messages since it, not the
        // stream's start. One refused is said and left for the journal.
        std::optional<slave::NetworkSource::State> kept_state;
        if (!o.state_path.empty()) {
            slave::NetworkSource::State state;
            if (load_kept_state(o.state_path, environment().catch_up_bytes, state, error)) {
                std::fprintf(stderr, "glcast keeper: starting from its kept state of frame %" PRIu64 " (%zu messages)\n",
                             state.frame, state.messages.size());
                kept_state = std::move(state);
            } else if (!error.empty()) {
                std::fprintf(stderr, "glcast keeper: not starting from its kept state: %s\n", error.c_str());
            }
        }
        slave::NetworkSource live(o.connect, o.journal, o.wait_seconds, "", 0, 0, std::move(kept_state));
        slave::Replayer keeper(std::move(backend), slave::ReplayOptions{});
        keeper.set_frame(live.joined_frame());
        KeptCalls kept(keeper);
        keeper.watch(&kept);
        live.on_restart = [&] {
            throw std::runtime_error("the keeper lost messages the master's journal no longer holds (" + live.gap() +
                                     "): its state is gone; restart it while the journal holds the stream's start");
        };
        KeeperSource source(live, keeper, kept, router, o);
        keeper.replay(source);
        if (!o.state_path.empty()) unlink(o.state_path.c_str());  // the program's state is of no more use
        std::fprintf(stderr, "glcast keeper: the program ended at frame %" PRIu64 " (%" PRIu64 " frames replayed here, %" PRIu64
                             " calls refused)\n", keeper.frame(), keeper.stats().frames, keeper.stats().errors);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast keeper: %s\n", e.what());
        return 1;
    }
}

}  // namespace glcast::keeper
