// `glcast capture -o FILE [--frames N] [--start-frame S] -- PROGRAM [ARGS...]`: the program with
// the shim, its GL stream written to FILE. From a later frame on, the program publishes on a
// private endpoint; a keeper replays it and `glcast record` writes the keeper's snapshot at frame
// S and the messages after it (docs/keeper.md).
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <thread>

#include "cli/commands.h"
#include "cli/launcher.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "protocol/decoder.h"

namespace glcast::cli {

namespace {

struct CaptureArgs {
    std::string output;
    uint64_t frames = 0;  // 0: as long as the program runs
    uint64_t start_frame = 0;
};

// Waits for a child, at most `seconds`; then stops it. Its exit status, or -1.
int wait_child(int pid, int seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    for (;;) {
        int st = 0;
        if (waitpid(pid, &st, WNOHANG) == pid) return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
        if (std::chrono::steady_clock::now() > deadline) {
            kill(pid, SIGTERM);
            waitpid(pid, &st, 0);
            return -1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

int capture_from(const CaptureArgs& a, const std::string& output, const std::vector<std::string>& program) {
    char dir[] = "/tmp/glcast-capture-XXXXXX";
    if (!mkdtemp(dir)) {
        std::fprintf(stderr, "glcast capture: mkdtemp: %s\n", std::strerror(errno));
        return 1;
    }
    const std::string stream = std::string("ipc://") + dir + "/stream", journal = stream + "-journal",
                      keeper = stream + "-keeper", exe = self_exe();
    const int keeper_pid = spawn({exe, "keeper", "--connect", stream, "--journal", journal, "--bind", keeper});
    std::vector<std::string> record = {exe, "record", "--connect", stream, "--journal", journal, "--keeper", keeper,
                                       "-o", output, "--start-frame", std::to_string(a.start_frame)};
    if (a.frames) record.insert(record.end(), {"--frames", std::to_string(a.frames)});
    const int record_pid = spawn(record);
    std::map<std::string, std::string> env{{"GLCAST_PUBLISH", stream}, {"GLCAST_JOURNAL_ENDPOINT", journal},
                                           {"GLCAST_WAIT_SUBSCRIBERS", "1"}};  // the keeper, from the first message
    if (a.frames) {
        env["GLCAST_FRAMES"] = std::to_string(a.start_frame + a.frames);
        env["GLCAST_EXIT_AFTER_FRAMES"] = "1";
    }
    const int status = run_with_shim(program, env);
    const int recorded = wait_child(record_pid, 120);
    wait_child(keeper_pid, 30);
    for (const char* f : {"/stream", "/stream-journal", "/stream-keeper"}) ::unlink((std::string(dir) + f).c_str());
    ::rmdir(dir);
    if (recorded != 0) {
        std::fprintf(stderr, "glcast capture: the recording from frame %llu failed (did the program reach it?)\n",
                     (unsigned long long)a.start_frame);
        return status > 0 ? status : 1;
    }
    return status < 0 ? 1 : status;
}

int capture(const CaptureArgs& a, const std::vector<std::string>& program) {
    // Absolute: the program may change directory before its first GL call opens the file.
    const std::string output = absolute_path(a.output);
    if (a.start_frame) return capture_from(a, output, program);
    std::map<std::string, std::string> env{{"GLCAST_CAPTURE", output}};
    if (a.frames) {
        env["GLCAST_FRAMES"] = std::to_string(a.frames);
        env["GLCAST_EXIT_AFTER_FRAMES"] = "1";
    }
    const int status = run_with_shim(program, env);
    if (status < 0) return 1;
    FILE* f = std::fopen(output.c_str(), "rb");
    if (!f) {
        std::fprintf(stderr, "glcast: %s made no GL calls; no capture written\n", program[0].c_str());
        return status;
    }
    std::fclose(f);
    // A capture stopped by a full disk, or a program that ended without closing it: said, and
    // not a success (what it holds replays, to its last whole message).
    const CaptureEnd end = capture_end(output);
    if (!end.complete) {
        std::fprintf(stderr, "glcast capture: %s was %s\n", output.c_str(), end.why.c_str());
        return status ? status : 1;
    }
    return status;
}

}  // namespace

Command add_capture(CLI::App& glcast) {
    auto a = std::make_shared<CaptureArgs>();
    CLI::App* app = glcast.add_subcommand("capture", "run a program with the shim and write its GL stream to a file");
    app->footer("PROGRAM and its arguments follow '--'; glcast reads none of them. The exit status is the program's.");
    app->add_option("-o,--output", a->output, "the capture file to write")->required()->type_name("FILE");
    add_u64(*app, "--frames", a->frames, 1, UINT32_MAX, "end the program once N frames are written");
    add_u64(*app, "--start-frame", a->start_frame, 0, UINT32_MAX,
            "begin at frame S of the program, with a snapshot of its state there (a keeper\n"
            "replays it meanwhile); with --frames, N frames from S on");
    return {app, [a](const std::vector<std::string>& program) { return capture(*a, program); }, true};
}

}  // namespace glcast::cli
