#include "slave/wall_link.h"

#include <unistd.h>

#include <zmq.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
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

// Whatever else comes in the meantime is heard (older GOs are skipped). An answer ends at a
// space or at its end: "GO 1" is not "GO 12".
bool WallLink::ask(const std::string& request, const std::string& answer, int timeout_ms,
                   const std::function<bool(const std::string&)>& accept) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    // Nothing is queued before the run's channel is connected (CURVE's handshake takes a while
    // across machines): the request is offered again until it is taken, within the same wait.
    while (!socket_->send(zmq::buffer(request), zmq::send_flags::dontwait)) {
        if (std::chrono::steady_clock::now() >= deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    for (auto now = std::chrono::steady_clock::now(); now < deadline; now = std::chrono::steady_clock::now()) {
        zmq::pollitem_t item{socket_->handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::min(std::chrono::milliseconds(50),
                                     std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now) +
                                         std::chrono::milliseconds(1)));
        if (!(item.revents & ZMQ_POLLIN)) continue;
        zmq::message_t message;
        const std::string text = socket_->recv(message) ? message.to_string() : std::string();
        if (text.compare(0, answer.size(), answer) == 0 && (text.size() == answer.size() || text[answer.size()] == ' ') &&
            accept(text))
            return true;
        heard(text);
    }
    return false;
}

bool WallLink::barrier(uint64_t frame, int timeout_ms, HeadPose* next_head, bool* has_head) {
    if (has_head) *has_head = false;
    const std::string go = "GO " + std::to_string(frame);
    return ask("READY " + tile_ + " " + std::to_string(frame), go, timeout_ms,
               [&](const std::string& text) { return parse_go(text, go, next_head, has_head); });
}

bool WallLink::first_head(uint64_t frame, int timeout_ms, HeadPose& head) {
    bool has_head = false;
    const std::string answer = "HEAD " + std::to_string(frame);
    return ask("HEAD " + tile_ + " " + std::to_string(frame), answer, timeout_ms,
               [&](const std::string& text) { return parse_go(text, answer, &head, &has_head); }) &&
           has_head;
}

double steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void ClockOffset::sample(double t0, double run_time, double t2) {
    if (!(t2 >= t0) || !std::isfinite(run_time)) return;
    if (samples_.size() == kSamples) samples_.pop_front();
    samples_.push_back({run_time - (t0 + t2) / 2, t2 - t0});
}

ClockOffset::Sample ClockOffset::best() const {
    Sample b{0, 0};
    for (size_t i = 0; i < samples_.size(); i++)
        if (i == 0 || samples_[i].round_trip < b.round_trip) b = samples_[i];
    return b;
}

void WallLink::sync_clock() {
    const double now = steady_seconds();
    if (now < next_sample_) return;
    char t0_text[64];
    std::snprintf(t0_text, sizeof t0_text, "%.9f", now);
    const std::string answer = std::string("CLOCK ") + t0_text;
    double run_time = NAN;
    const bool answered = ask("CLOCK " + tile_ + " " + t0_text, answer, kClockWaitMs, [&](const std::string& text) {
        char* end = nullptr;
        run_time = std::strtod(text.c_str() + answer.size(), &end);
        return end && *end == 0 && std::isfinite(run_time);
    });
    const double t2 = steady_seconds();
    if (answered) clock_.sample(std::strtod(t0_text, nullptr), run_time, t2);
    // Unanswered (no run serves the channel, or one of before CLOCK): asked again in 5 s.
    next_sample_ = t2 + (!answered ? 5.0 : clock_.samples() < kQuickSamples ? 0.0 : 1.0);
}

void WallLink::timing(const FrameTiming& t) {
    if (timings_.size() < kMaxHeldTimings) timings_.push_back(t);
    if (clock_.known() && steady_seconds() - timings_sent_ >= 0.1) send_timings();
}

void WallLink::flush_timings() {
    while (clock_.known() && !timings_.empty()) send_timings();
}

// "TIMING TILE OFFSET ERROR" and, as a second part, a line "FRAME ARRIVED REPLAYED PRESENTED"
// a frame, on the run's clock (cli/wall_control.h bounds both).
void WallLink::send_timings() {
    char head[160];
    std::snprintf(head, sizeof head, "TIMING %s %.9f %.9f", tile_.c_str(), clock_.offset(), clock_.error());
    std::string lines;
    const double offset = clock_.offset(), stale = steady_seconds() - 5;
    size_t n = 0;
    for (; n < timings_.size() && lines.size() < kMaxThumbnailBytes - 128; n++) {
        const FrameTiming& t = timings_[n];
        if (t.presented < stale) continue;  // held while no run answered: another program's, perhaps
        char line[128];
        std::snprintf(line, sizeof line, "%llu %.6f %.6f %.6f\n", (unsigned long long)t.frame, t.arrived + offset,
                      t.replayed + offset, t.presented + offset);
        lines += line;
    }
    timings_.erase(timings_.begin(), timings_.begin() + n);
    timings_sent_ = steady_seconds();
    if (socket_->send(zmq::buffer(std::string(head)), zmq::send_flags::sndmore | zmq::send_flags::dontwait))
        (void)socket_->send(zmq::buffer(lines), zmq::send_flags::dontwait);
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
