#include "cli/wall_control.h"

#include <zmq.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "net/security.h"

namespace glcast::cli {

BarrierState::BarrierState(std::vector<std::string> tiles, double drop_seconds, double now) : drop_seconds_(drop_seconds) {
    for (const std::string& t : tiles) tiles_[t].last_heard = now;
}

bool BarrierState::ready(const std::string& tile, uint64_t frame, double now) {
    auto it = tiles_.find(tile);
    if (it == tiles_.end()) return false;
    Tile& t = it->second;
    t.waiting = true;
    t.frame = frame;
    t.last_heard = now;
    if (t.dropped) {
        t.dropped = false;
        back.push_back(tile);
    }
    return true;
}

void BarrierState::heard(const std::string& tile, double now) {
    if (auto it = tiles_.find(tile); it != tiles_.end()) it->second.last_heard = std::max(it->second.last_heard, now);
}

bool BarrierState::counted(const std::string& tile) const {
    auto it = tiles_.find(tile);
    return it != tiles_.end() && !it->second.dropped;
}

std::vector<BarrierState::Release> BarrierState::release(double now, std::vector<std::string>* dropped) {
    std::vector<Release> out;
    bool anyone_waits = false;
    for (auto& [name, t] : tiles_) anyone_waits |= t.waiting;
    if (!anyone_waits) return out;
    // A tile that keeps the others waiting and has said nothing for drop_seconds_ is gone.
    for (auto& [name, t] : tiles_)
        if (!t.dropped && !t.waiting && now - t.last_heard > drop_seconds_) {
            t.dropped = true;
            if (dropped) dropped->push_back(name);
        }
    uint64_t lowest = UINT64_MAX;
    for (auto& [name, t] : tiles_) {
        if (t.dropped) continue;
        if (!t.waiting) return out;  // still drawing
        lowest = std::min(lowest, t.frame);
    }
    for (auto& [name, t] : tiles_)
        if (t.waiting && t.frame == lowest) {
            out.push_back({name, t.frame});
            t.waiting = false;
            t.last_heard = now;  // drawing the next frame from now on
        }
    started_ |= !out.empty();
    return out;
}

struct WallControl::Sockets {
    zmq::context_t context{1};
    std::unique_ptr<net::Authenticator> authenticator;
    zmq::socket_t router{context, zmq::socket_type::router};
};

namespace {

constexpr size_t kMaxRequestBytes = 256;

bool plain_name(const std::string& s) {
    return !s.empty() && s.size() <= 64 &&
           std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(uint8_t(c)) || c == '_' || c == '.' || c == '-'; });
}

double seconds_since_start() {
    static const auto start = std::chrono::steady_clock::now();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

bool TileOwners::speaks_for(const std::string& tile, const std::string& peer, double now) {
    auto [it, fresh] = owners_.try_emplace(tile, Owner{peer, now});
    Owner& o = it->second;
    if (!fresh && o.peer != peer) {
        if (now - o.last <= takeover_seconds_) {
            refused_++;
            return false;
        }
        o.peer = peer;  // the owner went silent: a restarted slave takes its name back
    }
    o.last = now;
    return true;
}

WallControl::WallControl(std::string endpoint, std::vector<std::string> tiles, bool barrier, HeadPoseFor head_for)
    : endpoint_(std::move(endpoint)), tiles_(std::move(tiles)), barrier_(barrier), head_for_(std::move(head_for)),
      sockets_(std::make_unique<Sockets>()) {
    for (const std::string& t : tiles_) status_[t];
    zmq::socket_t& router = sockets_->router;
    try {
        sockets_->authenticator = net::authenticator_for(sockets_->context, "the wall's control channel");
        router.set(zmq::sockopt::linger, 0);
        router.set(zmq::sockopt::maxmsgsize, int64_t(kMaxRequestBytes));
        router.set(zmq::sockopt::sndhwm, 64);
        net::secure_server(router, endpoint_);
        router.bind(endpoint_);
    } catch (const std::exception& e) {
        throw std::runtime_error("the wall's control channel on " + endpoint_ + ": " + e.what());
    }
    thread_ = std::thread([this] { serve(); });
}

WallControl::~WallControl() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
}

std::map<std::string, TileStatus> WallControl::status() const {
    std::lock_guard lock(mutex_);
    std::map<std::string, TileStatus> out = status_;
    const auto now = std::chrono::steady_clock::now();
    for (auto& [tile, s] : out)
        if (auto it = heard_.find(tile); it != heard_.end())
            s.age_seconds = std::chrono::duration<double>(now - it->second).count();
    return out;
}

// The pose words of frame n's GO: the same for every tile released at n (the tracker's pose may
// change between two of them).
std::string WallControl::pose_words(uint64_t frame) {
    if (!head_for_) return "";
    auto known = pose_words_.find(frame);
    if (known != pose_words_.end()) return known->second;
    slave::HeadPose h;
    std::string words;
    if (head_for_(frame + 1, h)) {
        char text[256];
        std::snprintf(text, sizeof text, " POSE %.17g %.17g %.17g %.17g %.17g %.17g %.17g", h.position.x, h.position.y,
                      h.position.z, h.orientation.w, h.orientation.x, h.orientation.y, h.orientation.z);
        words = text;
        if (h.eye_separation >= 0) {
            std::snprintf(text, sizeof text, " SEP %.17g", h.eye_separation);
            words += text;
        }
    }
    while (pose_words_.size() >= 64) pose_words_.erase(pose_words_.begin());  // frames long gone
    return pose_words_[frame] = words;
}

void WallControl::serve() {
    zmq::socket_t& router = sockets_->router;
    BarrierState state(tiles_, kDropSeconds, seconds_since_start());
    std::map<std::string, std::string> identity_of;  // tile -> the ROUTER identity of its owner
    TileOwners owners(kTakeoverSeconds);
    bool said_refused = false;
    while (!stopping_) {
        zmq::pollitem_t item{router.handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(50));
        for (int n = 0; n < 256 && (item.revents & ZMQ_POLLIN); n++) {
            zmq::message_t identity, body;
            if (!router.recv(identity, zmq::recv_flags::dontwait)) break;
            bool well_formed = router.get(zmq::sockopt::rcvmore) && router.recv(body) && !router.get(zmq::sockopt::rcvmore);
            while (router.get(zmq::sockopt::rcvmore)) (void)router.recv(body);  // extra parts: read and forget
            if (!well_formed || identity.size() == 0 || identity.size() > 255) continue;
            std::istringstream words(body.to_string());
            std::string verb, tile;
            words >> verb >> tile;
            if (verb == "TIME" && tile.empty()) {  // glcast doctor's clock: this machine's, in seconds
                char now[64];
                std::snprintf(now, sizeof now, "TIME %.6f",
                              std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count());
                router.send(zmq::buffer(identity.data(), identity.size()), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
                router.send(zmq::buffer(std::string(now)), zmq::send_flags::dontwait);
                continue;
            }
            if (!plain_name(tile) || !std::count(tiles_.begin(), tiles_.end(), tile)) continue;
            // The peer: the CURVE key the ZAP handler proved (its User-Id), else the connection.
            const char* key = nullptr;
            try {
                key = body.gets("User-Id");
            } catch (const zmq::error_t&) {
            }
            const std::string peer = key && *key ? std::string("key ") + key : "connection " + identity.to_string();
            if (!owners.speaks_for(tile, peer, seconds_since_start())) {
                if (!said_refused)
                    std::fprintf(stderr, "\nglcast run: control channel: a peer spoke for tile %s, which another "
                                         "peer speaks for; ignored (counted from now on)\n", tile.c_str());
                said_refused = true;
                continue;
            }
            if (verb == "READY" && barrier_) {
                uint64_t frame = 0;
                if (!(words >> frame)) continue;
                identity_of[tile] = identity.to_string();
                state.ready(tile, frame, seconds_since_start());
            } else if (verb == "STATUS") {
                TileStatus s;
                if (!(words >> s.state >> s.frame >> s.master_frame >> s.fps >> s.mbps >> s.lag >> s.recoveries >> s.machine) ||
                    !plain_name(s.machine) || !(s.state == "idle" || s.state == "joining" || s.state == "live") ||
                    !std::isfinite(s.fps) || !std::isfinite(s.mbps))
                    continue;
                if (s.state == "live" || (s.state == "joining" && !state.started()))
                    state.heard(tile, seconds_since_start());
                std::lock_guard lock(mutex_);
                s.dropped = status_[tile].dropped;
                status_[tile] = s;
                heard_[tile] = std::chrono::steady_clock::now();
            }
        }
        if (!barrier_) continue;
        std::vector<std::string> dropped;
        for (const auto& r : state.release(seconds_since_start(), &dropped)) {
            const std::string go = "GO " + std::to_string(r.frame) + pose_words(r.frame);
            router.send(zmq::buffer(identity_of[r.tile]), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
            router.send(zmq::buffer(go), zmq::send_flags::dontwait);
        }
        std::lock_guard lock(mutex_);
        for (const std::string& t : dropped) {
            std::fprintf(stderr, "\nglcast run: swap barrier: tile %s said nothing for %g s; going on without it until it is back\n",
                         t.c_str(), kDropSeconds);
            status_[t].dropped = true;
        }
        for (const std::string& t : state.back) {
            std::fprintf(stderr, "\nglcast run: swap barrier: tile %s is back\n", t.c_str());
            status_[t].dropped = false;
        }
        state.back.clear();
    }
}

}  // namespace glcast::cli
