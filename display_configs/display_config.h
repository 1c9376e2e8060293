// Display configurations: which tiles a wall has, where each sits on the canvas, and, for
// rotated or asymmetric walls, what each tile's camera sees (docs/display-configs.md). They are JSON
// files in display_configs/, documented field by field in docs/display-configs.md.
//
// Loading validates everything and never crashes: any input (random bytes, huge numbers, wrong
// types, deep nesting) gives false and one error that names the file, the JSON path of the bad
// field and what is wrong, e.g.
//   wall.json: tiles[2].width: must be a positive integer, got -5
//   wall.json: line 3, column 7: syntax error while parsing object key - ...
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "slave/effects/effect_params.h"

namespace glcast::slave {

// A tile's own view for rotated or asymmetric walls (cylinders, CAVEs): the tile shows what a
// camera rotated by yaw/pitch/roll relative to the program's camera sees through an
// asymmetric frustum given as angles from its own view axis.
struct TileView {
    bool enabled = false;                 // false: planar tile (a rectangle of the canvas)
    double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;   // yaw: positive turns right; pitch: positive looks up
    double left_deg = -30, right_deg = 30, bottom_deg = -20, top_deg = 30;  // frustum edges, angles from the axis
    // Or a physical screen ("screen", docs/immersive.md): three corners of its rectangle in the
    // room, in metres (x right, y up, z towards the viewer), seen from the viewer's eye.
    bool screen = false;
    std::array<double, 3> bottom_left{}, bottom_right{}, top_left{};
};

// Which of the viewer's eyes a tile shows: the head's centre (mono), one eye (passive stereo:
// one output per eye), or both in one output by `Stereo`.
enum class TileEye { centre, left, right };
enum class Stereo { none, quad_buffer, side_by_side, top_bottom, anaglyph };

struct Tile {
    std::string name;
    std::string machine;  // the display machine that shows it ("machine"); empty: the master's
    int x = 0, y = 0, width = 0, height = 0;  // rectangle on the canvas in pixels; origin top-left, y down
    TileView view;
    TileEye eye = TileEye::centre;
    Stereo stereo = Stereo::none;
    // A projector's warp and blend (docs/projectors.md), paths as the config gives them (relative
    // to its folder): the plain pair, or one region of an MPCDI file.
    std::string warp, blend, mpcdi, region;
};

// Where the viewer's eyes are when no tracker says otherwise ("viewer", docs/immersive.md).
struct ViewerConfig {
    std::array<double, 3> position{};  // metres, room coordinates
    double eye_separation = 0.064;     // metres
    double units_per_metre = 1;        // the program's eye-space units in a metre
    std::string tracker;               // where glcast run binds the pose socket (empty: no tracker)
};

// The projection of a program whose projection the stream does not show (shader programs), for
// rotated tiles: a symmetric perspective of this vertical field of view, at the aspect of the
// program's window.
struct ProgramProjection {
    bool given = false;
    double fov_y_deg = 60, near = 0.1, far = 1000;
};

// Where a wall's display machines reach the machine that runs programs: the stream on
// tcp://address:port, the journal on port + 1, the keeper on port + 2, the control channel (swap
// barrier, status) on port + 3 (docs/wall.md).
struct WallMaster {
    bool given = false;
    std::string address;
    int port = 5555;
};

struct DisplayConfig {
    std::string name, description;
    int canvas_width = 0, canvas_height = 0;  // planar walls: the whole image incl. hidden bezel pixels
    std::vector<Tile> tiles;
    bool swap_barrier = false;
    std::vector<std::string> effects;          // e.g. "snow", "shadows" (names only; validated against a list)
    std::vector<std::pair<std::string, std::string>> effect_params;  // name, value (checked: slave/effects/effect_params.h)
    ProgramProjection program_projection;
    ViewerConfig viewer;
    WallMaster master;
    std::string keys;  // a folder of CURVE keys (net/security.h); empty: GLCAST_KEYS or none
    const Tile* find(const std::string& name) const;   // nullptr if absent
};

// Parses and validates `json_text`; `origin` (usually the file name) starts every error message.
// On failure returns false, sets `error` and leaves `out` unchanged.
bool parse_display_config(const std::string& json_text, const std::string& origin, DisplayConfig& out, std::string& error);
// Reads `path` (at most kMaxDisplayConfigBytes) and parses it with `path` as the origin.
bool load_display_config(const std::string& path, DisplayConfig& out, std::string& error);

// Limits the loader enforces (documented in docs/display-configs.md).
constexpr size_t kMaxDisplayConfigBytes = 1 << 20;  // 1 MiB
constexpr int kMaxDisplaySize = 16384;               // pixels, any width, height or canvas side
constexpr double kMaxFrustumAngleDeg = 89;           // frustum edges lie strictly within +-89 degrees
constexpr int kMaxJsonDepth = 64;                    // nesting of arrays and objects
constexpr double kMaxRoomMetres = 10000;             // screen corners and the viewer lie within +-10 km

// The effect names "effects" may list, in the order the documentation gives them.
using effects::known_display_effects;

// True if `name` is a valid tile or config name: non-empty, only [A-Za-z0-9_.-].
bool is_valid_display_name(const std::string& name);

}  // namespace glcast::slave
