#include "slave/tile_options.h"

#include "slave/display_config.h"

namespace glcast::slave {

bool tile_options(const std::string& path, const std::string& name, ReplayOptions& options, std::string& error) {
    DisplayConfig config;
    if (!load_display_config(path, config, error)) return false;
    const Tile* tile = config.find(name);
    if (!tile) {
        error = path + ": no tile named \"" + name + "\" (tiles:";
        for (const Tile& t : config.tiles) error += " " + t.name;
        error += ")";
        return false;
    }
    if (tile->view.enabled) {
        error = path + ": tile \"" + name + "\" has a rotated view; this slave shows planar tiles only so far";
        return false;
    }
    TileMapping& m = options.tile;
    m.enabled = true;
    m.canvas_width = config.canvas_width;
    m.canvas_height = config.canvas_height;
    m.x = tile->x;
    m.width = tile->width;
    m.height = tile->height;
    m.y = config.canvas_height - tile->y - tile->height;  // GL's origin is the bottom left
    return true;
}

}  // namespace glcast::slave
