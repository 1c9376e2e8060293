// Spectral snow synthesis time per frame on one core (slave/effects/snow/spectral_snow.h,
// docs/snow.md), split into the paper's stages (sec. 6.1): phase update (advance(): phases,
// coefficients, temporal blur), inverse FFT (field(): scatter into the half spectrum + c2r), and
// mapping (opacity(): shift, scale, clip, square). Prints a markdown table of medians.
//
//   spectral_snow_bench [frames=400] [--measure]
#include "slave/effects/snow/spectral_snow.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

using glcast::slave::effects::SpectralSnow;
using glcast::slave::effects::SpectralSnowParams;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    int frames = 400;
    bool measure = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--measure") == 0) measure = true;
        else frames = std::max(10, std::atoi(argv[i]));
    }
    std::printf("Spectral snow synthesis, one core, median of %d frames, FFTW_%s, "
                "annulus M/32..M/4, C varying 40..90 rad/s\n\n",
                frames, measure ? "MEASURE" : "ESTIMATE");
    std::printf("| size | components | phase update (ms) | inverse FFT (ms) | mapping (ms) | "
                "total (ms) | setup (ms) |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    float sink = 0;
    for (int size : {256, 512, 1024}) {
        SpectralSnowParams p;
        p.size = size;
        p.fftw_measure = measure;
        auto t_setup = std::chrono::steady_clock::now();
        SpectralSnow snow(p);
        const double setup = ms_since(t_setup);
        std::vector<double> phase, fft, map, total;
        for (int f = -10; f < frames; ++f) {  // 10 warm-up frames
            const double C = 65 + 25 * std::sin(0.01 * f), theta = 1.57 + 0.2 * std::sin(0.02 * f);
            auto t0 = std::chrono::steady_clock::now();
            snow.advance(p.frame_time, C, theta);
            auto t1 = std::chrono::steady_clock::now();
            const std::vector<float>& field = snow.field();
            auto t2 = std::chrono::steady_clock::now();
            const std::vector<float>& opacity = snow.opacity();
            auto t3 = std::chrono::steady_clock::now();
            sink += field[f & 255] + opacity[(f * 7) & 255];
            if (f < 0) continue;
            using ms = std::chrono::duration<double, std::milli>;
            phase.push_back(ms(t1 - t0).count());
            fft.push_back(ms(t2 - t1).count());
            map.push_back(ms(t3 - t2).count());
            total.push_back(ms(t3 - t0).count());
        }
        std::printf("| %d^2 | %d | %.3f | %.3f | %.3f | %.3f | %.1f |\n", size,
                    snow.component_count(), median(phase), median(fft), median(map),
                    median(total), setup);
    }
    std::printf("\n(goal: 512^2 under 2 ms per frame)%s\n", sink == 12345.f ? " " : "");
    return 0;
}
