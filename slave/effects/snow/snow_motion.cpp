#include "slave/effects/snow/snow_motion.h"

#include <cmath>

namespace glcast::slave::effects {

namespace {
constexpr double kPi = 3.14159265358979323846;

bool perspective(const glm::dmat4& p) { return p[2][3] != 0 && p[3][3] == 0; }
}  // namespace

glm::dvec2 image_velocity(const glm::dmat4& p, double canvas_w, double canvas_h, glm::dvec2 q, glm::dvec3 u,
                          double depth) {
    const glm::dvec2 ndc(2 * q.x / canvas_w - 1, 2 * q.y / canvas_h - 1);
    glm::dvec2 ndc_velocity;
    if (perspective(p)) {
        // ndc = -P00 X / Z - P20  =>  a = (ndc + P20) / P00
        const glm::dvec2 a((ndc.x + p[2][0]) / p[0][0], (ndc.y + p[2][1]) / p[1][1]);
        const glm::dvec2 da = (glm::dvec2(u.x, u.y) + a * u.z) / depth;
        ndc_velocity = glm::dvec2(p[0][0] * da.x, p[1][1] * da.y);
    } else {
        ndc_velocity = glm::dvec2(p[0][0] * u.x, p[1][1] * u.y);
    }
    return glm::dvec2(ndc_velocity.x * canvas_w / 2, ndc_velocity.y * canvas_h / 2);
}

bool focus_of_expansion(const glm::dmat4& p, double canvas_w, double canvas_h, glm::dvec3 u, glm::dvec2& foe) {
    if (!perspective(p) || std::abs(u.z) < 1e-9 * (std::abs(u.x) + std::abs(u.y) + 1e-30)) return false;
    const glm::dvec2 a(-u.x / u.z, -u.y / u.z);
    const glm::dvec2 ndc(p[0][0] * a.x - p[2][0], p[1][1] * a.y - p[2][1]);
    foe = glm::dvec2((ndc.x + 1) * canvas_w / 2, (ndc.y + 1) * canvas_h / 2);
    return true;
}

glm::dvec3 camera_velocity_eye(const glm::dmat4& previous_view, const glm::dmat4& view, double dt) {
    const glm::dvec3 before(glm::inverse(previous_view)[3]), now(glm::inverse(view)[3]);
    return glm::dmat3(view) * ((now - before) / dt);
}

void spectral_c_theta(glm::dvec2 v, double min_frequency_fraction, double& c, double& theta) {
    // The fastest band moves C / (2 pi min_frequency_fraction) texels per second.
    c = glm::length(v) * 2 * kPi * min_frequency_fraction;
    theta = std::atan2(v.y, v.x) + kPi;
}

}  // namespace glcast::slave::effects
