// The passes' depth convention (depth_convention.h).
#include "slave/scene/depth_convention.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace glcast::slave {

namespace {

glm::dvec4 row(const glm::dmat4& m, int r) { return {m[0][r], m[1][r], m[2][r], m[3][r]}; }

void set_row(glm::dmat4& m, int r, const glm::dvec4& v) {
    for (int c = 0; c < 4; ++c) m[c][r] = v[c];
}

// The clip-space z range the program's NDC spans: [-1, 1], or [0, 1] with GL_ZERO_TO_ONE.
double ndc_min(const ProgramDepthState& s) { return s.zero_to_one ? 0.0 : -1.0; }

}  // namespace

DepthConvention depth_convention(const glm::dmat4& projection, const ProgramDepthState& state) {
    DepthConvention c;
    c.program = state;
    c.pass_projection = c.program_projection = projection;
    // The program's z row as a multiple of its w row plus a constant: NDC z = a + b / w (a
    // perspective projection's z row has this form; w grows with the eye distance).
    const glm::dvec4 z = row(projection, 2), w = row(projection, 3);
    const glm::dvec3 wv(w);
    const double scale = glm::length(wv);
    if (scale < 1e-12 || std::abs(w.w) > 1e-9 * scale) return c;  // not perspective
    const double a = glm::dot(glm::dvec3(z), wv) / (scale * scale), b = z.w;
    // (1e-6: on a rotated tile the projection is read back through the tile's correction in
    // single precision, with 1e-8s where a perspective projection has zeros)
    if (std::abs(b) < 1e-12 || glm::length(glm::dvec3(z) - a * wv) > 1e-6 * (std::abs(a) + 1) * scale)
        return c;  // depth does not follow 1 / w: not one the passes can read
    // Reversed: NDC z falls as w grows (b > 0), the near plane at NDC 1.
    const bool reversed = b > 0;
    const double low = ndc_min(state);
    auto w_at = [&](double ndc) {  // the w at which NDC z is `ndc`; infinity where it never is
        const double d = ndc - a;
        const double v = std::abs(d) < 1e-12 ? std::numeric_limits<double>::infinity() : b / d;
        return v > 0 ? v : std::numeric_limits<double>::infinity();
    };
    const double near = w_at(reversed ? 1.0 : low);
    double far = w_at(reversed ? low : 1.0);
    if (!std::isfinite(near)) return c;
    const bool standard = !reversed && !state.zero_to_one && !state.flipped() && !state.flipped_columns() &&
                          state.range_near == 0 &&
                          state.range_far == 1 && state.clear_depth == 1;
    if (standard) return c;  // today's path, untouched
    if (!std::isfinite(far) || far <= near) far = near * kInfiniteFarInNears;
    c.standard = false;
    c.reversed = reversed;
    c.near = near / scale;  // eye distances: w is `scale` times the distance along the view
    c.far = far / scale;
    // The program's projection as the window shows it: an upper-left origin (or a scene shown
    // upside down) flips y, a scene shown mirrored left to right x.
    glm::dmat4 program = projection;
    if (state.flipped()) set_row(program, 1, -row(projection, 1));
    if (state.flipped_columns()) set_row(program, 0, -row(projection, 0));
    // NDC z = alpha + beta / w: -1 at near, +1 at far.
    glm::dmat4 pass = program;
    glm::dvec4 zrow = (far + near) / (far - near) * w;
    zrow.w = -2 * near * far / (far - near);
    set_row(pass, 2, zrow);
    c.pass_projection = pass;
    c.program_projection = program;
    c.pass_from_program = pass * glm::inverse(projection);
    return c;
}

double to_pass_depth(const DepthConvention& c, const glm::dmat4& m, double x, double y, double depth) {
    const ProgramDepthState& s = c.program;
    if (depth == s.clear_depth) return 1.0;
    const double t = (depth - s.range_near) / (s.range_far - s.range_near);
    const double z = s.zero_to_one ? t : 2 * t - 1;
    const glm::dvec4 p = m * glm::dvec4(x, y, z, 1.0);
    if (!(p.w > 0)) return 1.0;
    return std::clamp(0.5 * p.z / p.w + 0.5, 0.0, 1.0);
}

}  // namespace glcast::slave
