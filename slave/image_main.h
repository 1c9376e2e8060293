#pragma once
#include <string>
#include <vector>

namespace glcast::slave {
// `glcast image mosaic|compare ...`: look at tiles together, compare frames.
int image_main(const std::vector<std::string>& args);
extern const char* kImageUsage;
}  // namespace glcast::slave
