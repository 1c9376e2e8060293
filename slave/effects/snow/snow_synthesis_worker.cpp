#include "slave/effects/snow/snow_synthesis_worker.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace glcast::slave::effects {

SnowSynthesisWorker::SnowSynthesisWorker(const SpectralSnowParams& params, int regions, double sharpness,
                                         double grey, double strength)
    : size_(params.size), regions_(regions), grey_(uint8_t(std::lround(grey * 255))) {
    for (int i = 0; i <= 4096; ++i) alpha_[i] = uint8_t(std::lround(strength * std::pow(i / 4096.0, sharpness) * 255));
    for (int i = 0; i < regions * regions; ++i) snow_.emplace_back(params);
    done_.assign(size_t(regions) * regions * size_t(size_) * size_ * 4, 0);
    thread_ = std::thread([this] { loop(); });
}

SnowSynthesisWorker::~SnowSynthesisWorker() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
}

void SnowSynthesisWorker::submit(double dt, std::vector<std::pair<double, double>> c_theta, bool only_first) {
    result();  // the previous job must be finished before its buffers are reused
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = std::move(c_theta);
    job_dt_ = dt;
    job_only_first_ = only_first;
    job_pending_ = true;
    job_done_ = false;
    cv_.notify_all();
}

const std::vector<uint8_t>& SnowSynthesisWorker::result() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!job_done_) {
        const auto start = std::chrono::steady_clock::now();
        cv_.wait(lock, [this] { return job_done_; });
        waited_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    return done_;
}

void SnowSynthesisWorker::loop() {
    for (;;) {
        std::vector<std::pair<double, double>> job;
        double dt = 0;
        bool only_first = false;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            cv_.wait(lock, [this] { return job_pending_ || stop_; });
            if (stop_) return;
            job = job_;
            dt = job_dt_;
            only_first = job_only_first_;
            job_pending_ = false;
        }
        // done_ is only read by result() after job_done_ is set, so it is written unlocked.
        const size_t texels = size_t(size_) * size_;
        for (size_t r = 0; r < snow_.size(); ++r) {
            snow_[r].advance(dt, job[r].first, job[r].second);
            if (only_first && r > 0) continue;
            const std::vector<float>& a = snow_[r].opacity();
            uint8_t* out = done_.data() + r * texels * 4;
            for (size_t i = 0; i < texels; ++i, out += 4) {
                out[0] = out[1] = out[2] = grey_;
                out[3] = alpha_[int(a[i] * 4096.0f + 0.5f)];
            }
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            job_done_ = true;
        }
        cv_.notify_all();
    }
}

}  // namespace glcast::slave::effects
