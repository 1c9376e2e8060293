// Display configurations (display_config.h): JSON text -> DisplayConfig, with every rule of
// docs/display-configs.md checked and reported as "<origin>: <json path>: <what is wrong>".
//
// Parsing goes through nlohmann-json's SAX interface into our own small DOM builder rather than
// json::parse, for three reasons: a key given twice in one object is an error here (json::parse
// silently keeps the last one, which hides typos just as unknown keys would); nesting is capped
// (kMaxJsonDepth) so hostile input cannot grow without bound; and nothing throws out of the
// parser. Values echoed in messages are quoted, escaped and shortened, so random bytes in a file
// never reach a terminal raw.
#include "display_configs/display_config.h"

#include "display_configs/config_check.h"
#include "display_configs/immersive_config.h"
#include "slave/effects/effect_params.h"


#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <map>
#include <utility>

namespace glcast::slave {

namespace {

using namespace config_check;

// "line L, column C" of byte offset `pos`, counted as nlohmann-json counts them (1-based line;
// column = bytes read on the line so far, the offending one included), except that the end of
// input on an empty line is column 1 rather than 0.
std::string line_column(const std::string& text, size_t pos) {
    pos = std::min(pos, text.size());
    size_t line = 1, line_start = 0;
    for (size_t i = 0; i < pos; ++i) {
        if (text[i] == '\n') {
            ++line;
            line_start = i + 1;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(std::max<size_t>(pos - line_start, 1));
}

// nlohmann-json's exception text without its "[json.exception.parse_error.101] parse error at
// line 1, column 2: " prefix (we print the position ourselves), with a long "last read" token
// shortened and any byte that is not printable ASCII escaped.
std::string parse_error_text(const std::string& what) {
    std::string text = what;
    if (!text.empty() && text[0] == '[') {
        size_t close = text.find("] ");
        if (close != std::string::npos) text.erase(0, close + 2);
    }
    if (text.compare(0, 11, "parse error") == 0) {
        size_t column = text.find("column ");
        size_t colon = column == std::string::npos ? text.find(": ") : text.find(": ", column);
        if (colon != std::string::npos) text.erase(0, colon + 2);
    }
    const std::string marker = "last read: '";
    size_t token = text.find(marker);
    if (token != std::string::npos) {
        size_t begin = token + marker.size();
        size_t end = text.find("'; expected", begin);
        if (end == std::string::npos) end = text.rfind('\'');
        if (end != std::string::npos && end > begin && end - begin > 40)
            text.replace(begin + 30, end - begin - 30, "...");
    }
    std::string clean;
    for (unsigned char c : text) {
        if (c >= 0x20 && c < 0x7f) {
            clean += static_cast<char>(c);
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", c);
            clean += buf;
        }
    }
    if (clean.size() > 300) clean = clean.substr(0, 300) + "...";
    return clean;
}

// ---- JSON text -> json, via SAX ------------------------------------------------------------

class Builder final : public nlohmann::json_sax<json> {
public:
    explicit Builder(const std::string& text) : text_(text) {}

    json root;
    std::string error;  // set when parsing stopped: "<where>: <what>" without the origin

    bool null() override { return put(json(nullptr)); }
    bool boolean(bool v) override { return put(json(v)); }
    bool number_integer(number_integer_t v) override { return put(json(v)); }
    bool number_unsigned(number_unsigned_t v) override { return put(json(v)); }
    bool number_float(number_float_t v, const string_t&) override { return put(json(v)); }
    bool string(string_t& v) override { return put(json(std::move(v))); }
    bool binary(binary_t&) override {  // not produced by the JSON text parser
        error = "binary values are not JSON";
        return false;
    }
    bool start_object(std::size_t) override { return open(json::object()); }
    bool start_array(std::size_t) override { return open(json::array()); }
    bool end_object() override { return close(); }
    bool end_array() override { return close(); }

    bool key(string_t& k) override {
        Open& top = stack_.back();
        if (top.value->contains(k)) {
            error = join_key(top.path, k) + ": given twice in the same object (each key may appear once)";
            return false;
        }
        pending_key_ = k;
        return true;
    }

    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& ex) override {
        error = line_column(text_, position) + ": " + parse_error_text(ex.what());
        return false;
    }

private:
    struct Open {
        json* value;
        std::string path;
    };

    // Adds `v` where the parser is (root, next array element or value of the pending key) and
    // returns where it went, with its JSON path if `path` is given.
    json* place(json&& v, std::string* path = nullptr) {
        if (stack_.empty()) {
            root = std::move(v);
            return &root;
        }
        Open& top = stack_.back();
        if (top.value->is_array()) {
            if (path) *path = join_index(top.path, top.value->size());
            top.value->push_back(std::move(v));
            return &top.value->back();
        }
        if (path) *path = join_key(top.path, pending_key_);
        json& slot = (*top.value)[pending_key_];
        slot = std::move(v);
        return &slot;
    }

    bool put(json&& v) {
        place(std::move(v));
        return true;
    }

    bool open(json&& container) {
        if (stack_.size() >= static_cast<size_t>(kMaxJsonDepth)) {
            std::string path = stack_.back().path;
            error = (path.empty() ? std::string() : path + ": ") + "nested deeper than " +
                    std::to_string(kMaxJsonDepth) + " levels";
            return false;
        }
        std::string path;
        json* where = place(std::move(container), &path);
        // Pointers stay valid: a container is only ever the last element of its parent array
        // (which grows no further while it is open) or a std::map node.
        stack_.push_back({where, std::move(path)});
        return true;
    }

    bool close() {
        stack_.pop_back();
        return true;
    }

    const std::string& text_;
    std::vector<Open> stack_;
    std::string pending_key_;
};

// ---- validation -------------------------------------------------------------------------

const char* const kRootKeys[] = {"name", "description", "canvas", "tiles", "swap_barrier", "effects",
                                 "effect_params", "program_projection", "master", "keys", "viewer"};
const char* const kMasterKeys[] = {"address", "port"};
const char* const kProjectionKeys[] = {"fov_y", "near", "far"};
const char* const kCanvasKeys[] = {"width", "height"};
const char* const kTileKeys[] = {"name", "x", "y", "width", "height", "view", "screen", "eye", "stereo", "machine",
                                 "warp", "blend", "mpcdi", "region"};
const char* const kViewKeys[] = {"yaw", "pitch", "roll", "left", "right", "bottom", "top"};


bool parse_view(Validator& check, const json& v, const std::string& path, TileView& view) {
    if (!v.is_object()) return check.fail(path, "must be an object, got " + describe(v));
    if (!check.check_keys(v, path, kViewKeys)) return false;
    view.enabled = true;
    if (!check.number_field(v, path, "yaw", view.yaw_deg) || !check.number_field(v, path, "pitch", view.pitch_deg) ||
        !check.number_field(v, path, "roll", view.roll_deg))
        return false;
    struct Edge {
        const char* key;
        double* value;
    } edges[] = {{"left", &view.left_deg}, {"right", &view.right_deg}, {"bottom", &view.bottom_deg}, {"top", &view.top_deg}};
    for (const Edge& edge : edges) {
        if (!check.number_field(v, path, edge.key, *edge.value)) return false;
        if (!(*edge.value > -kMaxFrustumAngleDeg && *edge.value < kMaxFrustumAngleDeg))
            return check.fail(join_key(path, edge.key), "must be strictly between -89 and 89 degrees, got " + format_double(*edge.value));
    }
    if (!(view.left_deg < view.right_deg))
        return check.fail(path, "left must be less than right, got left " + format_double(view.left_deg) + " and right " +
                                    format_double(view.right_deg));
    if (!(view.bottom_deg < view.top_deg))
        return check.fail(path, "bottom must be less than top, got bottom " + format_double(view.bottom_deg) + " and top " +
                                    format_double(view.top_deg));
    return true;
}

// "warp" and "blend" (files), or "mpcdi" (a file) with "region" (an id in it).
bool parse_projector_maps(Validator& check, const json& v, const std::string& path, Tile& tile) {
    struct Field {
        const char* key;
        std::string* value;
    } fields[] = {{"warp", &tile.warp}, {"blend", &tile.blend}, {"mpcdi", &tile.mpcdi}, {"region", &tile.region}};
    for (const Field& f : fields) {
        auto it = v.find(f.key);
        if (it == v.end()) continue;
        if (!it->is_string() || it->get<std::string>().empty() || it->get<std::string>().size() > 4096)
            return check.fail(join_key(path, f.key), "must be a file name (a non-empty string), got " + describe(*it));
        *f.value = it->get<std::string>();
    }
    if (!tile.mpcdi.empty() && (!tile.warp.empty() || !tile.blend.empty()))
        return check.fail(path, "has \"mpcdi\" and \"warp\" or \"blend\": the MPCDI file holds both, give one");
    if (tile.mpcdi.empty() != tile.region.empty())
        return check.fail(path, "\"mpcdi\" and \"region\" come together (the region of the file this tile shows)");
    return true;
}

// x and y of view tiles may be omitted: then the tile sits right of the previous one, at y 0.
bool parse_tile(Validator& check, const json& v, const std::string& path, int next_x, Tile& tile) {
    if (!v.is_object()) return check.fail(path, "must be an object, got " + describe(v));
    if (!check.check_keys(v, path, kTileKeys)) return false;
    if (!check.name_field(v, path, tile.name)) return false;
    if (auto machine = v.find("machine"); machine != v.end()) {
        if (!machine->is_string() || !is_valid_display_name(machine->get<std::string>()))
            return check.fail(join_key(path, "machine"),
                              "must be a machine name of letters, digits, '_', '.' and '-', got " + describe(*machine));
        tile.machine = machine->get<std::string>();
    }
    auto view = v.find("view"), screen = v.find("screen");
    if (view != v.end() && screen != v.end())
        return check.fail(path, "has both \"view\" (angles) and \"screen\" (corners in metres): give one");
    if (view != v.end() && !parse_view(check, *view, join_key(path, "view"), tile.view)) return false;
    if (screen != v.end() && !parse_screen(check, *screen, join_key(path, "screen"), tile.view)) return false;
    if (!parse_tile_eyes(check, v, path, tile)) return false;
    if (!parse_projector_maps(check, v, path, tile)) return false;
    bool planar = !tile.view.enabled, has_x = false, has_y = false;
    if (!check.int_field(v, path, "x", planar, 0, tile.x, &has_x) || !check.int_field(v, path, "y", planar, 0, tile.y, &has_y) ||
        !check.int_field(v, path, "width", true, 1, tile.width) || !check.int_field(v, path, "height", true, 1, tile.height))
        return false;
    if (!has_x) {
        if (next_x > kMaxDisplaySize)
            return check.fail(join_key(path, "x"), "missing, and right of the previous tile it would be " + std::to_string(next_x) +
                                                       ", more than " + std::to_string(kMaxDisplaySize));
        tile.x = next_x;
    }
    if (!has_y) tile.y = 0;
    return true;
}

bool parse_config(Validator& check, const json& root, DisplayConfig& config) {
    if (!root.is_object()) return check.fail("", "the top level must be a JSON object, got " + describe(root));
    if (!check.check_keys(root, "", kRootKeys)) return false;
    if (!check.name_field(root, "", config.name)) return false;

    if (auto it = root.find("description"); it != root.end()) {
        if (!it->is_string()) return check.fail("description", "must be a string, got " + describe(*it));
        config.description = it->get<std::string>();
    }

    auto canvas = root.find("canvas");
    if (canvas != root.end()) {
        if (!canvas->is_object()) return check.fail("canvas", "must be an object, got " + describe(*canvas));
        if (!check.check_keys(*canvas, "canvas", kCanvasKeys) ||
            !check.int_field(*canvas, "canvas", "width", true, 1, config.canvas_width) ||
            !check.int_field(*canvas, "canvas", "height", true, 1, config.canvas_height))
            return false;
    }

    auto tiles = root.find("tiles");
    if (tiles == root.end()) return check.fail("tiles", "missing required key");
    if (!tiles->is_array()) return check.fail("tiles", "must be an array of tiles, got " + describe(*tiles));
    if (tiles->empty()) return check.fail("tiles", "must list at least one tile");
    int64_t next_x = 0, widths = 0, max_height = 0;  // next_x <= 2 * kMaxDisplaySize
    std::map<std::string, size_t> names;
    for (size_t i = 0; i < tiles->size(); ++i) {
        std::string path = join_index("tiles", i);
        Tile tile;
        if (!parse_tile(check, (*tiles)[i], path, static_cast<int>(next_x), tile)) return false;
        auto [previous, added] = names.emplace(tile.name, i);
        if (!added)
            return check.fail(join_key(path, "name"),
                              quote(tile.name) + " is used twice (also " + join_index("tiles", previous->second) + ".name)");
        next_x = int64_t{tile.x} + tile.width;
        widths += tile.width;
        max_height = std::max<int64_t>(max_height, tile.height);
        config.tiles.push_back(std::move(tile));
    }

    if (canvas == root.end()) {
        for (size_t i = 0; i < config.tiles.size(); ++i)
            if (!config.tiles[i].view.enabled)
                return check.fail("canvas", "missing; it is required because " + join_index("tiles", i) +
                                                " has no \"view\" or \"screen\" (a planar tile is a rectangle of the canvas)");
        if (widths > kMaxDisplaySize)
            return check.fail("canvas", "missing, and the tiles side by side would make it " + std::to_string(widths) + "x" +
                                            std::to_string(max_height) + ", wider than " + std::to_string(kMaxDisplaySize) +
                                            "; give \"canvas\" explicitly");
        config.canvas_width = static_cast<int>(widths);
        config.canvas_height = static_cast<int>(max_height);
    }

    for (size_t i = 0; i < config.tiles.size(); ++i) {
        const Tile& t = config.tiles[i];
        if (t.view.enabled) continue;  // a view tile's rectangle only places it for canvas-indexed effects
        std::string size = std::to_string(config.canvas_width) + "x" + std::to_string(config.canvas_height);
        if (int64_t{t.x} + t.width > config.canvas_width)
            return check.fail(join_index("tiles", i), "does not fit on the " + size + " canvas: x + width = " + std::to_string(t.x) +
                                                          " + " + std::to_string(t.width) + " = " +
                                                          std::to_string(int64_t{t.x} + t.width) + " > " +
                                                          std::to_string(config.canvas_width));
        if (int64_t{t.y} + t.height > config.canvas_height)
            return check.fail(join_index("tiles", i), "does not fit on the " + size + " canvas: y + height = " + std::to_string(t.y) +
                                                          " + " + std::to_string(t.height) + " = " +
                                                          std::to_string(int64_t{t.y} + t.height) + " > " +
                                                          std::to_string(config.canvas_height));
    }

    if (auto it = root.find("program_projection"); it != root.end()) {
        ProgramProjection& p = config.program_projection;
        if (!it->is_object()) return check.fail("program_projection", "must be an object, got " + describe(*it));
        if (!check.check_keys(*it, "program_projection", kProjectionKeys) ||
            !check.number_field(*it, "program_projection", "fov_y", p.fov_y_deg) ||
            !check.number_field(*it, "program_projection", "near", p.near) ||
            !check.number_field(*it, "program_projection", "far", p.far))
            return false;
        if (!(p.fov_y_deg > 0 && p.fov_y_deg < 179)) return check.fail("program_projection.fov_y", "must be in (0, 179) degrees");
        if (!(p.near > 0 && p.far > p.near)) return check.fail("program_projection", "needs 0 < near < far");
        p.given = true;
    }

    if (!parse_viewer(check, root, config)) return false;

    if (auto it = root.find("master"); it != root.end()) {
        WallMaster& m = config.master;
        if (!it->is_object()) return check.fail("master", "must be an object, got " + describe(*it));
        if (!check.check_keys(*it, "master", kMasterKeys)) return false;
        auto address = it->find("address");
        if (address == it->end()) return check.fail("master.address", "missing required key");
        const bool host_like = address->is_string() && !address->get_ref<const std::string&>().empty() &&
                               address->get_ref<const std::string&>().size() <= 253 &&
                               std::all_of(address->get_ref<const std::string&>().begin(),
                                           address->get_ref<const std::string&>().end(),
                                           [](char c) { return std::isalnum(uint8_t(c)) || c == '.' || c == '-' || c == ':'; });
        if (!host_like)
            return check.fail("master.address", "must be a host name or IP address, got " + describe(*address));
        m.address = address->get<std::string>();
        if (auto port = it->find("port"); port != it->end()) {
            if (!port->is_number_integer() || port->get<int64_t>() < 1 || port->get<int64_t>() > 65532)
                return check.fail("master.port", "must be an integer from 1 to 65532 (it and the next three ports are "
                                                 "used), got " + describe(*port));
            m.port = int(port->get<int64_t>());
        }
        m.given = true;
    }

    if (auto it = root.find("keys"); it != root.end()) {
        if (!it->is_string() || it->get_ref<const std::string&>().empty() || it->get_ref<const std::string&>().size() > 4096)
            return check.fail("keys", "must be the path of a folder of keys, got " + describe(*it));
        config.keys = it->get<std::string>();
    }

    if (auto it = root.find("swap_barrier"); it != root.end()) {
        if (!it->is_boolean()) return check.fail("swap_barrier", "must be true or false, got " + describe(*it));
        config.swap_barrier = it->get<bool>();
    }

    if (auto it = root.find("effects"); it != root.end()) {
        if (!it->is_array()) return check.fail("effects", "must be an array of effect names, got " + describe(*it));
        const auto& known = known_display_effects();
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        for (size_t i = 0; i < it->size(); ++i) {
            const json& e = (*it)[i];
            std::string path = join_index("effects", i);
            if (!e.is_string()) return check.fail(path, "must be a string (an effect name), got " + describe(e));
            const std::string& name = e.get_ref<const std::string&>();
            if (std::find(known.begin(), known.end(), name) == known.end())
                return check.fail(path, "unknown effect " + quote(name) + " (known effects: " + list + ")");
            if (std::find(config.effects.begin(), config.effects.end(), name) != config.effects.end())
                return check.fail(path, quote(name) + " is listed twice");
            config.effects.push_back(name);
        }
    }

    if (auto it = root.find("effect_params"); it != root.end()) {
        if (!it->is_object())
            return check.fail("effect_params", "must be an object of parameter names and values, got " + describe(*it));
        effects::EffectParams checked;
        for (auto p = it->begin(); p != it->end(); ++p) {
            const std::string path = "effect_params." + p.key();
            std::string value;
            if (p->is_number()) value = p->dump();
            else if (p->is_string()) value = p->get<std::string>();
            else if (p->is_boolean()) value = p->get<bool>() ? "1" : "0";
            else return check.fail(path, "must be a number, a string or true/false, got " + describe(*p));
            std::string why;
            if (!checked.set(p.key(), value, why)) return check.fail(path, why);
            config.effect_params.emplace_back(p.key(), value);
        }
    }
    return true;
}

}  // namespace

const Tile* DisplayConfig::find(const std::string& tile_name) const {
    for (const Tile& t : tiles)
        if (t.name == tile_name) return &t;
    return nullptr;
}

// A tile's or machine's name names folders (glcast run --out DIR/TILE) and travels as a
// command-line word: "." and ".." would leave the folder, "-x" would read as an option.
bool is_valid_display_name(const std::string& name) {
    if (name.empty() || name[0] == '.' || name[0] == '-') return false;
    for (unsigned char c : name) {
        bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '-';
        if (!ok) return false;
    }
    return true;
}

bool parse_display_config(const std::string& json_text, const std::string& origin, DisplayConfig& out, std::string& error) {
    if (json_text.size() > kMaxDisplayConfigBytes) {
        error = origin + ": " + std::to_string(json_text.size()) + " bytes, more than the " +
                std::to_string(kMaxDisplayConfigBytes) + "-byte (1 MiB) limit for a display config";
        return false;
    }
    try {
        Builder builder(json_text);
        if (!json::sax_parse(json_text, &builder)) {
            error = origin + ": " + (builder.error.empty() ? std::string("invalid JSON") : builder.error);
            return false;
        }
        DisplayConfig config;
        Validator check(origin, error);
        if (!parse_config(check, builder.root, config)) return false;
        out = std::move(config);
        return true;
    } catch (const std::exception& e) {  // not expected; a bug here must still not crash the slave
        error = origin + ": internal error while reading the display config: " + parse_error_text(e.what());
        return false;
    }
}

bool load_display_config(const std::string& path, DisplayConfig& out, std::string& error) {
    std::string text, kind;
    int error_number = 0;
    switch (read_regular_file(path, kMaxDisplayConfigBytes, text, error_number, kind)) {
    case FileProblem::none: return parse_display_config(text, path, out, error);
    case FileProblem::cannot_open: error = path + ": cannot open: " + std::strerror(error_number); break;
    case FileProblem::not_regular: error = path + ": is " + kind + ", not a regular file"; break;
    case FileProblem::too_large:
        error = path + ": larger than the " + std::to_string(kMaxDisplayConfigBytes) + "-byte (1 MiB) limit for a display config";
        break;
    case FileProblem::cannot_read: error = path + ": cannot read: " + std::strerror(error_number); break;
    }
    return false;
}

}  // namespace glcast::slave
