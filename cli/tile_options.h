#pragma once
#include <string>

#include "slave/replayer.h"

namespace glcast::slave {
// Fills the replay options of tile `tile` of the display config at `path`.
bool tile_options(const std::string& path, const std::string& tile, ReplayOptions& options, std::string& error);
}  // namespace glcast::slave
