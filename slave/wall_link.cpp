#include "slave/wall_link.h"

#include <unistd.h>

#include <zmq.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "common/environment.h"
#include "net/security.h"

namespace glcast::slave {

namespace {
constexpr size_t kMaxAnswerBytes = 4096;  // "GO n" with a head pose, "EFFECTS ..." with its parameters
}  // namespace

WallLink::WallLink(std::string endpoint, std::string tile, std::string machine)
    : endpoint_(std::move(endpoint)), tile_(std::move(tile)), machine_(std::move(machine)),
      context_(std::make_unique<zmq::context_t>(1)) {
    socket_ = std::make_unique<zmq::socket_t>(*context_, zmq::socket_type::dealer);
    socket_->set(zmq::sockopt::linger, 0);
    socket_->set(zmq::sockopt::sndhwm, 16);
    socket_->set(zmq::sockopt::maxmsgsize, int64_t(kMaxAnswerBytes));
    // Nothing is queued while no run serves the wall: what this tile says between two runs (the
    // last program's frames, its READYs) would reach the next run as if about its program.
    socket_->set(zmq::sockopt::immediate, 1);
    net::secure_client(*socket_, endpoint_);
    socket_->connect(endpoint_);
}

WallLink::~WallLink() {
    socket_.reset();
    context_->shutdown();
}

namespace {

// "GO n" and, for a tracked viewer, " POSE px py pz qw qx qy qz" (cli/wall_control.h).
bool parse_go(const std::string& answer, const std::string& go, HeadPose* head, bool* has_head) {
    if (answer.compare(0, go.size(), go) != 0) return false;
    if (answer.size() == go.size()) return true;
    double v[7], separation = -1;
    int used = 0;
    if (std::sscanf(answer.c_str() + go.size(), " POSE %lf %lf %lf %lf %lf %lf %lf%n", &v[0], &v[1], &v[2], &v[3], &v[4],
                    &v[5], &v[6], &used) != 7)
        return false;
    const char* rest = answer.c_str() + go.size() + used;
    int more = 0;
    if (*rest && (std::sscanf(rest, " SEP %lf%n", &separation, &more) != 1 || rest[more] != 0)) return false;
    if (!(separation >= -1 && separation <= 1)) separation = -1;  // (NaN too) not taken
    for (double x : v)
        if (!std::isfinite(x) || std::fabs(x) > 1e4) return true;  // the frame goes, the pose is not taken
    const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
    if (std::fabs(norm - 1) > 0.01) return true;
    if (head && has_head) {
        head->position = glm::dvec3(v[0], v[1], v[2]);
        head->orientation = glm::dquat(v[3] / norm, v[4] / norm, v[5] / norm, v[6] / norm);
        head->eye_separation = separation >= 0 ? separation : -1;
        *has_head = true;
    }
    return true;
}

}  // namespace

// Sends `request` and waits at most timeout_ms for the answer that starts with `answer` (ending at
// a space or the end: "GO 1" is not "GO 12"), with the pose it may carry; whatever else comes in
// the meantime is heard (older GOs are skipped).
bool WallLink::ask(const std::string& request, const std::string& answer, int timeout_ms, HeadPose* head,
                   bool* has_head) {
    if (has_head) *has_head = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    // Nothing is queued before the run's channel is connected (CURVE's handshake takes a while
    // across machines): the request is offered again until it is taken, within the same wait.
    while (!socket_->send(zmq::buffer(request), zmq::send_flags::dontwait)) {
        if (std::chrono::steady_clock::now() >= deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    while (std::chrono::steady_clock::now() < deadline) {
        zmq::pollitem_t item{socket_->handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(50));
        if (!(item.revents & ZMQ_POLLIN)) continue;
        zmq::message_t message;
        const std::string text = socket_->recv(message) ? message.to_string() : std::string();
        if ((text.size() == answer.size() || (text.size() > answer.size() && text[answer.size()] == ' ')) &&
            parse_go(text, answer, head, has_head))
            return true;
        heard(text);
    }
    return false;
}

bool WallLink::barrier(uint64_t frame, int timeout_ms, HeadPose* next_head, bool* has_head) {
    return ask("READY " + tile_ + " " + std::to_string(frame), "GO " + std::to_string(frame), timeout_ms, next_head,
               has_head);
}

bool WallLink::first_head(uint64_t frame, int timeout_ms, HeadPose& head) {
    bool has_head = false;
    return ask("HEAD " + tile_ + " " + std::to_string(frame), "HEAD " + std::to_string(frame), timeout_ms, &head,
               &has_head) &&
           has_head;
}

void WallLink::heard(const std::string& text) {
    LiveEffects e;
    if (text.compare(0, 8, "EFFECTS ") == 0 && LiveEffects::parse(text, e) &&
        (!has_effects_ || e.version >= effects_.version)) {
        effects_ = e;
        has_effects_ = true;
    }
}

bool WallLink::take_effects(LiveEffects& out) {
    for (int n = 0; n < 64; n++) {
        zmq::message_t answer;
        if (!socket_->recv(answer, zmq::recv_flags::dontwait)) break;
        heard(answer.to_string());
    }
    if (!has_effects_) return false;
    out = effects_;
    has_effects_ = false;
    return true;
}

void WallLink::thumbnail(uint64_t frame, const std::string& jpeg) {
    if (jpeg.empty() || jpeg.size() > kMaxThumbnailBytes) return;
    const std::string head = "THUMB " + tile_ + " " + std::to_string(frame);
    if (socket_->send(zmq::buffer(head), zmq::send_flags::sndmore | zmq::send_flags::dontwait))
        (void)socket_->send(zmq::buffer(jpeg), zmq::send_flags::dontwait);
}

void WallLink::report(const TileReport& r) {
    char text[256];
    std::snprintf(text, sizeof text, "STATUS %s %s %llu %llu %.2f %.3f %lld %llu %s %llu", tile_.c_str(), r.state.c_str(),
                  (unsigned long long)r.frame, (unsigned long long)r.master_frame, r.fps, r.mbps, (long long)r.lag,
                  (unsigned long long)r.recoveries, machine_.c_str(), (unsigned long long)r.effects_version);
    (void)socket_->send(zmq::buffer(std::string(text)), zmq::send_flags::dontwait);
}

std::string machine_name() {
    if (const std::string& m = environment().machine; !m.empty()) return m;
    char host[256] = {};
    if (gethostname(host, sizeof host - 1) != 0 || !*host) return "localhost";
    return host;
}

}  // namespace glcast::slave
