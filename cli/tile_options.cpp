#include "cli/tile_options.h"

#include <cstdio>

#include "cli/paths.h"
#include "display_configs/display_config.h"
#include "display_configs/mpcdi.h"
#include "display_configs/projector_maps.h"
#include "slave/stereo.h"

namespace glcast::cli {

using namespace glcast::slave;

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
    // The config's effects join those of the command line, whose parameters win.
    for (const std::string& effect : config.effects)
        if (!options.effects.enable(effect, error)) return false;
    for (const auto& [param, value] : config.effect_params)
        if (!options.effects.params.has(param) && !options.effects.params.set(param, value, error)) return false;
    if (!tile->warp.empty() || !tile->blend.empty() || !tile->mpcdi.empty()) {
        auto maps = std::make_shared<ProjectorMaps>();
        const bool loaded = tile->mpcdi.empty()
                                ? load_plain_maps(tile->warp.empty() ? "" : relative_to(path, tile->warp),
                                                  tile->blend.empty() ? "" : relative_to(path, tile->blend), *maps, error)
                                : load_mpcdi_region(relative_to(path, tile->mpcdi), tile->region,
                                                    BufferRect{double(tile->x) / config.canvas_width,
                                                               double(tile->y) / config.canvas_height,
                                                               double(tile->width) / config.canvas_width,
                                                               double(tile->height) / config.canvas_height},
                                                    *maps, error, &tile->view);
        if (!loaded) {
            error = path + ": tile " + name + ": " + error;
            return false;
        }
        options.projector = maps;
    }
    TileMapping& m = options.tile;
    if (config.program_projection.given) {  // shader programs: for rotated tiles and for effects
        options.view.program_fov_y_deg = config.program_projection.fov_y_deg;
        options.view.program_near = config.program_projection.near;
        options.view.program_far = config.program_projection.far;
    }
    if (tile->view.enabled) {
        // The program's whole window on the tile, seen through the tile's own camera.
        const TileView& v = tile->view;
        ViewCorrection& c = options.view;
        c.enabled = true;
        c.yaw_deg = v.yaw_deg, c.pitch_deg = v.pitch_deg, c.roll_deg = v.roll_deg;
        c.left_deg = v.left_deg, c.right_deg = v.right_deg, c.bottom_deg = v.bottom_deg, c.top_deg = v.top_deg;
        if (v.screen) {
            c.screen = true;
            c.bottom_left = glm::dvec3(v.bottom_left[0], v.bottom_left[1], v.bottom_left[2]);
            c.bottom_right = glm::dvec3(v.bottom_right[0], v.bottom_right[1], v.bottom_right[2]);
            c.top_left = glm::dvec3(v.top_left[0], v.top_left[1], v.top_left[2]);
        }
        c.units_per_metre = config.viewer.units_per_metre;
        Viewer& viewer = options.viewer;
        viewer.head.position = glm::dvec3(config.viewer.position[0], config.viewer.position[1], config.viewer.position[2]);
        viewer.eye_separation = config.viewer.eye_separation;
        viewer.eye = tile->eye == TileEye::left ? Eye::left : tile->eye == TileEye::right ? Eye::right : Eye::centre;
        c.set_eye(eye_position(viewer));  // the config checked that the viewer faces every screen
        options.stereo = tile->stereo == Stereo::quad_buffer    ? StereoMode::quad_buffer
                         : tile->stereo == Stereo::side_by_side ? StereoMode::side_by_side
                         : tile->stereo == Stereo::top_bottom   ? StereoMode::top_bottom
                         : tile->stereo == Stereo::anaglyph     ? StereoMode::anaglyph
                                                                : StereoMode::none;
        m.enabled = true;
        eye_size(options.stereo, tile->width, tile->height, m.width, m.height);  // each eye's image
        m.canvas_width = m.width;
        m.canvas_height = m.height;
        m.x = m.y = 0;
        m.place_x = tile->x;
        m.place_y = config.canvas_height - tile->y - tile->height;
        m.place_canvas_width = config.canvas_width;
        m.place_canvas_height = config.canvas_height;
        return true;
    }
    m.enabled = true;
    m.canvas_width = config.canvas_width;
    m.canvas_height = config.canvas_height;
    m.x = tile->x;
    m.width = tile->width;
    m.height = tile->height;
    m.y = config.canvas_height - tile->y - tile->height;  // GL's origin is the bottom left
    m.place_x = m.x, m.place_y = m.y;
    m.place_canvas_width = m.canvas_width, m.place_canvas_height = m.canvas_height;
    return true;
}

}  // namespace glcast::cli

namespace glcast::cli {

void move_head(slave::Replayer& replayer, const slave::HeadPose& head, uint64_t frame, const char* who) {
    static bool said = false;
    if (!replayer.move_head(head) && !said) {
        said = true;
        std::fprintf(stderr, "%s: frame %llu: the head pose puts the eye behind this tile's screen or on it; the last "
                             "eye is kept (said once)\n", who, (unsigned long long)frame);
    }
}

}  // namespace glcast::cli
