// Starting a program with the shim preloaded, the way `vglrun` and `apitrace trace` do.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace glcast::cli {

// Path of libglcast.so: $GLCAST_SHIM, else beside the glcast executable, else where the install
// rules put it relative to the executable, else the build dir.
std::string shim_path();

// Runs argv with LD_PRELOAD=shim and `env` added; returns the program's exit status
// (128 + signal when it was killed), or -1 when it could not be started.
int run_with_shim(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env);

// The glcast executable itself, for starting its own commands (slaves, a keeper, a recorder).
std::string self_exe();
// Starts argv[0] (a path) with argv in a child process; returns its pid.
int spawn(const std::vector<std::string>& argv);

}  // namespace glcast::cli
