// `glcast slave`: one tile of a wall on this machine, fed by the master over ZeroMQ.
#include "cli/commands.h"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "slave/image.h"
#include "slave/network_source.h"
#include "slave/replayer.h"
#include "cli/tile_options.h"

namespace glcast::slave {

const char* kSlaveUsage =
    "  slave --connect ENDPOINT [--journal ENDPOINT] [--config FILE --tile NAME]\n"
    "        [--backend egl|osmesa|window] [--out DIR] [--frames A:B] [--wait SECONDS] [--quiet]\n"
    "        [--swap-barrier ENDPOINT] [--lockstep] [--effects LIST] [--effect-param NAME=VALUE]...\n"
    "        one tile of a wall: subscribe to a master (glcast run prints its endpoints), join\n"
    "        through its journal, replay; --out writes the tile's frames as PNGs; --swap-barrier\n"
    "        presents each frame only when every tile of the wall has it (glcast run prints the endpoint);\n"
    "        --lockstep reports each replayed frame to a master that waits for its slaves;\n"
    "        --effects/--effect-param as for replay (a display config's \"effects\" add to them)\n";

namespace {

int usage(const std::string& msg) {
    std::fprintf(stderr, "glcast slave: %s\nusage: glcast\n%s", msg.c_str(), kSlaveUsage);
    return 2;
}

}  // namespace

int slave_main(const std::vector<std::string>& args) {
    std::string endpoint, journal, backend_kind = "egl", out_dir, config_path, tile_name;
    ReplayOptions opt;
    int wait_seconds = 60;
    bool quiet = false, lockstep = false;
    std::string barrier_endpoint;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const bool v = i + 1 < args.size();
        if (a == "--connect" && v) endpoint = args[++i];
        else if (a == "--journal" && v) journal = args[++i];
        else if (a == "--config" && v) config_path = args[++i];
        else if (a == "--tile" && v) tile_name = args[++i];
        else if (a == "--backend" && v) backend_kind = args[++i];
        else if (a == "--out" && v) out_dir = args[++i];
        else if (a == "--quiet") quiet = true;
        else if (a == "--swap-barrier" && v) barrier_endpoint = args[++i];
        else if (a == "--lockstep") lockstep = true;
        else if (a == "--effects" && v) {
            std::string error;
            if (!opt.effects.enable(args[++i], error)) return usage("--effects: " + error);
        } else if (a == "--effect-param" && v) {
            std::string error;
            if (!opt.effects.params.set_assignment(args[++i], error)) return usage(error);
        } else if (a == "--wait" && v) {
            wait_seconds = std::atoi(args[++i].c_str());
            if (wait_seconds <= 0 || wait_seconds > 86400) return usage("--wait takes 1..86400 seconds");
        } else if (a == "--frames" && v) {
            unsigned long long lo = 0, hi = UINT64_MAX;
            if (std::sscanf(args[++i].c_str(), "%llu:%llu", &lo, &hi) < 1 || lo > hi) return usage("--frames takes A:B");
            opt.first_frame = lo;
            opt.last_frame = hi;
        } else {
            return usage("unknown option '" + a + "'");
        }
    }
    if (endpoint.empty()) return usage("--connect ENDPOINT is required");
    std::string error;
    if (!config_path.empty() || !tile_name.empty()) {
        if (config_path.empty() || tile_name.empty()) return usage("--config and --tile go together");
        if (!tile_options(config_path, tile_name, opt, error)) {
            std::fprintf(stderr, "glcast slave: %s\n", error.c_str());
            return 1;
        }
    }
    if (!out_dir.empty() && mkdir(out_dir.c_str(), 0755) != 0 && errno != EEXIST) {
        std::fprintf(stderr, "glcast slave: cannot create %s: %s\n", out_dir.c_str(), std::strerror(errno));
        return 1;
    }
    std::unique_ptr<Backend> backend = make_backend(backend_kind, error);
    if (!backend) {
        std::fprintf(stderr, "glcast slave: %s\n", error.c_str());
        return 1;
    }
    const std::string label = tile_name.empty() ? std::string("slave") : tile_name;
    if (opt.tile.enabled && !opt.view.enabled)  // a window at its tile's place on the canvas
        backend->set_position(opt.tile.x, opt.tile.canvas_height - opt.tile.y - opt.tile.height);
    try {
        NetworkSource source(endpoint, journal, wait_seconds);
        Replayer replayer(std::move(backend), opt);
        source.on_restart = [&] {
            std::fprintf(stderr, "glcast slave %s: messages lost (%s); starting over from the master's journal\n",
                         label.c_str(), source.gap().c_str());
            replayer.reset();
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
            if (lockstep && source.live()) source.done(frame);
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

}  // namespace glcast::slave
