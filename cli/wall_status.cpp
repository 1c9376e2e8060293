#include "cli/wall_status.h"

#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstring>
#include <stdexcept>

namespace glcast::cli {

WallStatus::WallStatus(const WallControl& control, std::vector<std::pair<std::string, std::string>> tiles,
                       const std::string& json_path)
    : control_(control), tiles_(std::move(tiles)), terminal_(isatty(2)) {
    if (!json_path.empty()) {
        json_ = std::fopen(json_path.c_str(), "w");
        if (!json_) throw std::runtime_error("--status-json " + json_path + ": " + std::strerror(errno));
    }
    thread_ = std::thread([this] {
        while (!stopping_) {
            {
                std::unique_lock lock(wake_mutex_);
                wake_.wait_for(lock, std::chrono::seconds(1), [this] { return bool(stopping_); });
            }
            const nlohmann::json s = sample();
            show(s);
            std::lock_guard lock(mutex_);
            history_.push_back(s);
            while (history_.size() > kHistorySeconds) history_.pop_front();
        }
    });
}

WallStatus::~WallStatus() {
    stopping_ = true;
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    if (terminal_ && shown_) std::fputc('\n', stderr);
    if (json_) std::fclose(json_);
}

nlohmann::json WallStatus::latest() const {
    std::lock_guard lock(mutex_);
    return history_.empty() ? nlohmann::json() : history_.back();
}

std::vector<nlohmann::json> WallStatus::history() const {
    std::lock_guard lock(mutex_);
    return {history_.begin(), history_.end()};
}

nlohmann::json WallStatus::sample() {
    const auto status = control_.status();
    const auto now = std::chrono::steady_clock::now();
    uint64_t master_frame = 0;
    double mbps = 0;
    for (const auto& [name, s] : status) {
        master_frame = std::max(master_frame, s.master_frame);
        mbps = std::max(mbps, s.age_seconds >= 0 && s.age_seconds < 3 ? s.mbps : 0.0);
    }
    const double dt = std::chrono::duration<double>(now - last_).count();
    const double fps = last_frame_ && master_frame >= last_frame_ && dt > 0 ? (master_frame - last_frame_) / dt : 0;
    last_ = now, last_frame_ = master_frame;
    nlohmann::json tiles = nlohmann::json::array();
    for (const auto& [name, machine] : tiles_) {
        const TileStatus& s = status.at(name);
        const bool silent = s.age_seconds < 0 || s.age_seconds > 3;
        const std::string state = s.dropped ? "dropped" : silent ? (s.age_seconds < 0 ? "absent" : "silent") : s.state;
        tiles.push_back({{"tile", name}, {"machine", s.machine.empty() ? machine : s.machine}, {"state", state},
                         {"frame", s.frame}, {"fps", s.fps}, {"mbps", s.mbps}, {"lag", s.lag},
                         {"recoveries", s.recoveries}, {"age_seconds", s.age_seconds},
                         {"effects_version", s.effects_version}});
    }
    return {{"time", std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count()},
            {"program", {{"frame", master_frame}, {"fps", fps}, {"mbps", mbps}}},
            {"tiles", tiles}};
}

void WallStatus::show(const nlohmann::json& s) {
    char line[160];
    std::snprintf(line, sizeof line, "wall: program frame %" PRIu64 ", %.1f fps, %.2f MB/s",
                  s["program"]["frame"].get<uint64_t>(), s["program"]["fps"].get<double>(),
                  s["program"]["mbps"].get<double>());
    std::string text = line;
    for (const auto& t : s["tiles"]) {
        const std::string state = t["state"], name = t["tile"], machine = t["machine"];
        if (state == "live" || state == "joining")
            std::snprintf(line, sizeof line, " | %s@%s %s%" PRIu64 " %.0ffps lag %" PRId64 " rec %" PRIu64, name.c_str(),
                          machine.c_str(), state == "joining" ? "joining " : "f", t["frame"].get<uint64_t>(),
                          t["fps"].get<double>(), t["lag"].get<int64_t>(), t["recoveries"].get<uint64_t>());
        else
            std::snprintf(line, sizeof line, " | %s@%s %s", name.c_str(), machine.c_str(), state.c_str());
        text += line;
    }
    if (terminal_) {
        std::fprintf(stderr, "\r%s\033[K", text.c_str());
        shown_ = true;
    }
    if (json_) {
        std::fprintf(json_, "%s\n", s.dump().c_str());
        std::fflush(json_);
    }
}

}  // namespace glcast::cli
