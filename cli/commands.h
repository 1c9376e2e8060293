#pragma once
#include <string>
#include <vector>

namespace glcast {
int run_main(const std::vector<std::string>& args);
extern const char* kRunUsage;
}  // namespace glcast

namespace glcast::slave {
// `glcast replay FILE [options]`; returns the process exit status.
int replay_main(const std::vector<std::string>& args);
extern const char* kReplayUsage;
// `glcast slave --connect ENDPOINT ...`: one tile of a wall, fed by a live master.
int slave_main(const std::vector<std::string>& args);
extern const char* kSlaveUsage;
// `glcast image mosaic|compare ...`: look at tiles together, compare frames.
int image_main(const std::vector<std::string>& args);
extern const char* kImageUsage;
}  // namespace glcast::slave
