// A keeper or journal that answers a catching-up slave with more than it may hold, or too slowly
// to ever end (slave/network_source.cpp receive_parts): the slave gives up with a message that
// names the limit, its memory bounded, instead of taking parts forever.
#include <gtest/gtest.h>
#include <zmq.hpp>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>
#include <string>
#include <thread>
#include <unistd.h>

#include "protocol/format.h"
#include "slave/network_source.h"

using namespace glcast;

namespace {

// A fake keeper on `endpoint`: answers the first request with "STATE 1 1", then sends parts of
// `part_bytes` every `every` until stopped.
class FakeKeeper {
public:
    FakeKeeper(const std::string& endpoint, size_t part_bytes, std::chrono::milliseconds every)
        : router_(context_, zmq::socket_type::router) {
        router_.set(zmq::sockopt::linger, 0);
        router_.set(zmq::sockopt::sndhwm, 4);
        router_.bind(endpoint);
        thread_ = std::thread([this, part_bytes, every] {
            zmq::pollitem_t item{router_.handle(), 0, ZMQ_POLLIN, 0};
            while (!stop_ && !(zmq::poll(&item, 1, std::chrono::milliseconds(50)), item.revents & ZMQ_POLLIN)) {
            }
            if (stop_) return;
            zmq::message_t identity, request;
            (void)router_.recv(identity);
            (void)router_.recv(request);
            auto send = [&](const std::string& body) {
                router_.send(zmq::buffer(identity.data(), identity.size()), zmq::send_flags::sndmore);
                return router_.send(zmq::buffer(body), zmq::send_flags::dontwait).has_value();
            };
            send("STATE 1 1");
            const std::string part(part_bytes, 'x');
            while (!stop_) {
                if (!send(part)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
                if (every.count()) std::this_thread::sleep_for(every);
            }
        });
    }
    ~FakeKeeper() {
        stop_ = true;
        thread_.join();
    }

private:
    zmq::context_t context_{1};
    zmq::socket_t router_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

// The sockets' files are removed when the test program ends.
struct SocketFiles {
    std::vector<std::string> paths;
    ~SocketFiles() {
        for (const std::string& p : paths) std::remove(p.c_str());
    }
};

std::string endpoint(const char* name) {
    static SocketFiles made;
    const std::string path = "/tmp/glcast-hostile-" + std::to_string(getpid()) + "-" + name;
    made.paths.push_back(path);
    return "ipc://" + path;
}

std::string join_error(const std::string& keeper, int wait_seconds, uint64_t catch_up_bytes = 0) {
    try {
        slave::NetworkSource source(endpoint("stream"), "", wait_seconds, keeper, 0, catch_up_bytes);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

}  // namespace

// Endless zero-byte parts cost the slave memory (a message each) but counted nothing against the
// catch-up limit, which only bytes fed: the first part that is no message ends the join.
TEST(HostilePeer, AKeeperThatSendsPartsThatAreNoMessagesIsRefusedAtTheFirst) {
    const std::string at = endpoint("empty");
    FakeKeeper empty(at, 0, std::chrono::milliseconds(0));
    const auto start = std::chrono::steady_clock::now();
    const std::string error = join_error(at, 30);
    EXPECT_NE(error.find("a part of 0 bytes, which is no message"), std::string::npos) << error;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(3));
}

TEST(HostilePeer, AKeeperThatNeverStopsSendingIsCutOffAtTheCatchUpLimit) {
    const std::string at = endpoint("flood");
    FakeKeeper flood(at, 64 << 10, std::chrono::milliseconds(0));
    const auto start = std::chrono::steady_clock::now();
    const std::string error = join_error(at, 30, uint64_t(8) << 20);
    EXPECT_NE(error.find("sent more than 8 MiB to catch up with (GLCAST_CATCH_UP_MB)"), std::string::npos) << error;
    EXPECT_NE(error.find(at), std::string::npos) << error;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
}

TEST(HostilePeer, AKeeperThatTricklesIsCutOffAfterTheWait) {
    const std::string at = endpoint("trickle");
    FakeKeeper trickle(at, 100, std::chrono::milliseconds(20));
    const auto start = std::chrono::steady_clock::now();
    const std::string error = join_error(at, 1);
    EXPECT_NE(error.find("slower than 1 MiB a second"), std::string::npos) << error;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

namespace {

std::vector<uint8_t> empty_message(uint64_t sequence) {
    std::vector<uint8_t> m(sizeof(MessageHeader), 0);
    MessageHeader h{};
    h.magic = kMessageMagic;
    h.sequence = sequence;
    h.frame = sequence;
    h.flags = kMsgFrameEnd;
    std::memcpy(m.data(), &h, sizeof h);
    return m;
}

// A master whose journal answers "SNAPSHOT" with messages 0 and 1 and every "SINCE" with nothing
// at all, and whose stream sends message 1 until `gap` is set, then message 9 (7 were lost).
class LyingJournalMaster {
public:
    explicit LyingJournalMaster(const std::string& stream, const std::string& journal)
        : pub_(context_, zmq::socket_type::pub), router_(context_, zmq::socket_type::router) {
        pub_.set(zmq::sockopt::linger, 0);
        router_.set(zmq::sockopt::linger, 0);
        pub_.bind(stream);
        router_.bind(journal);
        thread_ = std::thread([this] {
            while (!stop_) {
                const auto m = empty_message(gap_ ? 9 : 1);
                (void)pub_.send(zmq::buffer(m), zmq::send_flags::dontwait);
                zmq::pollitem_t item{router_.handle(), 0, ZMQ_POLLIN, 0};
                zmq::poll(&item, 1, std::chrono::milliseconds(20));
                if (!(item.revents & ZMQ_POLLIN)) continue;
                zmq::message_t identity, request;
                (void)router_.recv(identity);
                (void)router_.recv(request);
                auto send = [&](const void* data, size_t size, bool more) {
                    router_.send(zmq::buffer(identity.data(), identity.size()), zmq::send_flags::sndmore);
                    (void)router_.send(zmq::buffer(data, size), more ? zmq::send_flags::sndmore : zmq::send_flags::none);
                };
                const std::string text = request.to_string();
                if (text == "SNAPSHOT") {
                    for (uint64_t s : {0, 1}) {
                        const auto part = empty_message(s);
                        send(part.data(), part.size(), false);
                    }
                } else if (text.rfind("SINCE", 0) == 0) {
                    sinces_++;
                    if (silent_since_) continue;  // a program that ended: its journal answers nothing
                }
                send("END", 3, false);
            }
        });
    }
    ~LyingJournalMaster() {
        stop_ = true;
        thread_.join();
    }
    std::atomic<bool> gap_{false};
    std::atomic<int> sinces_{0};
    std::atomic<bool> silent_since_{false};

private:
    zmq::context_t context_{1};
    zmq::socket_t pub_, router_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace

// After a gap, a journal that answers SINCE with nothing (or a live message far ahead of what
// the journal has): the slave asked again and again forever. It gives up after a few tries that
// bring nothing, with a message that says so.
TEST(HostilePeer, AJournalThatAnswersAGapWithNothingIsGivenUpOn) {
    const std::string base = "ipc:///tmp/glcast-lying-journal-" + std::to_string(getpid());
    LyingJournalMaster master(base + "-stream", base + "-journal");
    std::atomic<bool> finished{false};
    std::string error;
    std::thread slave([&] {
        try {
            slave::NetworkSource source(base + "-stream", base + "-journal", 5);
            Message m;
            while (source.next(m)) master.gap_ = true;  // the snapshot's messages are in: now the gap
        } catch (const std::exception& e) {
            error = e.what();
        }
        finished = true;
    });
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!finished && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!finished) {
        std::fprintf(stderr, "the slave still asks after 20 s (%d SINCE requests)\n", master.sinces_.load());
        std::fflush(stderr);
        _exit(1);  // its thread cannot be stopped
    }
    slave.join();
    std::printf("%d SINCE requests, then: %s\n", master.sinces_.load(), error.c_str());
    EXPECT_NE(error.find("journal"), std::string::npos) << error;
    EXPECT_LE(master.sinces_.load(), 4);
}

// After a gap, a journal that never answers (the program ended, and its journal with it): the
// slave waited the whole --wait (glcast run gives 120 s, and then waited as long for the slave,
// scripts/chaos.py). The journal answers from memory: 10 s of silence and the slave gives up,
// saying so.
TEST(HostilePeer, AJournalThatNeverAnswersIsGivenUpOnBeforeTheWait) {
    const std::string base = "ipc:///tmp/glcast-silent-journal-" + std::to_string(getpid());
    LyingJournalMaster master(base + "-stream", base + "-journal");
    master.silent_since_ = true;
    std::atomic<bool> finished{false};
    std::string error;
    const auto start = std::chrono::steady_clock::now();
    std::thread slave([&] {
        try {
            slave::NetworkSource source(base + "-stream", base + "-journal", 60);
            Message m;
            while (source.next(m)) master.gap_ = true;
        } catch (const std::exception& e) {
            error = e.what();
        }
        finished = true;
    });
    const auto deadline = start + std::chrono::seconds(30);
    while (!finished && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!finished) {
        std::fprintf(stderr, "the slave still waits for the journal after 30 s\n");
        std::fflush(stderr);
        _exit(1);  // its thread cannot be stopped
    }
    slave.join();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("given up after %.1f s: %s\n", seconds, error.c_str());
    EXPECT_NE(error.find("did not answer within 10 s"), std::string::npos) << error;
    EXPECT_LT(seconds, 20.0);
}

// A keeper that takes the request and never answers (one restarted and still rebuilding the
// state from the stream's start: the hour-long chaos run, docs/reliability.md): the slave waited
// the whole --wait and gave up, so no restarted tile joined again. The keeper answers a plain
// SNAPSHOT at its live edge, from memory: after 10 s of silence the slave catches up from the
// journal instead, as it does when a keeper says it has nothing yet.
TEST(HostilePeer, ASilentKeeperIsLeftForTheJournal) {
    const std::string base = "ipc:///tmp/glcast-silent-keeper-" + std::to_string(getpid());
    LyingJournalMaster master(base + "-stream", base + "-journal");
    zmq::context_t context(1);
    zmq::socket_t keeper(context, zmq::socket_type::router);  // takes requests, answers none
    keeper.set(zmq::sockopt::linger, 0);
    keeper.bind(base + "-keeper");
    const auto start = std::chrono::steady_clock::now();
    std::string error;
    uint64_t first = UINT64_MAX;
    try {
        slave::NetworkSource source(base + "-stream", base + "-journal", 60, base + "-keeper");
        Message m;
        if (source.next(m)) first = m.header.sequence;
    } catch (const std::exception& e) {
        error = e.what();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("joined after %.1f s at message %llu%s%s\n", seconds, (unsigned long long)first, error.empty() ? "" : ": ",
                error.c_str());
    EXPECT_TRUE(error.empty()) << error;
    EXPECT_EQ(first, 0u);  // the journal's whole stream, from its first message
    EXPECT_LT(seconds, 20.0);
}
