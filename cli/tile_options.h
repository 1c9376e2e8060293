// The replay options of one tile of a display config: what `glcast replay --config --tile` and
// `glcast slave --config --tile` show.
#pragma once
#include <string>

#include "slave/replayer.h"

namespace glcast::cli {
// Fills the replay options of tile `tile` of the display config at `path`.
bool tile_options(const std::string& path, const std::string& tile, slave::ReplayOptions& options, std::string& error);

// Moves the replayer's viewer to `head` at the start of a frame (a recorded track, a pose the
// wall's run handed on); says once, as `who`, when a pose puts the eye where the tile cannot show
// it (behind its screen), which leaves the last eye.
void move_head(slave::Replayer& replayer, const slave::HeadPose& head, uint64_t frame, const char* who);
}  // namespace glcast::cli
