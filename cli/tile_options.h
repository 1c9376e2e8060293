// The replay options of one tile of a display config: what `glcast replay --config --tile` and
// `glcast slave --config --tile` show.
#pragma once
#include <string>

#include "slave/replayer.h"

namespace glcast::cli {
// Fills the replay options of tile `tile` of the display config at `path`.
bool tile_options(const std::string& path, const std::string& tile, slave::ReplayOptions& options, std::string& error);
}  // namespace glcast::cli
