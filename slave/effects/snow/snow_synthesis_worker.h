// Spectral snow synthesized off the render thread (a frame never waits for the IFFT):
// frame f's textures are computed while frame f - 1 is composited. One SpectralSnow per region
// of the method's grid (docs/snow.md) (regions x regions over the canvas), all with the same seed, so
// that regions with equal C and theta are identical and blend without a trace.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "slave/effects/snow/spectral_snow.h"

namespace glcast::slave::effects {

class SnowSynthesisWorker {
public:
    // The result is what the composite blends: RGBA8 texels of colour (grey, grey, grey) and
    // alpha strength * opacity^sharpness (sharpness 1: the opacity as synthesized). Made here,
    // off the render thread, so that the GPU only uploads and samples.
    SnowSynthesisWorker(const SpectralSnowParams& params, int regions, double sharpness = 1.0, double grey = 1.0,
                        double strength = 1.0);
    ~SnowSynthesisWorker();

    // Starts the next frame: every region advances by dt with its own (C, theta) (row-major,
    // region (i, j) at index j * regions + i, j counting up the canvas). With `only_first`, all
    // regions have moved alike so far and only region 0's texels are made (the phases of all
    // advance; the inverse FFTs of the others are skipped). Returns at once.
    void submit(double dt, std::vector<std::pair<double, double>> c_theta, bool only_first = false);
    // The RGBA8 texels of the frame last submitted: regions^2 textures of M x M, one after the
    // other. Blocks only if that synthesis has not finished; the wait is added to waited_ms().
    const std::vector<uint8_t>& result();
    double waited_ms() const { return waited_ms_; }
    int size() const { return size_; }
    int regions() const { return regions_; }

private:
    void loop();

    int size_, regions_;
    uint8_t alpha_[4097];  // strength * opacity^sharpness * 255, indexed by opacity * 4096
    uint8_t grey_;
    std::vector<SpectralSnow> snow_;
    std::vector<uint8_t> done_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool job_pending_ = false, job_done_ = true, stop_ = false, job_only_first_ = false;
    double job_dt_ = 0, waited_ms_ = 0;
    std::vector<std::pair<double, double>> job_;
    std::thread thread_;
};

}  // namespace glcast::slave::effects
