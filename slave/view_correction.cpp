#include "slave/view_correction.h"

#include <cmath>

namespace glcast::slave {

static double radians(double deg) { return deg * 3.14159265358979323846 / 180.0; }

glm::dmat4 ViewCorrection::correction(const glm::dmat4& app) const {
    // Near and far of a perspective projection (glFrustum's matrix: m[2][2] = -(f+n)/(f-n),
    // m[3][2] = -2fn/(f-n)); an orthographic or odd one gets a generic range.
    double n = 0.1, f = 1000.0;
    const double a = app[2][2], b = app[3][2];
    if (std::abs(app[2][3] + 1.0) < 1e-6 && std::abs(a - 1.0) > 1e-9 && std::abs(a + 1.0) > 1e-9) {
        n = b / (a - 1.0);
        f = b / (a + 1.0);
        if (!(n > 0 && f > n)) n = 0.1, f = 1000.0;
    }
    const double l = n * std::tan(radians(left_deg)), r = n * std::tan(radians(right_deg));
    const double bo = n * std::tan(radians(bottom_deg)), t = n * std::tan(radians(top_deg));
    glm::dmat4 tile(0.0);  // glFrustum(l, r, bo, t, n, f)
    tile[0][0] = 2 * n / (r - l);
    tile[1][1] = 2 * n / (t - bo);
    tile[2][0] = (r + l) / (r - l);
    tile[2][1] = (t + bo) / (t - bo);
    tile[2][2] = -(f + n) / (f - n);
    tile[2][3] = -1;
    tile[3][2] = -2 * f * n / (f - n);
    // The tile camera in the program's eye space (looking down -Z, +Y up): heading (yaw, positive
    // turns right), then pitch (positive looks up), then roll (positive lowers the right side).
    const glm::dvec3 up(0, 1, 0), right(1, 0, 0), back(0, 0, 1);
    auto rotate = [](double deg, const glm::dvec3& axis) {
        const double c = std::cos(radians(deg)), s = std::sin(radians(deg));
        const glm::dvec3 u = glm::normalize(axis);
        glm::dmat4 m(1.0);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                m[j][i] = (i == j ? c : 0) + (1 - c) * u[i] * u[j] +
                          s * (i == 0 ? (j == 1 ? -u[2] : j == 2 ? u[1] : 0)
                                      : i == 1 ? (j == 0 ? u[2] : j == 2 ? -u[0] : 0)
                                               : (j == 0 ? -u[1] : j == 1 ? u[0] : 0));
        return m;
    };
    const glm::dmat4 orientation = rotate(-yaw_deg, up) * rotate(pitch_deg, right) * rotate(roll_deg, back);
    return tile * glm::transpose(orientation) * glm::inverse(app);
}

glm::dmat4 ViewCorrection::program_projection(double aspect) const {
    const double t = program_near * std::tan(radians(program_fov_y_deg) / 2), r = t * aspect;
    glm::dmat4 p(0.0);
    p[0][0] = program_near / r;
    p[1][1] = program_near / t;
    p[2][2] = -(program_far + program_near) / (program_far - program_near);
    p[2][3] = -1;
    p[3][2] = -2 * program_far * program_near / (program_far - program_near);
    return p;
}

}  // namespace glcast::slave
