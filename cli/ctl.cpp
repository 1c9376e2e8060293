// `glcast ctl WALL effects +snow -shadows`, `glcast ctl WALL param snow.density=0.4`: the
// operator switches a running wall's passes (cli/wall_control.h, "Live effects").
#include <zmq.hpp>

#include <chrono>
#include <cstdio>
#include <sys/stat.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "cli/wall_control.h"
#include "display_configs/display_config.h"
#include "net/security.h"
#include "net/wall_endpoints.h"

namespace glcast::cli {

using slave::DisplayConfig;
using slave::load_display_config;

namespace {

struct CtlArgs {
    std::string wall, keys;
    bool insecure = false;
    int wait_seconds = 5;
};

// WALL: the control endpoint glcast run printed (ipc://..., tcp://HOST:PORT), the HOST:PORT of a
// display config's "master", or a display config (its "master", and its "keys").
bool control_endpoint(CtlArgs& a, std::string& endpoint, std::string& error) {
    if (a.wall.find("://") != std::string::npos) {
        endpoint = a.wall;
        return true;
    }
    struct stat st {};
    if (stat(a.wall.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
        DisplayConfig config;
        if (!load_display_config(a.wall, config, error)) return false;
        if (!config.master.given) {
            error = a.wall + " has no \"master\": give the control endpoint glcast run printed";
            return false;
        }
        if (a.keys.empty() && !config.keys.empty()) a.keys = relative_to(a.wall, config.keys);
        endpoint = net::wall_endpoints_at(config.master.address, config.master.port).control;
        return true;
    }
    const size_t colon = a.wall.rfind(':');
    char* end = nullptr;
    const long port = colon == std::string::npos ? 0 : std::strtol(a.wall.c_str() + colon + 1, &end, 10);
    if (colon == 0 || colon == std::string::npos || !end || *end || port < 1 || port > 65535) {
        error = "the wall \"" + a.wall + "\" is neither an endpoint (ipc://PATH, tcp://HOST:PORT), a HOST:PORT nor a "
                "display config";
        return false;
    }
    endpoint = net::wall_endpoints_at(a.wall.substr(0, colon), int(port)).control;
    return true;
}

int ctl(CtlArgs& a, const std::vector<std::string>& words) {
    std::string endpoint, error;
    if (!control_endpoint(a, endpoint, error)) {
        std::fprintf(stderr, "glcast ctl: %s\n", error.c_str());
        return 2;
    }
    if (!use_keys(a.keys, a.insecure, "glcast ctl", error)) return 1;
    std::string request = "CTL";
    for (const std::string& w : words) request += " " + w;
    if (words.empty()) {
        std::fprintf(stderr, "glcast ctl: what to change? (effects +NAME -NAME, or param NAME=VALUE)\n");
        return 2;
    }
    if (request.size() > 1024) {  // the control channel's bound (cli/wall_control.cpp)
        std::fprintf(stderr, "glcast ctl: a request of %zu bytes: the wall takes at most 1024\n", request.size());
        return 2;
    }
    try {
        // The operator's own key pair when it has one (operator.key), else this machine's.
        net::Security security = net::process_security();
        if (security.has_operator_pair) security.client = security.operator_pair, security.has_client_pair = true;
        zmq::context_t context(1);
        zmq::socket_t socket(context, zmq::socket_type::dealer);
        socket.set(zmq::sockopt::linger, 0);
        socket.set(zmq::sockopt::maxmsgsize, int64_t(WallControl::kMaxReplyBytes));
        net::secure_client(socket, endpoint, security);
        socket.connect(endpoint);
        socket.send(zmq::buffer(request), zmq::send_flags::none);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(a.wait_seconds);
        while (std::chrono::steady_clock::now() < deadline) {
            zmq::pollitem_t item{socket.handle(), 0, ZMQ_POLLIN, 0};
            zmq::poll(&item, 1, std::chrono::milliseconds(100));
            if (!(item.revents & ZMQ_POLLIN)) continue;
            zmq::message_t answer;
            if (!socket.recv(answer)) continue;
            const std::string text = answer.to_string();
            if (text.compare(0, 3, "OK ") == 0) {
                std::printf("%s\n", text.c_str() + 3);
                return 0;
            }
            if (text.compare(0, 6, "ERROR ") == 0) {
                std::fprintf(stderr, "glcast ctl: %s\n", text.c_str() + 6);
                return 1;
            }
        }
        std::fprintf(stderr, "glcast ctl: no answer from %s within %d s (is glcast run serving that wall, and are "
                             "these keys its operator's?)\n", endpoint.c_str(), a.wait_seconds);
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast ctl: %s\n", e.what());
        return 1;
    }
}

}  // namespace

Command add_ctl(CLI::App& glcast) {
    auto a = std::make_shared<CtlArgs>();
    CLI::App* app = glcast.add_subcommand("ctl", "switch a running wall's passes: effects +snow -shadows, param NAME=VALUE");
    app->footer("The request follows WALL:\n"
                "  effects +NAME -NAME ...   switch passes on (+NAME, or NAME) and off (-NAME): snow, rain,\n"
                "                            cover, icicles, shadows\n"
                "  param NAME=VALUE ...      set passes' parameters (`glcast effects` lists them)\n"
                "e.g. glcast ctl tcp://wall:5557 effects +snow -shadows\n\n"
                "Every tile switches at the same frame of the program (docs/wall.md, \"Live control\"). On a wall\n"
                "with keys only the operator may: the master's key, or one of the master's operators/NAME.pub\n"
                "(this machine's operator.key).");
    app->add_option("WALL", a->wall,
                    "the control endpoint glcast run printed (ipc://PATH, tcp://HOST:PORT), the HOST:PORT\n"
                    "of the config's \"master\", or the display config itself")
        ->required();
    add_security_options(*app, a->keys, a->insecure);
    add_int(*app, "--wait", a->wait_seconds, 1, 600, "how long to wait for the wall's answer (default 5)")
        ->type_name("SECONDS");
    app->prefix_command();  // the request's words are ours, "-shadows" too
    return {app, [a, app](const std::vector<std::string>&) { return ctl(*a, app->remaining()); }};
}

}  // namespace glcast::cli
