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
#include <optional>
#include <string>
#include <thread>
#include <atomic>
#include <algorithm>
#include <cinttypes>
#include <condition_variable>
#include <mutex>

#include <nlohmann/json.hpp>
#include <vector>

#include "cli/commands.h"
#include "cli/launcher.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "cli/pose_receiver.h"
#include "cli/run_session.h"
#include "cli/wall_control.h"
#include "cli/wall_status.h"
#include "cli/dashboard.h"
#include "common/environment.h"
#include "net/bind_probe.h"
#include "net/security.h"
#include "net/wall_endpoints.h"
#include "slave/wall_link.h"
#include "display_configs/display_config.h"
#include "display_configs/head_poses.h"
#include "slave/effects/effect_params.h"

namespace glcast::cli {

namespace {

struct RunArgs {
    std::string config_path, backend = std::getenv("DISPLAY") ? "window" : "egl", out_dir, endpoint, keys, machine,
                                     status_json, head_poses, tracker, dashboard, timing;
    uint64_t frames = 0;  // 0: as long as the program runs
    bool lockstep = false, insecure = false;
    int wait_tiles = 10;  // seconds to wait for the tiles of other machines before the program starts
    int max_local_slaves = 16;  // a slave is a process of its own (about 90 MB with its driver)
    slave::effects::EffectsSettings effects;  // checked here, so that a typo fails before any slave starts
    std::vector<std::string> effect_args;     // passed on to every slave
};

// The wall as this machine runs it: every tile with its machine, and which are shown here.
struct WallPlan {
    std::vector<std::pair<std::string, std::string>> tiles;  // name, machine
    std::vector<std::string> local_tiles, remote_tiles;      // "" for the one window without a config
    std::optional<slave::DisplayConfig> config;
    slave::effects::EffectsSettings effects;  // what every tile starts with: the command line's and the config's
    bool swap_barrier = false;
    std::string keys, endpoint, tracker;
};

bool plan_wall(const RunArgs& a, const std::string& here, WallPlan& plan) {
    plan.keys = a.keys;
    plan.endpoint = a.endpoint;
    plan.effects = a.effects;
    if (a.config_path.empty()) {
        plan.tiles.push_back({"window", here});
        plan.local_tiles.push_back("");
        return true;
    }
    slave::DisplayConfig config;
    std::string error;
    if (!slave::load_display_config(a.config_path, config, error)) {
        std::fprintf(stderr, "glcast run: %s\n", error.c_str());
        return false;
    }
    for (const auto& t : config.tiles) {
        const bool local = t.machine.empty() || t.machine == here;
        plan.tiles.push_back({t.name, local ? here : t.machine});
        (local ? plan.local_tiles : plan.remote_tiles).push_back(t.name);
    }
    if (plan.local_tiles.size() > size_t(a.max_local_slaves)) {
        std::fprintf(stderr, "glcast run: %s puts %zu tiles on this machine (%s), each shown by a slave of its own "
                             "(about 90 MB): more than --max-local-slaves %d; raise it, or give the tiles other "
                             "machines\n",
                     a.config_path.c_str(), plan.local_tiles.size(), here.c_str(), a.max_local_slaves);
        return false;
    }
    plan.swap_barrier = config.swap_barrier;
    plan.tracker = config.viewer.tracker;
    for (const std::string& effect : config.effects)
        if (!plan.effects.enable(effect, error)) return false;  // (checked when the config was loaded)
    plan.config = config;
    if (plan.keys.empty() && !config.keys.empty()) plan.keys = relative_to(a.config_path, config.keys);
    if (plan.endpoint.empty() && config.master.given) plan.endpoint = "tcp://*:" + std::to_string(config.master.port);
    return true;
}

// The wall's four channels (net/wall_endpoints.h), and where this machine's slaves and keeper
// subscribe and the program publishes. Throws std::invalid_argument on an endpoint without a
// usable port.
struct RunEndpoints : net::WallEndpoints {
    std::string local;    // where this machine's slaves and keeper subscribe
    std::string publish;  // where the program publishes
};

RunEndpoints plan_endpoints(std::string endpoint, const std::string& dir) {
    const bool multicast = endpoint.rfind("epgm://", 0) == 0 || endpoint.rfind("pgm://", 0) == 0;
    const std::string local_stream = "ipc://" + dir + "/stream";
    if (endpoint.empty()) endpoint = local_stream;
    RunEndpoints e;
    static_cast<net::WallEndpoints&>(e) = net::wall_endpoints(endpoint);
    if (!e.reachable) e.keeper.clear();  // every slave is local, and joins through the journal
    // Multicast does not loop back to the sending machine: the program publishes there too, on
    // an ipc:// path, for the local slaves and the keeper.
    e.local = multicast ? local_stream : net::connectable(endpoint);
    e.publish = multicast ? endpoint + "," + local_stream : endpoint;
    return e;
}

void start_slaves(RunSession& session, const RunArgs& a, const WallPlan& plan, const RunEndpoints& e,
                  const std::string& here) {
    const std::string exe = self_exe();
    for (const std::string& tile : plan.local_tiles) {
        const std::string name = tile.empty() ? "window" : tile;
        std::vector<std::string> argv = {exe,       "slave",   "--connect", e.local, "--journal", net::connectable(e.journal),
                                         "--backend", a.backend, "--wait",  "120",   "--control", net::connectable(e.control),
                                         "--quiet", "--machine", here};
        if (!tile.empty()) argv.insert(argv.end(), {"--config", a.config_path, "--tile", tile});
        if (!a.out_dir.empty()) argv.insert(argv.end(), {"--out", a.out_dir + "/" + name});
        if (plan.swap_barrier) argv.push_back("--swap-barrier");
        if (a.lockstep) argv.push_back("--lockstep");
        argv.insert(argv.end(), a.effect_args.begin(), a.effect_args.end());
        if (const std::string& logs = environment().test_present_log_dir; !logs.empty())
            setenv("GLCAST_TEST_PRESENT_LOG", (logs + "/" + name).c_str(), 1);
        session.start("slave " + name, argv, true);
    }
    if (e.reachable)
        session.keep("keeper", {exe, "keeper", "--connect", e.local, "--journal", net::connectable(e.journal), "--bind",
                                 e.keeper, "--wait", "120", "--state", session.dir() + "/keeper.state"});
}

// The tiles of other machines: their slaves (glcast slave --service) report to the control
// channel while they wait for a program; they are waited for, counted and named. Returns how
// many are there.
int wait_for_remote_tiles(const WallControl& wall, const std::vector<std::string>& remote_tiles, int seconds) {
    if (remote_tiles.empty()) return 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    for (;;) {
        const auto status = wall.status();
        std::vector<std::string> missing;
        for (const std::string& t : remote_tiles)
            if (status.at(t).age_seconds < 0) missing.push_back(t);
        const int here = int(remote_tiles.size() - missing.size());
        if (missing.empty() || std::chrono::steady_clock::now() > deadline) {
            std::string names;
            for (const std::string& t : missing) names += (names.empty() ? "" : ", ") + t;
            std::fprintf(stderr, "glcast run: %d of %zu tiles on other machines are there%s%s%s\n", here,
                         remote_tiles.size(), missing.empty() ? "" : "; not yet: ", names.c_str(),
                         missing.empty() ? "" : " (they join when they come)");
            return here;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
}

// Tiles of other machines finish the program's last frames at the barrier this process serves:
// it stays until they say they are idle again (at most 30 s).
void wait_for_remote_tiles_idle(const WallControl& wall, const std::vector<std::string>& remote_tiles) {
    for (const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
         !remote_tiles.empty() && std::chrono::steady_clock::now() < until;
         std::this_thread::sleep_for(std::chrono::milliseconds(100))) {
        const auto status = wall.status();
        if (std::none_of(remote_tiles.begin(), remote_tiles.end(), [&](const std::string& t) {
                const TileStatus& s = status.at(t);
                return s.age_seconds >= 0 && s.age_seconds < 3 && s.state != "idle";
            }))
            return;
    }
}

int run(RunArgs& a, const std::vector<std::string>& program) {
    const std::string here = a.machine.empty() ? slave::machine_name() : a.machine;
    WallPlan plan;
    if (!plan_wall(a, here, plan)) return 1;
    std::string error;
    if (!use_keys(plan.keys, a.insecure, "glcast run", error)) return 1;
    if (!plan.remote_tiles.empty() && plan.endpoint.rfind("tcp://", 0) != 0 && plan.endpoint.rfind("epgm://", 0) != 0) {
        const std::string& tile = plan.remote_tiles[0];
        const auto machine = std::find_if(plan.tiles.begin(), plan.tiles.end(), [&](auto& t) { return t.first == tile; });
        std::fprintf(stderr, "glcast run: tile %s is on machine %s, not this one (%s): give the config a \"master\" "
                             "or --endpoint tcp://*:PORT so that it can be reached\n",
                     tile.c_str(), machine->second.c_str(), here.c_str());
        return 1;
    }
    if (!a.out_dir.empty() && !make_directories(a.out_dir, error)) {
        std::fprintf(stderr, "glcast run: --out: %s\n", error.c_str());
        return 1;
    }
    // A recorded viewer: each frame's pose goes to every tile with the barrier's GO, so the
    // barrier is on.
    auto track = std::make_shared<slave::HeadPoseTrack>();
    HeadPoseFor head_for;
    if (a.tracker.empty()) a.tracker = plan.tracker;
    if (!a.head_poses.empty() && !a.tracker.empty()) {
        std::fprintf(stderr, "glcast run: --head-poses plays recorded poses, the tracker (%s) sends live ones: give one\n",
                     a.tracker.c_str());
        return 1;
    }
    if (!a.head_poses.empty()) {
        if (!track->load(a.head_poses, error)) {
            std::fprintf(stderr, "glcast run: --head-poses: %s\n", error.c_str());
            return 1;
        }
        plan.swap_barrier = true;
        head_for = [track](uint64_t frame, slave::HeadPose& out) {
            const slave::HeadPose* pose = track->at(frame);
            if (pose) out = *pose;
            return pose != nullptr;
        };
    }
    try {
        RunSession session;  // its folder and children go however this block is left
        const RunEndpoints e = plan_endpoints(plan.endpoint, session.dir());
        // Refused here, before anything starts, rather than inside the program: an endpoint its
        // keys do not allow, or a port another process holds.
        const std::pair<const char*, const std::string*> channels[] = {
            {"stream", &e.stream}, {"journal", &e.journal}, {"keeper", &e.keeper}, {"control channel", &e.control}};
        for (const auto& [role, endpoint] : channels) {
            if (endpoint->empty()) continue;
            net::check_endpoint(*endpoint, net::process_security(), true);
            net::check_can_bind(*endpoint, role);
        }
        std::fprintf(stderr, "glcast run: stream on %s, journal on %s%s%s, control on %s%s\n", e.stream.c_str(),
                     e.journal.c_str(), e.reachable ? ", keeper on " : "", e.keeper.c_str(), e.control.c_str(),
                     net::process_security().keyed() ? " (CURVE)" : "");
        // The control channel (swap barrier, status) outlives the program: slaves may present its
        // last frames after it ended.
        std::vector<std::string> tile_names;
        for (const auto& t : plan.tiles) tile_names.push_back(t.first);
        // A live tracker: its newest pose for every frame, the last one while it is silent.
        std::unique_ptr<PoseReceiver> tracker;
        if (!a.tracker.empty()) {
            net::check_endpoint(a.tracker, net::process_security(), true);
            tracker = std::make_unique<PoseReceiver>(a.tracker);
            std::fprintf(stderr, "glcast run: head poses on %s\n", tracker->bound().c_str());
            plan.swap_barrier = true;
            head_for = [&tracker](uint64_t, slave::HeadPose& out) { return tracker->latest(out); };
        }
        std::vector<std::string> unbound;
        const auto keys = tile_keys(plan.tiles, here, net::process_security(), &unbound);
        for (const std::string& tile : unbound)
            std::fprintf(stderr, "glcast run: tile %s is on a machine whose key is not in %s/authorized/ (as MACHINE.pub, "
                                 "the machine's name in the config): no slave can speak for it\n",
                         tile.c_str(), net::process_security().dir.c_str());
        // (before the channel that feeds it, so that it outlives it)
        std::unique_ptr<WallTiming> timing;
        if (!a.timing.empty()) timing = std::make_unique<WallTiming>(a.timing, session.dir() + "/swaps", tile_names);
        WallControl wall(e.control, tile_names, plan.swap_barrier, head_for, keys);
        if (timing)
            wall.set_timing_sink([&timing](const std::string& tile, uint64_t frame, const TileFrameTiming& t) {
                timing->add(tile, frame, t);
            });
        wall.set_started_effects(slave::LiveEffects::from(plan.effects));
        WallStatus view(wall, plan.tiles, a.status_json);
        std::unique_ptr<Dashboard> dashboard;
        if (!a.dashboard.empty()) {
            dashboard = std::make_unique<Dashboard>(a.dashboard, wall, view, wall_layout(plan.config ? &*plan.config : nullptr));
            std::fprintf(stderr, "glcast run: dashboard on %s%s\n", dashboard->url().c_str(),
                         dashboard->needs_token() ? " (not loopback: only with this token; keep it to the operators)" : "");
        }
        // Slaves first: they join through the journal whenever the program starts publishing.
        start_slaves(session, a, plan, e, here);
        const int remote_here = wait_for_remote_tiles(wall, plan.remote_tiles, a.wait_tiles);
        std::map<std::string, std::string> env{
            {"GLCAST_PUBLISH", e.publish},
            {"GLCAST_JOURNAL_ENDPOINT", e.journal},
            {"GLCAST_WAIT_SUBSCRIBERS", std::to_string(session.slaves() + size_t(remote_here) + (e.reachable ? 1 : 0))},
            {"GLCAST_LOCKSTEP", a.lockstep ? std::to_string(plan.tiles.size()) : "0"},
            {"GLCAST_PUBLISHED_MARK", session.dir() + "/published"}};
        if (timing) env["GLCAST_TEST_SWAP_LOG"] = session.dir() + "/swaps";
        if (a.frames) {
            env["GLCAST_FRAMES"] = std::to_string(a.frames);
            env["GLCAST_EXIT_AFTER_FRAMES"] = "1";
        }
        int status = 0, failed = 0;
        {
            status = run_with_shim(program, env);
            session.end_keeping();  // the keeper ends with the stream now
            // A program that never ran (run_with_shim failed, or execvp exited 127) published nothing:
            // its slaves have nothing to finish.
            if (status < 0 || status == 127) {
                std::fprintf(stderr, "glcast run: the program did not run; stopping the slaves\n");
                session.stop_all();
            } else if (access((session.dir() + "/published").c_str(), F_OK) != 0) {
                // (the shim makes the mark at the program's first GL call: without it the slaves
                // wait for a stream that will never come)
                std::fprintf(stderr, "glcast run: the program made no GL calls; nothing to show, stopping the slaves\n");
                session.stop_all();
            }
            // The program has ended: slaves finish the stream and exit; give them time, then stop them.
            failed = session.wait_for_slaves(std::chrono::steady_clock::now() + std::chrono::seconds(120));
            wait_for_remote_tiles_idle(wall, plan.remote_tiles);
        }
        if (tracker)
            std::fprintf(stderr, "glcast run: pose socket: %llu poses taken, %llu refused, %llu peers without an authorized key\n",
                         (unsigned long long)tracker->accepted(), (unsigned long long)tracker->refused(),
                         (unsigned long long)tracker->unauthenticated());
        if (status != 0) return status < 0 ? 1 : status;
        return failed ? 1 : 0;
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "glcast run: %s\n", ex.what());
        return 1;
    }
}

}  // namespace

Command add_run(CLI::App& glcast) {
    auto a = std::make_shared<RunArgs>();
    CLI::App* app = glcast.add_subcommand("run", "run a program on a wall: the shim, and one local slave per tile");
    app->footer("PROGRAM and its arguments follow '--'; glcast reads none of them. Tiles of other machines (a\n"
                "tile's \"machine\" in the config) are shown by their glcast slave --service (docs/wall.md).");
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
    app->add_flag("--lockstep", a->lockstep, "hold the program at each swap until every tile has replayed the frame");
    add_security_options(*app, a->keys, a->insecure);
    app->add_option("--machine", a->machine,
                    "this machine's name in the config's tiles: only its tiles get a slave here (default:\n"
                    "GLCAST_MACHINE or the host name)")
        ->type_name("NAME");
    add_int(*app, "--wait-tiles", a->wait_tiles, 0, 3600,
            "seconds to wait for the tiles of other machines before starting the program (default 10)")
        ->type_name("SECONDS");
    app->add_option("--head-poses", a->head_poses,
                    "play a recorded viewer's head poses on an immersive wall, JSON lines {\"frame\": N,\n"
                    "\"position\": [x,y,z], \"orientation\": [w,x,y,z]}, each handed to every tile with its frame\n"
                    "(turns the swap barrier on; docs/immersive.md)")
        ->type_name("FILE");
    app->add_option("--tracker", a->tracker,
                    "bind the wall's pose socket here (ZeroMQ PULL; a tracker bridge pushes JSON head poses,\n"
                    "docs/immersive.md); default: the config's viewer.tracker. Turns the swap barrier on")
        ->type_name("ENDPOINT");
    app->add_option("--status-json", a->status_json, "write the wall's status once a second as JSON lines")
        ->type_name("FILE");
    app->add_option("--timing", a->timing,
                    "write when each frame left the program and when each tile received, replayed and\n"
                    "presented it, on one clock, as JSON lines (docs/wall.md)")
        ->type_name("FILE");
    app->add_option("--dashboard", a->dashboard,
                    "serve the wall's dashboard here: its tiles with thumbnails and status, plots, effects\n"
                    "switched live (docs/wall.md). Loopback needs nothing; another address needs the token\n"
                    "printed at start")
        ->type_name("ADDRESS:PORT");
    add_int(*app, "--max-local-slaves", a->max_local_slaves, 1, 256,
            "the most tiles this machine may show, one slave process each (default 16)")
        ->type_name("N");
    add_effect_options(*app, a->effects, &a->effect_args);
    return {app, [a](const std::vector<std::string>& program) { return run(*a, program); }, true};
}

}  // namespace glcast::cli
