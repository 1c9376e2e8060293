// The dashboard's HTTP server under attack (cli/dashboard.cpp, cli/http_server.h): DNS rebinding
// (Host headers that only look like loopback), and what a client can make it hold (bodies of
// every encoding, header floods, idle and slow connections).
#include <gtest/gtest.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "cli/dashboard.h"
#include "cli/wall_control.h"
#include "cli/wall_status.h"

using glcast::cli::Dashboard;
using glcast::cli::WallControl;
using glcast::cli::WallStatus;

namespace {

int free_port() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t size = sizeof address;
    bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
    getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
    close(fd);
    return ntohs(address.sin_port);
}

int connect_to(int port) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(uint16_t(port));
    if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

bool send_all(int fd, const std::string& data) {
    size_t sent = 0;
    while (sent < data.size()) {
        const ssize_t n = send(fd, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) return false;
        sent += size_t(n);
    }
    return true;
}

// What the server said within `ms` (until it closed, or the whole response by Content-Length).
std::string read_reply(int fd, int ms) {
    std::string reply;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) {
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, 20) <= 0) continue;
        char buffer[65536];
        const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
        if (n <= 0) break;
        reply.append(buffer, size_t(n));
        const size_t head = reply.find("\r\n\r\n");
        const size_t length = reply.find("Content-Length: ");
        if (head != std::string::npos && length != std::string::npos && length < head &&
            reply.size() >= head + 4 + std::strtoul(reply.c_str() + length + 16, nullptr, 10))
            break;
    }
    return reply;
}

int status_of(const std::string& reply) { return reply.size() > 12 ? std::atoi(reply.c_str() + 9) : 0; }

// One request on a connection of its own: the status code (0: no answer within `ms`).
int request(int port, const std::string& text, int ms = 3000, std::string* reply = nullptr) {
    const int fd = connect_to(port);
    if (fd < 0) return -1;
    send_all(fd, text);
    const std::string r = read_reply(fd, ms);
    close(fd);
    if (reply) *reply = r;
    return status_of(r);
}

std::string get(const std::string& path, const std::string& host) {
    return "GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n";
}

long rss_kib() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::atol(line.c_str() + 6);
    return 0;
}

struct Wall {
    std::string dir = [] {
        char d[] = "/tmp/glcast-dashboard-XXXXXX";
        return std::string(mkdtemp(d));
    }();
    WallControl control{"ipc://" + dir + "/control", {"a", "b"}, false};
    WallStatus status{control, {{"a", "m"}, {"b", "m"}}, ""};
    ~Wall() { std::filesystem::remove_all(dir); }
};

}  // namespace

// A page of another site whose name resolves to 127.0.0.1 (DNS rebinding) names its own host;
// only an address literal of loopback, localhost or the server's own name is this server.
TEST(DashboardAttack, AHostThatOnlyLooksLikeLoopbackIsRefused) {
    unsetenv("GLCAST_KEYS");
    Wall wall;
    const int port = free_port();
    Dashboard dashboard("127.0.0.1:" + std::to_string(port), wall.control, wall.status, nlohmann::json::object());
    const std::string p = ":" + std::to_string(port);
    for (const std::string& host : std::vector<std::string>{"127.attacker.example", "127.0.0.1.attacker.example" + p, "127.evil" + p,
                                   "localhost.attacker.example", "127.1", "0x7f.0.0.1", "[::1].evil", "attacker.example",
                                   "[::2]" + p, "", "127.0.0.1 evil"})
        EXPECT_EQ(request(port, get("/api/status", host)), 403) << "Host: " << host;
    for (const std::string& host : std::vector<std::string>{"127.0.0.1" + p, "127.0.0.1", "127.3.4.5" + p, "localhost" + p, "LocalHost",
                                   "[::1]" + p, "[0:0:0:0:0:0:0:1]" + p, "[0000::0001]"})
        EXPECT_EQ(request(port, get("/api/status", host)), 200) << "Host: " << host;
    // A change needs the header a page of another site cannot send without asking.
    EXPECT_EQ(request(port, "POST /api/ctl HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 14\r\nConnection: close\r\n\r\n"
                            "effects +snow\n"),
              403);
}
