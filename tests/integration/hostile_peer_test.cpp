// A keeper or journal that answers a catching-up slave with more than it may hold, or too slowly
// to ever end (slave/network_source.cpp receive_parts): the slave gives up with a message that
// names the limit, its memory bounded, instead of taking parts forever.
#include <gtest/gtest.h>
#include <zmq.hpp>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <unistd.h>

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

std::string endpoint(const char* name) {
    return "ipc:///tmp/glcast-hostile-" + std::to_string(getpid()) + "-" + name;
}

std::string join_error(const std::string& keeper, int wait_seconds) {
    try {
        slave::NetworkSource source(endpoint("stream"), "", wait_seconds, keeper);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(HostilePeer, AKeeperThatNeverStopsSendingIsCutOffAtTheCatchUpLimit) {
    setenv("GLCAST_CATCH_UP_MB", "8", 1);
    const std::string at = endpoint("flood");
    FakeKeeper flood(at, 64 << 10, std::chrono::milliseconds(0));
    const auto start = std::chrono::steady_clock::now();
    const std::string error = join_error(at, 30);
    unsetenv("GLCAST_CATCH_UP_MB");
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
