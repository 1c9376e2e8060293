// `glcast run --dashboard ADDRESS:PORT`: the wall in a browser (docs/wall.md, "The dashboard").
// An HTTP server of its own (cli/http_server.h: bounded in all a client sends) serves the page of cli/dashboard/ (built into the binary) and its
// API: the wall's layout, its status and history (cli/wall_status.h), each tile's thumbnail and
// the live effects (cli/wall_control.h).
//
// Who may: on a loopback address anyone on this machine (as for the wall's other local
// channels); on any other address only a browser that gives the token printed at start
// (?token=... in the page's address, which the page passes on); the page's own files, which say
// nothing of the wall, are served to anyone. Requests that change the wall
// must carry the header X-Glcast-Request, which a page of another site cannot send without
// asking (CORS), and every request must name this server in its Host header (no DNS rebinding).
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

#include "cli/wall_control.h"
#include "cli/wall_status.h"
#include "display_configs/display_config.h"

namespace glcast::cli {

class HttpServer;

// The wall as the page draws it: planar tiles as rectangles of the canvas, view tiles (a
// cylinder, a CAVE) unrolled by the angles they cover. `config` null: the one window.
nlohmann::json wall_layout(const slave::DisplayConfig* config);

class Dashboard {
public:
    // Binds ADDRESS:PORT (":PORT" and "PORT" mean 127.0.0.1); throws std::runtime_error naming it.
    Dashboard(const std::string& address_port, WallControl& control, const WallStatus& status, nlohmann::json layout);
    ~Dashboard();
    const std::string& url() const { return url_; }  // with the token, when it needs one
    bool needs_token() const { return !token_.empty(); }

private:
    bool allowed(const std::string& host_header, const std::string& token) const;
    WallControl& control_;
    const WallStatus& status_;
    nlohmann::json layout_;
    std::string host_, token_, url_;
    int port_ = 0;
    std::unique_ptr<HttpServer> server_;
};

}  // namespace glcast::cli
