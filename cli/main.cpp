// The glcast command: one binary with subcommands, like git and apitrace (design.md 8).
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/launcher.h"
#include "protocol/decoder.h"
#include "protocol/dump.h"
#include "slave/effects/effect_params.h"

using namespace glcast;

namespace {

const char* kUsage =
    "usage: glcast <command> [options]\n"
    "\n"
    "commands:\n"
    "%s"
    "  capture -o FILE [--frames N] -- PROGRAM [ARGS...]\n"
    "        run PROGRAM with the shim and write its GL stream to FILE; with --frames the\n"
    "        program is ended once N frames are written\n"
    "  dump FILE [--frames A:B] [--summary]\n"
    "        print one call per line with arguments and replies, and a summary per frame;\n"
    "        --frames limits the output to frames A through B (either may be omitted)\n"
    "%s"
    "%s"
    "%s"
    "  effects  the injected passes' parameters (name, default, range, meaning) as a markdown table\n"
    "  help  this text\n"
    "\n"
    "The shim reads GLCAST_* variables; see docs/environment.md.\n";

void print_usage(FILE* f) {
    std::fprintf(f, kUsage, glcast::kRunUsage, glcast::slave::kReplayUsage, glcast::slave::kSlaveUsage,
                 glcast::slave::kImageUsage);
}

int usage_error(const std::string& msg) {
    std::fprintf(stderr, "glcast: %s\n\n", msg.c_str());
    print_usage(stderr);
    return 2;
}

bool parse_u64(const std::string& s, uint64_t& out) {
    if (s.empty() || s.size() > 19 || s.find_first_not_of("0123456789") != std::string::npos) return false;
    out = std::strtoull(s.c_str(), nullptr, 10);
    return true;
}

int cmd_capture(const std::vector<std::string>& args) {
    std::string output;
    uint64_t frames = 0;
    size_t i = 0;
    for (; i < args.size() && args[i] != "--"; ++i) {
        if ((args[i] == "-o" || args[i] == "--output") && i + 1 < args.size()) output = args[++i];
        else if (args[i] == "--frames" && i + 1 < args.size()) {
            if (!parse_u64(args[++i], frames) || frames == 0 || frames > UINT32_MAX)
                return usage_error("--frames needs a positive integer, got '" + args[i] + "'");
        } else
            return usage_error("capture: unknown option '" + args[i] + "'");
    }
    if (output.empty()) return usage_error("capture: -o FILE is required");
    if (i + 1 >= args.size()) return usage_error("capture: the program to run follows '--'");
    std::vector<std::string> program(args.begin() + long(i) + 1, args.end());
    std::map<std::string, std::string> env{{"GLCAST_CAPTURE", output}};
    if (frames) {
        env["GLCAST_FRAMES"] = std::to_string(frames);
        env["GLCAST_EXIT_AFTER_FRAMES"] = "1";
    }
    const int status = run_with_shim(program, env);
    if (status < 0) return 1;
    if (FILE* f = std::fopen(output.c_str(), "rb")) std::fclose(f);
    else std::fprintf(stderr, "glcast: %s made no GL calls; no capture written\n", program[0].c_str());
    return status;
}

int cmd_dump(const std::vector<std::string>& args) {
    std::string path;
    DumpOptions opt;
    for (size_t i = 0; i < args.size(); ++i) {
        if (args[i] == "--frames" && i + 1 < args.size()) {
            const std::string r = args[++i];
            const size_t colon = r.find(':');
            const std::string a = colon == std::string::npos ? r : r.substr(0, colon);
            const std::string b = colon == std::string::npos ? r : r.substr(colon + 1);
            if ((!a.empty() && !parse_u64(a, opt.first_frame)) || (!b.empty() && !parse_u64(b, opt.last_frame)) ||
                opt.first_frame > opt.last_frame)
                return usage_error("--frames takes A:B with A <= B, got '" + r + "'");
        } else if (args[i] == "--summary") {
            opt.calls = false;
        } else if (!args[i].empty() && args[i][0] == '-') {
            return usage_error("dump: unknown option '" + args[i] + "'");
        } else if (path.empty()) {
            path = args[i];
        } else {
            return usage_error("dump: one capture file at a time");
        }
    }
    if (path.empty()) return usage_error("dump: which capture file?");
    try {
        CaptureReader reader(open_file_source(path));
        dump_capture(reader, opt, stdout);
    } catch (const DecodeError& e) {
        std::fflush(stdout);
        std::fprintf(stderr, "glcast: %s: %s\n", path.c_str(), e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fflush(stdout);
        std::fprintf(stderr, "glcast: %s\n", e.what());
        return 1;
    }
    return 0;
}

int cmd_effects(const std::vector<std::string>& args) {
    if (!args.empty()) return usage_error("effects takes no arguments");
    std::printf("| parameter | default | range | meaning |\n|---|---|---|---|\n");
    for (const auto& p : glcast::slave::effects::all_param_specs()) {
        if (p.text) std::printf("| `%s` | (none) | text | %s |\n", p.name.c_str(), p.help.c_str());
        else std::printf("| `%s` | %g | %g .. %g | %s |\n", p.name.c_str(), p.value, p.min, p.max, p.help.c_str());
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return usage_error("which command?");
    const std::string cmd = argv[1];
    const std::vector<std::string> args(argv + 2, argv + argc);
    if (cmd == "capture") return cmd_capture(args);
    if (cmd == "dump") return cmd_dump(args);
    if (cmd == "replay") return glcast::slave::replay_main(args);
    if (cmd == "image") return glcast::slave::image_main(args);
    if (cmd == "slave") return glcast::slave::slave_main(args);
    if (cmd == "run") return glcast::run_main(args);
    if (cmd == "effects") return cmd_effects(args);
    if (cmd == "help" || cmd == "--help" || cmd == "-h") {
        print_usage(stdout);
        return 0;
    }
    return usage_error("unknown command '" + cmd + "'");
}
