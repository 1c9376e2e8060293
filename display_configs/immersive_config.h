// The immersive parts of a display config (docs/immersive.md): screens in metres, the eye a
// tile shows, and the viewer. Called by display_config.cpp's parser.
#pragma once

#include <string>

#include "display_configs/config_check.h"
#include "display_configs/display_config.h"

namespace glcast::slave::config_check {

// A tile's "screen": three corners of a rectangle, in metres.
bool parse_screen(Validator& check, const json& v, const std::string& path, TileView& view);
// A tile's "eye" and "stereo" (`tile` is the tile's object, `path` its JSON path).
bool parse_tile_eyes(Validator& check, const json& tile_json, const std::string& path, Tile& tile);
// The top-level "viewer", and that every screen faces its position.
bool parse_viewer(Validator& check, const json& root, DisplayConfig& config);

}  // namespace glcast::slave::config_check
