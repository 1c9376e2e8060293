// `glcast config FILE`: checks a display config as every command loads it, and lists its tiles
// (docs/display-configs.md); `--names` lists only their names (bash completion of --tile).
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "display_configs/display_config.h"

namespace glcast::cli {

namespace {

struct ConfigArgs {
    std::string path;
    bool names = false;
};

const char* kind(const slave::Tile& t) {
    if (t.view.screen) return "screen";
    return t.view.enabled ? "view" : "planar";
}

int config(const ConfigArgs& a) {
    slave::DisplayConfig c;
    std::string error;
    if (!slave::load_display_config(a.path, c, error)) {
        std::fprintf(stderr, "glcast config: %s\n", error.c_str());
        return 1;
    }
    for (const slave::Tile& t : c.tiles) {
        if (a.names) {
            std::printf("%s\n", t.name.c_str());
            continue;
        }
        std::printf("%-16s %-7s %5dx%-5d at %d,%d%s%s\n", t.name.c_str(), kind(t), t.width, t.height, t.x, t.y,
                    t.machine.empty() ? "" : ("  on " + t.machine).c_str(),
                    t.stereo != slave::Stereo::none ? "  stereo" : t.eye != slave::TileEye::centre ? "  one eye" : "");
    }
    if (!a.names)
        std::printf("%s: %s, %zu tiles, canvas %dx%d%s\n", a.path.c_str(), c.name.c_str(), c.tiles.size(), c.canvas_width,
                    c.canvas_height, c.swap_barrier ? ", swap barrier" : "");
    return 0;
}

}  // namespace

Command add_config(CLI::App& glcast) {
    auto a = std::make_shared<ConfigArgs>();
    CLI::App* app = glcast.add_subcommand("config", "check a display config and list its tiles");
    app->add_option("FILE", a->path, "the display config (docs/display-configs.md)")->required();
    app->add_flag("--names", a->names, "only the tiles' names, one a line");
    return {app, [a](const std::vector<std::string>&) { return config(*a); }};
}

}  // namespace glcast::cli
