// The whole wall once a second (glcast run): one line on the terminal, a JSON line to
// --status-json, and the last ten minutes of them for the dashboard's plots (cli/dashboard.h).
#pragma once

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "cli/wall_control.h"

namespace glcast::cli {

class WallStatus {
public:
    static constexpr size_t kHistorySeconds = 600;
    // Throws std::runtime_error when `json_path` cannot be written.
    WallStatus(const WallControl& control, std::vector<std::pair<std::string, std::string>> tiles,
               const std::string& json_path);
    ~WallStatus();
    // The newest sample: {"time", "program": {frame, fps, mbps}, "tiles": [{tile, machine, state,
    // frame, fps, mbps, lag, recoveries, age_seconds, effects_version}]}; null before the first.
    nlohmann::json latest() const;
    // Every sample of the last kHistorySeconds, oldest first.
    std::vector<nlohmann::json> history() const;

private:
    nlohmann::json sample();
    void show(const nlohmann::json& s);

    const WallControl& control_;
    std::vector<std::pair<std::string, std::string>> tiles_;  // name, machine
    bool terminal_;
    FILE* json_ = nullptr;
    bool shown_ = false;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
    uint64_t last_frame_ = 0;
    mutable std::mutex mutex_;
    std::deque<nlohmann::json> history_;
    std::atomic<bool> stopping_{false};
    std::mutex wake_mutex_;
    std::condition_variable wake_;
    std::thread thread_;
};

}  // namespace glcast::cli
