#include "cli/dashboard.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <stdexcept>

#include "cli/http_server.h"
#include "net/security.h"
#include "slave/effects/effect_params.h"

namespace glcast::cli {

const std::map<std::string, std::string>& dashboard_files();  // generated: cmake/embed_files.cmake

namespace {

double degrees(double radians) { return radians * 180.0 / M_PI; }

// A screen's corners as the viewer sees them: yaw (right positive) and pitch (up positive).
void screen_angles(const slave::TileView& v, const std::array<double, 3>& eye, double out[4]) {
    const std::array<double, 3> top_right = {v.top_left[0] + v.bottom_right[0] - v.bottom_left[0],
                                             v.top_left[1] + v.bottom_right[1] - v.bottom_left[1],
                                             v.top_left[2] + v.bottom_right[2] - v.bottom_left[2]};
    out[0] = out[2] = 1e9, out[1] = out[3] = -1e9;  // yaw min, max; pitch min, max
    for (const auto& c : {v.bottom_left, v.bottom_right, v.top_left, top_right}) {
        const double x = c[0] - eye[0], y = c[1] - eye[1], z = c[2] - eye[2];
        const double yaw = degrees(std::atan2(x, -z)), pitch = degrees(std::atan2(y, std::hypot(x, z)));
        out[0] = std::min(out[0], yaw), out[1] = std::max(out[1], yaw);
        out[2] = std::min(out[2], pitch), out[3] = std::max(out[3], pitch);
    }
}

std::string random_token() {
    std::random_device device;
    char hex[33];
    for (int i = 0; i < 4; i++) std::snprintf(hex + 8 * i, 9, "%08x", unsigned(device()));
    return hex;
}

// ADDRESS:PORT, :PORT or PORT.
void split_address(const std::string& address_port, std::string& host, int& port) {
    const size_t colon = address_port.rfind(':');
    host = colon == std::string::npos || colon == 0 ? "127.0.0.1" : address_port.substr(0, colon);
    if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    const std::string digits = colon == std::string::npos ? address_port : address_port.substr(colon + 1);
    char* end = nullptr;
    const long p = std::strtol(digits.c_str(), &end, 10);
    if (digits.empty() || *end || p < 1 || p > 65535)
        throw std::runtime_error("--dashboard " + address_port + ": want ADDRESS:PORT (a port of 1 to 65535)");
    port = int(p);
}

bool same_name(const std::string& a, const std::string& b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return std::tolower(uint8_t(x)) == std::tolower(uint8_t(y)); });
}

// An address literal of loopback (127.0.0.0/8 in dotted decimal, ::1 however it is spelled, or
// ::ffff:127.x.y.z), or `localhost`. Not a name that starts with "127.": a page of another site
// can make its own name resolve to 127.0.0.1 (DNS rebinding).
bool loopback(const std::string& host) {
    if (same_name(host, "localhost")) return true;
    in_addr v4{};
    if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
    in6_addr v6{};
    if (inet_pton(AF_INET6, host.c_str(), &v6) != 1) return false;
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    return IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127;
}

std::string content_type(const std::string& name) {
    if (name.size() >= 5 && name.compare(name.size() - 5, 5, ".html") == 0) return "text/html; charset=utf-8";
    if (name.size() >= 4 && name.compare(name.size() - 4, 4, ".css") == 0) return "text/css; charset=utf-8";
    if (name.size() >= 3 && name.compare(name.size() - 3, 3, ".js") == 0) return "text/javascript; charset=utf-8";
    return "application/octet-stream";
}

// The plots' series: one point a second.
nlohmann::json history_series(const std::vector<nlohmann::json>& history) {
    nlohmann::json out = {{"time", nlohmann::json::array()}, {"program_fps", nlohmann::json::array()},
                          {"mbps", nlohmann::json::array()}, {"tiles", nlohmann::json::object()}};
    for (const nlohmann::json& s : history) {
        out["time"].push_back(s["time"]);
        out["program_fps"].push_back(s["program"]["fps"]);
        out["mbps"].push_back(s["program"]["mbps"]);
        for (const auto& t : s["tiles"]) {
            nlohmann::json& series = out["tiles"][t["tile"].get<std::string>()];
            series["fps"].push_back(t["fps"]);
            series["lag"].push_back(t["lag"]);
        }
    }
    return out;
}

nlohmann::json effects_json(const slave::LiveEffects& e) {
    nlohmann::json on = nlohmann::json::object();
    const std::string list = "," + e.enabled_list() + ",";
    for (const std::string& name : slave::effects::known_display_effects())
        on[name] = list.find("," + name + ",") != std::string::npos;
    return {{"version", e.version}, {"frame", e.frame}, {"on", on}, {"params", e.params}};
}

}  // namespace

nlohmann::json wall_layout(const slave::DisplayConfig* config) {
    nlohmann::json tiles = nlohmann::json::array();
    if (!config) {
        tiles.push_back({{"name", "window"}, {"machine", ""}, {"rect", {0, 0, 4, 3}}});
        return {{"units", "window"}, {"width", 4}, {"height", 3}, {"tiles", tiles}};
    }
    const bool views = std::any_of(config->tiles.begin(), config->tiles.end(), [](const auto& t) { return t.view.enabled; });
    if (!views) {
        for (const slave::Tile& t : config->tiles)
            tiles.push_back({{"name", t.name}, {"machine", t.machine}, {"rect", {t.x, t.y, t.width, t.height}}});
        return {{"name", config->name}, {"units", "pixels"}, {"width", config->canvas_width},
                {"height", config->canvas_height}, {"tiles", tiles}};
    }
    // Unrolled: x is the yaw a tile covers, y the pitch (up is up on the page).
    double box[4] = {1e9, -1e9, 1e9, -1e9};
    std::vector<std::array<double, 4>> spans;
    for (const slave::Tile& t : config->tiles) {
        double a[4];
        if (t.view.screen) {
            screen_angles(t.view, config->viewer.position, a);
        } else {
            a[0] = t.view.yaw_deg + t.view.left_deg, a[1] = t.view.yaw_deg + t.view.right_deg;
            a[2] = t.view.pitch_deg + t.view.bottom_deg, a[3] = t.view.pitch_deg + t.view.top_deg;
        }
        spans.push_back({a[0], a[1], a[2], a[3]});
        box[0] = std::min(box[0], a[0]), box[1] = std::max(box[1], a[1]);
        box[2] = std::min(box[2], a[2]), box[3] = std::max(box[3], a[3]);
    }
    for (size_t i = 0; i < config->tiles.size(); i++) {
        const slave::Tile& t = config->tiles[i];
        const auto& a = spans[i];
        tiles.push_back({{"name", t.name}, {"machine", t.machine},
                         {"rect", {a[0] - box[0], box[3] - a[3], a[1] - a[0], a[3] - a[2]}},
                         {"eye", t.eye == slave::TileEye::left ? "left" : t.eye == slave::TileEye::right ? "right" : ""}});
    }
    return {{"name", config->name}, {"units", "degrees"}, {"width", box[1] - box[0]}, {"height", box[3] - box[2]},
            {"tiles", tiles}};
}

Dashboard::Dashboard(const std::string& address_port, WallControl& control, const WallStatus& status,
                     nlohmann::json layout)
    : control_(control), status_(status), layout_(std::move(layout)) {
    split_address(address_port, host_, port_);
    if (!loopback(host_)) token_ = random_token();
    layout_["effects"] = slave::effects::known_display_effects();
    nlohmann::json params = nlohmann::json::array();
    for (const auto& p : slave::effects::all_param_specs())
        if (!p.text) params.push_back({{"name", p.name}, {"value", p.value}, {"min", p.min}, {"max", p.max}, {"help", p.help}});
    layout_["params"] = params;

    // Names of the page's files and of tiles, as the thumbnails' path takes them.
    auto plain = [](const std::string& s) {
        return !s.empty() && s.size() <= 64 && std::all_of(s.begin(), s.end(), [](char c) {
            return std::isalnum(uint8_t(c)) || c == '_' || c == '.' || c == '-';
        });
    };
    auto handle = [this, plain](const HttpRequest& req, HttpResponse& res) {
        res.headers.push_back({"Cache-Control", "no-store"});
        const std::string& path = req.path;
        if (path.rfind("/api/", 0) != 0) {
            // The page, its style and script say nothing of the wall: served to anyone, so that
            // the page can load them by plain links; everything under /api/ asks.
            const std::string name = path == "/" ? "index.html" : path.substr(1);
            const auto& files = dashboard_files();
            if (req.method != "GET" || !plain(name) || !files.count(name)) return res.set(404, "no such page\n");
            res.headers = {{"Cache-Control", "no-cache"}};
            return res.set(200, files.at(name), content_type(name));
        }
        if (!allowed(req.header("Host"), req.param("token")))
            return res.set(403, token_.empty() ? "this dashboard answers only to its own address (the Host header)\n"
                                               : "this dashboard needs the token glcast run printed at its start (?token=...)\n");
        if (req.method == "POST" && path == "/api/ctl") {
            if (!req.has_header("X-Glcast-Request"))  // a form of another site cannot set it
                return res.set(403, "a request that changes the wall needs the header X-Glcast-Request\n");
            std::string reply;
            const bool ok = control_.change_effects(req.body, reply);
            return res.set(ok ? 200 : 400, nlohmann::json{{"ok", ok}, {"reply", reply}}.dump(), "application/json");
        }
        if (req.method != "GET") return res.set(405, "the dashboard takes GET, and POST of /api/ctl\n");
        if (path == "/api/wall") return res.set(200, layout_.dump(), "application/json");
        if (path == "/api/status") {
            const nlohmann::json j = {{"latest", status_.latest()},
                                      {"history", history_series(status_.history())},
                                      {"effects", effects_json(control_.effects())}};
            return res.set(200, j.dump(), "application/json");
        }
        const std::string thumbnail = "/api/thumbnail/";
        if (path.rfind(thumbnail, 0) == 0 && plain(path.substr(thumbnail.size()))) {
            std::string jpeg;
            uint64_t frame = 0;
            if (!control_.thumbnail(path.substr(thumbnail.size()), jpeg, frame))
                return res.set(404, "no thumbnail of that tile yet\n");
            res.headers.push_back({"X-Glcast-Frame", std::to_string(frame)});
            return res.set(200, std::move(jpeg), "image/jpeg");
        }
        res.set(404, "no such request\n");
    };
    try {
        server_ = std::make_unique<HttpServer>(host_, port_, handle);
    } catch (const std::exception& e) {
        throw std::runtime_error("--dashboard " + address_port + ": " + e.what());
    }
    const std::string shown = host_.find(':') != std::string::npos ? "[" + host_ + "]" : host_;
    url_ = "http://" + shown + ":" + std::to_string(port_) + "/" + (token_.empty() ? "" : "?token=" + token_);
}

Dashboard::~Dashboard() = default;

bool Dashboard::allowed(const std::string& host_header, const std::string& token) const {
    if (!token_.empty()) return token.size() == token_.size() && token == token_;
    // Loopback: only requests that name this server (a page of another site resolved to
    // 127.0.0.1 names its own host): HOST or HOST:PORT, [IPV6] or [IPV6]:PORT, nothing after.
    std::string host = host_header, port;
    if (!host.empty() && host[0] == '[') {
        const size_t end = host.find(']');
        if (end == std::string::npos) return false;
        port = host.substr(end + 1);
        host = host.substr(1, end - 1);
        if (!port.empty() && port[0] != ':') return false;
    } else if (const size_t colon = host.find(':'); colon != std::string::npos) {
        port = host.substr(colon);
        host = host.substr(0, colon);
    }
    if (!port.empty() && (port.size() < 2 || port.size() > 6 || !std::all_of(port.begin() + 1, port.end(), ::isdigit)))
        return false;
    return loopback(host) || same_name(host, host_);
}

}  // namespace glcast::cli
