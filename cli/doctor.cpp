// `glcast doctor`: on a display machine, what would stop a tile from working, one line each
// (docs/wall.md, "Before a wall runs"): the GL driver headless (EGL) and on the display (GLX),
// a software rasterizer, the keys, the master's four ports and its clock, the multicast route.
// Exit 1 when any line is a problem; a warning alone exits 0.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include <zmq.hpp>

#include <chrono>
#include <cmath>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "common/environment.h"
#include "common/gl_headers.h"
#include "display_configs/display_config.h"
#include "net/security.h"
#include "slave/backend.h"

namespace glcast::cli {

namespace {

struct DoctorArgs {
    std::string config_path, keys, master, multicast;
    int timeout_ms = 2000;
};

class Report {
public:
    void ok(const std::string& what) { line("ok  ", what); }
    void warn(const std::string& what) { line("WARN", what); }
    void fail(const std::string& what) {
        line("FAIL", what);
        failed_ = true;
    }
    bool failed() const { return failed_; }

private:
    static void line(const char* level, const std::string& what) { std::printf("%s %s\n", level, what.c_str()); }
    bool failed_ = false;
};

// The renderer and version of a context of backend `kind`; false with `error` set.
bool gl_driver(const std::string& kind, std::string& renderer, std::string& version, std::string& error) {
    std::unique_ptr<slave::Backend> backend = slave::make_backend(kind, error);
    if (!backend) return false;
    if (!backend->create_context(1, 0, slave::ContextRequest{}, error) || !backend->make_current(1, 16, 16, error))
        return false;
    using GetString = const GLubyte*(APIENTRY*)(GLenum);
    auto get = reinterpret_cast<GetString>(backend->proc_address("glGetString"));
    const GLubyte* r = get ? get(GL_RENDERER) : nullptr;
    const GLubyte* v = get ? get(GL_VERSION) : nullptr;
    if (!r || !v) {
        error = "the context answers no GL_RENDERER";
        return false;
    }
    renderer = reinterpret_cast<const char*>(r);
    version = reinterpret_cast<const char*>(v);
    std::string ignored;
    backend->make_current(0, 0, 0, ignored);
    backend->destroy_context(1);
    return true;
}

void check_gl(Report& report) {
    std::string renderer, version, error;
    if (!gl_driver("egl", renderer, version, error)) {
        report.fail("gl (egl, headless tiles): " + error);
    } else {
        report.ok("gl (egl, headless tiles): " + renderer + ", OpenGL " + version);
        for (const char* software : {"llvmpipe", "softpipe", "swrast", "SVGA3D"})
            if (renderer.find(software) != std::string::npos) {
                report.warn(std::string("gl: ") + software + " is a software rasterizer: a 1080p tile replays at tens of "
                            "frames a second, with the passes at a few (docs/performance.md); a GPU's driver is missing "
                            "or not in use");
                break;
            }
    }
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display) {
        report.warn("glx (window tiles): no DISPLAY: a tile cannot be shown in a window here (--backend egl writes "
                    "frames only)");
        return;
    }
    const std::string where = std::string("glx (window tiles, DISPLAY ") + display + "): ";
    if (!gl_driver("window", renderer, version, error)) report.fail(where + error);
    else report.ok(where + renderer);
}

void check_keys(Report& report, const std::string& dir, bool needed) {
    if (dir.empty()) {
        if (needed) report.fail("keys: none (--keys, the config's \"keys\" or GLCAST_KEYS), and the master is on the network: "
                                "a display machine needs master.pub and slave.key (docs/security.md)");
        else report.ok("keys: none; only loopback and ipc:// walls run without them");
        return;
    }
    net::Security s;
    std::string error;
    if (!net::load_security(dir, false, s, error)) {
        report.fail("keys: " + error);
        return;
    }
    if (!s.has_client_pair && !s.has_master_pair) {
        report.fail("keys: " + dir + " has master.pub but neither slave.key nor master.key: a display machine needs "
                    "its pair (glcast keygen " + dir + "/slave, its .pub among the master's authorized keys)");
        return;
    }
    report.ok("keys: " + dir + ": master.pub" + (s.has_client_pair ? ", slave.key (mode 0600)" : "") +
              (s.has_master_pair ? ", master.key (mode 0600)" : ""));
}

// Connects to host:port within timeout_ms; "" when it answered, else why not.
std::string tcp_reach(const std::string& host, int port, int timeout_ms) {
    addrinfo hints{}, *found = nullptr;
    hints.ai_socktype = SOCK_STREAM;
    const int rc = getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found);
    if (rc != 0) return std::string("cannot resolve ") + host + ": " + gai_strerror(rc);
    std::string why = "no address";
    for (addrinfo* a = found; a; a = a->ai_next) {
        const int fd = socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) continue;
        int err = connect(fd, a->ai_addr, a->ai_addrlen) == 0 ? 0 : errno;
        if (err == EINPROGRESS) {
            pollfd p{fd, POLLOUT, 0};
            if (poll(&p, 1, timeout_ms) == 1) {
                socklen_t len = sizeof err;
                getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len);
            } else {
                err = ETIMEDOUT;
            }
        }
        close(fd);
        if (err == 0) {
            freeaddrinfo(found);
            return "";
        }
        why = std::strerror(err);
    }
    freeaddrinfo(found);
    return why;
}

// True: the control port answers.
bool check_master(Report& report, const std::string& host, int port, int timeout_ms) {
    const char* names[] = {"stream", "journal", "keeper", "control"};
    std::string there, missing;
    bool control = false;
    for (int i = 0; i < 4; ++i) {
        const std::string why = tcp_reach(host, port + i, timeout_ms);
        const std::string name = std::string(names[i]) + " " + std::to_string(port + i);
        if (why.empty()) there += (there.empty() ? "" : ", ") + name;
        else missing += (missing.empty() ? "" : "; ") + name + ": " + why;
        control = control || (i == 3 && why.empty());
    }
    // glcast run serves the control channel as long as it runs, the stream and journal only while
    // a program publishes: the control port decides.
    if (control)
        report.ok("master " + host + ": reachable (" + there + ")" + (missing.empty() ? "" : "; not now: " + missing));
    else
        report.fail("master " + host + ": unreachable (" + missing + ")" + (there.empty() ? "" : "; reachable: " + there) +
                    ": is glcast run up there, and are its ports open?");
    return control;
}

// The master's clock against this one: "TIME" on the control channel (cli/wall_control.h),
// the offset taken at the middle of the round trip.
void check_clock(Report& report, const std::string& host, int port, int timeout_ms) {
    try {
        zmq::context_t context(1);
        zmq::socket_t dealer(context, zmq::socket_type::dealer);
        dealer.set(zmq::sockopt::linger, 0);
        dealer.set(zmq::sockopt::maxmsgsize, int64_t(64));
        const std::string endpoint = "tcp://" + host + ":" + std::to_string(port + 3);
        net::secure_client(dealer, endpoint);
        dealer.connect(endpoint);
        auto now = [] { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); };
        const double sent = now();
        dealer.send(zmq::str_buffer("TIME"), zmq::send_flags::dontwait);
        zmq::pollitem_t item{dealer.handle(), 0, ZMQ_POLLIN, 0};
        zmq::message_t answer;
        double master = 0;
        if (zmq::poll(&item, 1, std::chrono::milliseconds(timeout_ms)) != 1 || !dealer.recv(answer) ||
            std::sscanf(answer.to_string().c_str(), "TIME %lf", &master) != 1 || !std::isfinite(master)) {
            report.warn("clock: the master's control channel gave no time within " + std::to_string(timeout_ms) +
                        " ms (a glcast run older than doctor, or keys it does not know)");
            return;
        }
        const double back = now(), offset = master - (sent + back) / 2;
        char text[160];
        std::snprintf(text, sizeof text, "clock: %+.1f ms from the master's (round trip %.1f ms)", offset * 1e3,
                      (back - sent) * 1e3);
        if (std::fabs(offset) > 0.1) {
            report.warn(std::string(text) + ": the wall's status times and logs disagree (the swap barrier uses no "
                        "clock); run NTP or chrony on every machine");
        } else {
            report.ok(text);
        }
    } catch (const std::exception& e) {
        report.warn(std::string("clock: not measured: ") + e.what());
    }
}

void check_multicast(Report& report, const std::string& group) {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(5555);
    if (inet_pton(AF_INET, group.c_str(), &to.sin_addr) != 1 || (ntohl(to.sin_addr.s_addr) >> 28) != 0xE) {
        report.fail("multicast: " + group + " is not an IPv4 multicast group (224.0.0.0 to 239.255.255.255)");
        return;
    }
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
        report.fail("multicast: no route to " + group + " (" + std::strerror(errno) + "): add one, e.g. ip route add "
                    "224.0.0.0/4 dev IFACE");
        if (fd >= 0) close(fd);
        return;
    }
    sockaddr_in from{};
    socklen_t len = sizeof from;
    getsockname(fd, reinterpret_cast<sockaddr*>(&from), &len);
    char address[INET_ADDRSTRLEN] = "?";
    inet_ntop(AF_INET, &from.sin_addr, address, sizeof address);
    close(fd);
    report.ok("multicast: " + group + " is routed, from " + address);
}

int doctor(const DoctorArgs& a) {
    Report report;
    check_gl(report);
    std::string keys = a.keys, host;
    int port = 0;
    if (!a.config_path.empty()) {
        slave::DisplayConfig config;
        std::string error;
        if (!slave::load_display_config(a.config_path, config, error)) {
            report.fail("config: " + error);
        } else {
            report.ok("config: " + a.config_path + ": " + std::to_string(config.tiles.size()) + " tiles");
            if (keys.empty() && !config.keys.empty()) keys = relative_to(a.config_path, config.keys);
            if (config.master.given) host = config.master.address, port = config.master.port;
        }
    }
    if (!a.master.empty()) {
        const size_t colon = a.master.rfind(':');
        host = a.master.substr(0, colon);
        port = colon == std::string::npos ? 5555 : std::atoi(a.master.c_str() + colon + 1);
        if (host.empty() || port < 1 || port > 65532) {
            report.fail("master: " + a.master + " is not HOST:PORT (PORT 1 to 65532)");
            host.clear();
        }
    }
    if (keys.empty()) keys = environment().keys;
    const bool network = !host.empty() && host != "127.0.0.1" && host != "localhost" && host != "::1";
    check_keys(report, keys, network);
    if (!host.empty() && check_master(report, host, port, a.timeout_ms)) {
        std::string error;
        if (use_keys(keys, false, "glcast doctor", error)) check_clock(report, host, port, a.timeout_ms);
    }
    if (!a.multicast.empty()) check_multicast(report, a.multicast);
    return report.failed() ? 1 : 0;
}

}  // namespace

Command add_doctor(CLI::App& glcast) {
    auto a = std::make_shared<DoctorArgs>();
    CLI::App* app = glcast.add_subcommand("doctor", "on a display machine: what would stop a tile from working, one line each");
    app->footer("Each line is ok, WARN or FAIL; the exit status is 1 when any is FAIL (docs/wall.md).");
    app->add_option("--config", a->config_path, "the wall's display config: its master and keys are checked")->type_name("FILE");
    app->add_option("--keys", a->keys, "this machine's keys folder (default: the config's \"keys\", else GLCAST_KEYS)")
        ->type_name("DIR");
    app->add_option("--master", a->master, "the master's HOST:PORT (default: the config's \"master\")")->type_name("HOST:PORT");
    app->add_option("--multicast", a->multicast, "a multicast group the wall uses: is it routed here?")->type_name("GROUP");
    app->add_option("--timeout", a->timeout_ms, "milliseconds to wait for each of the master's ports (default 2000)")
        ->check(CLI::Range(1, 60000))
        ->type_name("MS");
    return {app, [a](const std::vector<std::string>&) { return doctor(*a); }};
}

}  // namespace glcast::cli
