// Spectral snow synthesis core (docs/snow.md, slave/effects/snow/spectral_snow.h).
#include "slave/effects/snow/spectral_snow.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace glcast::slave::effects {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2 * kPi;

// SplitMix64 finalizer: a counter-based hash, identical on every machine.
uint64_t mix64(uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Initial phase in [0, 2 pi) of frequency (wx, wy) for a seed. Exact: 53 hash bits -> double.
double initial_phase(uint64_t seed, int wx, int wy) {
    uint64_t key = (uint64_t(uint32_t(wx)) << 32) | uint64_t(uint32_t(wy));
    uint64_t h = mix64(mix64(seed) ^ mix64(key ^ 0x5eedc0de5eedc0deull));
    return double(h >> 11) * (1.0 / 9007199254740992.0) * kTwoPi;
}

struct FftwFree {
    void operator()(void* p) const { fftwf_free(p); }
};

}  // namespace

std::mutex& fftw_planner_mutex() {
    static std::mutex m;
    return m;
}

struct SpectralSnow::Impl {
    SpectralSnowParams p;
    int M = 0, H = 0;  // H = M/2 + 1 columns of the half spectrum
    double C = 0, theta = 0, t = 0;

    // Independent components (kx > 0, or kx == 0 and ky > 0), structure of arrays.
    std::vector<int32_t> index;    // row * H + col in the half spectrum
    std::vector<int32_t> mirror;   // for kx == 0: index of (0, -ky), else -1
    std::vector<float> ux, uy;     // w / |w|
    std::vector<float> amp;        // 1 / |w|
    std::vector<double> phase;     // phi(w), kept in [-pi, pi]
    std::vector<float> re, im;     // current coefficient (0 when blurred)
    int blurred = 0;
    double variance = 0;           // of the raw field (Parseval)

    std::unique_ptr<fftwf_complex, FftwFree> spec;  // M x H, FFT input (destroyed by c2r)
    std::unique_ptr<float, FftwFree> out;           // M x M, FFT output
    fftwf_plan plan = nullptr;
    std::vector<float> field, opacity;
    bool field_valid = false, opacity_valid = false;

    ~Impl() {
        if (plan) {
            std::lock_guard<std::mutex> lock(fftw_planner_mutex());
            fftwf_destroy_plan(plan);
        }
    }

    // Coefficients, blur mask and variance for the current phases, C and theta.
    void coefficients() {
        const float cx = float(C * std::cos(theta)), cy = float(C * std::sin(theta));
        const float nyquist = p.temporal_blur ? float(kPi / p.frame_time) : INFINITY;
        const size_t n = index.size();
        double var = 0;
        int nb = 0;
        for (size_t i = 0; i < n; ++i) {
            float w = cx * ux[i] + cy * uy[i];
            if (std::fabs(w) > nyquist) {
                re[i] = im[i] = 0;
                ++nb;
                continue;
            }
            float ph = float(phase[i]);
            re[i] = amp[i] * std::cos(ph);
            im[i] = amp[i] * std::sin(ph);
            var += double(amp[i]) * amp[i];
        }
        variance = 2 * var;  // each independent component has its conjugate twin
        blurred = nb;
        field_valid = opacity_valid = false;
    }

    void compute_field() {
        fftwf_complex* s = spec.get();
        std::memset(s, 0, sizeof(fftwf_complex) * size_t(M) * H);
        const size_t n = index.size();
        for (size_t i = 0; i < n; ++i) {
            s[index[i]][0] = re[i];
            s[index[i]][1] = im[i];
            if (mirror[i] >= 0) {
                s[mirror[i]][0] = re[i];
                s[mirror[i]][1] = -im[i];
            }
        }
        fftwf_execute(plan);
        std::memcpy(field.data(), out.get(), sizeof(float) * size_t(M) * M);
        field_valid = true;
    }

    void compute_opacity() {
        if (!field_valid) compute_field();
        const size_t n = size_t(M) * M;
        const float* f = field.data();
        float* o = opacity.data();
        // The field's mean is exactly 0 (no DC component): shift to 0.5, scale +-k sigma to
        // [0, 1], clip, square.
        const double sd = std::sqrt(variance);
        const float scale = sd > 0 ? float(0.5 / (p.clip_sigmas * sd)) : 0.0f;
        if (p.square) {
            for (size_t i = 0; i < n; ++i) {
                float a = std::min(std::max(0.5f + scale * f[i], 0.0f), 1.0f);
                o[i] = a * a;
            }
        } else {
            for (size_t i = 0; i < n; ++i) o[i] = std::min(std::max(0.5f + scale * f[i], 0.0f), 1.0f);
        }
        opacity_valid = true;
    }
};

SpectralSnow::SpectralSnow(const SpectralSnowParams& params) : impl_(new Impl) {
    Impl& d = *impl_;
    d.p = params;
    const int M = params.size;
    if (M < 8 || M % 2 != 0 || M > (1 << 15))
        throw std::invalid_argument("spectral snow: size must be even, 8..32768, got " +
                                    std::to_string(M));
    if (!(params.min_frequency_fraction > 0) ||
        !(params.max_frequency_fraction >= params.min_frequency_fraction) ||
        !(params.max_frequency_fraction < 0.5))
        throw std::invalid_argument(
            "spectral snow: need 0 < min_frequency_fraction <= max_frequency_fraction < 0.5");
    if (!(params.frame_time > 0)) throw std::invalid_argument("spectral snow: frame_time <= 0");
    if (!(params.clip_sigmas > 0)) throw std::invalid_argument("spectral snow: clip_sigmas <= 0");
    d.M = M;
    d.H = M / 2 + 1;
    d.C = params.speed_c;
    d.theta = params.direction_theta;

    // Annulus, in integer cycles per tile: rmin <= |w| <= rmax (small tolerance so that
    // M/32 and M/4 themselves are included despite rounding).
    const double rmin = params.min_frequency_fraction * M, rmax = params.max_frequency_fraction * M;
    const double r2min = rmin * rmin * (1 - 1e-12), r2max = rmax * rmax * (1 + 1e-12);
    for (int row = 0; row < M; ++row) {
        const int ky = row <= M / 2 ? row : row - M;
        for (int kx = 0; kx < d.H; ++kx) {
            if (kx == 0 && ky <= 0) continue;  // conjugate twin of (0, -ky), or DC
            const double r2 = double(kx) * kx + double(ky) * ky;
            if (r2 < r2min || r2 > r2max) continue;
            const double r = std::sqrt(r2);
            d.index.push_back(row * d.H + kx);
            d.mirror.push_back(kx == 0 ? ((M - row) % M) * d.H : -1);
            d.ux.push_back(float(kx / r));
            d.uy.push_back(float(ky / r));
            d.amp.push_back(float(1 / r));
            double ph = initial_phase(params.seed, kx, ky);
            d.phase.push_back(ph - kTwoPi * std::round(ph / kTwoPi));
        }
    }
    d.re.resize(d.index.size());
    d.im.resize(d.index.size());

    d.spec.reset(static_cast<fftwf_complex*>(fftwf_malloc(sizeof(fftwf_complex) * size_t(M) * d.H)));
    d.out.reset(static_cast<float*>(fftwf_malloc(sizeof(float) * size_t(M) * M)));
    if (!d.spec || !d.out) throw std::bad_alloc();
    {
        std::lock_guard<std::mutex> lock(fftw_planner_mutex());
        d.plan = fftwf_plan_dft_c2r_2d(M, M, d.spec.get(), d.out.get(),
                                       params.fftw_measure ? FFTW_MEASURE : FFTW_ESTIMATE);
    }
    if (!d.plan) throw std::runtime_error("spectral snow: FFTW planning failed");
    d.field.assign(size_t(M) * M, 0.0f);
    d.opacity.assign(size_t(M) * M, 0.0f);
    d.coefficients();
}

SpectralSnow::~SpectralSnow() = default;
SpectralSnow::SpectralSnow(SpectralSnow&&) noexcept = default;
SpectralSnow& SpectralSnow::operator=(SpectralSnow&&) noexcept = default;

void SpectralSnow::advance(double dt, double C, double theta) {
    Impl& d = *impl_;
    const double cx = C * std::cos(theta) * dt, cy = C * std::sin(theta) * dt;
    const size_t n = d.index.size();
    for (size_t i = 0; i < n; ++i) {
        // phi += omega_t * dt, omega_t = C (cos theta wx + sin theta wy) / |w|. Wrapped with a
        // sign-symmetric rounding so that the phases stay small and exact to double precision.
        double ph = d.phase[i] + (cx * double(d.ux[i]) + cy * double(d.uy[i]));
        d.phase[i] = ph - kTwoPi * std::nearbyint(ph * (1 / kTwoPi));
    }
    d.C = C;
    d.theta = theta;
    d.t += dt;
    d.coefficients();
}

const std::vector<float>& SpectralSnow::field() {
    if (!impl_->field_valid) impl_->compute_field();
    return impl_->field;
}

const std::vector<float>& SpectralSnow::opacity() {
    if (!impl_->opacity_valid) impl_->compute_opacity();
    return impl_->opacity;
}

std::vector<std::complex<float>> SpectralSnow::spectrum() const {
    const Impl& d = *impl_;
    std::vector<std::complex<float>> s(size_t(d.M) * d.H);
    for (size_t i = 0; i < d.index.size(); ++i) {
        s[d.index[i]] = {d.re[i], d.im[i]};
        if (d.mirror[i] >= 0) s[d.mirror[i]] = {d.re[i], -d.im[i]};
    }
    return s;
}

int SpectralSnow::size() const { return impl_->M; }
double SpectralSnow::time() const { return impl_->t; }
double SpectralSnow::current_c() const { return impl_->C; }
double SpectralSnow::current_theta() const { return impl_->theta; }
int SpectralSnow::component_count() const { return int(impl_->index.size()); }
int SpectralSnow::blurred_count() const { return impl_->blurred; }
double SpectralSnow::field_stddev() const { return std::sqrt(impl_->variance); }
const SpectralSnowParams& SpectralSnow::params() const { return impl_->p; }

double SpectralSnow::dispersion(double C, double theta, int wx, int wy) {
    const double r = std::sqrt(double(wx) * wx + double(wy) * wy);
    if (r == 0) return 0;
    return C * (std::cos(theta) * wx + std::sin(theta) * wy) / r;
}

}  // namespace glcast::slave::effects
