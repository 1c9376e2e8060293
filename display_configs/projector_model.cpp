#include "display_configs/projector_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace glcast::slave {

namespace {

constexpr double kDeg = M_PI / 180.0;

glm::dmat3 rotation(double yaw, double pitch, double roll) {
    // Yaw turns right (about -y), then pitch up (about x), then roll (about the view axis).
    glm::dmat4 m = glm::rotate(glm::dmat4(1.0), -yaw * kDeg, glm::dvec3(0, 1, 0));
    m = glm::rotate(m, pitch * kDeg, glm::dvec3(1, 0, 0));
    m = glm::rotate(m, roll * kDeg, glm::dvec3(0, 0, -1));
    return glm::dmat3(m);
}

double share(double x, double y) {  // distance to the image edge, 0 at it
    return std::max(0.0, std::min(std::min(x, 1 - x), std::min(y, 1 - y)));
}

}  // namespace

double Surface::aspect() const {
    switch (kind) {
    case cylinder: return radius * (azimuth_to - azimuth_from) * kDeg / (height_to - height_from);
    case dome: return 1;
    case plane: return (x_to - x_from) / (y_to - y_from);
    }
    return 1;
}

std::optional<glm::dvec2> Surface::unroll(const glm::dvec3& p, bool beyond) const {
    glm::dvec2 st;
    switch (kind) {
    case cylinder: {
        const double azimuth = std::atan2(p.x, -p.z) / kDeg;
        st = {(azimuth - azimuth_from) / (azimuth_to - azimuth_from), (height_to - p.y) / (height_to - height_from)};
        break;
    }
    case dome: {
        const double from_zenith = std::acos(std::clamp(p.y / radius, -1.0, 1.0)) / kDeg;  // 0..90
        const double r = from_zenith / 90, flat = std::hypot(p.x, p.z);
        const glm::dvec2 d = flat > 0 ? glm::dvec2(p.x, p.z) / flat * r : glm::dvec2(0.0);
        if (r > 1 && !beyond) return std::nullopt;
        st = {(d.x + 1) / 2, (d.y + 1) / 2};  // up the image is ahead (-z)
        break;
    }
    case plane:
        st = {(p.x - x_from) / (x_to - x_from), (y_to - p.y) / (y_to - y_from)};
        break;
    }
    if (!beyond && (st.x < 0 || st.x > 1 || st.y < 0 || st.y > 1)) return std::nullopt;
    return st;
}

std::optional<glm::dvec3> Surface::roll(const glm::dvec2& st) const {
    switch (kind) {
    case cylinder: {
        const double azimuth = (azimuth_from + st.x * (azimuth_to - azimuth_from)) * kDeg;
        return glm::dvec3(radius * std::sin(azimuth), height_to - st.y * (height_to - height_from), -radius * std::cos(azimuth));
    }
    case dome: {
        const glm::dvec2 d(st.x * 2 - 1, st.y * 2 - 1);
        const double r = glm::length(d);
        if (r > 1) return std::nullopt;
        const double from_zenith = r * 90 * kDeg;
        const glm::dvec2 flat = r > 0 ? d / r : glm::dvec2(0.0);
        return glm::dvec3(radius * std::sin(from_zenith) * flat.x, radius * std::cos(from_zenith),
                          radius * std::sin(from_zenith) * flat.y);
    }
    case plane:
        return glm::dvec3(x_from + st.x * (x_to - x_from), y_to - st.y * (y_to - y_from), -distance);
    }
    return std::nullopt;
}

std::optional<glm::dvec3> Surface::hit(const glm::dvec3& o, const glm::dvec3& d) const {
    double t = -1;
    if (kind == plane) {
        if (std::fabs(d.z) < 1e-12) return std::nullopt;
        t = (-distance - o.z) / d.z;
    } else {
        // |o + t d| = r, in xz for the cylinder, in 3D for the dome: the far root (from inside).
        const glm::dvec3 m = kind == cylinder ? glm::dvec3(1, 0, 1) : glm::dvec3(1.0);
        const glm::dvec3 om = o * m, dm = d * m;
        const double a = glm::dot(dm, dm), b = 2 * glm::dot(om, dm), c = glm::dot(om, om) - radius * radius;
        const double disc = b * b - 4 * a * c;
        if (a < 1e-12 || disc < 0) return std::nullopt;
        t = (-b + std::sqrt(disc)) / (2 * a);
    }
    if (!(t > 0)) return std::nullopt;
    const glm::dvec3 p = o + t * d;
    if (kind == dome && p.y < 0) return std::nullopt;
    return p;
}

glm::dvec3 Projector::ray(double x, double y) const {
    const double tl = std::tan(left * kDeg), tr = std::tan(right * kDeg), td = std::tan(down * kDeg),
                 tu = std::tan(up * kDeg);
    const glm::dvec3 local(tl + x * (tr - tl), tu - y * (tu - td), -1);
    return glm::normalize(rotation(yaw, pitch, roll) * local);
}

std::optional<glm::dvec2> Projector::project(const glm::dvec3& p) const {
    const glm::dvec3 local = glm::transpose(rotation(yaw, pitch, roll)) * (p - position);
    if (local.z >= -1e-9) return std::nullopt;
    const double x = local.x / -local.z, y = local.y / -local.z;
    const double tl = std::tan(left * kDeg), tr = std::tan(right * kDeg), td = std::tan(down * kDeg),
                 tu = std::tan(up * kDeg);
    const glm::dvec2 out((x - tl) / (tr - tl), (tu - y) / (tu - td));
    if (out.x < 0 || out.x > 1 || out.y < 0 || out.y > 1) return std::nullopt;
    return out;
}

CanvasRect footprint(const Surface& s, const Projector& p, int canvas_width, int canvas_height) {
    double lo_x = 1e30, lo_y = 1e30, hi_x = -1e30, hi_y = -1e30;
    const int steps = 256;
    for (int j = 0; j <= steps; j++)
        for (int i = 0; i <= steps; i++) {
            const auto hit = s.hit(p.position, p.ray(double(i) / steps, double(j) / steps));
            const auto st = hit ? s.unroll(*hit) : std::nullopt;
            if (!st) continue;
            lo_x = std::min(lo_x, st->x * canvas_width), hi_x = std::max(hi_x, st->x * canvas_width);
            lo_y = std::min(lo_y, st->y * canvas_height), hi_y = std::max(hi_y, st->y * canvas_height);
        }
    if (hi_x < lo_x) return {};
    CanvasRect r;
    r.x = std::max(0, int(std::floor(lo_x)) - 1), r.y = std::max(0, int(std::floor(lo_y)) - 1);
    r.width = std::min(canvas_width, int(std::ceil(hi_x)) + 1) - r.x;
    r.height = std::min(canvas_height, int(std::ceil(hi_y)) + 1) - r.y;
    return r;
}

WarpMap projector_warp(const Surface& s, const Projector& p, const CanvasRect& tile, int canvas_width, int canvas_height,
                       int nodes_x, int nodes_y) {
    WarpMap w;
    w.width = nodes_x, w.height = nodes_y;
    w.uv.assign(size_t(nodes_x) * nodes_y * 2, std::numeric_limits<float>::quiet_NaN());
    for (int j = 0; j < nodes_y; j++)
        for (int i = 0; i < nodes_x; i++) {
            const auto hit = s.hit(p.position, p.ray(double(i) / (nodes_x - 1), double(j) / (nodes_y - 1)));
            const auto st = hit ? s.unroll(*hit, /*beyond=*/true) : std::nullopt;
            if (!st) continue;
            float* uv = &w.uv[(size_t(j) * nodes_x + i) * 2];
            uv[0] = float((st->x * canvas_width - tile.x) / tile.width);
            uv[1] = float((st->y * canvas_height - tile.y) / tile.height);
        }
    return w;
}

std::optional<EyeFrustum> eye_frustum(const Surface& s, const Projector& p) {
    constexpr int kSamples = 65;  // along each side of the output: the frustum's edges within a fraction of a degree
    std::vector<glm::dvec3> directions;
    glm::dvec3 sum(0.0);
    for (int j = 0; j < kSamples; j++)
        for (int i = 0; i < kSamples; i++)
            if (const auto hit = s.hit(p.position, p.ray(double(i) / (kSamples - 1), double(j) / (kSamples - 1)))) {
                directions.push_back(glm::normalize(*hit));
                sum += directions.back();
            }
    if (directions.empty() || glm::length(sum) == 0) return std::nullopt;
    // Its axis: towards the middle of what it lights, from the eye.
    const auto centre = s.hit(p.position, p.ray(0.5, 0.5));
    const glm::dvec3 axis = glm::normalize(centre ? *centre : sum);
    EyeFrustum f;
    f.yaw = std::atan2(axis.x, -axis.z) / kDeg;
    f.pitch = std::asin(std::clamp(axis.y, -1.0, 1.0)) / kDeg;
    const glm::dmat3 to_view = glm::transpose(rotation(f.yaw, f.pitch, 0));
    f.left = f.down = 90, f.right = f.up = -90;
    for (const glm::dvec3& d : directions) {
        const glm::dvec3 v = to_view * d;
        if (!(v.z < 0)) return std::nullopt;
        const double across = std::atan(v.x / -v.z) / kDeg, upward = std::atan(v.y / -v.z) / kDeg;
        f.left = std::min(f.left, across), f.right = std::max(f.right, across);
        f.down = std::min(f.down, upward), f.up = std::max(f.up, upward);
    }
    // A little beyond the outermost samples (the light between them), and never 80 degrees or more.
    f.left -= 0.25, f.right += 0.25, f.down -= 0.25, f.up += 0.25;
    if (f.left <= -80 || f.right >= 80 || f.down <= -80 || f.up >= 80) return std::nullopt;
    return f;
}

std::vector<float> projector_points(const Surface& s, const Projector& p, int nodes_x, int nodes_y) {
    std::vector<float> points(size_t(nodes_x) * nodes_y * 3, std::numeric_limits<float>::quiet_NaN());
    for (int j = 0; j < nodes_y; j++)
        for (int i = 0; i < nodes_x; i++)
            if (const auto hit = s.hit(p.position, p.ray(double(i) / (nodes_x - 1), double(j) / (nodes_y - 1)))) {
                float* out = &points[(size_t(j) * nodes_x + i) * 3];
                out[0] = float(hit->x), out[1] = float(hit->y), out[2] = float(hit->z);
            }
    return points;
}

BlendMap projector_blend(const Surface& s, const std::vector<Projector>& all, size_t index, int width, int height) {
    BlendMap b;
    b.width = width, b.height = height;
    b.rgb.assign(size_t(width) * height * 3, 0.0f);
    const Projector& p = all[index];
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            const double ox = (x + 0.5) / width, oy = (y + 0.5) / height;
            // (off the section too: its light is black there, and no step at the section's edge)
            const auto hit = s.hit(p.position, p.ray(ox, oy));
            if (!hit) continue;
            const double own = share(ox, oy);
            double total = 0;
            for (const Projector& q : all)
                if (auto o = q.project(*hit)) total += std::pow(share(o->x, o->y), 2);
            const float a = total > 0 ? float(own * own / total) : 0.0f;
            for (int c = 0; c < 3; c++) b.rgb[(size_t(y) * width + x) * 3 + c] = a;
        }
    return b;
}

}  // namespace glcast::slave
