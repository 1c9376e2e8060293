// Screens in metres, eyes and the viewer of a display config (immersive_config.h).
#include "display_configs/immersive_config.h"

#include <cmath>

namespace glcast::slave::config_check {

namespace {

using Vec = std::array<double, 3>;

const char* const kScreenKeys[] = {"bottom_left", "bottom_right", "top_left"};
const char* const kViewerKeys[] = {"position", "eye_separation", "units_per_metre", "tracker"};

Vec minus(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
std::string text(const Vec& v) {
    return "[" + format_double(v[0]) + ", " + format_double(v[1]) + ", " + format_double(v[2]) + "]";
}

// [x, y, z] in metres within the room's bounds.
bool point_field(Validator& check, const json& object, const std::string& path, const char* key, Vec& out) {
    const std::string field = join_key(path, key);
    const auto it = object.find(key);
    if (it == object.end()) return check.fail(field, "missing required key");
    if (!it->is_array() || it->size() != 3)
        return check.fail(field, "must be [x, y, z] in metres, got " + describe(*it));
    for (size_t i = 0; i < 3; ++i) {
        const json& c = (*it)[i];
        if (!c.is_number() || !std::isfinite(c.get<double>()) || std::fabs(c.get<double>()) > kMaxRoomMetres)
            return check.fail(join_index(field, i), "must be a number of metres within +-" + format_double(kMaxRoomMetres) +
                                                        ", got " + describe(c));
        out[i] = c.get<double>();
    }
    return true;
}

}  // namespace

bool parse_screen(Validator& check, const json& v, const std::string& path, TileView& view) {
    if (!v.is_object()) return check.fail(path, "must be an object of three corners, got " + describe(v));
    if (!check.check_keys(v, path, kScreenKeys)) return false;
    if (!point_field(check, v, path, "bottom_left", view.bottom_left) ||
        !point_field(check, v, path, "bottom_right", view.bottom_right) || !point_field(check, v, path, "top_left", view.top_left))
        return false;
    const Vec across = minus(view.bottom_right, view.bottom_left), up = minus(view.top_left, view.bottom_left);
    const double width = std::sqrt(dot(across, across)), height = std::sqrt(dot(up, up));
    if (width < 1e-3 || height < 1e-3)
        return check.fail(path, "the screen is " + format_double(width) + " m wide and " + format_double(height) +
                                    " m high: both must be at least a millimetre");
    const double cosine = dot(across, up) / (width * height);
    if (std::fabs(cosine) > 1e-3)
        return check.fail(path, "the corners must make a rectangle: bottom_left->bottom_right and bottom_left->top_left "
                                "meet at " + format_double(std::round(std::acos(cosine) * 180 / M_PI * 100) / 100) +
                                    " degrees, not 90");
    view.enabled = view.screen = true;
    return true;
}

bool parse_tile_eyes(Validator& check, const json& tile_json, const std::string& path, Tile& tile) {
    const auto eye = tile_json.find("eye");
    const auto stereo = tile_json.find("stereo");
    if (eye != tile_json.end() && stereo != tile_json.end())
        return check.fail(path, "has both \"eye\" (one eye per output) and \"stereo\" (both eyes in one output): give one");
    if ((eye != tile_json.end() || stereo != tile_json.end()) && !tile.view.enabled)
        return check.fail(join_key(path, eye != tile_json.end() ? "eye" : "stereo"),
                          "needs a \"view\" or a \"screen\": a planar tile has no camera to move to an eye");
    if (eye != tile_json.end()) {
        const std::string name = eye->is_string() ? eye->get<std::string>() : "";
        if (name == "left") tile.eye = TileEye::left;
        else if (name == "right") tile.eye = TileEye::right;
        else return check.fail(join_key(path, "eye"), "must be \"left\" or \"right\", got " + describe(*eye));
    }
    if (stereo != tile_json.end()) {
        const std::string name = stereo->is_string() ? stereo->get<std::string>() : "";
        if (name == "quad-buffer") tile.stereo = Stereo::quad_buffer;
        else if (name == "side-by-side") tile.stereo = Stereo::side_by_side;
        else if (name == "top-bottom") tile.stereo = Stereo::top_bottom;
        else if (name == "anaglyph") tile.stereo = Stereo::anaglyph;
        else
            return check.fail(join_key(path, "stereo"),
                              "must be \"quad-buffer\", \"side-by-side\", \"top-bottom\" or \"anaglyph\", got " + describe(*stereo));
    }
    return true;
}

bool parse_viewer(Validator& check, const json& root, DisplayConfig& config) {
    ViewerConfig& viewer = config.viewer;
    if (const auto it = root.find("viewer"); it != root.end()) {
        if (!it->is_object()) return check.fail("viewer", "must be an object, got " + describe(*it));
        if (!check.check_keys(*it, "viewer", kViewerKeys)) return false;
        if (it->contains("position") && !point_field(check, *it, "viewer", "position", viewer.position)) return false;
        if (const auto sep = it->find("eye_separation"); sep != it->end()) {
            if (!sep->is_number() || !(sep->get<double>() >= 0 && sep->get<double>() <= 1))
                return check.fail("viewer.eye_separation", "must be a number of metres from 0 to 1, got " + describe(*sep));
            viewer.eye_separation = sep->get<double>();
        }
        if (const auto tracker = it->find("tracker"); tracker != it->end()) {
            const bool endpoint_like = tracker->is_string() && tracker->get_ref<const std::string&>().size() <= 256 &&
                                       tracker->get_ref<const std::string&>().find("://") != std::string::npos;
            if (!endpoint_like)
                return check.fail("viewer.tracker", "must be a ZeroMQ endpoint to bind, e.g. \"tcp://*:5560\", got " + describe(*tracker));
            viewer.tracker = tracker->get<std::string>();
        }
        if (const auto units = it->find("units_per_metre"); units != it->end()) {
            if (!units->is_number() || !(units->get<double>() >= 1e-6 && units->get<double>() <= 1e6))
                return check.fail("viewer.units_per_metre", "must be a number from 1e-6 to 1e6, got " + describe(*units));
            viewer.units_per_metre = units->get<double>();
        }
    }
    for (size_t i = 0; i < config.tiles.size(); ++i) {
        const TileView& v = config.tiles[i].view;
        if (!v.screen) continue;
        const Vec normal = cross(minus(v.bottom_right, v.bottom_left), minus(v.top_left, v.bottom_left));
        const double distance = dot(normal, minus(viewer.position, v.bottom_left)) / std::sqrt(dot(normal, normal));
        if (distance < 1e-3)
            return check.fail(join_key(join_index("tiles", i), "screen"),
                              "the viewer's position " + text(viewer.position) + " is " +
                                  (distance < 0 ? "behind this screen" : "on this screen's plane") +
                                  " (its front is where bottom_left->bottom_right x bottom_left->top_left points): "
                                  "turn the corners or move the viewer");
    }
    return true;
}

}  // namespace glcast::slave::config_check
