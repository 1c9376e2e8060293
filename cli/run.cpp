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

#include "cli/commands.h"
#include "cli/launcher.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "cli/swap_barrier.h"
#include "display_configs/display_config.h"
#include "slave/effects/effect_params.h"

namespace glcast::cli {

namespace {

struct RunArgs {
    std::string config_path, backend = std::getenv("DISPLAY") ? "window" : "egl", out_dir, endpoint;
    uint64_t frames = 0;  // 0: as long as the program runs
    bool lockstep = false;
    slave::effects::EffectsSettings effects;  // checked here, so that a typo fails before any slave starts
    std::vector<std::string> effect_args;     // passed on to every slave
};

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

// The keeper's beside the journal's: the port after it, or a sibling IPC path.
std::string keeper_endpoint(const std::string& journal) {
    const size_t colon = journal.rfind(':');
    if (journal.rfind("tcp://", 0) == 0 && colon != std::string::npos && colon > 6) {
        const int port = std::atoi(journal.c_str() + colon + 1);
        if (port > 0 && port < 65535) return journal.substr(0, colon + 1) + std::to_string(port + 1);
    }
    return journal + "-keeper";
}

std::string connectable(const std::string& bound) {  // tcp://*:5555 -> tcp://127.0.0.1:5555
    const size_t star = bound.find("://*");
    return star == std::string::npos ? bound : bound.substr(0, star) + "://127.0.0.1" + bound.substr(star + 4);
}

int run(const RunArgs& a, const std::vector<std::string>& program) {
    const std::string &config_path = a.config_path, &backend = a.backend, &out_dir = a.out_dir;
    const uint64_t frames = a.frames;
    const bool lockstep = a.lockstep;
    const std::vector<std::string>& effect_args = a.effect_args;
    std::string endpoint = a.endpoint;
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
    // Slaves elsewhere (--endpoint tcp://) may start at any time: a keeper lets them join from a
    // snapshot of the live state once the journal no longer holds the stream's start.
    const bool multicast = endpoint.rfind("epgm://", 0) == 0 || endpoint.rfind("pgm://", 0) == 0;
    const bool remote = endpoint.rfind("tcp://", 0) == 0 || multicast;
    const std::string local_stream = std::string("ipc://") + dir + "/stream";
    if (endpoint.empty()) endpoint = local_stream;
    const std::string journal = journal_endpoint(endpoint);
    // Multicast does not loop back to the sending machine: the program publishes there too, on
    // an ipc:// path, for the local slaves and the keeper.
    const std::string local = multicast ? local_stream : connectable(endpoint);
    const std::string publish = multicast ? endpoint + "," + local_stream : endpoint;
    const std::string keeper = remote ? keeper_endpoint(journal) : "";
    std::fprintf(stderr, "glcast run: stream on %s, journal on %s%s%s\n", endpoint.c_str(), journal.c_str(),
                 remote ? ", keeper on " : "", keeper.c_str());
    std::string mkdir_error;
    if (!out_dir.empty() && !make_directories(out_dir, mkdir_error)) {
        std::fprintf(stderr, "glcast run: --out: %s\n", mkdir_error.c_str());
        return 1;
    }

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
        std::vector<std::string> argv = {exe, "slave", "--connect", local, "--journal",
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
    pid_t keeper_pid = -1;
    if (remote)
        keeper_pid = spawn({exe, "keeper", "--connect", local, "--journal", connectable(journal), "--bind",
                            keeper, "--wait", "120"});
    std::map<std::string, std::string> env{{"GLCAST_PUBLISH", publish},
                                           {"GLCAST_JOURNAL_ENDPOINT", journal},
                                           {"GLCAST_WAIT_SUBSCRIBERS", std::to_string(slaves.size() + (remote ? 1 : 0))},
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
            if (pid == keeper_pid) continue;  // it ends with the stream; a failure is its own message
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
    if (keeper_pid > 0 && waitpid(keeper_pid, nullptr, WNOHANG) == 0) {
        kill(keeper_pid, SIGTERM);
        waitpid(keeper_pid, nullptr, 0);
    }
    std::string cleanup = std::string(dir);
    barrier.reset();
    for (const char* f : {"/stream", "/stream-journal", "/barrier"}) ::unlink((cleanup + f).c_str());
    ::rmdir(dir);
    if (status != 0) return status < 0 ? 1 : status;
    return failed ? 1 : 0;
}

}  // namespace

Command add_run(CLI::App& glcast) {
    auto a = std::make_shared<RunArgs>();
    CLI::App* app = glcast.add_subcommand("run", "run a program on a wall: the shim, and one local slave per tile");
    app->footer("PROGRAM and its arguments follow '--'; glcast reads none of them. Slaves on other machines run\n"
                "glcast slave with the endpoints this prints.");
    app->add_option("--config", a->config_path, "a display config: one local slave per tile (default: one slave\n"
                                                "showing the whole window)")
        ->type_name("FILE");
    app->add_option("--backend", a->backend,
                    "the slaves' backend (default: window with $DISPLAY, else egl)")
        ->type_name("egl|osmesa|window");
    app->add_option("--out", a->out_dir, "write each tile's frames to DIR/TILE/")->type_name("DIR");
    add_u64(*app, "--frames", a->frames, 1, UINT32_MAX, "end the program after N frames");
    app->add_option("--endpoint", a->endpoint,
                    "publish for slaves on other machines: tcp://*:PORT, or multicast epgm://ADDRESS;GROUP:PORT\n"
                    "(the journal and the keeper on ADDRESS's next TCP ports)")
        ->type_name("ENDPOINT");
    app->add_flag("--lockstep", a->lockstep, "hold the program at each swap until every slave has replayed the frame");
    add_effect_options(*app, a->effects, &a->effect_args);
    return {app, [a](const std::vector<std::string>& program) { return run(*a, program); }, true};
}

}  // namespace glcast::cli
