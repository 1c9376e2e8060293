// Head poses (head_poses.h): the same checks for a tracker's message and a recorded line.
#include "display_configs/head_poses.h"

#include <algorithm>
#include <cmath>

#include "display_configs/config_check.h"

namespace glcast::slave {

using namespace config_check;

namespace {

const char* const kPoseKeys[] = {"frame", "time", "position", "orientation", "eye_separation"};

bool numbers(const json& v, size_t n, double bound, double* out) {
    if (!v.is_array() || v.size() != n) return false;
    for (size_t i = 0; i < n; ++i) {
        if (!v[i].is_number()) return false;
        out[i] = v[i].get<double>();
        if (!std::isfinite(out[i]) || std::fabs(out[i]) > bound) return false;
    }
    return true;
}

}  // namespace

bool parse_head_pose(const std::string& text, HeadPose& out, uint64_t* frame, double* time, std::string& error) {
    if (text.size() > kMaxPoseBytes) {
        error = std::to_string(text.size()) + " bytes, more than the " + std::to_string(kMaxPoseBytes) + " a pose may have";
        return false;
    }
    const json v = json::parse(text, nullptr, false);  // (no exceptions; a discarded value on bad JSON)
    if (v.is_discarded()) {
        error = "not JSON";
        return false;
    }
    const std::string origin = "pose";  // (the validator keeps a reference)
    Validator check(origin, error);
    if (!v.is_object()) return check.fail("", "must be a JSON object, got " + describe(v));
    if (!check.check_keys(v, "", kPoseKeys)) return false;
    double p[3], q[4];
    const auto position = v.find("position"), orientation = v.find("orientation");
    if (position == v.end() || !numbers(*position, 3, kMaxRoomMetres, p))
        return check.fail("position", "must be [x, y, z], metres within +-" + format_double(kMaxRoomMetres) + ", got " +
                                          (position == v.end() ? std::string("nothing") : describe(*position)));
    if (orientation == v.end() || !numbers(*orientation, 4, 2, q))
        return check.fail("orientation", "must be a quaternion [w, x, y, z], got " +
                                             (orientation == v.end() ? std::string("nothing") : describe(*orientation)));
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (std::fabs(norm - 1) > 0.01)
        return check.fail("orientation", "must be a unit quaternion, its length is " + format_double(norm));
    if (frame) {
        const auto f = v.find("frame");
        if (f == v.end() || !f->is_number_unsigned())
            return check.fail("frame", "must be a frame number (0 or more), got " +
                                           (f == v.end() ? std::string("nothing") : describe(*f)));
        *frame = f->get<uint64_t>();
    }
    if (const auto t = v.find("time"); t != v.end()) {
        if (!t->is_number() || !std::isfinite(t->get<double>())) return check.fail("time", "must be seconds, got " + describe(*t));
        if (time) *time = t->get<double>();
    }
    out.eye_separation = -1;
    if (const auto sep = v.find("eye_separation"); sep != v.end()) {
        if (!sep->is_number() || !(sep->get<double>() >= 0 && sep->get<double>() <= 1))
            return check.fail("eye_separation", "must be a number of metres from 0 to 1, got " + describe(*sep));
        out.eye_separation = sep->get<double>();
    }
    out.position = glm::dvec3(p[0], p[1], p[2]);
    out.orientation = glm::dquat(q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm);
    return true;
}

bool HeadPoseTrack::load(const std::string& path, std::string& error) {
    poses_.clear();
    std::string text, kind;
    int error_number = 0;
    switch (read_regular_file(path, kMaxPoseTrackBytes, text, error_number, kind)) {
    case FileProblem::none: break;
    case FileProblem::cannot_open: error = path + ": cannot open"; return false;
    case FileProblem::not_regular: error = path + ": is " + kind + ", not a regular file"; return false;
    case FileProblem::too_large:
        error = path + ": larger than the " + std::to_string(kMaxPoseTrackBytes >> 20) + " MiB a pose track may have";
        return false;
    case FileProblem::cannot_read: error = path + ": cannot read"; return false;
    }
    std::vector<Stamped> poses;
    size_t number = 0;
    for (size_t start = 0; start < text.size();) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(start, end - start);
        start = end + 1;
        ++number;
        const size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        Stamped s{};
        std::string why;
        if (!parse_head_pose(line, s.pose, &s.frame, nullptr, why)) {
            error = path + ": line " + std::to_string(number) + ": " + why;
            return false;
        }
        if (!poses.empty() && s.frame <= poses.back().frame) {
            error = path + ": line " + std::to_string(number) + ": frame " + std::to_string(s.frame) +
                    " does not come after the previous line's " + std::to_string(poses.back().frame);
            return false;
        }
        poses.push_back(s);
    }
    poses_ = std::move(poses);
    return true;
}

const HeadPose* HeadPoseTrack::at(uint64_t frame) const {
    auto after = std::upper_bound(poses_.begin(), poses_.end(), frame, [](uint64_t f, const Stamped& s) { return f < s.frame; });
    return after == poses_.begin() ? nullptr : &std::prev(after)->pose;
}

}  // namespace glcast::slave
