#include "slave/effects/shadows/shadow_light.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace glcast::slave::effects {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGoldenAngle = 2.39996322972865332;  // pi (3 - sqrt 5): the Vogel spiral's step

// An up vector for lookAt that is far from parallel to `forward`.
glm::dvec3 up_for(const glm::dvec3& forward) {
    const glm::dvec3 a = std::abs(forward.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    return glm::normalize(a - forward * glm::dot(a, forward));
}

glm::dvec3 centroid(const std::array<glm::dvec3, 8>& corners) {
    glm::dvec3 c(0.0);
    for (const auto& p : corners) c += p;
    return c / 8.0;
}

}  // namespace

bool is_headlight(const glm::dvec4& p) {
    const double cos_limit = std::cos(glm::radians(10.0)), sin_limit = std::sin(glm::radians(10.0));
    const glm::dvec3 v(p);
    const double n = glm::length(v);
    if (p.w == 0) return n > 0 && v.z >= cos_limit * n;  // towards the light: the eye's +Z
    const glm::dvec3 at = v / p.w;
    return glm::length(at) < 1e-9 || (at.z > 0 && glm::length(glm::dvec2(at)) <= sin_limit * glm::length(at));
}

ShadowLight choose_light(const FrameView& view, const ShadowSettings& settings) {
    const bool program = settings.use_program_light && view.light.known && !is_headlight(view.light.eye_position);
    const glm::dvec4 gl_position = program ? view.light.eye_position : settings.fallback_light;
    ShadowLight light;
    light.directional = gl_position.w == 0;
    if (light.directional) {
        const double n = glm::length(glm::dvec3(gl_position));
        light.direction = n > 0 ? glm::dvec3(gl_position) / n : glm::dvec3(0, 0, 1);
    } else {
        light.position = glm::dvec3(gl_position) / gl_position.w;
    }
    return light;
}

double shadow_reach(const ShadowSettings& settings, const glm::dmat4& p) {
    if (settings.max_distance > 0) return settings.max_distance;
    // GL's perspective, w = -z: p[2][2] = -(f + n) / (f - n), p[3][2] = -2 f n / (f - n); an
    // infinite far plane has p[2][2] = -1. (w = -k z: the same divided by k.)
    const double k = -p[2][3];
    if (!(k > 0)) return kShadowReachAtLeast;  // no perspective
    const double a = p[2][2] / k, b = p[3][2] / k;
    const double near = b / (a - 1), far = b / (a + 1);
    if (!(near > 0) || !std::isfinite(near)) return kShadowReachAtLeast;
    // (a near plane pulled in for depth precision, VTK's a thousandth of its far plane, says
    // nothing of the scene's size: at least the old fixed reach)
    const double reach = std::max(kShadowReachInNearPlanes * near, kShadowReachAtLeast);
    return far > near && std::isfinite(far) ? std::min(far, reach) : reach;
}

std::array<glm::dvec3, 8> view_frustum_corners(const glm::dmat4& projection, double max_distance) {
    const glm::dmat4 inv = glm::inverse(projection);
    std::array<glm::dvec3, 8> c;
    for (int i = 0; i < 8; ++i) {
        const glm::dvec4 ndc((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, i < 4 ? -1 : 1, 1);
        const glm::dvec4 e = inv * ndc;
        c[i] = glm::dvec3(e) / e.w;
    }
    // Far corners beyond max_distance, or at infinity (an infinite far plane, as programs with
    // shadow volumes project: NDC z = 1 unprojects to w = 0), move along their ray, which the
    // near corner and the point at NDC z = 0 (finite for every projection) span.
    for (int i = 0; i < 4; ++i) {
        const glm::dvec4 mid = inv * glm::dvec4((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, 0, 1);
        const glm::dvec3 n = c[i], m = glm::dvec3(mid) / mid.w, f = c[i + 4];
        const double dn = -n.z, dm = -m.z, df = -f.z;
        const bool finite = std::isfinite(df) && std::isfinite(f.x) && std::isfinite(f.y) && df > dn;
        if ((!finite || df > max_distance) && dm != dn)
            c[i + 4] = n + (m - n) * (std::max(max_distance, dn) - dn) / (dm - dn);
    }
    return c;
}

LightFrame fit_light_frame(const ShadowLight& light, const std::array<glm::dvec3, 8>& corners, double max_fov_deg) {
    LightFrame frame;
    const glm::dvec3 center = centroid(corners);
    if (light.directional) {
        const glm::dvec3 forward = -light.direction;
        frame.orthographic = true;
        frame.view = glm::lookAt(center, center + forward, up_for(forward));
        glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (const auto& p : corners) {
            const glm::dvec3 q = glm::dvec3(frame.view * glm::dvec4(p, 1.0));
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        // Casters between the light and the view volume must be in the map: extend it towards
        // the light by the volume's largest extent (depth clamp flattens anything beyond).
        const glm::dvec3 extent = hi - lo;
        const double reach = std::max({extent.x, extent.y, extent.z});
        const glm::dvec2 margin = glm::dvec2(extent) * 0.02 + 1e-6;
        frame.near = -(hi.z + reach);
        frame.far = -lo.z + 1e-6 * reach;
        frame.projection = glm::ortho(lo.x - margin.x, hi.x + margin.x, lo.y - margin.y, hi.y + margin.y, frame.near, frame.far);
        frame.uv_per_unit = {0.5 * frame.projection[0][0], 0.5 * frame.projection[1][1]};
        return frame;
    }
    frame.orthographic = false;
    glm::dvec3 forward = center - light.position;
    forward = glm::length(forward) > 0 ? glm::normalize(forward) : glm::dvec3(0, 0, -1);
    frame.view = glm::lookAt(light.position, light.position + forward, up_for(forward));
    double tan_max = 0, nearest = std::numeric_limits<double>::max(), farthest = 0;
    bool behind = false;
    for (const auto& p : corners) {
        const glm::dvec3 q = glm::dvec3(frame.view * glm::dvec4(p, 1.0));
        const double depth = -q.z;
        farthest = std::max(farthest, depth);
        if (depth <= 1e-9) {
            behind = true;
            continue;
        }
        nearest = std::min(nearest, depth);
        tan_max = std::max({tan_max, std::abs(q.x) / depth, std::abs(q.y) / depth});
    }
    const double half_limit = 0.5 * max_fov_deg * kPi / 180;
    const double half = behind ? half_limit : std::min(std::atan(tan_max) * 1.02 + 1e-4, half_limit);
    frame.far = farthest > 0 ? farthest * 1.02 : 1.0;
    // A linear function's minimum over the volume is at a corner, unless the volume reaches
    // behind the light: then it comes arbitrarily close. A 32-bit float depth keeps a near
    // plane of far/1000 precise enough (~1e-4 of far at the far end).
    frame.near = behind ? frame.far * 1e-3 : std::max(0.5 * nearest, frame.far * 1e-3);
    frame.projection = glm::perspective(2 * half, 1.0, frame.near, frame.far);
    frame.uv_per_unit = {0.5 * frame.projection[0][0], 0.5 * frame.projection[1][1]};
    return frame;
}

std::vector<ShadowLight> area_light_samples(const ShadowLight& light, const LightFrame& center_frame, double size,
                                            double angle_deg, int count) {
    // The light frame's x and y axes in eye space (rows of its rotation).
    const glm::dvec3 u(center_frame.view[0][0], center_frame.view[1][0], center_frame.view[2][0]);
    const glm::dvec3 v(center_frame.view[0][1], center_frame.view[1][1], center_frame.view[2][1]);
    const double radius = light.directional ? std::tan(0.5 * angle_deg * kPi / 180) : 0.5 * size;
    std::vector<ShadowLight> samples;
    samples.reserve(size_t(std::max(count, 0)));
    for (int i = 0; i < count; ++i) {
        const double r = radius * std::sqrt((i + 0.5) / count), a = i * kGoldenAngle;
        const glm::dvec3 offset = r * (std::cos(a) * u + std::sin(a) * v);
        ShadowLight s = light;
        if (light.directional) s.direction = glm::normalize(light.direction + offset);
        else s.position = light.position + offset;
        samples.push_back(s);
    }
    return samples;
}

double penumbra_width(const ShadowLight& light, double size, double angle_deg, double receiver, double blocker) {
    const double gap = std::max(receiver - blocker, 0.0);
    if (light.directional) return 2 * std::tan(0.5 * angle_deg * kPi / 180) * gap;
    return blocker > 0 ? size * gap / blocker : 0;
}

}  // namespace glcast::slave::effects
