#include "cli/wall_timing.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace glcast::cli {

namespace {

double steady_now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

bool parse_timing_lines(const std::string& lines, double offset, double error,
                        std::vector<std::pair<uint64_t, TileFrameTiming>>& out) {
    if (!std::isfinite(offset) || !std::isfinite(error) || error < 0) return false;
    std::vector<std::pair<uint64_t, TileFrameTiming>> taken;
    std::istringstream in(lines);
    std::string line;
    while (std::getline(in, line)) {
        unsigned long long frame = 0;
        TileFrameTiming t;
        int used = 0;
        if (std::sscanf(line.c_str(), "%llu %lf %lf %lf%n", &frame, &t.arrived, &t.replayed, &t.presented, &used) != 4 ||
            line[used] != 0 || !std::isfinite(t.arrived) || !std::isfinite(t.replayed) || !std::isfinite(t.presented))
            return false;
        t.clock_offset = offset, t.clock_error = error;
        taken.push_back({frame, t});
    }
    out.insert(out.end(), taken.begin(), taken.end());
    return true;
}

WallTiming::WallTiming(const std::string& path, std::string swap_log, std::vector<std::string> tiles)
    : swap_log_(std::move(swap_log)), tiles_(std::move(tiles)) {
    out_ = std::fopen(path.c_str(), "w");
    if (!out_) throw std::runtime_error("--timing " + path + ": " + std::strerror(errno));
    thread_ = std::thread([this] {
        std::unique_lock lock(wake_mutex_);
        while (!stopping_) {
            wake_.wait_for(lock, std::chrono::milliseconds(200));
            read_swaps();
            write_ready(false);
        }
    });
}

WallTiming::~WallTiming() {
    {
        std::lock_guard lock(wake_mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
    read_swaps();
    write_ready(true);
    if (swaps_) std::fclose(swaps_);
    std::fclose(out_);
}

void WallTiming::add(const std::string& tile, uint64_t frame, const TileFrameTiming& t) {
    std::lock_guard lock(mutex_);
    if (done_.count(frame)) return;
    auto [it, fresh] = frames_.try_emplace(frame);
    if (fresh) it->second.first_heard = steady_now();
    it->second.tiles[tile] = t;
}

// The shim appends "FRAME SECONDS" a swap; the file appears with the program's first.
void WallTiming::read_swaps() {
    if (!swaps_ && !(swaps_ = std::fopen(swap_log_.c_str(), "r"))) return;
    char buffer[4096];
    size_t n;
    std::string text;
    while ((n = std::fread(buffer, 1, sizeof buffer, swaps_)) > 0) text.append(buffer, n);
    std::clearerr(swaps_);  // (at its end now; the program writes more)
    partial_ += text;
    size_t start = 0;
    std::lock_guard lock(mutex_);
    for (size_t end; (end = partial_.find('\n', start)) != std::string::npos; start = end + 1) {
        unsigned long long frame = 0;
        double seconds = 0;
        if (std::sscanf(partial_.c_str() + start, "%llu %lf", &frame, &seconds) != 2 || done_.count(frame)) continue;
        auto [it, fresh] = frames_.try_emplace(frame);
        if (fresh) it->second.first_heard = steady_now();
        it->second.swap = seconds;
    }
    partial_.erase(0, start);
}

void WallTiming::write_ready(bool all) {
    std::lock_guard lock(mutex_);
    const double now = steady_now();
    for (auto it = frames_.begin(); it != frames_.end();) {
        const Frame& f = it->second;
        const bool complete = f.swap >= 0 && f.tiles.size() >= tiles_.size();
        if (all || complete || now - f.first_heard > kWaitSeconds || frames_.size() > kMaxHeldFrames) {
            write(it->first, f);
            it = frames_.erase(it);
        } else {
            ++it;
        }
    }
    std::fflush(out_);
}

void WallTiming::write(uint64_t frame, const Frame& f) {
    nlohmann::json line = {{"frame", frame}, {"swap", f.swap >= 0 ? nlohmann::json(f.swap) : nlohmann::json()}};
    nlohmann::json tiles = nlohmann::json::object();
    for (const auto& [tile, t] : f.tiles)
        tiles[tile] = {{"arrived", t.arrived}, {"replayed", t.replayed}, {"presented", t.presented},
                       {"clock_offset", t.clock_offset}, {"clock_error", t.clock_error}};
    line["tiles"] = tiles;
    const std::string text = line.dump() + "\n";
    std::fwrite(text.data(), 1, text.size(), out_);
    written_++;
    done_.insert(frame);
    while (done_.size() > kMaxHeldFrames) done_.erase(done_.begin());
}

}  // namespace glcast::cli
