// `glcast run`: the program with the shim, and one local slave per tile of a display config,
// like `vglrun` for walls. Slaves on other machines run `glcast slave` with the endpoints this
// prints.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "cli/launcher.h"
#include "cli/swap_barrier.h"
#include "slave/display_config.h"
#include "slave/effects/effect_params.h"

namespace glcast {

const char* kRunUsage =
    "  run [--config FILE] [--backend egl|osmesa|window] [--out DIR] [--frames N] [--endpoint tcp://*:PORT]\n"
    "      [--lockstep] [--effects LIST] [--effect-param NAME=VALUE]...\n"
    "      -- PROGRAM [ARGS...]\n"
    "        run PROGRAM on a wall: one local slave per tile of FILE (default: one slave showing the\n"
    "        whole window); --out DIR writes each tile's frames to DIR/TILE/; --frames ends the\n"
    "        program after N frames; --endpoint publishes on TCP for slaves on other machines;\n"
    "        --lockstep holds the program at each swap until every slave has replayed the frame;\n"
    "        --effects/--effect-param are passed to every slave (injected passes, docs/effects.md)\n";

namespace {

int usage(const std::string& msg) {
    std::fprintf(stderr, "glcast run: %s\nusage: glcast\n%s", msg.c_str(), kRunUsage);
    return 2;
}

std::string self_exe() {
    char exe[PATH_MAX] = {};
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    return n > 0 ? std::string(exe, size_t(n)) : "glcast";
}

pid_t spawn(const std::vector<std::string>& argv) {
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> args;
        for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execv(args[0], args.data());
        std::fprintf(stderr, "glcast run: cannot start %s: %s\n", args[0], std::strerror(errno));
        _exit(127);
    }
    return pid;
}

// The journal's endpoint beside the stream's: the next TCP port (on the multicast interface's
// address for epgm://ADDRESS;GROUP:PORT), or a sibling IPC path.
std::string journal_endpoint(const std::string& stream) {
    const size_t colon = stream.rfind(':');
    const size_t semicolon = stream.find(';');
    if (stream.rfind("epgm://", 0) == 0 && semicolon != std::string::npos && colon != std::string::npos) {
        const int port = std::atoi(stream.c_str() + colon + 1);
        return "tcp://" + stream.substr(7, semicolon - 7) + ":" + std::to_string(port + 1);
    }
    if (stream.rfind("tcp://", 0) == 0 && colon != std::string::npos && colon > 6) {
        const int port = std::atoi(stream.c_str() + colon + 1);
        if (port > 0 && port < 65535) return stream.substr(0, colon + 1) + std::to_string(port + 1);
    }
    return stream + "-journal";
}

std::string connectable(const std::string& bound) {  // tcp://*:5555 -> tcp://127.0.0.1:5555
    const size_t star = bound.find("://*");
    return star == std::string::npos ? bound : bound.substr(0, star) + "://127.0.0.1" + bound.substr(star + 4);
}

}  // namespace

int run_main(const std::vector<std::string>& args) {
    std::string config_path, backend = std::getenv("DISPLAY") ? "window" : "egl", out_dir, endpoint;
    uint64_t frames = 0;
    bool lockstep = false;
    slave::effects::EffectsSettings effects;
    std::vector<std::string> effect_args;
    size_t i = 0;
    for (; i < args.size() && args[i] != "--"; ++i) {
        const bool v = i + 1 < args.size();
        if (args[i] == "--config" && v) config_path = args[++i];
        else if (args[i] == "--backend" && v) backend = args[++i];
        else if (args[i] == "--out" && v) out_dir = args[++i];
        else if (args[i] == "--endpoint" && v) endpoint = args[++i];
        else if (args[i] == "--lockstep") lockstep = true;
        else if (args[i] == "--frames" && v) frames = std::strtoull(args[++i].c_str(), nullptr, 10);
        else if ((args[i] == "--effects" || args[i] == "--effect-param") && v) {
            std::string error;  // checked here, so that a typo fails before any slave starts
            const bool ok = args[i] == "--effects" ? effects.enable(args[i + 1], error)
                                                   : effects.params.set_assignment(args[i + 1], error);
            if (!ok) return usage(args[i] + ": " + error);
            effect_args.push_back(args[i]);
            effect_args.push_back(args[++i]);
        }
        else return usage("unknown option '" + args[i] + "'");
    }
    if (i + 1 >= args.size()) return usage("the program to run follows '--'");
    const std::vector<std::string> program(args.begin() + long(i) + 1, args.end());

    std::vector<std::string> tiles;
    bool swap_barrier = false;
    if (!config_path.empty()) {
        slave::DisplayConfig config;
        std::string error;
        if (!slave::load_display_config(config_path, config, error)) {
            std::fprintf(stderr, "glcast run: %s\n", error.c_str());
            return 1;
        }
        for (const auto& t : config.tiles) tiles.push_back(t.name);
        swap_barrier = config.swap_barrier;
    }
    char dir[] = "/tmp/glcast-run-XXXXXX";
    if (!mkdtemp(dir)) {
        std::fprintf(stderr, "glcast run: mkdtemp: %s\n", std::strerror(errno));
        return 1;
    }
    if (endpoint.empty()) endpoint = std::string("ipc://") + dir + "/stream";
    const std::string journal = journal_endpoint(endpoint);
    std::fprintf(stderr, "glcast run: stream on %s, journal on %s\n", endpoint.c_str(), journal.c_str());
    if (!out_dir.empty()) ::mkdir(out_dir.c_str(), 0755);

    // The swap barrier outlives the program: slaves may present its last frames after it ended.
    const std::string barrier_endpoint = std::string("ipc://") + dir + "/barrier";
    std::unique_ptr<SwapBarrier> barrier;
    if (swap_barrier) {
        barrier = std::make_unique<SwapBarrier>(barrier_endpoint, int(tiles.size()));
        std::fprintf(stderr, "glcast run: swap barrier on %s for %zu tiles\n", barrier_endpoint.c_str(), tiles.size());
    }

    // Slaves first: they join through the journal whenever the program starts publishing.
    std::map<pid_t, std::string> slaves;
    const std::string exe = self_exe();
    const std::vector<std::string> names = tiles.empty() ? std::vector<std::string>{""} : tiles;
    for (const std::string& tile : names) {
        std::vector<std::string> argv = {exe, "slave", "--connect", connectable(endpoint), "--journal",
                                         connectable(journal), "--backend", backend, "--wait", "120"};
        if (!tile.empty()) argv.insert(argv.end(), {"--config", config_path, "--tile", tile});
        if (!out_dir.empty()) argv.insert(argv.end(), {"--out", out_dir + "/" + (tile.empty() ? "window" : tile)});
        if (swap_barrier) argv.insert(argv.end(), {"--swap-barrier", barrier_endpoint});
        if (lockstep) argv.push_back("--lockstep");
        argv.insert(argv.end(), effect_args.begin(), effect_args.end());
        if (const char* log = std::getenv("GLCAST_TEST_PRESENT_LOG_DIR"))
            setenv("GLCAST_TEST_PRESENT_LOG", (std::string(log) + "/" + (tile.empty() ? "window" : tile)).c_str(), 1);
        slaves[spawn(argv)] = tile.empty() ? "window" : tile;
    }
    std::map<std::string, std::string> env{{"GLCAST_PUBLISH", endpoint},
                                           {"GLCAST_JOURNAL_ENDPOINT", journal},
                                           {"GLCAST_WAIT_SUBSCRIBERS", std::to_string(slaves.size())},
                                           {"GLCAST_LOCKSTEP", lockstep ? std::to_string(slaves.size()) : "0"}};
    if (frames) {
        env["GLCAST_FRAMES"] = std::to_string(frames);
        env["GLCAST_EXIT_AFTER_FRAMES"] = "1";
    }
    const int status = run_with_shim(program, env);

    // The program has ended: slaves finish the stream and exit; give them time, then stop them.
    int failed = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!slaves.empty()) {
        int st = 0;
        const pid_t pid = waitpid(-1, &st, WNOHANG);
        if (pid > 0) {
            if (slaves.count(pid) && !(WIFEXITED(st) && WEXITSTATUS(st) == 0)) {
                std::fprintf(stderr, "glcast run: slave %s failed\n", slaves[pid].c_str());
                failed++;
            }
            slaves.erase(pid);
            continue;
        }
        if (std::chrono::steady_clock::now() > deadline) {
            for (auto& [p, name] : slaves) {
                std::fprintf(stderr, "glcast run: slave %s did not finish; stopping it\n", name.c_str());
                kill(p, SIGTERM);
            }
            failed += int(slaves.size());
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    std::string cleanup = std::string(dir);
    barrier.reset();
    for (const char* f : {"/stream", "/stream-journal", "/barrier"}) ::unlink((cleanup + f).c_str());
    ::rmdir(dir);
    if (status != 0) return status < 0 ? 1 : status;
    return failed ? 1 : 0;
}

}  // namespace glcast
