// A keeper's state kept on disk (keeper/kept_state.h): what it wrote comes back whole; a file cut,
// grown, lying about itself, of another user's or in the place of a FIFO is refused with the
// file and what is wrong named, never a hang or an allocation its header asks for; and a state
// of another stream (the journal's message where it ends differs) is dropped for the journal's
// start, never replayed in front of the wrong messages.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>
#include <zmq.hpp>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "keeper/kept_state.h"
#include "protocol/format.h"
#include "slave/network_source.h"

using namespace glcast;

namespace {

// An uncompressed message of `payload`, ending frame `sequence`.
std::vector<uint8_t> message(uint64_t sequence, const std::string& payload) {
    MessageHeader h{};
    h.magic = kMessageMagic;
    h.flags = kMsgFrameEnd;
    h.sequence = sequence;
    h.frame = uint32_t(sequence);
    h.stored_bytes = h.raw_bytes = uint32_t(payload.size());
    h.crc32 = uint32_t(crc32(0, reinterpret_cast<const Bytef*>(payload.data()), uInt(payload.size())));
    std::vector<uint8_t> m(sizeof h + payload.size());
    std::memcpy(m.data(), &h, sizeof h);
    std::memcpy(m.data() + sizeof h, payload.data(), payload.size());
    return m;
}

std::string payload_of(uint64_t sequence) { return "message " + std::to_string(sequence); }

uint32_t crc_of(const std::string& s) {
    return uint32_t(crc32(0, reinterpret_cast<const Bytef*>(s.data()), uInt(s.size())));
}

slave::NetworkSource::State a_state() {
    slave::NetworkSource::State s;
    s.sequence = 3;
    s.frame = 4;
    s.boundary_crc = crc_of(payload_of(3));
    s.messages.push_back(message(0, "the state's first"));
    s.messages.push_back(message(1, "the state's second, longer message"));
    return s;
}

struct Folder {
    std::string path = "/tmp/glcast-kept-state-" + std::to_string(getpid());
    Folder() { std::filesystem::create_directories(path); }
    ~Folder() { std::filesystem::remove_all(path); }
};

std::string read_all(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

void write_all(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    chmod(path.c_str(), 0600);
}

std::string load_error(const std::string& path, uint64_t max_bytes = 1 << 20) {
    slave::NetworkSource::State s;
    std::string error;
    EXPECT_FALSE(keeper::load_kept_state(path, max_bytes, s, error)) << path << " was taken";
    return error;
}

}  // namespace

TEST(KeptState, ComesBackAsItWasWritten) {
    Folder dir;
    const std::string path = dir.path + "/keeper.state";
    std::string error;
    const auto written = a_state();
    ASSERT_TRUE(keeper::save_kept_state(path, written, error)) << error;
    struct stat st {};
    ASSERT_EQ(stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
    EXPECT_FALSE(std::filesystem::exists(path + ".new"));
    slave::NetworkSource::State read;
    ASSERT_TRUE(keeper::load_kept_state(path, 1 << 20, read, error)) << error;
    EXPECT_EQ(read.sequence, written.sequence);
    EXPECT_EQ(read.frame, written.frame);
    EXPECT_EQ(read.boundary_crc, written.boundary_crc);
    EXPECT_EQ(read.messages, written.messages);
    EXPECT_FALSE(keeper::load_kept_state(dir.path + "/none", 1 << 20, read, error));
    EXPECT_TRUE(error.empty()) << "a missing state is no error: " << error;
}

TEST(KeptState, CraftedFilesAreRefusedNamingTheFileAndWhat) {
    Folder dir;
    const std::string good = dir.path + "/good";
    std::string error;
    ASSERT_TRUE(keeper::save_kept_state(good, a_state(), error)) << error;
    const std::string bytes = read_all(good);
    const size_t body = bytes.find('\n', bytes.find("CHECK")) + 1;
    struct Case {
        const char* name;
        std::string contents;
        const char* says;
    };
    std::string huge_length = bytes;
    huge_length[body] = char(0xff), huge_length[body + 1] = char(0xff), huge_length[body + 2] = char(0xff),
    huge_length[body + 3] = char(0x7f);
    std::string flipped = bytes;
    flipped[bytes.size() - 2] ^= 0x40;
    std::string lying_count = bytes;  // CHECK <crc> <messages> ...: 2 messages said to be 1
    const size_t count_at = lying_count.find(' ', lying_count.find("CHECK ") + 6) + 1;
    ASSERT_EQ(lying_count.substr(count_at, 2), "2 ");
    lying_count.replace(count_at, 1, "3");
    const Case cases[] = {
        {"other", "not a keeper's state at all\n", "not a keeper's state"},
        {"cut_header", bytes.substr(0, 30), "header is cut"},
        {"cut_message", bytes.substr(0, bytes.size() - 5), "more than the file holds"},
        {"huge_length", huge_length, "claims"},
        {"flipped", flipped, "checksum differs"},
        {"lying_count", lying_count, "header says"},
        {"more_messages", bytes + std::string(bytes.begin() + std::ptrdiff_t(body), bytes.end()), "more messages"},
        {"huge_frame", std::string(bytes).replace(bytes.find("STATE 3 4"), 9, "STATE 3 18446744073709551615"),
         "no STATE"},
        {"bad_check", std::string(bytes).replace(bytes.find("CHECK"), 5, "CHECK -1"), "no CHECK"},
    };
    for (const Case& c : cases) {
        const std::string path = dir.path + "/" + c.name;
        write_all(path, c.contents);
        const std::string why = load_error(path);
        EXPECT_NE(why.find(path), std::string::npos) << c.name << ": " << why;
        EXPECT_NE(why.find(c.says), std::string::npos) << c.name << ": " << why;
    }
    // Larger than a catching up may take: refused before it is read.
    auto large = a_state();
    large.messages.push_back(message(2, std::string(4096, 'x')));
    const std::string big = dir.path + "/big";
    ASSERT_TRUE(keeper::save_kept_state(big, large, error)) << error;
    EXPECT_NE(load_error(big, 1024).find("larger"), std::string::npos);
    // Others may write to it: they could put any stream in front of the journal's.
    chmod(good.c_str(), 0620);
    EXPECT_NE(load_error(good).find("others may write"), std::string::npos);
    chmod(good.c_str(), 0600);
    // A FIFO in its place (opened without blocking) and a link (not followed).
    const std::string fifo = dir.path + "/fifo";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_NE(load_error(fifo).find("not a regular file"), std::string::npos);
    const std::string link = dir.path + "/link";
    ASSERT_EQ(symlink(good.c_str(), link.c_str()), 0);
    EXPECT_FALSE(load_error(link).empty());
    // Another user's (root may hand it over; others cannot make one to try).
    if (geteuid() == 0) {
        ASSERT_EQ(chown(good.c_str(), 12345, 12345), 0);
        EXPECT_NE(load_error(good).find("another user"), std::string::npos);
    }
}

namespace {

// A master whose stream repeats message 5 and whose journal answers "SNAPSHOT" with messages 0
// to 5 and "SINCE n" with n - 1 to 5 (from the key message before, as the real one does).
class SmallMaster {
public:
    SmallMaster(const std::string& stream, const std::string& journal)
        : pub_(context_, zmq::socket_type::pub), router_(context_, zmq::socket_type::router) {
        pub_.set(zmq::sockopt::linger, 0);
        router_.set(zmq::sockopt::linger, 0);
        pub_.bind(stream);
        router_.bind(journal);
        thread_ = std::thread([this] {
            while (!stop_) {
                const auto live = message(5, payload_of(5));
                (void)pub_.send(zmq::buffer(live), zmq::send_flags::dontwait);
                zmq::pollitem_t item{router_.handle(), 0, ZMQ_POLLIN, 0};
                zmq::poll(&item, 1, std::chrono::milliseconds(20));
                if (!(item.revents & ZMQ_POLLIN)) continue;
                zmq::message_t identity, request;
                (void)router_.recv(identity);
                (void)router_.recv(request);
                auto send = [&](const void* data, size_t size) {
                    router_.send(zmq::buffer(identity.data(), identity.size()), zmq::send_flags::sndmore);
                    (void)router_.send(zmq::buffer(data, size), zmq::send_flags::none);
                };
                const std::string text = request.to_string();
                uint64_t first = text == "SNAPSHOT" ? 0 : std::stoull(text.substr(6)) - 1;
                for (uint64_t s = first; s <= 5; ++s) {
                    const auto m = message(s, payload_of(s));
                    send(m.data(), m.size());
                }
                send("END", 3);
            }
        });
    }
    ~SmallMaster() {
        stop_ = true;
        thread_.join();
    }

private:
    zmq::context_t context_{1};
    zmq::socket_t pub_, router_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

// The sequence numbers a source gives up to the live message 5, and whether each came from the
// kept state.
std::vector<std::pair<uint64_t, bool>> replayed(slave::NetworkSource& source) {
    std::vector<std::pair<uint64_t, bool>> out;
    Message m;
    while (source.next(m)) {
        out.emplace_back(m.header.sequence, source.from_state());
        if (!source.from_state() && m.header.sequence == 5) break;
    }
    return out;
}

}  // namespace

TEST(KeptState, StartsAKeeperWhereItEndsAndOnlyOnItsOwnStream) {
    const std::string base = "ipc:///tmp/glcast-kept-state-master-" + std::to_string(getpid());
    SmallMaster master(base + "-stream", base + "-journal");
    using Seen = std::vector<std::pair<uint64_t, bool>>;
    {  // this stream's: the state, then the journal's messages after message 3
        slave::NetworkSource source(base + "-stream", base + "-journal", 10, "", 0, 0, a_state());
        EXPECT_EQ(source.joined_frame(), 4u);
        EXPECT_EQ(replayed(source), (Seen{{0, true}, {1, true}, {4, false}, {5, false}}));
    }
    {  // another stream's (message 3 differs): dropped, the journal's whole stream instead
        auto other = a_state();
        other.boundary_crc = crc_of("another program's message 3");
        slave::NetworkSource source(base + "-stream", base + "-journal", 10, "", 0, 0, std::move(other));
        EXPECT_EQ(source.joined_frame(), 0u);
        EXPECT_EQ(replayed(source), (Seen{{0, false}, {1, false}, {2, false}, {3, false}, {4, false}, {5, false}}));
    }
}

// A sparse state file under the size limit (a header, then 1 GiB of nothing) must be refused by
// what its header says before the keeper holds it: it was read whole into memory and every message
// copied out of it (twice the file), and the keeper ended in std::bad_alloc instead of leaving it
// for the journal. Read in a child with 512 MiB of address space to spare: it must answer, not abort.
TEST(KeptState, AFileLargerThanMemoryIsRefusedBeforeItIsHeld) {
    Folder dir;
    const std::string path = dir.path + "/sparse.state";
    {
        std::string error;
        ASSERT_TRUE(keeper::save_kept_state(path, a_state(), error)) << error;
        ASSERT_EQ(truncate(path.c_str(), off_t(1) << 30), 0);
    }
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        size_t used = 0;  // what the process maps already, then 512 MiB more
        std::ifstream maps("/proc/self/statm");
        maps >> used;
        used *= size_t(sysconf(_SC_PAGESIZE));
        rlimit limit{used + (size_t(512) << 20), used + (size_t(512) << 20)};
        setrlimit(RLIMIT_AS, &limit);
        slave::NetworkSource::State s;
        std::string error;
        try {
            const bool taken = keeper::load_kept_state(path, uint64_t(2) << 30, s, error);
            _exit(!taken && error.find(path) != std::string::npos ? 0 : 1);
        } catch (...) {
            _exit(2);
        }
    }
    int status = 0;
    waitpid(child, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << (WIFSIGNALED(status) ? "the reader died of signal " + std::to_string(WTERMSIG(status))
                                : "the reader exited " + std::to_string(WEXITSTATUS(status)));
}
