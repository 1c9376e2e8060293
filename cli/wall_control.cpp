#include "cli/wall_control.h"

#include <zmq.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <sstream>

#include "net/security.h"
#include "slave/wall_link.h"

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
    // A dropped tile counts again once it reaches a frame the wall has not presented; before,
    // it is behind (its backlog after a stop) and each of its frames goes at once.
    if (t.dropped && !(started_ && frame <= last_released_)) {
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
    for (auto& [name, t] : tiles_)  // dropped and behind: it holds no one, and no one holds it
        if (t.dropped && t.waiting) {
            out.push_back({name, t.frame});
            t.waiting = false;
        }
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
    if (lowest == UINT64_MAX) return out;  // every tile dropped
    for (auto& [name, t] : tiles_)
        if (!t.dropped && t.waiting && t.frame == lowest) {
            out.push_back({name, t.frame});
            t.waiting = false;
            t.last_heard = now;  // drawing the next frame from now on
            last_released_ = started_ ? std::max(last_released_, lowest) : lowest;
            started_ = true;
        }
    return out;
}

struct WallControl::Sockets {
    zmq::context_t context{1};
    std::unique_ptr<net::Authenticator> authenticator;
    zmq::socket_t router{context, zmq::socket_type::router};
};

namespace {

// A part: a request, or a thumbnail's JPEG (slave/wall_link.h).
constexpr size_t kMaxRequestBytes = slave::WallLink::kMaxThumbnailBytes;
constexpr size_t kMaxWordsBytes = 1024;  // the words of a request
constexpr size_t kMaxReplyBytes = WallControl::kMaxReplyBytes;
static_assert(slave::LiveEffects::kMaxWordsBytes + 128 < kMaxReplyBytes, "an OK names the whole state");

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
    // A proven key speaks only for the tiles bound to it. (A peer without one is on this
    // machine's ipc:// path: the first to name a tile speaks for it, as below.)
    if (auto bound = keys_.find(tile); bound != keys_.end() && peer.rfind("key ", 0) == 0 && peer != bound->second) {
        refused_++;
        return false;
    }
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

std::map<std::string, std::string> tile_keys(const std::vector<std::pair<std::string, std::string>>& tiles,
                                             const std::string& here, const net::Security& security,
                                             std::vector<std::string>* unbound) {
    std::map<std::string, std::string> keys;
    if (!security.keyed()) return keys;
    for (const auto& [tile, machine] : tiles) {
        std::string& key = keys[tile];
        if (machine.empty() || machine == here) {
            if (security.has_client_pair) key = "key " + security.client.public_key;
        } else if (auto it = security.machines.find(machine); it != security.machines.end()) {
            key = "key " + it->second;
        }
        if (key.empty() && unbound) unbound->push_back(tile);
    }
    return keys;
}

WallControl::WallControl(std::string endpoint, std::vector<std::string> tiles, bool barrier, HeadPoseFor head_for,
                         std::map<std::string, std::string> keys)
    : endpoint_(std::move(endpoint)), tiles_(std::move(tiles)), keys_(std::move(keys)), barrier_(barrier), head_for_(std::move(head_for)),
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

slave::LiveEffects WallControl::effects() const {
    std::lock_guard lock(mutex_);
    return effects_;
}

void WallControl::set_started_effects(const slave::LiveEffects& e) {
    std::lock_guard lock(mutex_);
    effects_ = e;
    effects_.version = 0, effects_.frame = 0;
}

void WallControl::set_timing_sink(TimingSink sink) {
    std::lock_guard lock(mutex_);
    timing_sink_ = std::move(sink);
}

bool WallControl::thumbnail(const std::string& tile, std::string& jpeg, uint64_t& frame) const {
    std::lock_guard lock(mutex_);
    auto it = thumbnails_.find(tile);
    if (it == thumbnails_.end()) return false;
    jpeg = it->second.jpeg, frame = it->second.frame;
    return true;
}

bool WallControl::change_effects(const std::string& request, std::string& reply) {
    auto r = std::make_shared<Request>();
    r->words = request;
    std::unique_lock lock(mutex_);
    requests_.push_back(r);
    if (!requests_done_.wait_for(lock, std::chrono::seconds(5), [&] { return r->done; })) {
        reply = "ERROR the control channel did not take the request within 5 s";
        return false;
    }
    reply = r->reply;
    return r->ok;
}

// A frame no tile has presented: with the barrier, every tile waits for (or replays) the frame
// after the last released, so the one after that is the first that all of them can still switch
// at; without it, the newest frame a tile reported, moved on by its rate for the report's age
// and half a second more for the request to reach every tile.
uint64_t WallControl::switch_frame() const {
    if (barrier_ && released_any_) return last_released_ + 2;
    const auto now = std::chrono::steady_clock::now();
    double newest = 0;
    for (const auto& [tile, s] : status_) {
        auto heard = heard_.find(tile);
        if (heard == heard_.end() || s.state == "idle") continue;
        const double age = std::chrono::duration<double>(now - heard->second).count();
        if (age > 3) continue;
        newest = std::max(newest, double(s.frame) + s.fps * (age + 0.5));
    }
    return newest > 0 ? uint64_t(newest) + 2 : 0;
}

bool WallControl::apply_request(const std::string& request, std::string& reply) {
    if (request.size() > kMaxWordsBytes) {  // (the dashboard's; the channel's are bounded where read)
        reply = "ERROR a request of more than " + std::to_string(kMaxWordsBytes) + " bytes";
        return false;
    }
    std::unique_lock lock(mutex_);
    slave::LiveEffects next = effects_;
    std::string error;
    if (!next.change(request, error)) {
        reply = "ERROR " + error;
        return false;
    }
    next.version = effects_.version + 1;
    next.frame = switch_frame();
    effects_ = next;
    lock.unlock();
    std::set<std::string> sent;
    for (const auto& [tile, identity] : identity_of_)
        if (sent.insert(identity).second) send_effects(identity);
    reply = "OK effects " + next.enabled_list() + " from frame " + std::to_string(next.frame) + " (version " +
            std::to_string(next.version) + ")";
    for (const auto& [name, value] : next.params) reply += " " + name + "=" + value;
    std::fprintf(stderr, "\nglcast run: %s\n", reply.c_str() + 3);
    return true;
}

void WallControl::send_effects(const std::string& identity) {
    const std::string words = effects().words();
    zmq::socket_t& router = sockets_->router;
    if (router.send(zmq::buffer(identity), zmq::send_flags::sndmore | zmq::send_flags::dontwait))
        (void)router.send(zmq::buffer(words), zmq::send_flags::dontwait);
}

// The pose words of frame n's GO (the pose of frame n + 1): the same for every tile released at n
// (the tracker's pose may change between two of them).
std::string WallControl::pose_words(uint64_t frame) {
    if (!head_for_) return "";
    auto known = pose_words_.find(frame);
    if (known != pose_words_.end()) return known->second;
    while (pose_words_.size() >= 64) pose_words_.erase(pose_words_.begin());  // frames long gone
    return pose_words_[frame] = pose_text(frame + 1);
}

// " POSE px py pz qw qx qy qz [SEP s]" for the pose that holds at `frame`; "" for none.
std::string WallControl::pose_text(uint64_t frame) {
    slave::HeadPose h;
    std::string words;
    if (head_for_ && head_for_(frame, h)) {
        char text[256];
        std::snprintf(text, sizeof text, " POSE %.17g %.17g %.17g %.17g %.17g %.17g %.17g", h.position.x, h.position.y,
                      h.position.z, h.orientation.w, h.orientation.x, h.orientation.y, h.orientation.z);
        words = text;
        if (h.eye_separation >= 0) {
            std::snprintf(text, sizeof text, " SEP %.17g", h.eye_separation);
            words += text;
        }
    }
    return words;
}

void WallControl::serve() {
    zmq::socket_t& router = sockets_->router;
    // An answer never longer than what glcast ctl reads (kMaxReplyBytes): a longer one would
    // make libzmq hang up on it, and the operator hear nothing of a request that was applied.
    auto reply_to = [&](const zmq::message_t& identity, std::string reply) {
        if (reply.size() > kMaxReplyBytes) reply = reply.substr(0, kMaxReplyBytes - 3) + "...";
        router.send(zmq::buffer(identity.data(), identity.size()), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
        router.send(zmq::buffer(reply), zmq::send_flags::dontwait);
    };
    BarrierState state(tiles_, kDropSeconds, seconds_since_start());
    TileOwners owners(kTakeoverSeconds, keys_);
    bool said_refused = false;
    while (!stopping_) {
        zmq::pollitem_t item{router.handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(50));
        for (int n = 0; n < 256 && (item.revents & ZMQ_POLLIN); n++) {
            zmq::message_t identity, body, jpeg;  // (jpeg: a second part, a thumbnail's or a TIMING's lines)
            if (!router.recv(identity, zmq::recv_flags::dontwait)) break;
            bool well_formed = router.get(zmq::sockopt::rcvmore) && router.recv(body);
            const bool thumb = well_formed && body.size() > 6 && std::memcmp(body.data(), "THUMB ", 6) == 0;
            const bool timing = well_formed && body.size() > 7 && std::memcmp(body.data(), "TIMING ", 7) == 0;
            if (thumb || timing) well_formed = router.get(zmq::sockopt::rcvmore) && router.recv(jpeg);
            well_formed = well_formed && !router.get(zmq::sockopt::rcvmore);
            while (router.get(zmq::sockopt::rcvmore)) (void)router.recv(jpeg);  // extra parts: read and forget
            if (!well_formed || identity.size() == 0 || identity.size() > 255) continue;
            if (body.size() > kMaxWordsBytes) {
                if (body.size() >= 4 && std::memcmp(body.data(), "CTL ", 4) == 0)  // an operator waits for an answer
                    reply_to(identity, "ERROR a request of more than " + std::to_string(kMaxWordsBytes) + " bytes");
                continue;
            }
            std::istringstream words(body.to_string());
            std::string verb, tile;
            words >> verb >> tile;
            // The peer: the CURVE key the ZAP handler proved (its User-Id), else the connection.
            const char* key = nullptr;
            try {
                key = body.gets("User-Id");
            } catch (const zmq::error_t&) {
            }
            if (verb == "CTL") {
                const net::Security& security = net::process_security();
                std::string reply;
                if (security.keyed() && !(key && security.operators.count(key)))
                    reply = "ERROR only the wall's operator may change it (a key of operators/ in the master's keys, "
                            "or the master's own)";
                else
                    apply_request(body.to_string().substr(4), reply);
                reply_to(identity, reply);
                continue;
            }
            if (verb == "TIME" && tile.empty()) {  // glcast doctor's clock: this machine's, in seconds
                char now[64];
                std::snprintf(now, sizeof now, "TIME %.6f",
                              std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count());
                router.send(zmq::buffer(identity.data(), identity.size()), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
                router.send(zmq::buffer(std::string(now)), zmq::send_flags::dontwait);
                continue;
            }
            if (verb == "CLOCK") {  // a slave's clock offset: this machine's steady clock, the swaps' clock
                std::string t0;
                char* end = nullptr;
                if (!(words >> t0) || t0.size() > 32 || (std::strtod(t0.c_str(), &end), !end || *end)) continue;
                char now[96];
                std::snprintf(now, sizeof now, "CLOCK %s %.9f", t0.c_str(),
                              std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count());
                router.send(zmq::buffer(identity.data(), identity.size()), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
                router.send(zmq::buffer(std::string(now)), zmq::send_flags::dontwait);
                continue;
            }
            if (!plain_name(tile) || !std::count(tiles_.begin(), tiles_.end(), tile)) continue;
            const std::string peer = key && *key ? std::string("key ") + key : "connection " + identity.to_string();
            if (!owners.speaks_for(tile, peer, seconds_since_start())) {
                if (!said_refused)
                    std::fprintf(stderr, "\nglcast run: control channel: a peer spoke for tile %s, which another "
                                         "peer speaks for; ignored (counted from now on)\n", tile.c_str());
                said_refused = true;
                continue;
            }
            if (verb == "HEAD") {  // a tile's first frame, which no GO before it carried a pose for
                uint64_t frame = 0;
                if (!(words >> frame)) continue;
                const std::string reply = "HEAD " + std::to_string(frame) + pose_text(frame);
                router.send(zmq::buffer(identity.data(), identity.size()), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
                router.send(zmq::buffer(reply), zmq::send_flags::dontwait);
            } else if (verb == "READY" && barrier_) {
                uint64_t frame = 0;
                if (!(words >> frame)) continue;
                identity_of_[tile] = identity.to_string();
                state.ready(tile, frame, seconds_since_start());
            } else if (verb == "STATUS") {
                TileStatus s;
                if (!(words >> s.state >> s.frame >> s.master_frame >> s.fps >> s.mbps >> s.lag >> s.recoveries >> s.machine) ||
                    !plain_name(s.machine) || !(s.state == "idle" || s.state == "joining" || s.state == "live") ||
                    !std::isfinite(s.fps) || !std::isfinite(s.mbps))
                    continue;
                words >> s.effects_version;  // (0 from a slave of before live effects)
                if (s.state == "live" || (s.state == "joining" && !state.started()))
                    state.heard(tile, seconds_since_start());
                identity_of_[tile] = identity.to_string();
                std::unique_lock lock(mutex_);
                s.dropped = status_[tile].dropped;
                status_[tile] = s;
                heard_[tile] = std::chrono::steady_clock::now();
                const bool behind = s.effects_version < effects_.version;
                lock.unlock();
                if (behind) send_effects(identity.to_string());  // it joined later, or lost the last
            } else if (timing) {
                double offset = NAN, error = NAN;
                std::vector<std::pair<uint64_t, TileFrameTiming>> frames;
                if (!(words >> offset >> error) || !parse_timing_lines(jpeg.to_string(), offset, error, frames)) continue;
                std::lock_guard lock(mutex_);
                if (timing_sink_)
                    for (const auto& [frame, t] : frames) timing_sink_(tile, frame, t);
            } else if (thumb) {
                uint64_t frame = 0;
                if (!(words >> frame) || jpeg.size() < 4 || std::memcmp(jpeg.data(), "\xff\xd8", 2) != 0) continue;
                std::lock_guard lock(mutex_);
                thumbnails_[tile] = Thumbnail{jpeg.to_string(), frame};
            }
        }
        std::vector<std::shared_ptr<Request>> asked;
        {
            std::lock_guard lock(mutex_);
            asked.swap(requests_);
        }
        for (const auto& r : asked) {
            r->ok = apply_request(r->words, r->reply);
            std::lock_guard lock(mutex_);
            r->done = true;
        }
        if (!asked.empty()) requests_done_.notify_all();
        if (!barrier_) continue;
        std::vector<std::string> dropped;
        for (const auto& r : state.release(seconds_since_start(), &dropped)) {
            const std::string go = "GO " + std::to_string(r.frame) + pose_words(r.frame);
            last_released_ = std::max(last_released_, r.frame);
            released_any_ = true;
            router.send(zmq::buffer(identity_of_[r.tile]), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
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
