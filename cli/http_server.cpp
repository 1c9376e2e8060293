#include "cli/http_server.h"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <list>
#include <stdexcept>

namespace glcast::cli {

namespace {

using Clock = std::chrono::steady_clock;

bool same_name(const std::string& a, const std::string& b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return std::tolower(uint8_t(x)) == std::tolower(uint8_t(y)); });
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

std::string percent_decoded(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); i++) {
        if (s[i] == '%' && i + 2 < s.size() + 0 && hex_digit(s[i + 1]) >= 0 && hex_digit(s[i + 2]) >= 0) {
            out += char(hex_digit(s[i + 1]) * 16 + hex_digit(s[i + 2]));
            i += 2;
        } else {
            out += s[i] == '+' ? ' ' : s[i];
        }
    }
    return out;
}

const char* reason(int status) {
    switch (status) {
        case 200: return "OK";
        case 400: return "Bad Request";
        case 403: return "Forbidden";
        case 404: return "Not Found";
        case 405: return "Method Not Allowed";
        case 411: return "Length Required";
        case 413: return "Payload Too Large";
        case 415: return "Unsupported Media Type";
        case 431: return "Request Header Fields Too Large";
        case 503: return "Service Unavailable";
        default: return "Status";
    }
}

bool token_char(char c) { return std::isalnum(uint8_t(c)) || std::strchr("!#$%&'*+-.^_`|~", c); }

struct Connection {
    int fd = -1;
    std::string in, out;
    size_t written = 0;
    bool writing = false, close_after = false;
    Clock::time_point deadline, waiting_since;  // the request's (or the answer's) deadline
};

// What a whole head says: >0 a status to refuse with, 0 parsed into `request` with the body's
// length in `body_bytes`.
int parse_head(const std::string& head, const HttpLimits& limits, HttpRequest& request, size_t& body_bytes,
               bool& keep_alive) {
    size_t line_end = head.find("\r\n");
    const std::string line = head.substr(0, line_end);
    const size_t sp1 = line.find(' '), sp2 = line.rfind(' ');
    if (sp1 == std::string::npos || sp2 == sp1) return 400;
    request.method = line.substr(0, sp1);
    const std::string target = line.substr(sp1 + 1, sp2 - sp1 - 1), version = line.substr(sp2 + 1);
    if (request.method.empty() || !std::all_of(request.method.begin(), request.method.end(), token_char)) return 400;
    if (target.empty() || target[0] != '/' || target.find(' ') != std::string::npos) return 400;
    if (version != "HTTP/1.1" && version != "HTTP/1.0") return 400;
    const size_t q = target.find('?');
    request.path = target.substr(0, q);
    request.query = q == std::string::npos ? "" : target.substr(q + 1);
    keep_alive = version == "HTTP/1.1";
    body_bytes = 0;
    bool has_length = false;
    while (line_end != std::string::npos && line_end + 2 < head.size()) {
        const size_t start = line_end + 2;
        line_end = head.find("\r\n", start);
        const std::string h = head.substr(start, line_end == std::string::npos ? std::string::npos : line_end - start);
        if (h.empty()) break;
        if (request.headers.size() >= limits.max_headers) return 431;
        const size_t colon = h.find(':');
        if (colon == std::string::npos || colon == 0 || !std::all_of(h.begin(), h.begin() + colon, token_char)) return 400;
        std::string value = h.substr(colon + 1);
        value.erase(0, value.find_first_not_of(" \t"));
        value.erase(value.find_last_not_of(" \t") + 1);
        request.headers.push_back({h.substr(0, colon), value});
    }
    for (const auto& [name, value] : request.headers) {
        if (same_name(name, "Transfer-Encoding")) return 411;
        if (same_name(name, "Content-Encoding")) return 415;
        if (same_name(name, "Connection")) keep_alive = same_name(value, "keep-alive") || (keep_alive && !same_name(value, "close"));
        if (!same_name(name, "Content-Length")) continue;
        if (has_length || value.empty() || value.size() > 19 || !std::all_of(value.begin(), value.end(), ::isdigit)) return 400;
        has_length = true;
        body_bytes = std::stoull(value);
        if (body_bytes > limits.max_body_bytes) return 413;
    }
    return 0;
}

std::string serialized(const HttpResponse& r, bool keep_alive) {
    std::string out = "HTTP/1.1 " + std::to_string(r.status) + " " + reason(r.status) + "\r\nContent-Type: " +
                      r.content_type + "\r\nContent-Length: " + std::to_string(r.body.size()) + "\r\n";
    for (const auto& [name, value] : r.headers) out += name + ": " + value + "\r\n";
    out += keep_alive ? "Connection: keep-alive\r\n\r\n" : "Connection: close\r\n\r\n";
    return out + r.body;
}

}  // namespace

bool HttpRequest::has_header(const std::string& name) const {
    return std::any_of(headers.begin(), headers.end(), [&](const auto& h) { return same_name(h.first, name); });
}

std::string HttpRequest::header(const std::string& name) const {
    for (const auto& [n, value] : headers)
        if (same_name(n, name)) return value;
    return "";
}

std::string HttpRequest::param(const std::string& name) const {
    size_t start = 0;
    while (start <= query.size()) {
        size_t end = query.find('&', start);
        if (end == std::string::npos) end = query.size();
        const std::string pair = query.substr(start, end - start);
        const size_t eq = pair.find('=');
        if (percent_decoded(pair.substr(0, eq)) == name) return eq == std::string::npos ? "" : percent_decoded(pair.substr(eq + 1));
        start = end + 1;
    }
    return "";
}

HttpServer::HttpServer(const std::string& host, int port, Handler handler, HttpLimits limits)
    : handler_(std::move(handler)), limits_(limits) {
    addrinfo hints{}, *found = nullptr;
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    const std::string service = std::to_string(port);
    if (const int e = getaddrinfo(host.c_str(), service.c_str(), &hints, &found); e != 0)
        throw std::runtime_error(host + ": " + gai_strerror(e));
    for (addrinfo* a = found; a && listener_ < 0; a = a->ai_next) {
        const int fd = socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) continue;
        const int on = 1;
        setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
        if (bind(fd, a->ai_addr, a->ai_addrlen) == 0 && listen(fd, 128) == 0) {
            sockaddr_storage bound{};
            socklen_t size = sizeof bound;
            getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &size);
            port_ = ntohs(bound.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                                                      : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
            listener_ = fd;
        } else {
            close(fd);
        }
    }
    freeaddrinfo(found);
    if (listener_ < 0) throw std::runtime_error(host + ":" + service + ": cannot listen there (in use, or not an address of this machine)");
    if (pipe2(wake_, O_NONBLOCK | O_CLOEXEC) != 0) {
        close(listener_);
        throw std::runtime_error(std::string("a pipe: ") + std::strerror(errno));
    }
    thread_ = std::thread([this] { serve(); });
}

HttpServer::~HttpServer() {
    stopping_ = true;
    (void)!write(wake_[1], "x", 1);
    if (thread_.joinable()) thread_.join();
    close(listener_);
    close(wake_[0]);
    close(wake_[1]);
}

HttpCounts HttpServer::counts() const { return {answered_, refused_, timed_out_, evicted_}; }

void HttpServer::serve() {
    const auto request_time = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limits_.request_seconds));
    std::list<Connection> connections;
    auto answer = [&](Connection& c, const HttpResponse& r, bool keep_alive) {
        c.out = serialized(r, keep_alive);
        c.written = 0;
        c.writing = true;
        c.close_after = !keep_alive;
        c.deadline = Clock::now() + request_time;
    };
    auto refuse = [&](Connection& c, int status, const std::string& why) {
        HttpResponse r;
        r.set(status, why + "\n");
        answer(c, r, false);
        c.in.clear();
        refused_++;
    };
    // Answers a whole request in what a connection has sent, reading more while there is none.
    // False: close it.
    auto take = [&](Connection& c) {
        char buffer[16384];
        for (;;) {
            const size_t head_end = c.in.find("\r\n\r\n");
            if ((head_end == std::string::npos ? c.in.size() : head_end + 4) > limits_.max_header_bytes) {
                refuse(c, 431, "the request's head is over " + std::to_string(limits_.max_header_bytes) + " bytes");
                return true;
            }
            if (head_end != std::string::npos) {
                HttpRequest request;
                size_t body_bytes = 0;
                bool keep_alive = false;
                if (const int refused = parse_head(c.in.substr(0, head_end + 2), limits_, request, body_bytes, keep_alive)) {
                    refuse(c, refused,
                           refused == 431   ? "more than " + std::to_string(limits_.max_headers) + " header lines"
                           : refused == 413 ? "a body of more than " + std::to_string(limits_.max_body_bytes) + " bytes"
                           : refused == 411 ? "no Transfer-Encoding is taken: send a body of Content-Length"
                           : refused == 415 ? "no Content-Encoding is taken"
                                            : "a malformed request");
                    return true;
                }
                if (c.in.size() >= head_end + 4 + body_bytes) {
                    request.body = c.in.substr(head_end + 4, body_bytes);
                    c.in.erase(0, head_end + 4 + body_bytes);
                    HttpResponse response;
                    handler_(request, response);
                    answer(c, response, keep_alive);
                    answered_++;
                    return true;
                }
            }
            // (Never more than a head and a body: both are bounded above.)
            const ssize_t n = recv(c.fd, buffer, sizeof buffer, 0);
            if (n == 0) return false;
            if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
            c.in.append(buffer, size_t(n));
        }
    };
    auto flush = [&](Connection& c) {
        while (c.written < c.out.size()) {
            const ssize_t n = send(c.fd, c.out.data() + c.written, c.out.size() - c.written, MSG_NOSIGNAL);
            if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
            c.written += size_t(n);
        }
        if (c.close_after) return false;
        c.out.clear();
        c.writing = false;
        c.deadline = c.waiting_since = Clock::now();
        c.deadline += request_time;
        return true;
    };
    std::vector<pollfd> polled;
    std::vector<std::list<Connection>::iterator> of;
    while (!stopping_) {
        polled.assign({{wake_[0], POLLIN, 0}, {listener_, POLLIN, 0}});
        of.assign(2, connections.end());
        auto now = Clock::now();
        auto next = now + std::chrono::seconds(1);
        for (auto it = connections.begin(); it != connections.end(); ++it) {
            polled.push_back({it->fd, short(it->writing ? POLLOUT : POLLIN), 0});
            of.push_back(it);
            next = std::min(next, it->deadline);
        }
        const int wait_ms = int(std::max<int64_t>(0, std::chrono::duration_cast<std::chrono::milliseconds>(next - now).count()) + 1);
        if (poll(polled.data(), polled.size(), wait_ms) < 0 && errno != EINTR) break;
        std::vector<std::list<Connection>::iterator> closing;
        for (size_t i = 2; i < polled.size(); i++) {
            if (!polled[i].revents) continue;
            Connection& c = *of[i];
            bool keep = true;
            if (polled[i].revents & (POLLERR | POLLNVAL)) keep = false;
            else if (!c.writing) keep = take(c);
            if (keep && c.writing) keep = flush(c);
            // Bytes of the next request that came with this one (pipelined): read them now.
            if (keep && !c.writing && !c.in.empty()) keep = take(c) && (!c.writing || flush(c));
            if (!keep) closing.push_back(of[i]);
        }
        now = Clock::now();
        for (auto it = connections.begin(); it != connections.end(); ++it)
            if (it->deadline <= now && std::find(closing.begin(), closing.end(), it) == closing.end()) {
                closing.push_back(it);
                timed_out_++;
            }
        for (auto it : closing) {
            close(it->fd);
            connections.erase(it);
        }
        if (polled[1].revents & POLLIN) {
            for (int n = 0; n < 64; n++) {
                const int fd = accept4(listener_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
                if (fd < 0) break;
                if (connections.size() >= limits_.max_connections) {
                    // The one that has waited longest without a whole request goes, so that a
                    // client that asks now is answered whatever the others hold.
                    auto oldest = connections.end();
                    for (auto it = connections.begin(); it != connections.end(); ++it)
                        if (!it->writing && (oldest == connections.end() || it->waiting_since < oldest->waiting_since)) oldest = it;
                    if (oldest == connections.end()) {
                        close(fd);
                        evicted_++;
                        continue;
                    }
                    close(oldest->fd);
                    connections.erase(oldest);
                    evicted_++;
                }
                Connection c;
                c.fd = fd;
                c.waiting_since = now;
                c.deadline = now + request_time;
                connections.push_back(std::move(c));
            }
        }
        char drained[64];
        while (read(wake_[0], drained, sizeof drained) > 0) {
        }
    }
    for (Connection& c : connections) close(c.fd);
}

}  // namespace glcast::cli
