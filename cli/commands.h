// The glcast subcommands, one file each in cli/. Each registers a CLI11 subcommand of `glcast`
// with its options and returns how to run it once the command line has been parsed; cli/main.cpp
// dispatches and maps errors to exit codes (2: usage, 1: the command failed).
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace glcast::cli {

struct Command {
    CLI::App* app = nullptr;
    // Runs the parsed command and returns its exit status. `program` is what followed "--" for
    // a command that runs one (never seen by CLI11, so its options stay its own). A usage error
    // found only here throws CLI::ParseError (usage_error in cli/options.h): exit 2.
    std::function<int(const std::vector<std::string>& program)> run;
    bool runs_program = false;  // glcast CMD [options] -- PROGRAM [ARGS...]
};

Command add_capture(CLI::App& glcast);  // cli/capture.cpp
Command add_dump(CLI::App& glcast);     // cli/dump.cpp
Command add_replay(CLI::App& glcast);   // cli/replay.cpp
Command add_run(CLI::App& glcast);      // cli/run.cpp
Command add_slave(CLI::App& glcast);    // cli/slave.cpp
Command add_image(CLI::App& glcast);    // cli/image.cpp
Command add_effects(CLI::App& glcast);  // cli/effects.cpp
Command add_trim(CLI::App& glcast);     // cli/trim.cpp
Command add_keeper(CLI::App& glcast);   // cli/keeper.cpp
Command add_record(CLI::App& glcast);   // cli/record.cpp
Command add_keygen(CLI::App& glcast);   // cli/keygen.cpp
Command add_doctor(CLI::App& glcast);   // cli/doctor.cpp
Command add_config(CLI::App& glcast);   // cli/config.cpp
Command add_ctl(CLI::App& glcast);      // cli/ctl.cpp
Command add_calibrate(CLI::App& glcast);  // cli/calibrate.cpp

}  // namespace glcast::cli
