#pragma once
#include <string>
#include <vector>

namespace glcast::slave {
// `glcast replay FILE [options]`; returns the process exit status.
int replay_main(const std::vector<std::string>& args);
extern const char* kReplayUsage;
}  // namespace glcast::slave
