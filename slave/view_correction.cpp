#include "slave/view_correction.h"

#include <cmath>

namespace glcast::slave {

static double radians(double deg) { return deg * 3.14159265358979323846 / 180.0; }

// The tile camera from angles (a turn of the program's camera), or from a screen's corners and
// the eye (the generalized perspective projection: the screen's axes, the eye's distance to its
// plane, the corners' offsets along the axes over that distance).
ViewCorrection::Camera ViewCorrection::camera() const {
    Camera c;
    if (screen) {
        const glm::dvec3 across = glm::normalize(bottom_right - bottom_left), up = glm::normalize(top_left - bottom_left);
        const glm::dvec3 normal = glm::normalize(glm::cross(across, up));  // towards the viewer
        const glm::dvec3 a = bottom_left - eye, b = bottom_right - eye, t = top_left - eye;
        const double distance = -glm::dot(normal, a);
        c.left = glm::dot(across, a) / distance, c.right = glm::dot(across, b) / distance;
        c.bottom = glm::dot(up, a) / distance, c.top = glm::dot(up, t) / distance;
        glm::dmat4 axes(1.0);  // rows: the screen's axes
        for (int i = 0; i < 3; ++i) axes[i][0] = across[i], axes[i][1] = up[i], axes[i][2] = normal[i];
        glm::dmat4 offset(1.0);
        offset[3] = glm::dvec4(-eye * units_per_metre, 1.0);
        c.view = axes * offset;
        return c;
    }
    c.left = std::tan(radians(left_deg)), c.right = std::tan(radians(right_deg));
    c.bottom = std::tan(radians(bottom_deg)), c.top = std::tan(radians(top_deg));
    // The tile camera in the program's eye space (looking down -Z, +Y up): heading (yaw, positive
    // turns right), then pitch (positive looks up), then roll (positive lowers the right side).
    const glm::dvec3 up(0, 1, 0), right(1, 0, 0), back(0, 0, 1);
    auto rotate = [](double deg, const glm::dvec3& axis) {
        const double cs = std::cos(radians(deg)), s = std::sin(radians(deg));
        const glm::dvec3 u = glm::normalize(axis);
        glm::dmat4 m(1.0);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                m[j][i] = (i == j ? cs : 0) + (1 - cs) * u[i] * u[j] +
                          s * (i == 0 ? (j == 1 ? -u[2] : j == 2 ? u[1] : 0)
                                      : i == 1 ? (j == 0 ? u[2] : j == 2 ? -u[0] : 0)
                                               : (j == 0 ? -u[1] : j == 1 ? u[0] : 0));
        return m;
    };
    const glm::dmat4 orientation = rotate(-yaw_deg, up) * rotate(pitch_deg, right) * rotate(roll_deg, back);
    glm::dmat4 offset(1.0);  // an eye off the origin (stereo) looks the same way from there
    offset[3] = glm::dvec4(-eye * units_per_metre, 1.0);
    c.view = glm::transpose(orientation) * offset;
    return c;
}

bool ViewCorrection::image_position(const glm::dvec3& point, glm::dvec2& uv) const {
    const Camera c = camera();
    const glm::dvec4 v = c.view * glm::dvec4(point, 1.0);
    if (!(v.z < 0)) return false;
    const double x = v.x / -v.z, y = v.y / -v.z;
    uv = glm::dvec2((x - c.left) / (c.right - c.left), (c.top - y) / (c.top - c.bottom));
    return std::isfinite(uv.x) && std::isfinite(uv.y);
}

bool ViewCorrection::set_eye(const glm::dvec3& position) {
    if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z)) return false;
    if (screen) {
        const glm::dvec3 normal = glm::normalize(glm::cross(bottom_right - bottom_left, top_left - bottom_left));
        if (glm::dot(normal, position - bottom_left) < 1e-3) return false;
    }
    eye = position;
    return true;
}

glm::dmat4 ViewCorrection::correction(const glm::dmat4& app) const {
    const Camera cam = camera();
    const double tl = cam.left, tr = cam.right, tb = cam.bottom, tt = cam.top;
    glm::dmat4 tile(0.0);
    // A perspective projection (w = k * -z): the tile's frustum across, the program's own depth
    // mapping (its z and w rows) along the view, so that what it does with depth stays true on
    // every tile: reversed depth, clip control GL_ZERO_TO_ONE, an infinite far plane.
    // (up to rounding: a projection read back through an inverted correction has 1e-16s there)
    // w = s z: s < 0 in GL's right-handed eye space (looking down -Z), s > 0 in a left-handed
    // one (looking down +Z, as Direct3D-minded engines such as Irrlicht keep it).
    const double s = app[2][3], k = std::abs(s);
    const bool left_handed = s > 0;
    const double ahead = left_handed ? 1 : -1;  // the eye's forward z
    const double tiny = 1e-6 * k;
    if (k > 0 && std::abs(app[0][3]) <= tiny && std::abs(app[1][3]) <= tiny && std::abs(app[3][3]) <= tiny) {
        tile[0][0] = k * 2 / (tr - tl);
        tile[2][0] = -ahead * k * (tr + tl) / (tr - tl);
        tile[1][1] = k * 2 / (tt - tb);
        tile[2][1] = -ahead * k * (tt + tb) / (tt - tb);
        for (int c = 0; c < 4; ++c) tile[c][2] = app[c][2], tile[c][3] = app[c][3];
    } else {  // another kind: glFrustum(l, r, b, t, n, f) over a generic range
        const double n = 0.1, f = 1000.0;
        tile[0][0] = 2 / (tr - tl);
        tile[1][1] = 2 / (tt - tb);
        tile[2][0] = (tr + tl) / (tr - tl);
        tile[2][1] = (tt + tb) / (tt - tb);
        tile[2][2] = -(f + n) / (f - n);
        tile[2][3] = -1;
        tile[3][2] = -2 * f * n / (f - n);
    }
    // A program that draws its picture upside down (or mirrored) into a target it shows flipped
    // (glFrustum with bottom above top, Wine's way): the tile's frustum flipped the same way, so
    // that the blit that shows it turns it upright.
    if (app[1][1] < 0)
        for (int c = 0; c < 4; ++c) tile[c][1] = -tile[c][1];
    if (app[0][0] < 0)
        for (int c = 0; c < 4; ++c) tile[c][0] = -tile[c][0];
    glm::dmat4 view = cam.view;
    if (left_handed) {  // the same camera written in left-handed coordinates (z mirrored)
        glm::dmat4 mirror(1.0);
        mirror[2][2] = -1;
        view = mirror * view * mirror;
    }
    return tile * view * glm::inverse(app);
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
