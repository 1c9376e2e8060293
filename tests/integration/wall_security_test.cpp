// The wall across machines: the swap barrier's drop and return (cli/wall_control.h), CURVE keys,
// the ZAP handler and the endpoint checks (net/security.h), the control channel under garbage.
#include <gtest/gtest.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <zmq.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <cstdio>
#include <random>
#include <string>
#include <thread>

#include "cli/wall_control.h"
#include "net/bind_probe.h"
#include "net/security.h"
#include "slave/wall_link.h"

using glcast::cli::BarrierState;
using glcast::cli::TileFrameTiming;
using glcast::cli::WallControl;
namespace net = glcast::net;

namespace {

const std::vector<std::string> kTiles = {"a", "b", "c", "d"};

std::vector<std::string> released(BarrierState& s, double now, std::vector<std::string>* dropped = nullptr) {
    std::vector<std::string> out;
    for (const auto& r : s.release(now, dropped)) out.push_back(r.tile + "@" + std::to_string(r.frame));
    return out;
}

// Removed when the test program ends (they held key files and sockets).
struct TempDirs {
    std::vector<std::string> paths;
    ~TempDirs() {
        std::error_code ignored;
        for (const std::string& p : paths) std::filesystem::remove_all(p, ignored);
    }
};

std::string temp_dir() {
    static TempDirs made;
    char dir[] = "/tmp/glcast-keys-XXXXXX";
    EXPECT_NE(mkdtemp(dir), nullptr);
    made.paths.push_back(dir);
    return dir;
}

void write_file(const std::string& path, const std::string& text, mode_t mode = 0644) {
    std::ofstream(path) << text;
    chmod(path.c_str(), mode);
}

}  // namespace

TEST(SwapBarrier, ReleasesAFrameOnlyWhenEveryTileHasIt) {
    BarrierState s(kTiles, 2.0, 0);
    for (const char* t : {"a", "b", "c"}) EXPECT_TRUE(s.ready(t, 5, 0.1));
    EXPECT_TRUE(released(s, 0.2).empty());
    EXPECT_TRUE(s.ready("d", 5, 0.3));
    EXPECT_EQ(released(s, 0.3), (std::vector<std::string>{"a@5", "b@5", "c@5", "d@5"}));
    EXPECT_TRUE(released(s, 0.4).empty());
    EXPECT_FALSE(s.ready("stranger", 6, 0.4));  // not a tile of the wall
}

TEST(SwapBarrier, ATileAheadWaitsForTheOthersToCatchUp) {
    BarrierState s(kTiles, 2.0, 0);
    s.ready("a", 9, 0.1);  // joined late, further on
    for (const char* t : {"b", "c", "d"}) s.ready(t, 7, 0.1);
    EXPECT_EQ(released(s, 0.1), (std::vector<std::string>{"b@7", "c@7", "d@7"}));
    for (const char* t : {"b", "c", "d"}) s.ready(t, 8, 0.2);
    EXPECT_EQ(released(s, 0.2), (std::vector<std::string>{"b@8", "c@8", "d@8"}));
    for (const char* t : {"b", "c", "d"}) s.ready(t, 9, 0.3);
    EXPECT_EQ(released(s, 0.3).size(), 4u);
}

TEST(SwapBarrier, ASilentTileIsDroppedAndTakenBackWhenItReturns) {
    BarrierState s(kTiles, 2.0, 0);
    for (const char* t : {"a", "b", "c", "d"}) s.ready(t, 1, 0.1);
    EXPECT_EQ(released(s, 0.1).size(), 4u);
    for (const char* t : {"a", "b", "c"}) s.ready(t, 2, 0.2);
    std::vector<std::string> dropped;
    EXPECT_TRUE(released(s, 1.0, &dropped).empty());  // d has 2 s
    s.heard("d", 1.5);                                 // a status report: still alive, catching up
    EXPECT_TRUE(released(s, 3.0, &dropped).empty());
    EXPECT_TRUE(dropped.empty());
    EXPECT_EQ(released(s, 3.6, &dropped), (std::vector<std::string>{"a@2", "b@2", "c@2"}));
    EXPECT_EQ(dropped, std::vector<std::string>{"d"});
    EXPECT_FALSE(s.counted("d"));
    for (const char* t : {"a", "b", "c"}) s.ready(t, 3, 3.7);
    EXPECT_EQ(released(s, 3.7).size(), 3u);  // without d
    s.ready("d", 4, 3.8);                     // back
    EXPECT_TRUE(s.counted("d"));
    EXPECT_EQ(s.back, std::vector<std::string>{"d"});
    for (const char* t : {"a", "b", "c"}) s.ready(t, 4, 3.9);
    EXPECT_EQ(released(s, 3.9).size(), 4u);
}

// A tile stopped for a while (SIGSTOP, a machine that hung) comes back with frames the wall
// presented long ago: it shows them at once, as it replays them, and counts again only when it
// reaches a frame the others have not presented. Before, its first READY made it count at once
// with its old frame, and the others waited until it had replayed its whole backlog.
TEST(SwapBarrier, ATileThatComesBackBehindDoesNotHoldTheOthers) {
    BarrierState s(kTiles, 2.0, 0);
    for (const char* t : {"a", "b", "c", "d"}) s.ready(t, 1, 0.1);
    EXPECT_EQ(released(s, 0.1).size(), 4u);
    for (const char* t : {"a", "b", "c"}) s.ready(t, 2, 0.2);
    std::vector<std::string> dropped;
    EXPECT_EQ(released(s, 2.3, &dropped), (std::vector<std::string>{"a@2", "b@2", "c@2"}));
    EXPECT_EQ(dropped, std::vector<std::string>{"d"});
    for (uint64_t f = 3; f <= 40; f++) {
        for (const char* t : {"a", "b", "c"}) s.ready(t, f, 2.3 + f * 0.01);
        EXPECT_EQ(released(s, 2.3 + f * 0.01).size(), 3u);
    }
    // d continues: its backlog, frame 2 on, while the others go on from 41.
    for (const char* t : {"a", "b", "c"}) s.ready(t, 41, 3.0);
    s.ready("d", 2, 3.0);
    EXPECT_EQ(released(s, 3.0), (std::vector<std::string>{"d@2", "a@41", "b@41", "c@41"}));  // d at once: behind
    EXPECT_FALSE(s.counted("d"));
    EXPECT_TRUE(s.back.empty());
    for (uint64_t f = 3; f <= 41; f++) {  // d alone, at once; the others are never held by it
        s.ready("d", f, 3.0 + f * 0.001);
        EXPECT_EQ(released(s, 3.0 + f * 0.001), (std::vector<std::string>{"d@" + std::to_string(f)}));
    }
    EXPECT_FALSE(s.counted("d"));
    // 42: a frame the others have not presented: d counts again, and all four go together.
    for (const char* t : {"a", "b", "c"}) s.ready(t, 42, 3.1);
    s.ready("d", 42, 3.1);
    EXPECT_TRUE(s.counted("d"));
    EXPECT_EQ(s.back, std::vector<std::string>{"d"});
    EXPECT_EQ(released(s, 3.1).size(), 4u);
}

TEST(Endpoints, TransportsAndWhatNeedsKeys) {
    EXPECT_EQ(net::transport_of("ipc:///tmp/x"), net::Transport::local);
    EXPECT_EQ(net::transport_of("tcp://127.0.0.1:5"), net::Transport::loopback);
    EXPECT_EQ(net::transport_of("tcp://localhost:5"), net::Transport::loopback);
    EXPECT_EQ(net::transport_of("tcp://[::1]:5"), net::Transport::loopback);
    EXPECT_EQ(net::transport_of("tcp://*:5"), net::Transport::network);
    EXPECT_EQ(net::transport_of("tcp://10.0.0.1:5"), net::Transport::network);
    EXPECT_EQ(net::transport_of("tcp://eth0:5"), net::Transport::network);
    EXPECT_EQ(net::transport_of("epgm://eth0;239.1.1.1:5"), net::Transport::multicast);
    net::Security none, insecure;
    insecure.insecure = true;
    EXPECT_FALSE(net::check_endpoint("ipc:///tmp/x", none, true));
    EXPECT_FALSE(net::check_endpoint("tcp://127.0.0.1:5", none, true));
    EXPECT_THROW(net::check_endpoint("tcp://*:5", none, true), std::runtime_error);
    EXPECT_THROW(net::check_endpoint("tcp://10.0.0.1:5", none, false), std::runtime_error);
    EXPECT_FALSE(net::check_endpoint("tcp://*:5", insecure, true));
    EXPECT_THROW(net::check_endpoint("epgm://eth0;239.1.1.1:5", none, true), std::runtime_error);
    EXPECT_FALSE(net::check_endpoint("epgm://eth0;239.1.1.1:5", insecure, true));
    net::Security keyed;
    keyed.dir = "/keys";
    EXPECT_TRUE(net::check_endpoint("tcp://*:5", keyed, true));
    EXPECT_TRUE(net::check_endpoint("tcp://127.0.0.1:5", keyed, false));
    EXPECT_FALSE(net::check_endpoint("ipc:///tmp/x", keyed, true));
    EXPECT_THROW(net::check_endpoint("epgm://eth0;239.1.1.1:5", keyed, true), std::runtime_error);
    try {
        net::check_endpoint("tcp://*:5555", none, true);
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("tcp://*:5555"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("--insecure"), std::string::npos) << e.what();
    }
}

TEST(Keys, WrittenReadAndBadFilesRefusedWithTheirName) {
    const std::string dir = temp_dir();
    std::string error;
    ASSERT_TRUE(net::write_key_pair(dir + "/master", error)) << error;
    EXPECT_FALSE(net::write_key_pair(dir + "/master", error));  // never overwritten
    struct stat st {};
    stat((dir + "/master.key").c_str(), &st);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
    net::KeyPair pair, pub;
    ASSERT_TRUE(net::read_key_file(dir + "/master.key", true, pair, error)) << error;
    ASSERT_TRUE(net::read_key_file(dir + "/master.pub", false, pub, error)) << error;
    EXPECT_EQ(pair.public_key, pub.public_key);
    EXPECT_EQ(pair.secret_key.size(), 40u);

    chmod((dir + "/master.key").c_str(), 0644);
    EXPECT_FALSE(net::read_key_file(dir + "/master.key", true, pair, error));
    EXPECT_NE(error.find("master.key: a secret key others may read (mode 644)"), std::string::npos) << error;
    chmod((dir + "/master.key").c_str(), 0600);

    write_file(dir + "/short.pub", "public-key = \"abc\"\n");
    EXPECT_FALSE(net::read_key_file(dir + "/short.pub", false, pub, error));
    EXPECT_NE(error.find("short.pub:1: public-key is not a Z85 CURVE key"), std::string::npos) << error;
    write_file(dir + "/junk.pub", "# comment\nhello world\n");
    EXPECT_FALSE(net::read_key_file(dir + "/junk.pub", false, pub, error));
    EXPECT_NE(error.find("junk.pub:2: expected public-key"), std::string::npos) << error;
    write_file(dir + "/huge.pub", std::string(10000, 'x'));
    EXPECT_FALSE(net::read_key_file(dir + "/huge.pub", false, pub, error));
    EXPECT_NE(error.find("larger than 4 KiB"), std::string::npos) << error;
    ASSERT_TRUE(net::write_key_pair(dir + "/other", error)) << error;
    net::KeyPair other;
    net::read_key_file(dir + "/other.key", true, other, error);
    write_file(dir + "/mixed.key", "public-key = \"" + pair.public_key + "\"\nsecret-key = \"" + other.secret_key + "\"\n", 0600);
    EXPECT_FALSE(net::read_key_file(dir + "/mixed.key", true, pair, error));
    EXPECT_NE(error.find("its public-key is not the secret-key's"), std::string::npos) << error;

    net::Security s;
    EXPECT_FALSE(net::load_security(dir + "/absent", false, s, error));
    EXPECT_NE(error.find("absent: No such file or directory"), std::string::npos) << error;
    ASSERT_TRUE(net::load_security(dir, false, s, error)) << error;
    EXPECT_TRUE(s.has_master_pair && s.has_client_pair);
    EXPECT_EQ(s.authorized.size(), 1u);  // the master's own key
    mkdir((dir + "/authorized").c_str(), 0755);
    std::rename((dir + "/other.pub").c_str(), (dir + "/authorized/display-a.pub").c_str());
    ASSERT_TRUE(net::load_security(dir, false, s, error)) << error;
    EXPECT_EQ(s.authorized.count(other.public_key), 1u);
}

// Key files are trusted as ssh trusts authorized_keys: regular files, not writable by others, in
// folders others cannot write to; a FIFO never hangs the reader.
TEST(Keys, FilesAndFoldersOthersCouldReplaceAreRefused) {
    const std::string dir = temp_dir();
    std::string error;
    ASSERT_TRUE(net::write_key_pair(dir + "/master", error)) << error;
    ASSERT_TRUE(net::write_key_pair(dir + "/display", error)) << error;
    mkdir((dir + "/authorized").c_str(), 0755);
    std::rename((dir + "/display.pub").c_str(), (dir + "/authorized/display.pub").c_str());
    net::Security s;
    ASSERT_TRUE(net::load_security(dir, false, s, error)) << error;

    // A FIFO among the authorized keys: refused at once, not waited on.
    ASSERT_EQ(mkfifo((dir + "/authorized/waiting.pub").c_str(), 0644), 0);
    const auto start = std::chrono::steady_clock::now();
    EXPECT_FALSE(net::load_security(dir, false, s, error));
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
    EXPECT_NE(error.find("waiting.pub: not a regular file"), std::string::npos) << error;
    unlink((dir + "/authorized/waiting.pub").c_str());

    // A key anyone may rewrite, and a folder anyone may add keys to.
    chmod((dir + "/authorized/display.pub").c_str(), 0666);
    EXPECT_FALSE(net::load_security(dir, false, s, error));
    EXPECT_NE(error.find("display.pub: others may write to it (mode 666)"), std::string::npos) << error;
    chmod((dir + "/authorized/display.pub").c_str(), 0644);
    chmod((dir + "/authorized").c_str(), 0777);
    EXPECT_FALSE(net::load_security(dir, false, s, error));
    EXPECT_NE(error.find("authorized: others may write to it (mode 777)"), std::string::npos) << error;
    chmod((dir + "/authorized").c_str(), 0755);
    chmod(dir.c_str(), 0733);
    EXPECT_FALSE(net::load_security(dir, false, s, error));
    EXPECT_NE(error.find("others may write to it (mode 733)"), std::string::npos) << error;
    chmod(dir.c_str(), 0700);
    ASSERT_TRUE(net::load_security(dir, false, s, error)) << error;

    // glcast keygen does not write a secret key where others may replace it.
    const std::string open_dir = temp_dir();
    chmod(open_dir.c_str(), 01777);
    EXPECT_FALSE(net::write_key_pair(open_dir + "/master", error));
    EXPECT_NE(error.find("others may write to it (mode 1777)"), std::string::npos) << error;
    struct stat st {};
    EXPECT_NE(stat((open_dir + "/master.key").c_str(), &st), 0) << "a secret key was written";
}

// A CURVE server whose ZAP handler knows one slave's key: that slave receives, another does not.
TEST(Keys, TheMasterServesOnlyKeysItKnows) {
    const std::string master_dir = temp_dir(), known_dir = temp_dir(), stranger_dir = temp_dir();
    std::string error;
    ASSERT_TRUE(net::write_key_pair(master_dir + "/master", error)) << error;
    ASSERT_TRUE(net::write_key_pair(known_dir + "/slave", error)) << error;
    ASSERT_TRUE(net::write_key_pair(stranger_dir + "/slave", error)) << error;
    mkdir((master_dir + "/authorized").c_str(), 0755);
    for (const std::string& d : {known_dir, stranger_dir})
        std::ofstream(d + "/master.pub") << std::ifstream(master_dir + "/master.pub").rdbuf();
    std::ofstream(master_dir + "/authorized/known.pub") << std::ifstream(known_dir + "/slave.pub").rdbuf();
    net::Security master, known, stranger;
    ASSERT_TRUE(net::load_security(master_dir, false, master, error)) << error;
    ASSERT_TRUE(net::load_security(known_dir, false, known, error)) << error;
    ASSERT_TRUE(net::load_security(stranger_dir, false, stranger, error)) << error;

    zmq::context_t context(1);
    auto authenticator = net::authenticator_for(context, "the test's master", master);
    zmq::socket_t pub(context, zmq::socket_type::pub);
    pub.set(zmq::sockopt::linger, 0);
    net::secure_server(pub, "tcp://127.0.0.1:*", master);
    pub.bind("tcp://127.0.0.1:*");
    const std::string endpoint = pub.get(zmq::sockopt::last_endpoint);
    auto subscriber = [&](const net::Security& s) {
        auto sub = std::make_unique<zmq::socket_t>(context, zmq::socket_type::sub);
        sub->set(zmq::sockopt::linger, 0);
        sub->set(zmq::sockopt::subscribe, "");
        net::secure_client(*sub, endpoint, s);
        sub->connect(endpoint);
        return sub;
    };
    auto good = subscriber(known), bad = subscriber(stranger);
    zmq::socket_t plain(context, zmq::socket_type::sub);  // no keys at all: the NULL mechanism
    plain.set(zmq::sockopt::linger, 0);
    plain.set(zmq::sockopt::subscribe, "");
    plain.connect(endpoint);
    int good_got = 0, bad_got = 0, plain_got = 0;
    for (int i = 0; i < 40; i++) {
        pub.send(zmq::str_buffer("frame"), zmq::send_flags::dontwait);
        std::this_thread::sleep_for(std::chrono::milliseconds(25));
        zmq::message_t m;
        while (good->recv(m, zmq::recv_flags::dontwait)) good_got++;
        while (bad->recv(m, zmq::recv_flags::dontwait)) bad_got++;
        while (plain.recv(m, zmq::recv_flags::dontwait)) plain_got++;
    }
    EXPECT_GT(good_got, 20);
    EXPECT_EQ(bad_got, 0);
    EXPECT_EQ(plain_got, 0);
    EXPECT_GE(authenticator->refused(), 1u);
    good.reset();
    bad.reset();
}

TEST(WallControlChannel, ATilesNameBelongsToThePeerThatProvedItUntilItGoesSilent) {
    glcast::cli::TileOwners owners(5);
    EXPECT_TRUE(owners.speaks_for("a", "key A", 0));
    EXPECT_TRUE(owners.speaks_for("b", "key B", 0));
    EXPECT_FALSE(owners.speaks_for("a", "key S", 1));  // a stranger, while a's owner is alive
    EXPECT_TRUE(owners.speaks_for("a", "key A", 4));
    EXPECT_FALSE(owners.speaks_for("a", "key S", 8.9));
    EXPECT_TRUE(owners.speaks_for("a", "key A2", 9.5));  // silent for 5.5 s: a restarted slave takes it
    EXPECT_FALSE(owners.speaks_for("a", "key A", 10));
    EXPECT_EQ(owners.refused(), 3u);
}

// A tile that was restarted and is joining the program (from the keeper, then the journal) says
// "joining" once a second but draws none of the frames the others wait for: once the wall has
// started it must not hold them (found by the chaos run: three tiles waited 10 s, their own
// limit, at each restart of the fourth). It is counted again at its first READY. (At the wall's
// start every tile joins, and a joining one holds the others: wall_machines_tcp.)
TEST(WallControlChannel, AJoiningTileDoesNotHoldTheBarrier) {
    unsetenv("GLCAST_KEYS");
    const std::string endpoint = "ipc://" + temp_dir() + "/control";
    WallControl wall(endpoint, kTiles, true);
    zmq::context_t context(1);
    std::map<std::string, zmq::socket_t> tiles;
    for (const std::string& t : kTiles) {
        zmq::socket_t s(context, zmq::socket_type::dealer);
        s.set(zmq::sockopt::linger, 0);
        s.set(zmq::sockopt::rcvtimeo, 50);
        s.connect(endpoint);
        tiles.emplace(t, std::move(s));
    }
    // The wall has started: frame 6 went to all four.
    for (const std::string t : {"a", "b", "c", "d"}) tiles.at(t).send(zmq::buffer("READY " + t + " 6"), zmq::send_flags::none);
    for (const std::string t : {"a", "b", "c", "d"}) {
        zmq::message_t go;
        tiles.at(t).set(zmq::sockopt::rcvtimeo, 2000);
        ASSERT_TRUE(tiles.at(t).recv(go)) << t;
        tiles.at(t).set(zmq::sockopt::rcvtimeo, 50);
    }
    for (const std::string t : {"a", "b", "c"}) tiles.at(t).send(zmq::buffer("READY " + t + " 7"), zmq::send_flags::none);
    const auto start = std::chrono::steady_clock::now();
    int released = 0;
    double seconds = 0;
    while (released < 3 && seconds < 6) {
        tiles.at("d").send(zmq::str_buffer("STATUS d joining 0 7 0 0 0 0 display-b"), zmq::send_flags::dontwait);
        for (const char* t : {"a", "b", "c"}) {
            zmq::message_t go;
            if (tiles.at(t).recv(go, zmq::recv_flags::dontwait)) released += go.to_string() == "GO 7";
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    EXPECT_EQ(released, 3);
    EXPECT_LT(seconds, 3.0) << "the others waited for the joining tile";
    EXPECT_TRUE(wall.status().at("d").dropped);
}

// A stranger on the channel cannot report for a live tile (it could before: the newest report
// of any peer was the tile's).
TEST(WallControlChannel, AStrangerCannotReportForALiveTile) {
    unsetenv("GLCAST_KEYS");
    const std::string endpoint = "ipc://" + temp_dir() + "/control";
    WallControl wall(endpoint, kTiles, false);
    zmq::context_t context(1);
    zmq::socket_t tile(context, zmq::socket_type::dealer), stranger(context, zmq::socket_type::dealer);
    for (zmq::socket_t* s : {&tile, &stranger}) {
        s->set(zmq::sockopt::linger, 0);
        s->connect(endpoint);
    }
    tile.send(zmq::str_buffer("STATUS a live 10 10 60 1 0 0 display-a"), zmq::send_flags::dontwait);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    for (int i = 0; i < 20; i++) {
        tile.send(zmq::str_buffer("STATUS a live 11 11 60 1 0 0 display-a"), zmq::send_flags::dontwait);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        stranger.send(zmq::str_buffer("STATUS a idle 0 0 0 0 0 9 evil"), zmq::send_flags::dontwait);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const auto status = wall.status();
    EXPECT_EQ(status.at("a").machine, "display-a");
    EXPECT_EQ(status.at("a").state, "live");
    EXPECT_EQ(status.at("a").recoveries, 0u);
}

// Whatever arrives on the control channel, it keeps serving (and never takes a stranger's tile
// name or garbage as a report).
TEST(WallControlChannel, GarbageIsIgnored) {
    unsetenv("GLCAST_KEYS");
    const std::string endpoint = "ipc://" + temp_dir() + "/control";
    WallControl wall(endpoint, kTiles, true);
    zmq::context_t context(1);
    zmq::socket_t dealer(context, zmq::socket_type::dealer);
    dealer.set(zmq::sockopt::linger, 0);
    dealer.connect(endpoint);
    std::mt19937 random(7);
    for (int i = 0; i < 2000; i++) {
        std::string junk(random() % 300, '\0');
        for (char& c : junk) c = char(random());
        dealer.send(zmq::buffer(junk), zmq::send_flags::dontwait);
    }
    // A frame over 256 bytes made libzmq hang up on that peer: the reports come from another.
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    zmq::socket_t reporter(context, zmq::socket_type::dealer);
    reporter.set(zmq::sockopt::linger, 0);
    reporter.connect(endpoint);
    for (const char* text : {"STATUS a live 1 2 3 4 5 6 host extra", "STATUS a live x", "STATUS zz live 1 1 1 1 1 1 m",
                             "STATUS a dancing 1 1 1 1 1 1 m", "STATUS a live 1 1 nan 1 1 1 m", "READY a",
                             "STATUS a live 1 1 1 1 1 1 bad/name"})
        reporter.send(zmq::buffer(std::string(text)), zmq::send_flags::dontwait);
    reporter.send(zmq::str_buffer("STATUS b live 10 12 30.5 0.25 2 1 display-b"), zmq::send_flags::dontwait);
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    const auto status = wall.status();
    EXPECT_EQ(status.size(), 4u);
    EXPECT_EQ(status.at("b").machine, "display-b");
    EXPECT_EQ(status.at("b").frame, 10u);
    EXPECT_EQ(status.at("b").lag, 2);
    EXPECT_EQ(status.at("c").age_seconds, -1);  // never reported
    // "a": only the report with one word too many was well formed up to the machine: it counts.
    EXPECT_EQ(status.at("a").machine, "host");
}

// The tiles' frame times (glcast run --timing): a CLOCK is answered with the run's steady clock
// and the time asked at; TIMING lines reach the sink only when every line is well formed, from
// the peer that speaks for the tile.
TEST(WallControlChannel, ClockAndTimingsOnlyWhenWellFormed) {
    unsetenv("GLCAST_KEYS");
    const std::string endpoint = "ipc://" + temp_dir() + "/control";
    WallControl wall(endpoint, kTiles, false);
    std::mutex m;
    std::vector<std::string> got;
    wall.set_timing_sink([&](const std::string& tile, uint64_t frame, const TileFrameTiming& t) {
        std::lock_guard lock(m);
        got.push_back(tile + "@" + std::to_string(frame) + " " + std::to_string(t.presented + t.clock_offset * 0) +
                      " err " + std::to_string(t.clock_error));
    });
    zmq::context_t context(1);
    zmq::socket_t dealer(context, zmq::socket_type::dealer);
    dealer.set(zmq::sockopt::linger, 0);
    dealer.set(zmq::sockopt::rcvtimeo, 2000);
    dealer.connect(endpoint);
    const double before = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    dealer.send(zmq::str_buffer("CLOCK a 12.5x"), zmq::send_flags::none);  // not a number: no answer
    dealer.send(zmq::str_buffer("CLOCK a 12.5"), zmq::send_flags::none);
    zmq::message_t answer;
    ASSERT_TRUE(dealer.recv(answer));
    double t0 = 0, run_time = 0;
    ASSERT_EQ(std::sscanf(answer.to_string().c_str(), "CLOCK %lf %lf", &t0, &run_time), 2) << answer.to_string();
    EXPECT_EQ(t0, 12.5);
    EXPECT_GE(run_time, before);
    auto timing = [&](const std::string& head, const std::string& lines) {
        dealer.send(zmq::buffer(head), zmq::send_flags::sndmore);
        dealer.send(zmq::buffer(lines), zmq::send_flags::none);
    };
    timing("TIMING a 0 0.001", "1 1.0 2.0 3.0\n2 1.5 2.5 3.5\n");  // taken
    timing("TIMING a 0 0.001", "3 1.0 2.0 3.0\n4 1.5 2.5\n");      // a short line: none taken
    timing("TIMING a 0 0.001", "5 1.0 2.0 nan\n");
    timing("TIMING a 0 -1", "6 1.0 2.0 3.0\n");                    // a negative bound
    timing("TIMING a nan 0.001", "7 1.0 2.0 3.0\n");
    timing("TIMING stranger 0 0.001", "8 1.0 2.0 3.0\n");          // not a tile of the wall
    dealer.send(zmq::str_buffer("TIMING a 0 0.001"), zmq::send_flags::none);  // no second part
    timing("TIMING b 0 0.002", "9 4.0 5.0 6.0");                   // the last line unended: taken
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    std::lock_guard lock(m);
    EXPECT_EQ(got, (std::vector<std::string>{"a@1 3.000000 err 0.001000", "a@2 3.500000 err 0.001000",
                                             "b@9 6.000000 err 0.002000"}));
}

// One `glcast run` after another on the same wall: what a slave said while no run was serving
// (the previous program's last frames, queued by its socket) must not reach the next run, whose
// status line and swap barrier would take it for the new program's.
TEST(WallControlChannel, WhatATileSaidBetweenRunsIsNotDeliveredToTheNext) {
    unsetenv("GLCAST_KEYS");
    const std::string endpoint = "ipc://" + temp_dir() + "/control";
    glcast::slave::WallLink link(endpoint, "a", "host-a");
    glcast::slave::TileReport report;
    report.state = "live";
    auto wait_for = [](auto&& done) {
        for (int i = 0; i < 100 && !done(); i++) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        return done();
    };
    {
        WallControl first(endpoint, kTiles, true);
        report.frame = 1;
        EXPECT_TRUE(wait_for([&] {
            link.report(report);
            return first.status().at("a").frame == 1;
        }));
    }
    // Between the runs: the old program's frames go on for a while.
    report.frame = 5000;
    link.report(report);
    EXPECT_FALSE(link.barrier(5000, 100));
    WallControl second(endpoint, kTiles, true);
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // the link reconnects (100 ms)
    EXPECT_LT(second.status().at("a").age_seconds, 0) << "a report from before this run arrived: frame "
                                                      << second.status().at("a").frame;
    report.frame = 7;
    EXPECT_TRUE(wait_for([&] {
        link.report(report);
        return second.status().at("a").frame == 7;
    }));
}

namespace {

// What a tile's DEALER hears within `ms`: every message, in order.
std::vector<std::string> heard(zmq::socket_t& s, int ms) {
    std::vector<std::string> out;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) {
        zmq::message_t m;
        if (s.recv(m, zmq::recv_flags::dontwait)) out.push_back(m.to_string());
        else std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return out;
}

// A loopback TCP endpoint whose port was free a moment ago (bound to port 0 and released): a
// fixed port may be held by another test or taken as an outgoing connection's local port.
std::string free_loopback_endpoint() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t size = sizeof address;
    const bool ok = bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
                    getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size) == 0;
    close(fd);
    return ok ? "tcp://127.0.0.1:" + std::to_string(ntohs(address.sin_port)) : "tcp://127.0.0.1:47931";
}

std::string ask(zmq::socket_t& s, const std::string& request) {
    s.send(zmq::buffer(request), zmq::send_flags::none);
    zmq::message_t answer;
    s.set(zmq::sockopt::rcvtimeo, 3000);
    return s.recv(answer) ? answer.to_string() : "(no answer)";
}

}  // namespace

// Live effects with the barrier: a change holds from the frame after the one every tile waits
// for, and reaches each tile before that frame's GO; a tile that reports an older version (one
// that joined later) gets it again.
TEST(WallControlChannel, PassesSwitchAtTheFrameAfterTheOneEveryTileWaitsFor) {
    unsetenv("GLCAST_KEYS");
    const std::string endpoint = "ipc://" + temp_dir() + "/control";
    WallControl wall(endpoint, {"a", "b"}, true);
    zmq::context_t context(1);
    std::map<std::string, zmq::socket_t> tiles;
    for (const std::string t : {"a", "b"}) {
        zmq::socket_t s(context, zmq::socket_type::dealer);
        s.set(zmq::sockopt::linger, 0);
        s.connect(endpoint);
        tiles.emplace(t, std::move(s));
    }
    for (const std::string t : {"a", "b"}) tiles.at(t).send(zmq::buffer("READY " + t + " 40"), zmq::send_flags::none);
    for (const std::string t : {"a", "b"}) EXPECT_EQ(heard(tiles.at(t), 300), std::vector<std::string>{"GO 40"});
    tiles.at("a").send(zmq::str_buffer("READY a 41"), zmq::send_flags::none);  // b still draws 41
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    zmq::socket_t operator_socket(context, zmq::socket_type::dealer);
    operator_socket.set(zmq::sockopt::linger, 0);
    operator_socket.connect(endpoint);
    EXPECT_EQ(ask(operator_socket, "CTL effects +snow"), "OK effects snow from frame 42 (version 1)");
    EXPECT_EQ(ask(operator_socket, "CTL effects +fog").rfind("ERROR unknown effect \"fog\"", 0), 0u);
    tiles.at("b").send(zmq::str_buffer("READY b 41"), zmq::send_flags::none);
    for (const std::string t : {"a", "b"})
        EXPECT_EQ(heard(tiles.at(t), 300), (std::vector<std::string>{"EFFECTS 1 42 snow", "GO 41"})) << t;
    EXPECT_EQ(wall.effects().version, 1u);
    // b restarted: its report names version 0, so it hears the state again; a's names 1.
    tiles.at("a").send(zmq::str_buffer("STATUS a live 41 41 60 1 0 0 m 1"), zmq::send_flags::none);
    tiles.at("b").send(zmq::str_buffer("STATUS b joining 0 41 0 0 0 0 m 0"), zmq::send_flags::none);
    EXPECT_TRUE(heard(tiles.at("a"), 300).empty());
    EXPECT_EQ(heard(tiles.at("b"), 300), std::vector<std::string>{"EFFECTS 1 42 snow"});
    // The dashboard's way in, from another thread.
    std::string reply;
    EXPECT_TRUE(wall.change_effects("param snow.fall_speed=2", reply)) << reply;
    EXPECT_EQ(reply, "OK effects snow from frame 43 (version 2) snow.fall_speed=2");
}

// On a wall with keys only the operator may switch passes: the master's key or one of
// operators/; a display machine's key (authorized/) may not.
TEST(WallControlChannel, OnlyTheOperatorSwitchesPasses) {
    const std::string master_dir = temp_dir(), display_dir = temp_dir(), operator_dir = temp_dir();
    std::string error;
    ASSERT_TRUE(net::write_key_pair(master_dir + "/master", error)) << error;
    ASSERT_TRUE(net::write_key_pair(display_dir + "/slave", error)) << error;
    ASSERT_TRUE(net::write_key_pair(operator_dir + "/operator", error)) << error;
    mkdir((master_dir + "/authorized").c_str(), 0755);
    mkdir((master_dir + "/operators").c_str(), 0755);
    for (const std::string& d : {display_dir, operator_dir})
        std::ofstream(d + "/master.pub") << std::ifstream(master_dir + "/master.pub").rdbuf();
    std::ofstream(master_dir + "/authorized/display.pub") << std::ifstream(display_dir + "/slave.pub").rdbuf();
    std::ofstream(master_dir + "/operators/ops.pub") << std::ifstream(operator_dir + "/operator.pub").rdbuf();
    net::Security display, op;
    ASSERT_TRUE(net::load_security(display_dir, false, display, error)) << error;
    ASSERT_TRUE(net::load_security(operator_dir, false, op, error)) << error;
    ASSERT_TRUE(op.has_operator_pair);
    setenv("GLCAST_KEYS", master_dir.c_str(), 1);
    net::use_process_keys(master_dir, false);
    const std::string endpoint = free_loopback_endpoint();
    WallControl wall(endpoint, {"a"}, false);
    zmq::context_t context(1);
    auto peer = [&](net::Security s) {
        if (s.has_operator_pair) s.client = s.operator_pair, s.has_client_pair = true;
        auto socket = std::make_unique<zmq::socket_t>(context, zmq::socket_type::dealer);
        socket->set(zmq::sockopt::linger, 0);
        net::secure_client(*socket, endpoint, s);
        socket->connect(endpoint);
        return socket;
    };
    auto display_socket = peer(display), operator_socket = peer(op);
    EXPECT_EQ(ask(*display_socket, "CTL effects +snow").rfind("ERROR only the wall's operator", 0), 0u);
    EXPECT_EQ(wall.effects().version, 0u);
    EXPECT_EQ(ask(*operator_socket, "CTL effects +snow").rfind("OK effects snow", 0), 0u);
    EXPECT_EQ(wall.effects().version, 1u);
    display_socket.reset();
    operator_socket.reset();
    net::use_process_keys("", false);
    unsetenv("GLCAST_KEYS");
}

// A port another process listens on is refused before a wall starts, naming the channel and the
// port; a free one, and an ipc:// path, pass (and stay free: the probe lets go at once).
TEST(BindProbe, RefusesAPortInUseNamingTheChannel) {
    const std::string endpoint = free_loopback_endpoint();
    EXPECT_NO_THROW(net::check_can_bind(endpoint, "journal"));
    EXPECT_NO_THROW(net::check_can_bind(endpoint, "journal"));  // released by the first probe
    zmq::context_t context(1);
    zmq::socket_t holder(context, zmq::socket_type::pull);
    holder.set(zmq::sockopt::linger, 0);
    holder.bind(endpoint);
    try {
        net::check_can_bind(endpoint, "journal");
        ADD_FAILURE() << "a port in use passed";
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("journal"), std::string::npos) << what;
        EXPECT_NE(what.find(endpoint.substr(endpoint.rfind(':') + 1)), std::string::npos) << what;
        EXPECT_NE(what.find("in use"), std::string::npos) << what;
    }
    EXPECT_NO_THROW(net::check_can_bind("ipc:///nonexistent-folder/stream", "stream"));
}

// On a keyed wall a tile's name belongs to the key of the machine the config puts it on
// (authorized/MACHINE.pub): another authorized display key that names it first (a squatter
// reporting it live at frame 4242 before its slave is up) is refused, and the real slave is not.
TEST(WallControlChannel, ASquattingDisplayKeyCannotTakeAnotherMachinesTile) {
    const std::string master_dir = temp_dir(), a_dir = temp_dir(), b_dir = temp_dir();
    std::string error;
    ASSERT_TRUE(net::write_key_pair(master_dir + "/master", error)) << error;
    ASSERT_TRUE(net::write_key_pair(a_dir + "/slave", error)) << error;
    ASSERT_TRUE(net::write_key_pair(b_dir + "/slave", error)) << error;
    mkdir((master_dir + "/authorized").c_str(), 0755);
    for (const std::string& d : {a_dir, b_dir})
        std::ofstream(d + "/master.pub") << std::ifstream(master_dir + "/master.pub").rdbuf();
    std::ofstream(master_dir + "/authorized/display-a.pub") << std::ifstream(a_dir + "/slave.pub").rdbuf();
    std::ofstream(master_dir + "/authorized/display-b.pub") << std::ifstream(b_dir + "/slave.pub").rdbuf();
    net::Security master, a_keys, b_keys;
    ASSERT_TRUE(net::load_security(master_dir, false, master, error)) << error;
    ASSERT_TRUE(net::load_security(a_dir, false, a_keys, error)) << error;
    ASSERT_TRUE(net::load_security(b_dir, false, b_keys, error)) << error;
    setenv("GLCAST_KEYS", master_dir.c_str(), 1);
    net::use_process_keys(master_dir, false);
    const std::string endpoint = free_loopback_endpoint();
    const std::vector<std::pair<std::string, std::string>> tiles = {{"a", "display-a"}, {"b", "display-b"}};
    std::vector<std::string> unbound;
    WallControl wall(endpoint, {"a", "b"}, true, nullptr,
                     glcast::cli::tile_keys(tiles, "master", net::process_security(), &unbound));
    EXPECT_TRUE(unbound.empty());
    zmq::context_t context(1);
    auto peer = [&](const net::Security& s) {
        auto socket = std::make_unique<zmq::socket_t>(context, zmq::socket_type::dealer);
        socket->set(zmq::sockopt::linger, 0);
        net::secure_client(*socket, endpoint, s);
        socket->connect(endpoint);
        return socket;
    };
    auto squatter = peer(b_keys);
    squatter->send(zmq::str_buffer("STATUS a live 4242 4242 60 1 0 0 display-a"), zmq::send_flags::none);
    squatter->send(zmq::str_buffer("STATUS b live 7 7 60 1 0 0 display-b"), zmq::send_flags::none);  // its own
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    auto real = peer(a_keys);
    for (int i = 0; i < 5; i++) {
        real->send(zmq::str_buffer("STATUS a live 10 10 60 1 0 0 display-a"), zmq::send_flags::none);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto status = wall.status();
    EXPECT_EQ(status.at("a").frame, 10u) << "the squatter's report stood";
    EXPECT_EQ(status.at("b").frame, 7u);
    // The squatter's READY for a's frame does not hold or release the barrier for it.
    squatter->send(zmq::str_buffer("READY a 11"), zmq::send_flags::none);
    squatter->send(zmq::str_buffer("READY b 11"), zmq::send_flags::none);
    EXPECT_TRUE(heard(*squatter, 500).empty()) << "b was released while a had not said READY";
    real->send(zmq::str_buffer("READY a 11"), zmq::send_flags::none);
    EXPECT_EQ(heard(*real, 500), std::vector<std::string>{"GO 11"});
    // A machine whose key is not among authorized/ has no peer that may speak for its tiles: said.
    std::vector<std::string> none;
    glcast::cli::tile_keys({{"c", "display-c"}, {"m", "master"}}, "master", net::process_security(), &none);
    EXPECT_EQ(none, std::vector<std::string>{"c"});
    squatter.reset();
    real.reset();
    net::use_process_keys("", false);
    unsetenv("GLCAST_KEYS");
}

// Live control's state is carried to every tile in one message of the tile link (4,096 bytes at
// most) and the operator's answer in one of glcast ctl's (the same): requests each under the
// channel's 1,024 bytes must not add up past either. Six values of 990 characters (a number with
// 985 zeros: each in range) made a state of about 7 KB: the tiles never got it and the operator
// heard nothing, for requests that were applied.
TEST(WallControlChannel, LiveStateNeverOutgrowsTheBuffersThatCarryIt) {
    unsetenv("GLCAST_KEYS");
    const std::string endpoint = "ipc://" + temp_dir() + "/control";
    WallControl wall(endpoint, {"a"}, false);
    glcast::slave::WallLink link(endpoint, "a", "host-a");
    zmq::context_t context(1);
    zmq::socket_t operator_socket(context, zmq::socket_type::dealer);
    operator_socket.set(zmq::sockopt::linger, 0);
    operator_socket.set(zmq::sockopt::maxmsgsize, int64_t(4096));  // as glcast ctl reads
    operator_socket.set(zmq::sockopt::sndtimeo, 1000);  // a peer that hung up on a long answer takes no request
    operator_socket.connect(endpoint);
    std::vector<glcast::slave::effects::ParamSpec> numbers;
    for (const auto& s : glcast::slave::effects::all_param_specs())
        if (!s.text) numbers.push_back(s);
    ASSERT_GE(numbers.size(), 6u);
    int answered = 0;
    for (size_t i = 0; i < 6; i++) {
        char value[64];
        std::snprintf(value, sizeof value, "%.17g", numbers[i].min);
        std::string padded = value;
        if (padded.find('.') == std::string::npos) padded += ".";
        padded += std::string(990 - padded.size(), '0');
        const std::string reply = ask(operator_socket, "CTL param " + numbers[i].name + "=" + padded);
        answered += reply != "(no answer)";
        EXPECT_LT(reply.size(), 4096u);
    }
    EXPECT_EQ(answered, 6) << "requests were applied without an answer the operator could read";
    // Every parameter at once, each with a value of 17 digits: taken or refused, always answered.
    std::string all = "CTL param";
    for (const auto& s : numbers) {
        char value[64];
        std::snprintf(value, sizeof value, "%.17g", s.min + (s.max - s.min) / 3);
        all += " " + s.name + "=" + value;
    }
    if (all.size() <= 1024) EXPECT_NE(ask(operator_socket, all), "(no answer)");
    // Over the channel's bound for one request: refused with an answer, not dropped unanswered.
    EXPECT_EQ(ask(operator_socket, "CTL param " + numbers[0].name + "=" + std::string(1100, '1')).rfind("ERROR", 0), 0u);
    EXPECT_LE(wall.effects().words().size(), glcast::slave::LiveEffects::kMaxWordsBytes);
    // The tile, which joined at version 0, gets the wall's newest state.
    glcast::slave::TileReport report;
    report.state = "live";
    glcast::slave::LiveEffects got;
    bool took = false;
    for (int i = 0; i < 40 && !took; i++) {
        link.report(report);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        took = link.take_effects(got) && got.version == wall.effects().version;
    }
    EXPECT_TRUE(took) << "the tile never got version " << wall.effects().version << " ("
                      << wall.effects().words().size() << " bytes)";
}
