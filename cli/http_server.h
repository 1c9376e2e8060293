// The dashboard's HTTP/1.1 server (cli/dashboard.h): small, and bounded in everything a client
// controls (docs/security.md, "The dashboard"). One thread polls every connection without
// blocking, so that no client, idle, slow or flooding, holds up another: a request is read whole
// (request line and headers, then a body of Content-Length) within a deadline, then handled on
// that thread, and its answer written without waiting.
//
// Refused, with the status named and the connection closed: a head over `max_header_bytes` or of
// more than `max_headers` lines (431); a body over `max_body_bytes` by its Content-Length (413);
// any Transfer-Encoding (411: a chunked body could be endless) or Content-Encoding (415: a
// compressed one could grow); a malformed request line or header (400). A request not whole
// within `request_seconds` of its connection being ready for it, or an answer not taken within
// the same, closes the connection (idle keep-alive connections too). At `max_connections`, a new
// connection closes the one that has waited longest without a whole request.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace glcast::cli {

struct HttpRequest {
    std::string method, path, query, body;  // path without the query; query without the '?'
    std::vector<std::pair<std::string, std::string>> headers;
    bool has_header(const std::string& name) const;           // names compared without case
    std::string header(const std::string& name) const;        // "" when absent
    std::string param(const std::string& name) const;         // of the query, percent-decoded; "" when absent
};

struct HttpResponse {
    int status = 200;
    std::string body, content_type = "text/plain";
    std::vector<std::pair<std::string, std::string>> headers;
    void set(int code, std::string text, std::string type = "text/plain") {
        status = code, body = std::move(text), content_type = std::move(type);
    }
};

struct HttpLimits {
    size_t max_connections = 512;
    size_t max_header_bytes = 16384;  // the request line and every header
    size_t max_headers = 64;
    size_t max_body_bytes = 4096;
    double request_seconds = 10;
};

struct HttpCounts {
    uint64_t answered = 0, refused = 0, timed_out = 0, evicted = 0;
};

class HttpServer {
public:
    using Handler = std::function<void(const HttpRequest&, HttpResponse&)>;
    // Binds HOST:PORT (an address literal or a name; port 0: any); throws std::runtime_error.
    HttpServer(const std::string& host, int port, Handler handler, HttpLimits limits = {});
    ~HttpServer();
    int port() const { return port_; }
    HttpCounts counts() const;

private:
    void serve();
    Handler handler_;
    HttpLimits limits_;
    int listener_ = -1, wake_[2] = {-1, -1}, port_ = 0;
    std::atomic<uint64_t> answered_{0}, refused_{0}, timed_out_{0}, evicted_{0};
    std::atomic<bool> stopping_{false};
    std::thread thread_;
};

}  // namespace glcast::cli
