// What the glcast commands parse alike: whole numbers in a range, frame ranges A:B, sizes WxH,
// lists of integers X,Y,W,H, and the injected passes' --effects/--effect-param. Each comes as a
// plain parser (false, with what was expected and what was given) and as a CLI11 option whose
// bad value is a usage error naming the option: exit 2 with "glcast CMD: --option: ..." on
// stderr (cli/main.cpp).
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace glcast::slave {
struct ReplayLimits;
}  // namespace glcast::slave
namespace glcast::slave::effects {
struct EffectsSettings;
}

namespace glcast::cli {

// --- parsers ------------------------------------------------------------------------------
// Digits only (no sign, no spaces, no suffix), min <= value <= max.
bool parse_u64(const std::string& s, uint64_t min, uint64_t max, uint64_t& out, std::string& error);
// An optional '-' and digits, min <= value <= max.
bool parse_int(const std::string& s, int min, int max, int& out, std::string& error);

// Frames A:B (A <= B). Either end may be omitted: ":B" starts at 0, "A:" runs to the end. A
// lone number is that frame alone (dump, replay) or that frame onwards (slave).
enum class LoneFrame { only_that_frame, from_that_frame };
struct FrameRange {
    uint64_t first = 0, last = UINT64_MAX;
};
bool parse_frame_range(const std::string& s, LoneFrame lone, FrameRange& out, std::string& error);

// WxH with 1 <= W, H <= max.
bool parse_size(const std::string& s, int max, int& width, int& height, std::string& error);
// `count` integers separated by commas ("X,Y", "X,Y,W,H"), each in min..max; `what` names
// them in the message ("X,Y,W,H").
bool parse_ints(const std::string& s, size_t count, int min, int max, const std::string& what, std::vector<int>& out,
                std::string& error);

// --- usage errors -------------------------------------------------------------------------
// Throws the CLI11 error that cli/main.cpp turns into exit 2: "OPTION: MESSAGE", or MESSAGE
// alone when it already starts with the option's name.
[[noreturn]] void usage_error(const std::string& option, const std::string& message);
// "-o,--output" -> "--output": the name an error shows.
std::string option_display_name(const std::string& names);

// --- CLI11 options ------------------------------------------------------------------------
// Each sets its variable(s) once the command line is parsed; every value given is checked, and
// the last of repeated options wins.
CLI::Option* add_u64(CLI::App& app, const std::string& names, uint64_t& out, uint64_t min, uint64_t max,
                     const std::string& help);
CLI::Option* add_int(CLI::App& app, const std::string& names, int& out, int min, int max, const std::string& help);
CLI::Option* add_frame_range(CLI::App& app, const std::string& names, LoneFrame lone, uint64_t& first,
                             uint64_t& last, const std::string& help);
CLI::Option* add_size(CLI::App& app, const std::string& names, int max, int& width, int& height,
                      const std::string& help);
// `count` comma-separated integers in min..max (type name `what`, e.g. "X,Y,W,H").
CLI::Option* add_ints(CLI::App& app, const std::string& names, size_t count, int min, int max,
                      const std::string& what, std::vector<int>& out, const std::string& help);

// --effects LIST and --effect-param NAME=VALUE, both repeatable, checked as they are parsed
// (so a typo fails before anything starts). `forwarded`, when given, receives them again as
// command-line arguments (glcast run passes them to its slaves).
void add_effect_options(CLI::App& app, slave::effects::EffectsSettings& effects,
                        std::vector<std::string>* forwarded = nullptr);

// --limit NAME=VALUE, repeatable: the slave's bounds on what a stream may make it allocate
// (docs/slave.md "Limits of a stream").
void add_limit_option(CLI::App& app, slave::ReplayLimits& limits);

// --keys DIR and --insecure (docs/security.md).
void add_security_options(CLI::App& app, std::string& keys, bool& insecure);
// Makes `keys` (else GLCAST_KEYS) and `insecure` this process's and its children's (GLCAST_KEYS,
// GLCAST_INSECURE) and reads the keys; false, after saying why on stderr as `who`, when they
// cannot be read.
bool use_keys(const std::string& keys, bool insecure, const char* who, std::string& error);

}  // namespace glcast::cli
