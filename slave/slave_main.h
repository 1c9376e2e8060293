#pragma once
#include <string>
#include <vector>

namespace glcast::slave {
// `glcast slave --connect ENDPOINT ...`: one tile of a wall, fed by a live master.
int slave_main(const std::vector<std::string>& args);
extern const char* kSlaveUsage;
}  // namespace glcast::slave
