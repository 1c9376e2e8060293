// A peer that may subscribe to the program's stream sends endless distinct subscriptions: the
// program (the publisher runs inside it) must neither die, nor grow, nor wait for them, and once
// the peer is gone the slaves get the stream again. (Before: 2.4 GB more for 400,000
// subscriptions of 200 bytes, and libzmq's out-of-memory abort ends the program with more.)
#include <gtest/gtest.h>
#include <zmq.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "master/publisher.h"
#include "protocol/format.h"

using namespace glcast;

namespace {

size_t resident_bytes() {
    long pages = 0, resident = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
        std::fclose(f);
    }
    return size_t(resident) * size_t(sysconf(_SC_PAGESIZE));
}

std::vector<uint8_t> message(uint64_t sequence) {
    std::vector<uint8_t> m(sizeof(MessageHeader) + 64, 0);
    MessageHeader h{};
    h.magic = kMessageMagic;
    h.sequence = sequence;
    std::memcpy(m.data(), &h, sizeof h);
    return m;
}

}  // namespace

// The attacker in a process of its own (an XSUB keeps what it sent, to send it again on a
// reconnect: in this process its memory would be counted as the program's).
pid_t flood_subscriptions(const std::string& endpoint, int count) {
    const pid_t pid = fork();
    if (pid != 0) return pid;
    {
        zmq::context_t context(1);
        zmq::socket_t attacker(context, zmq::socket_type::xsub);
        attacker.set(zmq::sockopt::linger, 0);
        attacker.set(zmq::sockopt::sndhwm, 0);
        attacker.connect(endpoint);
        std::string topic(201, 'x');
        topic[0] = 1;  // an XSUB's subscription: 1, then the topic
        for (int i = 0; i < count; ++i) {
            std::snprintf(&topic[1], 12, "%010d", i);
            topic[11] = 'x';
            (void)attacker.send(zmq::buffer(topic), zmq::send_flags::dontwait);
        }
        std::this_thread::sleep_for(std::chrono::seconds(60));  // until killed
    }
    _exit(0);
}

TEST(PublisherSubscriptions, AFloodOfDistinctSubscriptionsNeitherGrowsNorStopsTheProgram) {
    const std::string endpoint = "ipc:///tmp/glcast-subscription-flood-" + std::to_string(getpid());
    const pid_t attacker = flood_subscriptions(endpoint, 200000);  // 200,000 distinct 200-byte topics: 40 MB
    PublisherOptions options;
    options.endpoint = endpoint;
    PublisherSink publisher(options);
    zmq::context_t context(1);
    zmq::socket_t slave(context, zmq::socket_type::sub);  // as slave/network_source.cpp subscribes
    slave.set(zmq::sockopt::linger, 0);
    slave.set(zmq::sockopt::subscribe, "");
    slave.connect(endpoint);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const size_t before = resident_bytes();
    uint64_t sequence = 0;
    double slowest = 0;  // the longest a write took: the program is never held
    for (int i = 0; i < 400; ++i) {  // the program publishes a message every 10 ms for 4 s
        const auto t0 = std::chrono::steady_clock::now();
        publisher.write(message(sequence++));
        slowest = std::max(slowest, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const size_t after = resident_bytes(), grown = after > before ? after - before : 0;
    kill(attacker, SIGKILL);
    waitpid(attacker, nullptr, 0);
    // The flood over, the slave (which may have been reconnected meanwhile) gets the stream again.
    zmq::message_t m;
    while (slave.recv(m, zmq::recv_flags::dontwait)) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    for (int i = 0; i < 100; ++i) {
        publisher.write(message(sequence++));
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    size_t received = 0;
    while (slave.recv(m, zmq::recv_flags::dontwait)) received++;
    std::printf("during the flood the program's resident memory grew by %.1f MiB, its slowest write took %.1f ms; "
                "after it the slave received %zu of 100 messages\n",
                grown / 1048576.0, slowest * 1000, received);
    EXPECT_LT(grown, size_t(32) << 20);
    EXPECT_LT(slowest, 0.5);
    EXPECT_GE(received, size_t(90));
    ::unlink(endpoint.c_str() + 6);
}
