// Spectral snow synthesis (slave/effects/snow/spectral_snow.h, docs/snow.md): the 3D spectrum of a
// synthesized sequence lies on the dispersion surface of Eq. 6 inside the annulus, the temporal
// blur removes everything above the temporal Nyquist limit, phases advance by omega_t dt with C
// and theta changing over time, the opacity has the mapped statistics and no seam, and a seed
// always gives the same texture.
#include "slave/effects/snow/spectral_snow.h"

#include <fftw3.h>
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <vector>

using glcast::slave::effects::SpectralSnow;
using glcast::slave::effects::SpectralSnowParams;

namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap_pi(double a) { return a - 2 * kPi * std::round(a / (2 * kPi)); }

int signed_freq(int index, int n) { return index <= n / 2 ? index : index - n; }

struct Spectrum3D {
    double total = 0;           // all power except DC
    double near_surface = 0;    // within one temporal bin of the (wrapped) dispersion surface
    double outside_annulus = 0;
    double above_nyquist = 0;   // at spatial frequencies whose |omega_t| > pi / frame_time
};

// Synthesize T frames of the raw field with a fixed C and theta, Kaiser-window them in time,
// 3D FFT, and sort the power. Returns the bins; `snow` is advanced T frames.
Spectrum3D analyse(SpectralSnow& snow, int T, double dt, double C, double theta) {
    const int M = snow.size();
    const int H = M / 2 + 1;
    std::vector<double> stack(size_t(T) * M * M);
    for (int t = 0; t < T; ++t) {
        const std::vector<float>& f = snow.field();
        // Kaiser window, beta 2.5 (close to the Slepian window that concentrates most energy
        // within +-1 bin): a tone between bins keeps >= 96.6% of its power within one bin of its
        // frequency (98% on average), where a Hann window keeps only 92% on average.
        const double x = 2.0 * t / T - 1;
        const double w = std::cyl_bessel_i(0.0, 2.5 * std::sqrt(1 - x * x));
        for (size_t i = 0; i < size_t(M) * M; ++i) stack[size_t(t) * M * M + i] = w * f[i];
        snow.advance(dt, C, theta);
    }
    std::vector<std::complex<double>> out(size_t(T) * M * H);
    fftw_plan plan = fftw_plan_dft_r2c_3d(T, M, M, stack.data(),
                                          reinterpret_cast<fftw_complex*>(out.data()),
                                          FFTW_ESTIMATE);
    fftw_execute(plan);
    fftw_destroy_plan(plan);

    const SpectralSnowParams& p = snow.params();
    const double rmin = p.min_frequency_fraction * M, rmax = p.max_frequency_fraction * M;
    const double nyquist = kPi / p.frame_time;
    Spectrum3D s;
    for (int ft = 0; ft < T; ++ft) {
        for (int row = 0; row < M; ++row) {
            const int ky = signed_freq(row, M);
            for (int kx = 0; kx < H; ++kx) {
                if (kx == 0 && ky == 0) continue;
                const double weight = (kx == 0 || kx == M / 2) ? 1 : 2;  // the omitted half
                const double power = weight * std::norm(out[(size_t(ft) * M + row) * H + kx]);
                s.total += power;
                const double r = std::sqrt(double(kx) * kx + double(ky) * ky);
                if (r < rmin - 1e-9 || r > rmax + 1e-9) s.outside_annulus += power;
                const double omega = SpectralSnow::dispersion(C, theta, kx, ky);
                if (std::fabs(omega) > nyquist) s.above_nyquist += power;
                // e^{+i omega t dt} shows at temporal bin omega dt T / (2 pi), modulo T.
                const double expected = omega * dt * T / (2 * kPi);
                double dist = std::fmod(std::fabs(ft - expected), double(T));
                dist = std::min(dist, T - dist);
                if (dist <= 1.0 + 1e-9) s.near_surface += power;
            }
        }
    }
    return s;
}

double mean_of(const std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += x;
    return s / v.size();
}

double stddev_of(const std::vector<float>& v) {
    const double m = mean_of(v);
    double s = 0;
    for (float x : v) s += (x - m) * (x - m);
    return std::sqrt(s / v.size());
}

}  // namespace

TEST(SpectralSnow, PowerLiesOnTheDispersionSurfaceInsideTheAnnulus) {
    SpectralSnowParams p;
    p.size = 64;
    p.seed = 7;
    const double C = 100, theta = 0.7;  // max |omega_t| = 100 < pi * 60 = 188.5: no blur
    p.speed_c = C;
    p.direction_theta = theta;
    SpectralSnow snow(p);
    EXPECT_EQ(snow.blurred_count(), 0);
    const Spectrum3D s = analyse(snow, 32, p.frame_time, C, theta);
    const double on = s.near_surface / s.total, out = s.outside_annulus / s.total;
    std::printf("[ fixed C ] M=64 T=32 C=100 theta=0.7: %.2f%% of power within one bin of the "
                "surface, %.2e outside the annulus\n", 100 * on, out);
    EXPECT_GE(on, 0.95);
    EXPECT_LT(out, 1e-9);
}

TEST(SpectralSnow, TemporalBlurRemovesEverythingAboveNyquist) {
    for (bool blur : {true, false}) {
        SpectralSnowParams p;
        p.size = 64;
        p.seed = 3;
        const double C = 400, theta = -2.0;  // Nyquist 188.5 rad/s: about half the tent aliases
        p.speed_c = C;
        p.direction_theta = theta;
        p.temporal_blur = blur;
        SpectralSnow snow(p);
        const Spectrum3D s = analyse(snow, 32, p.frame_time, C, theta);
        const double above = s.above_nyquist / s.total, on = s.near_surface / s.total;
        std::printf("[ blur=%d ] C=400: %d of %d components zeroed, %.3e of power above Nyquist, "
                    "%.2f%% within one bin of the wrapped surface\n", int(blur),
                    snow.blurred_count(), snow.component_count(), above, 100 * on);
        EXPECT_GE(on, 0.95);
        EXPECT_LT(s.outside_annulus / s.total, 1e-9);
        if (blur) {
            EXPECT_GT(snow.blurred_count(), snow.component_count() / 4);
            EXPECT_LT(above, 1e-9);
            // The spectrum itself: every component above the limit is exactly zero.
            const std::vector<std::complex<float>> spec = snow.spectrum();
            const int M = p.size, H = M / 2 + 1;
            for (int row = 0; row < M; ++row)
                for (int kx = 0; kx < H; ++kx)
                    if (std::fabs(SpectralSnow::dispersion(C, theta, kx, signed_freq(row, M))) >
                        kPi / p.frame_time) {
                        ASSERT_EQ(spec[row * H + kx], std::complex<float>(0, 0));
                    }
        } else {
            EXPECT_EQ(snow.blurred_count(), 0);
            EXPECT_GT(above, 0.2);  // aliased power is there without the blur
        }
    }
}

TEST(SpectralSnow, PhasesAdvanceByOmegaDtWithChangingCAndTheta) {
    SpectralSnowParams p;
    p.size = 64;
    p.temporal_blur = false;
    SpectralSnow snow(p);
    const int M = p.size, H = M / 2 + 1;
    const double dt = 1.0 / 60;
    double worst = 0;
    int checked = 0;
    for (int frame = 0; frame < 40; ++frame) {
        const double C = 60 + 50 * std::sin(0.3 * frame);   // rad/s
        const double theta = 1.0 + 0.8 * std::cos(0.2 * frame);
        const std::vector<std::complex<float>> before = snow.spectrum();
        snow.advance(dt, C, theta);
        const std::vector<std::complex<float>> after = snow.spectrum();
        for (int row = 0; row < M; ++row) {
            for (int kx = 0; kx < H; ++kx) {
                const std::complex<float> a = before[row * H + kx], b = after[row * H + kx];
                if (std::abs(a) == 0) continue;
                ASSERT_NEAR(std::abs(b), std::abs(a), 1e-6 * std::abs(a));
                const double r = std::hypot(double(kx), double(signed_freq(row, M)));
                ASSERT_NEAR(std::abs(a), 1 / r, 1e-6 / r);  // 1/|w| amplitudes
                const double measured =
                    std::arg(std::complex<double>(b) * std::conj(std::complex<double>(a)));
                const double expected =
                    SpectralSnow::dispersion(C, theta, kx, signed_freq(row, M)) * dt;
                worst = std::max(worst, std::fabs(wrap_pi(measured - expected)));
                ++checked;
            }
        }
    }
    std::printf("[ varying C, theta ] %d component steps: worst |dphi - omega_t dt| = %.2e rad\n",
                checked, worst);
    EXPECT_GT(checked, 1000);
    EXPECT_LT(worst, 2e-5);
}

TEST(SpectralSnow, VaryingParametersStayOnTheInstantaneousSurface) {
    // A slowly varying C and theta: over a short window the 3D power still follows the surface
    // of the window's mean C and theta.
    SpectralSnowParams p;
    p.size = 64;
    SpectralSnow snow(p);
    const int T = 32;
    const double dt = p.frame_time;
    double c_final = 0;
    for (int t = 0; t < 100; ++t) {  // vary first, then analyse with the same (final) values
        snow.advance(dt, 80 + 40 * std::sin(0.05 * t), 2.0 + 0.5 * std::sin(0.03 * t));
        c_final = snow.current_c();
    }
    const Spectrum3D s = analyse(snow, T, dt, snow.current_c(), snow.current_theta());
    std::printf("[ after varying ] C=%.1f theta=%.3f: %.2f%% within one bin\n", c_final,
                snow.current_theta(), 100 * s.near_surface / s.total);
    EXPECT_GE(s.near_surface / s.total, 0.95);
}

TEST(SpectralSnow, FieldIsTheRealInverseOfTheSpectrum) {
    SpectralSnowParams p;
    p.size = 64;
    p.seed = 11;
    SpectralSnow snow(p);
    snow.advance(0.1, 70, 0.3);
    const int M = p.size, H = M / 2 + 1;
    std::vector<float> f = snow.field();
    std::vector<std::complex<float>> back(size_t(M) * H);
    fftwf_plan plan = fftwf_plan_dft_r2c_2d(M, M, f.data(),
                                            reinterpret_cast<fftwf_complex*>(back.data()),
                                            FFTW_ESTIMATE);
    fftwf_execute(plan);
    fftwf_destroy_plan(plan);
    const std::vector<std::complex<float>> spec = snow.spectrum();
    double err = 0;
    for (size_t i = 0; i < spec.size(); ++i)
        err = std::max(err, double(std::abs(back[i] / float(M * M) - spec[i])));
    EXPECT_LT(err, 1e-5);
    EXPECT_NEAR(stddev_of(snow.field()), snow.field_stddev(), 1e-3 * snow.field_stddev());
    EXPECT_NEAR(mean_of(snow.field()), 0.0, 1e-6);
}

TEST(SpectralSnow, TextureDriftsTowardsThetaPlusPi) {
    // theta = pi/2: the texture moves towards -y (down in a bottom-up GL texture).
    SpectralSnowParams p;
    p.size = 256;
    p.direction_theta = kPi / 2;
    p.speed_c = 40;
    SpectralSnow snow(p);
    const int M = p.size;
    const std::vector<float> f0 = snow.field();
    snow.advance(1.0 / 60, p.speed_c, p.direction_theta);
    const std::vector<float>& f1 = snow.field();
    auto corr = [&](int dx, int dy) {  // sum f1(x, y) f0(x - dx, y - dy)
        double s = 0;
        for (int y = 0; y < M; ++y)
            for (int x = 0; x < M; ++x)
                s += double(f1[y * M + x]) *
                     f0[((y - dy + M) % M) * M + (x - dx + M) % M];
        return s;
    };
    const double down = corr(0, -1) + corr(0, -2), up = corr(0, 1) + corr(0, 2);
    const double left = corr(-1, 0) + corr(-2, 0), right = corr(1, 0) + corr(2, 0);
    std::printf("[ direction ] correlation down %.4g up %.4g left %.4g right %.4g\n", down, up,
                left, right);
    EXPECT_GT(down, 1.2 * up);
    EXPECT_NEAR(left, right, 0.05 * std::fabs(left) + 1e-9);
}

TEST(SpectralSnow, OpacityStatistics) {
    for (bool square : {false, true}) {
        SpectralSnowParams p;  // 512 x 512, paper annulus, 3 sigma
        p.square = square;
        SpectralSnow snow(p);
        double mean = 0, sd = 0, clipped = 0, lo = 1, hi = 0;
        const int frames = 8;
        for (int i = 0; i < frames; ++i) {
            snow.advance(0.25, p.speed_c, p.direction_theta);  // far apart: fresher samples
            const std::vector<float>& a = snow.opacity();
            mean += mean_of(a) / frames;
            sd += stddev_of(a) / frames;
            size_t c = 0;
            for (float x : a) {
                lo = std::min(lo, double(x));
                hi = std::max(hi, double(x));
                c += (x == 0.0f || x == 1.0f);
            }
            clipped += double(c) / a.size() / frames;
        }
        std::printf("[ opacity square=%d ] M=512: mean %.4f, stddev %.4f, clipped %.3f%%, "
                    "range [%.3f, %.3f] (Gaussian model: %s)\n", int(square), mean, sd,
                    100 * clipped, lo, hi,
                    square ? "mean 0.2778, stddev 0.1712" : "mean 0.5, stddev 0.1667");
        EXPECT_GE(lo, 0.0);
        EXPECT_LE(hi, 1.0);
        EXPECT_LT(clipped, 0.01);
        if (square) {
            EXPECT_NEAR(mean, 0.25 + 1.0 / 36, 0.01);
            EXPECT_NEAR(sd, 0.1712, 0.01);
        } else {
            EXPECT_NEAR(mean, 0.5, 0.005);
            EXPECT_NEAR(sd, 1.0 / 6, 0.005);
        }
    }
}

TEST(SpectralSnow, TextureIsToroidal) {
    SpectralSnowParams p;
    p.size = 128;
    SpectralSnow snow(p);
    snow.advance(0.5, 60, 1.2);
    const std::vector<float>& a = snow.opacity();
    const int M = p.size;
    auto at = [&](int x, int y) { return double(a[y * M + x]); };
    double inside = 0, seam = 0;
    int n_inside = 0, n_seam = 0;
    for (int y = 0; y < M; ++y) {
        for (int x = 0; x < M; ++x) {
            const double dx = std::fabs(at((x + 1) % M, y) - at(x, y));
            const double dy = std::fabs(at(x, (y + 1) % M) - at(x, y));
            if (x == M - 1) { seam += dx; ++n_seam; } else { inside += dx; ++n_inside; }
            if (y == M - 1) { seam += dy; ++n_seam; } else { inside += dy; ++n_inside; }
        }
    }
    inside /= n_inside;
    seam /= n_seam;
    std::printf("[ toroidal ] mean |neighbour difference|: inside %.5f, across the wrap %.5f\n",
                inside, seam);
    EXPECT_GT(seam, 0.7 * inside);
    EXPECT_LT(seam, 1.3 * inside);
}

TEST(SpectralSnow, SameSeedSameTextureDifferentSeedDifferent) {
    SpectralSnowParams p;
    p.size = 128;
    p.seed = 42;
    SpectralSnow a(p), b(p);
    p.seed = 43;
    SpectralSnow c(p);
    for (int i = 0; i < 5; ++i) {
        const double C = 50 + 10 * i, theta = 1.5 + 0.1 * i;
        a.advance(1.0 / 60, C, theta);
        b.advance(1.0 / 60, C, theta);
        c.advance(1.0 / 60, C, theta);
    }
    const std::vector<float>& oa = a.opacity();
    const std::vector<float>& ob = b.opacity();
    const std::vector<float>& oc = c.opacity();
    ASSERT_EQ(oa.size(), ob.size());
    EXPECT_EQ(std::memcmp(oa.data(), ob.data(), oa.size() * sizeof(float)), 0);
    size_t differ = 0;
    for (size_t i = 0; i < oa.size(); ++i) differ += oa[i] != oc[i];
    EXPECT_GT(differ, oa.size() * 9 / 10);
}

TEST(SpectralSnow, SeedPhasesArePinned) {
    // The hash is part of the format: a seed must give the same phases on every machine and in
    // every version. Pinned spectrum values at t = 0 (seed 1, M = 64).
    SpectralSnowParams p;
    p.size = 64;
    SpectralSnow snow(p);
    const std::vector<std::complex<float>> s = snow.spectrum();
    const int H = 64 / 2 + 1;
    struct Pin { int row, col; float re, im; };
    const Pin pins[] = {
        {2, 0, 0.347220868f, -0.35977447f},    {62, 0, 0.347220868f, 0.35977447f},
        {0, 2, -0.312073678f, 0.390653312f},   {5, 3, -0.107110217f, 0.13393718f},
        {60, 7, -0.119565345f, -0.0329960994f}, {16, 0, 0.000961054466f, -0.062492609f},
        {0, 16, -0.0621590726f, 0.00651918957f}, {30, 9, 0.0f, 0.0f}};
    for (const Pin& pin : pins) {
        EXPECT_NEAR(s[pin.row * H + pin.col].real(), pin.re, 1e-6) << pin.row << "," << pin.col;
        EXPECT_NEAR(s[pin.row * H + pin.col].imag(), pin.im, 1e-6) << pin.row << "," << pin.col;
    }
}

TEST(SpectralSnow, RejectsBadParameters) {
    SpectralSnowParams p;
    p.size = 63;
    EXPECT_THROW(SpectralSnow{p}, std::invalid_argument);
    p.size = 64;
    p.max_frequency_fraction = 0.5;
    EXPECT_THROW(SpectralSnow{p}, std::invalid_argument);
    p.max_frequency_fraction = 0.25;
    p.frame_time = 0;
    EXPECT_THROW(SpectralSnow{p}, std::invalid_argument);
}
