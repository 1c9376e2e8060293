// Paths the user names on the command line, made to mean what they meant where glcast started:
// a program may change directory before it writes its capture, and output folders are made
// with their parents.
#pragma once

#include <string>

namespace glcast::cli {

// `path` made absolute against the current directory (unchanged if already absolute or empty).
std::string absolute_path(const std::string& path);
// Creates `dir` and its missing parents (mkdir -p). False with `error` naming the failing part.
bool make_directories(const std::string& dir, std::string& error);

// `path` as seen from the folder of `file` (a display config's "keys"): unchanged when absolute.
std::string relative_to(const std::string& file, const std::string& path);

}  // namespace glcast::cli
