// The wall's pose socket (cli/pose_receiver.h) under a tracker bridge's good poses and a hostile
// peer's crafted ones: nothing malformed is applied, every refusal is counted, the last good pose
// holds while the tracker is silent, and a peer without an authorized key is not heard at all.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <zmq.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "cli/pose_receiver.h"
#include "slave/wall_link.h"
#include "net/security.h"

using glcast::cli::PoseReceiver;
namespace net = glcast::net;

namespace {

struct TempDir {
    std::string path;
    TempDir() {
        char dir[] = "/tmp/glcast-poses-XXXXXX";
        EXPECT_NE(mkdtemp(dir), nullptr);
        path = dir;
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
};

// Waits at most 5 s for `done`.
template <class Done>
bool eventually(Done done) {
    for (int i = 0; i < 500 && !done(); i++) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return done();
}

const char* const kGood = R"({"position": [0.1, 1.6, -0.2], "orientation": [1, 0, 0, 0], "time": 12.5})";

}  // namespace

TEST(PoseSocket, CraftedPosesAreRefusedCountedAndTheLastGoodOneHolds) {
    unsetenv("GLCAST_KEYS");
    TempDir dir;
    PoseReceiver receiver("ipc://" + dir.path + "/poses");
    zmq::context_t context(1);
    zmq::socket_t push(context, zmq::socket_type::push);
    push.set(zmq::sockopt::linger, 0);
    push.connect(receiver.bound());
    push.send(zmq::buffer(std::string(kGood)));
    ASSERT_TRUE(eventually([&] { return receiver.accepted() == 1; }));
    const std::string crafted[] = {
        "{",                                                                           // short
        R"({"position": [0, 0, NaN], "orientation": [1, 0, 0, 0]})",                   // NaN
        R"({"position": [0, 0, 1e308], "orientation": [1, 0, 0, 0]})",                 // huge
        R"({"position": [0, 0, 0], "orientation": [3, 0, 0, 0]})",                     // not a rotation
        R"({"position": [0, 0], "orientation": [1, 0, 0, 0]})",                        // short array
        std::string("\xff\xfe\x00garbage", 10),                                       // not text
        std::string(2000, '['),                                                        // deep
    };
    for (const std::string& m : crafted) push.send(zmq::buffer(m));
    push.send(zmq::str_buffer("{\"position\": [0, 0, 0],"), zmq::send_flags::sndmore);  // two parts
    push.send(zmq::str_buffer("\"orientation\": [1, 0, 0, 0]}"));
    ASSERT_TRUE(eventually([&] { return receiver.refused() == std::size(crafted) + 1; })) << receiver.refused();
    // Longer than a pose may be: the socket drops its sender, nothing is applied.
    zmq::socket_t flood(context, zmq::socket_type::push);
    flood.set(zmq::sockopt::linger, 0);
    flood.connect(receiver.bound());
    flood.send(zmq::buffer(std::string(1 << 20, ' ')));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // and a silent tracker
    glcast::slave::HeadPose pose;
    ASSERT_TRUE(receiver.latest(pose));
    EXPECT_EQ(pose.position, glm::dvec3(0.1, 1.6, -0.2));
    EXPECT_EQ(receiver.accepted(), 1u);
    // The bridge goes on: its next pose is taken.
    push.send(zmq::buffer(std::string(R"({"position": [0.5, 1.5, 0], "orientation": [0, 0, 1, 0]})")));
    ASSERT_TRUE(eventually([&] { return receiver.accepted() == 2; }));
    ASSERT_TRUE(receiver.latest(pose));
    EXPECT_EQ(pose.position, glm::dvec3(0.5, 1.5, 0));
}

TEST(PoseSocket, APeerWithoutAnAuthorizedKeyIsNotHeard) {
    TempDir master_dir, known_dir, stranger_dir;
    std::string error;
    ASSERT_TRUE(net::write_key_pair(master_dir.path + "/master", error)) << error;
    ASSERT_TRUE(net::write_key_pair(known_dir.path + "/slave", error)) << error;
    ASSERT_TRUE(net::write_key_pair(stranger_dir.path + "/slave", error)) << error;
    mkdir((master_dir.path + "/authorized").c_str(), 0755);
    for (const std::string& d : {known_dir.path, stranger_dir.path})
        std::ofstream(d + "/master.pub") << std::ifstream(master_dir.path + "/master.pub").rdbuf();
    std::ofstream(master_dir.path + "/authorized/tracker.pub") << std::ifstream(known_dir.path + "/slave.pub").rdbuf();
    net::Security master, known, stranger;
    ASSERT_TRUE(net::load_security(master_dir.path, false, master, error)) << error;
    ASSERT_TRUE(net::load_security(known_dir.path, false, known, error)) << error;
    ASSERT_TRUE(net::load_security(stranger_dir.path, false, stranger, error)) << error;

    PoseReceiver receiver("tcp://127.0.0.1:*", master);
    zmq::context_t context(1);
    auto bridge = [&](const net::Security* s) {
        auto push = std::make_unique<zmq::socket_t>(context, zmq::socket_type::push);
        push->set(zmq::sockopt::linger, 0);
        if (s) net::secure_client(*push, receiver.bound(), *s);
        push->connect(receiver.bound());
        return push;
    };
    auto bad = bridge(&stranger), plain = bridge(nullptr);
    const std::string pose = R"({"position": [9, 9, 9], "orientation": [1, 0, 0, 0]})";
    for (int i = 0; i < 10; i++) {
        bad->send(zmq::buffer(pose), zmq::send_flags::dontwait);
        plain->send(zmq::buffer(pose), zmq::send_flags::dontwait);
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
    }
    EXPECT_EQ(receiver.accepted(), 0u);
    EXPECT_GE(receiver.unauthenticated(), 1u);
    auto good = bridge(&known);
    good->send(zmq::buffer(std::string(kGood)));
    ASSERT_TRUE(eventually([&] { return receiver.accepted() == 1; }));
    glcast::slave::HeadPose got;
    ASSERT_TRUE(receiver.latest(got));
    EXPECT_EQ(got.position, glm::dvec3(0.1, 1.6, -0.2));
}

// The pose as it reaches a slave, in the barrier's GO (slave/wall_link.h): a crafted one is not
// taken, and the frame still goes.
TEST(PoseInGo, ACraftedPoseIsNotTakenAndTheFrameStillGoes) {
    unsetenv("GLCAST_KEYS");
    TempDir dir;
    const std::string endpoint = "ipc://" + dir.path + "/control";
    zmq::context_t context(1);
    zmq::socket_t run(context, zmq::socket_type::router);
    run.set(zmq::sockopt::linger, 0);
    run.bind(endpoint);
    glcast::slave::WallLink link(endpoint, "front", "here");
    struct Case {
        std::string words;
        bool goes, taken;
        double x, separation;
    } cases[] = {
        {" POSE 0.5 1.5 -0.25 1 0 0 0", true, true, 0.5, -1},
        {" POSE 0.5 1.5 -0.25 1 0 0 0 SEP 0.07", true, true, 0.5, 0.07},
        {" POSE nan 1.5 -0.25 1 0 0 0", true, false, 0, -1},
        {" POSE 1e300 1.5 -0.25 1 0 0 0", true, false, 0, -1},
        {" POSE 0.5 1.5 -0.25 3 0 0 0", true, false, 0, -1},
        {" POSE 0.5 1.5 -0.25 1 0 0 0 SEP nan", true, true, 0.5, -1},  // the pose, without the separation
        {" POSE 0.5 1.5", false, false, 0, -1},                          // not a GO: the slave waits on
        {" POSE 0.5 1.5 -0.25 1 0 0 0 rm -rf", false, false, 0, -1},
    };
    uint64_t frame = 10;
    for (const Case& c : cases) {
        std::thread answer([&] {
            zmq::message_t identity, ready;
            if (!run.recv(identity) || !run.recv(ready)) return;
            run.send(identity, zmq::send_flags::sndmore);
            run.send(zmq::buffer("GO " + std::to_string(frame) + c.words));
        });
        glcast::slave::HeadPose head;
        bool has_head = true;
        const bool went = link.barrier(frame, 300, &head, &has_head);
        answer.join();
        EXPECT_EQ(went, c.goes) << c.words;
        EXPECT_EQ(has_head, c.taken) << c.words;
        if (c.taken) {
            EXPECT_EQ(head.position.x, c.x) << c.words;
            EXPECT_EQ(head.eye_separation, c.separation) << c.words;
        }
        frame++;
    }
}
