// `glcast slave`: one tile of a wall on this machine, fed by the master over ZeroMQ.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "cli/tile_options.h"
#include "common/image.h"
#include "slave/network_source.h"
#include "slave/replayer.h"

namespace glcast::cli {

using namespace glcast::slave;

namespace {

struct SlaveArgs {
    std::string endpoint, journal, keeper, backend_kind = "egl", out_dir, config_path, tile_name, barrier_endpoint;
    ReplayOptions opt;
    int wait_seconds = 60;
    bool quiet = false, lockstep = false;
};

int slave(SlaveArgs& a) {
    const std::string &endpoint = a.endpoint, &journal = a.journal, &out_dir = a.out_dir, &tile_name = a.tile_name,
                      &barrier_endpoint = a.barrier_endpoint;
    ReplayOptions& opt = a.opt;
    const bool quiet = a.quiet, lockstep = a.lockstep;
    std::string error;
    if (!a.config_path.empty()) {  // --config and --tile come together (CLI11 checks)
        if (!tile_options(a.config_path, tile_name, opt, error)) {
            std::fprintf(stderr, "glcast slave: %s\n", error.c_str());
            return 1;
        }
    }
    if (!out_dir.empty() && !make_directories(out_dir, error)) {
        std::fprintf(stderr, "glcast slave: --out: %s\n", error.c_str());
        return 1;
    }
    std::unique_ptr<Backend> backend = make_backend(a.backend_kind, error);
    if (!backend) {
        std::fprintf(stderr, "glcast slave: %s\n", error.c_str());
        return 1;
    }
    const std::string label = tile_name.empty() ? std::string("slave") : tile_name;
    if (opt.tile.enabled && !opt.view.enabled)  // a window at its tile's place on the canvas
        backend->set_position(opt.tile.x, opt.tile.canvas_height - opt.tile.y - opt.tile.height);
    try {
        NetworkSource source(endpoint, journal, a.wait_seconds, a.keeper);
        Replayer replayer(std::move(backend), opt);
        replayer.set_frame(source.joined_frame());
        auto say_join = [&] {
            const NetworkSource::JoinCost& j = source.join_cost();
            if (j.state_messages || j.journal_messages)
                std::fprintf(stderr, "glcast slave %s: joined at frame %" PRIu64 ": %" PRIu64 " snapshot and %" PRIu64
                                     " journal messages, %" PRIu64 " bytes, in %.3f s (the keeper's state in %.3f s)\n",
                             label.c_str(), source.joined_frame(), j.state_messages, j.journal_messages, j.bytes, j.seconds,
                             j.state_seconds);
        };
        say_join();
        source.on_restart = [&] {
            std::fprintf(stderr, "glcast slave %s: the journal no longer holds them; starting over from %s\n",
                         label.c_str(), a.keeper.empty() ? "the master's journal" : "the keeper");
            replayer.reset();
        };
        source.on_joined = [&](uint64_t frame) {
            replayer.set_frame(frame);
            say_join();
        };
        source.on_gap = [&] {
            std::fprintf(stderr, "glcast slave %s: messages lost (%s); asking the master's journal for them\n",
                         label.c_str(), source.gap().c_str());
        };
        // Test hook: the time each frame is presented, one "frame seconds" line per present.
        FILE* present_log = std::getenv("GLCAST_TEST_PRESENT_LOG") ? std::fopen(std::getenv("GLCAST_TEST_PRESENT_LOG"), "w") : nullptr;
        replayer.before_present = [&](uint64_t frame) {
            if (!barrier_endpoint.empty() && source.live() && !source.barrier(barrier_endpoint, frame, 5000))
                std::fprintf(stderr, "glcast slave %s: swap barrier: frame %" PRIu64 " went alone after 5 s\n",
                             label.c_str(), frame);
            if (present_log)
                std::fprintf(present_log, "%" PRIu64 " %.6f\n", frame,
                             std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count());
            if (lockstep && source.caught_up()) source.done(frame);
        };
        auto last = std::chrono::steady_clock::now();
        uint64_t frames_at_last = 0, bytes_at_last = 0;
        replayer.on_frame = [&](uint64_t frame, int w, int h, const std::vector<uint8_t>& rgba) {
            // Frames replayed while catching up from the journal are written too: they are the
            // same frames, only late.
            if (!out_dir.empty()) {
                char name[48];
                std::snprintf(name, sizeof name, "/frame-%06" PRIu64 ".png", frame);
                std::string err;
                if (!write_png(out_dir + name, Image{w, h, rgba}, err)) std::fprintf(stderr, "glcast slave: %s\n", err.c_str());
            }
            const auto now = std::chrono::steady_clock::now();
            const double dt = std::chrono::duration<double>(now - last).count();
            if (!quiet && dt >= 1.0) {
                std::fprintf(stderr, "\rglcast slave %s: frame %" PRIu64 ", %.1f fps, %.2f MB/s, lag %" PRId64
                                     " frames, %" PRIu64 " recoveries   ",
                             label.c_str(), frame, (replayer.stats().frames - frames_at_last) / dt,
                             (source.bytes() - bytes_at_last) / dt / 1e6, int64_t(source.master_frame()) - int64_t(frame),
                             source.recoveries());
                last = now;
                frames_at_last = replayer.stats().frames;
                bytes_at_last = source.bytes();
            }
        };
        // Frames are read back only when written; without --out the status line still needs the
        // swap callback, which costs a readback: acceptable for a wall tile's status.
        replayer.replay(source);
        if (present_log) std::fclose(present_log);
        const ReplayStats& s = replayer.stats();
        std::fprintf(stderr, "\nglcast slave %s: the program ended; %" PRIu64 " frames, %" PRIu64 " errors, %" PRIu64
                             " recoveries\n",
                     label.c_str(), s.frames, s.errors, source.recoveries());
        return s.errors ? 1 : 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast slave %s: %s\n", label.c_str(), e.what());
        return 1;
    }
}

}  // namespace

Command add_slave(CLI::App& glcast) {
    auto a = std::make_shared<SlaveArgs>();
    CLI::App* app = glcast.add_subcommand("slave", "one tile of a wall: subscribe to a master (glcast run) and replay");
    app->footer("glcast run prints the endpoints of its stream, journal and swap barrier.");
    app->add_option("--connect", a->endpoint, "the master's stream (tcp://HOST:PORT, ipc://PATH, epgm://...)")
        ->required()
        ->type_name("ENDPOINT");
    app->add_option("--journal", a->journal, "the master's journal, to join a program already running")
        ->type_name("ENDPOINT");
    app->add_option("--keeper", a->keeper,
                    "a keeper of the master's stream (glcast keeper): join from a snapshot of the live\n"
                    "state instead of the whole journal")
        ->type_name("ENDPOINT");
    CLI::Option* config = app->add_option("--config", a->config_path, "a display config: with --tile, the tile to show")
                              ->type_name("FILE");
    CLI::Option* tile = app->add_option("--tile", a->tile_name, "the tile of --config to show")->type_name("NAME");
    config->needs(tile);
    tile->needs(config);
    app->add_option("--backend", a->backend_kind, "egl (headless, the default), osmesa or window")
        ->type_name("egl|osmesa|window");
    app->add_option("--out", a->out_dir, "write the tile's frames into DIR as frame-NNNNNN.png")->type_name("DIR");
    add_frame_range(*app, "--frames", LoneFrame::from_that_frame, a->opt.first_frame, a->opt.last_frame,
                    "only frames A through B (either may be omitted; N alone: from frame N on)");
    add_int(*app, "--wait", a->wait_seconds, 1, 86400, "how long to wait for the master (default 60)")
        ->type_name("SECONDS");
    app->add_flag("--quiet", a->quiet, "no status line");
    app->add_option("--swap-barrier", a->barrier_endpoint,
                    "present each frame only when every tile of the wall has it")
        ->type_name("ENDPOINT");
    app->add_flag("--lockstep", a->lockstep, "report each replayed frame to a master that waits for its slaves");
    add_effect_options(*app, a->opt.effects);  // a display config's "effects" add to them
    add_limit_option(*app, a->opt.limits);
    return {app, [a](const std::vector<std::string>&) { return slave(*a); }};
}

}  // namespace glcast::cli
