// Spectral snow (Langer, Zhang, Klein, Bhatia, Pereira, Rekhi: "A spectral-particle hybrid
// method for rendering falling snow"; docs/snow.md): the CPU synthesis core of the dynamic
// opacity texture that fills in between snow particles. One M x M toroidal tile, synthesized
// frame by frame with the paper's 2D method (sec. 5.2):
//
//   - every spatial frequency w = (wx, wy) on the annulus M/32 <= |w| <= M/4 (sec. 5.3; integer
//     cycles per tile width) carries amplitude 1/|w| (sec. 5.4) and a random initial phase;
//   - advance(dt, C, theta) adds omega_t * dt to each phase, with the dispersion relation
//     (Eq. 6) omega_t = C (cos theta wx + sin theta wy) / |w|, so C and theta may change every
//     frame;
//   - components with |omega_t| above the temporal Nyquist limit pi / frame_time are zeroed
//     (temporal blur, sec. 5.5);
//   - a real inverse 2D FFT (FFTW, fftw3f) gives the raw field, which is mapped to opacity:
//     mean 0.5, +-clip_sigmas standard deviations onto [0, 1], outliers clipped, squared
//     (sec. 5.6).
//
// Conventions. Pixel (x, y) of an M x M texture is element y * M + x (x = column, fast index).
// The raw field is  f(x, y) = sum_w X(w) exp(+i 2 pi (wx x + wy y) / M)  (FFTW's backward,
// unnormalized transform) with X(w) = exp(i phi(w)) / |w|. With phi += omega_t dt, a component
// w moves with image velocity  -omega_t M / (2 pi |w|^2) * w  pixels per second (Eq. 1 of the
// paper, omega_t = -v . w), so the texture drifts towards theta + pi: theta = pi/2 makes it move
// towards -y, i.e. DOWN in a GL texture whose row 0 is the bottom row. The fastest component
// (|w| = M/32, along theta) moves 32 C / (2 pi) ~= 5.09 C pixels per second whatever M is; the
// slowest on that line (|w| = M/4) 4 C / (2 pi) ~= 0.64 C pixels per second.
//
// Threading: an instance is not thread-safe, but instances are independent and may live on any
// thread (no globals). FFTW plan creation/destruction is serialized by fftw_planner_mutex(),
// which any other FFTW planning in the process must also hold.
#pragma once

#include <complex>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace glcast::slave::effects {

struct SpectralSnowParams {
    // Tile width and height M in pixels (texels). Even, >= 8. The texture is M x M and toroidal.
    int size = 512;
    // Initial C of Eq. 6, in radians per second: the temporal angular frequency of the
    // fundamental spatial frequency (1 cycle per tile width) along theta. omega_t of every
    // component lies in [-C, C]. See the header comment for the resulting speeds in pixels/s.
    // 50 rad/s: fastest flakes ~255 px/s (~4.2 px per frame at 60 Hz), below the Nyquist limit.
    double speed_c = 50.0;
    // Initial theta of Eq. 6, in radians, in the texture's (x, y) frame. The texture drifts
    // towards theta + pi (see header comment); pi/2 = falls towards -y.
    double direction_theta = 1.5707963267948966;
    // Annulus of spatial frequencies carrying power, as fractions of M (cycles per tile width
    // divided by M): min_frequency_fraction * M <= |w| <= max_frequency_fraction * M. The paper
    // uses M/32 .. M/4 (three octaves of depth/speed). max must be < 0.5 (spatial Nyquist).
    double min_frequency_fraction = 1.0 / 32;
    double max_frequency_fraction = 1.0 / 4;
    // Zero components whose |omega_t| exceeds the temporal Nyquist limit pi / frame_time (rad/s)
    // instead of letting them alias into motion the wrong way (sec. 5.5).
    bool temporal_blur = true;
    // Seed of the random initial phases (counter-based hash of (seed, wx, wy): the phases are
    // bit-identical on every machine).
    uint64_t seed = 1;
    // Display frame interval in seconds, for the temporal Nyquist limit pi / frame_time.
    double frame_time = 1.0 / 60;
    // Mapping to opacity (sec. 5.6; the paper gives no number): the raw field's mean (0) maps to
    // 0.5 and +-clip_sigmas standard deviations map to 0 and 1; values beyond are clipped
    // (~0.27% of texels for 3 sigma and a Gaussian field).
    double clip_sigmas = 3.0;
    // Square the mapped opacity (sec. 5.6). Gives mean ~0.278, standard deviation ~0.171.
    bool square = true;
    // FFTW planning rigor: false = FFTW_ESTIMATE (deterministic plan, bit-identical output from
    // run to run on one machine), true = FFTW_MEASURE (may be faster; plan chosen by timing, so
    // the float rounding of the output may differ between instances/runs).
    bool fftw_measure = false;
};

class SpectralSnow {
public:
    // Throws std::invalid_argument on bad parameters.
    explicit SpectralSnow(const SpectralSnowParams& params);
    ~SpectralSnow();
    SpectralSnow(SpectralSnow&&) noexcept;
    SpectralSnow& operator=(SpectralSnow&&) noexcept;
    SpectralSnow(const SpectralSnow&) = delete;
    SpectralSnow& operator=(const SpectralSnow&) = delete;

    // Advance time by dt seconds with C (rad/s) and theta (rad) of Eq. 6:
    // phi(w) += omega_t(w) * dt. C and theta also become the current ones for the temporal blur.
    void advance(double dt, double C, double theta);

    // Current frame, M * M floats, row-major (y * M + x). opacity() is in [0, 1]; field() is the
    // raw real field before mapping (inverse FFT of spectrum()). Computed lazily, cached until
    // the next advance(); the references stay valid for the object's lifetime.
    const std::vector<float>& opacity();
    const std::vector<float>& field();

    // Current frame's spectrum before the inverse FFT, FFTW's r2c half layout: M rows (wy = row,
    // or row - M for row > M/2) by M/2 + 1 columns (wx = column), element row * (M/2 + 1) + col.
    // The omitted half is the complex conjugate: X(-w) = conj(X(w)). Blurred components are 0.
    std::vector<std::complex<float>> spectrum() const;

    int size() const;
    double time() const;       // seconds advanced so far
    double current_c() const;  // C, theta of the last advance() (initially from the params)
    double current_theta() const;
    // Number of independent components on the annulus (half-plane), and how many of them the
    // temporal blur currently zeroes.
    int component_count() const;
    int blurred_count() const;
    // Standard deviation of the current raw field (exact, from Parseval).
    double field_stddev() const;

    const SpectralSnowParams& params() const;

    // omega_t of Eq. 6 in rad/s for integer frequency (wx, wy); 0 at w = 0.
    static double dispersion(double C, double theta, int wx, int wy);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Held around every FFTW plan creation and destruction (not thread-safe in FFTW).
std::mutex& fftw_planner_mutex();

}  // namespace glcast::slave::effects
