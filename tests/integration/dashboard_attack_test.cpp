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
#include "cli/http_server.h"
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

// What a client can make the dashboard hold: a chunked body of 32 MiB, 200,000 header lines, a
// compressed body, and 200 idle plus 64 slow connections while a browser asks for the status.
// Before (cpp-httplib with a body limit only on Content-Length): the chunked body and the header
// lines were read whole into memory, and the normal request waited behind the idle connections
// for the 8 workers (5 s of read timeout each).
TEST(DashboardAttack, BodiesHeadersAndConnectionsAreBounded) {
    unsetenv("GLCAST_KEYS");
    Wall wall;
    const int port = free_port();
    Dashboard dashboard("127.0.0.1:" + std::to_string(port), wall.control, wall.status, nlohmann::json::object());
    const long rss_before = rss_kib();
    {
        const int fd = connect_to(port);
        ASSERT_GE(fd, 0);
        send_all(fd, "POST /api/ctl HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Glcast-Request: 1\r\nTransfer-Encoding: chunked\r\n\r\n");
        const std::string chunk = "100000\r\n" + std::string(0x100000, 'a') + "\r\n";
        for (int i = 0; i < 32 && send_all(fd, chunk); i++) {
        }
        send_all(fd, "0\r\n\r\n");
        const int status = status_of(read_reply(fd, 3000));
        EXPECT_TRUE(status == 411 || status == 413) << "a chunked body of 32 MiB: " << status;
        close(fd);
    }
    {
        const int fd = connect_to(port);
        ASSERT_GE(fd, 0);
        send_all(fd, "GET /api/status HTTP/1.1\r\nHost: 127.0.0.1\r\n");
        std::string lines;
        for (int i = 0; i < 2000; i++) lines += "X-Flood-" + std::to_string(i) + ": yes\r\n";
        for (int i = 0; i < 100 && send_all(fd, lines); i++) {
        }
        send_all(fd, "\r\n");
        EXPECT_EQ(status_of(read_reply(fd, 3000)), 431) << "200,000 header lines";
        close(fd);
    }
    EXPECT_EQ(request(port, "POST /api/ctl HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Glcast-Request: 1\r\nContent-Encoding: gzip\r\n"
                            "Content-Length: 4\r\nConnection: close\r\n\r\nabcd"),
              415);
    EXPECT_EQ(request(port, "POST /api/ctl HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Glcast-Request: 1\r\nContent-Length: 5000\r\n"
                            "Connection: close\r\n\r\n" + std::string(5000, 'x')),
              413);
    const long grown = rss_kib() - rss_before;
    EXPECT_LT(grown, 8 * 1024) << "the dashboard held " << grown << " KiB of what clients sent";

    std::vector<int> idle, slow;
    for (int i = 0; i < 200; i++) idle.push_back(connect_to(port));
    for (int i = 0; i < 64; i++) {
        slow.push_back(connect_to(port));
        send_all(slow.back(), "GET /api/status HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ");
    }
    std::thread trickle([&] {
        for (int round = 0; round < 8; round++) {
            for (int fd : slow) send_all(fd, "z");
            std::this_thread::sleep_for(std::chrono::milliseconds(250));
        }
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto start = std::chrono::steady_clock::now();
    std::string reply;
    const int status = request(port, get("/api/status", "127.0.0.1"), 3000, &reply);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    trickle.join();
    for (int fd : idle) close(fd);
    for (int fd : slow) close(fd);
    EXPECT_EQ(status, 200) << "a normal request beside 200 idle and 64 slow connections";
    EXPECT_LT(seconds, 1.0);
}

// The server's own bounds, made small: a request still coming after its deadline is cut (a
// byte every 100 ms kept a connection forever: the read timeout counts from the last byte), and
// at the connection cap the one that waited longest without a request goes for a new one.
TEST(DashboardAttack, ADeadlinePerRequestAndACapOnConnections) {
    glcast::cli::HttpLimits limits;
    limits.request_seconds = 1;
    limits.max_connections = 4;
    glcast::cli::HttpServer server("127.0.0.1", 0, [](const glcast::cli::HttpRequest& r, glcast::cli::HttpResponse& out) {
        out.set(200, "path " + r.path + " token " + r.param("token") + "\n");
    }, limits);
    const int slow = connect_to(server.port());
    send_all(slow, "GET / HTTP/1.1\r\nHost: x\r\nX-Slow: ");
    const auto start = std::chrono::steady_clock::now();
    bool closed = false;
    while (!closed && std::chrono::steady_clock::now() - start < std::chrono::seconds(4)) {
        closed = !send_all(slow, "z") || [&] {
            pollfd p{slow, POLLIN, 0};
            char c;
            return poll(&p, 1, 0) == 1 && recv(slow, &c, 1, MSG_PEEK) <= 0;
        }();
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    close(slow);
    EXPECT_TRUE(closed);
    EXPECT_LT(seconds, 2.0);
    EXPECT_GE(server.counts().timed_out, 1u);
    std::vector<int> held;
    for (int i = 0; i < 6; i++) held.push_back(connect_to(server.port()));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::string reply;
    EXPECT_EQ(request(server.port(), get("/x?a=1&token=ab%2Fc", "x"), 2000, &reply), 200);
    EXPECT_NE(reply.find("path /x token ab/c"), std::string::npos) << reply;
    EXPECT_GE(server.counts().evicted, 3u);
    for (int fd : held) close(fd);
    // Keep-alive: two requests on one connection, then a malformed one closes it.
    const int fd = connect_to(server.port());
    send_all(fd, "GET /1 HTTP/1.1\r\nHost: x\r\n\r\nGET /2 HTTP/1.1\r\nHost: x\r\n\r\n");
    std::string both;
    for (int i = 0; i < 20 && both.find("path /2") == std::string::npos; i++) both += read_reply(fd, 100);
    EXPECT_NE(both.find("path /1"), std::string::npos);
    EXPECT_NE(both.find("path /2"), std::string::npos);
    send_all(fd, "NOT A REQUEST\r\n\r\n");
    EXPECT_EQ(status_of(read_reply(fd, 1000)), 400);
    close(fd);
}
