// `glcast capture -o FILE [--frames N] -- PROGRAM [ARGS...]`: the program with the shim, its GL
// stream written to FILE.
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>

#include "cli/commands.h"
#include "cli/launcher.h"
#include "cli/options.h"
#include "cli/paths.h"

namespace glcast::cli {

namespace {

struct CaptureArgs {
    std::string output;
    uint64_t frames = 0;  // 0: as long as the program runs
};

int capture(const CaptureArgs& a, const std::vector<std::string>& program) {
    // Absolute: the program may change directory before its first GL call opens the file.
    const std::string output = absolute_path(a.output);
    std::map<std::string, std::string> env{{"GLCAST_CAPTURE", output}};
    if (a.frames) {
        env["GLCAST_FRAMES"] = std::to_string(a.frames);
        env["GLCAST_EXIT_AFTER_FRAMES"] = "1";
    }
    const int status = run_with_shim(program, env);
    if (status < 0) return 1;
    if (FILE* f = std::fopen(output.c_str(), "rb")) std::fclose(f);
    else std::fprintf(stderr, "glcast: %s made no GL calls; no capture written\n", program[0].c_str());
    return status;
}

}  // namespace

Command add_capture(CLI::App& glcast) {
    auto a = std::make_shared<CaptureArgs>();
    CLI::App* app = glcast.add_subcommand("capture", "run a program with the shim and write its GL stream to a file");
    app->footer("PROGRAM and its arguments follow '--'; glcast reads none of them. The exit status is the program's.");
    app->add_option("-o,--output", a->output, "the capture file to write")->required()->type_name("FILE");
    add_u64(*app, "--frames", a->frames, 1, UINT32_MAX, "end the program once N frames are written");
    return {app, [a](const std::vector<std::string>& program) { return capture(*a, program); }, true};
}

}  // namespace glcast::cli
