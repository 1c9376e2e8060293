// `glcast slave`: one tile of a wall on this machine, fed by the master over ZeroMQ.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <thread>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "cli/stereo_tile.h"
#include "cli/tile_options.h"
#include "common/environment.h"
#include "common/image.h"
#include "common/jpeg.h"
#include "net/wall_endpoints.h"
#include "slave/network_source.h"
#include "slave/replayer.h"
#include "slave/wall_link.h"
#include "display_configs/display_config.h"

namespace glcast::cli {

using namespace glcast::slave;

namespace {

constexpr int kBarrierWaitMs = 10000;  // longer than the wall's own drop (cli/wall_control.h): the wall decides
constexpr int kFirstHeadWaitMs = 1000;  // the run answers at once; a run without a tracker says so with no pose

struct SlaveArgs {
    std::string endpoint, journal, keeper, backend_kind = "egl", out_dir, config_path, tile_name, control, keys, machine;
    ReplayOptions opt;
    int wait_seconds = 60;
    bool quiet = false, lockstep = false, swap_barrier = false, service = false, insecure = false;
};

// A display config's "master" gives a display machine's slave every endpoint (docs/wall.md).
void endpoints_from_config(const DisplayConfig& config, SlaveArgs& a) {
    if (!config.master.given) return;
    const net::WallEndpoints wall = net::wall_endpoints_at(config.master.address, config.master.port);
    if (a.endpoint.empty()) a.endpoint = wall.stream;
    if (a.journal.empty()) a.journal = wall.journal;
    if (a.keeper.empty()) a.keeper = wall.keeper;
    if (a.control.empty()) a.control = wall.control;
    a.swap_barrier |= config.swap_barrier;
}

// Settles --config, the endpoints, the keys and the output folder; false (with the exit status
// in `status`) when the slave cannot start.
bool prepare(SlaveArgs& a, int& status) {
    std::string error;
    status = 1;
    if (!a.config_path.empty()) {  // --config and --tile come together (CLI11 checks)
        DisplayConfig config;
        if (!tile_options(a.config_path, a.tile_name, a.opt, error) || !load_display_config(a.config_path, config, error)) {
            std::fprintf(stderr, "glcast slave: %s\n", error.c_str());
            return false;
        }
        endpoints_from_config(config, a);
        if (a.keys.empty() && !config.keys.empty()) a.keys = relative_to(a.config_path, config.keys);
    }
    if (a.endpoint.empty()) {
        std::fprintf(stderr, "glcast slave: no stream to subscribe to: give --connect, or --config with a \"master\"\n");
        status = 2;
        return false;
    }
    if (!use_keys(a.keys, a.insecure, "glcast slave", error)) return false;
    // A tile of a run's wall follows the scene from the start, so that the operator may switch
    // passes on while the program runs (glcast ctl, the dashboard).
    if (!a.control.empty()) a.opt.effects.live = true;
    if (!a.out_dir.empty() && !make_directories(a.out_dir, error)) {
        std::fprintf(stderr, "glcast slave: --out: %s\n", error.c_str());
        return false;
    }
    return true;
}

// One tile's slave: the replayer, its report to glcast run's control channel, and each program
// it replays in turn (one, or every program that comes with --service).
class SlaveRun {
public:
    SlaveRun(SlaveArgs& a, std::unique_ptr<Backend> backend)
        : a_(a), label_(a.tile_name.empty() ? std::string("window") : a.tile_name) {
        if (!a.control.empty())
            link_ = std::make_unique<WallLink>(a.control, label_, a.machine.empty() ? machine_name() : a.machine);
        std::string error;
        if (a.opt.stereo != StereoMode::none) {
            if (!open_stereo_tile(a.backend_kind, a.opt, stereo_, error)) throw std::runtime_error(error);
        } else {
            replayer_ = std::make_unique<Replayer>(std::move(backend), a.opt);
        }
        if (const std::string& log = environment().test_present_log; !log.empty())
            present_log_.reset(std::fopen(log.c_str(), "w"));
    }
    const std::string& label() const { return label_; }

    int run() {
        for (uint64_t program = 1;; program++) {
            if (a_.service) wait_for_program();
            std::unique_ptr<NetworkSource> source = join();
            if (!source) continue;
            const std::string out = program_folder(program);
            try {
                replay(*source, out);
            } catch (const std::exception& e) {
                if (!a_.service) throw;
                std::fprintf(stderr, "\nglcast slave %s: %s; waiting for the next program\n", label_.c_str(), e.what());
                continue;
            }
            const ReplayStats& s = first().stats();
            std::fprintf(stderr, "\nglcast slave %s: the program ended%s; %" PRIu64 " frames, %" PRIu64 " errors, %" PRIu64
                                 " recoveries\n",
                         label_.c_str(), source->replaced() ? " (a new one started)" : "", s.frames, s.errors,
                         source->recoveries());
            if (!a_.service) return s.errors ? 1 : 0;
        }
    }

private:
    struct FileCloser {
        void operator()(FILE* f) const { std::fclose(f); }
    };
    // What the status line and the report count between two of their updates.
    struct Rates {
        std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
        uint64_t frames = 0, bytes = 0;
    };

    void say_status(bool force) {  // to glcast run's status line, at most once a second
        const auto now = std::chrono::steady_clock::now();
        if (!link_ || (!force && now - last_report_ < std::chrono::seconds(1))) return;
        link_->report(report_);
        last_report_ = now;
    }

    // Idle until a program publishes; a display machine's slave outlives every program.
    void wait_for_program() {
        report_ = TileReport{};
        say_status(true);
        std::fprintf(stderr, "glcast slave %s: waiting for a program on %s\n", label_.c_str(), a_.endpoint.c_str());
        wait_for_stream(a_.endpoint, [this] { say_status(false); });
        report_.state = "joining";
        say_status(true);
    }

    // Subscribed and joined; null for a service whose program ended or vanished meanwhile.
    std::unique_ptr<NetworkSource> join() {
        try {
            return std::make_unique<NetworkSource>(a_.endpoint, a_.journal, a_.wait_seconds, a_.keeper);
        } catch (const std::exception& e) {
            if (!a_.service) throw;
            std::fprintf(stderr, "glcast slave %s: %s\n", label_.c_str(), e.what());
            std::this_thread::sleep_for(std::chrono::seconds(1));
            return nullptr;
        }
    }

    // A service writes each program's frames to a folder of its own: DIR/program-N.
    std::string program_folder(uint64_t program) const {
        if (!a_.service || a_.out_dir.empty()) return a_.out_dir;
        char sub[32];
        std::snprintf(sub, sizeof sub, "/program-%04" PRIu64, program);
        std::string error, folder = a_.out_dir + sub;
        if (!make_directories(folder, error)) throw std::runtime_error("--out: " + error);
        return folder;
    }

    void say_join(const NetworkSource& source) const {
        const NetworkSource::JoinCost& j = source.join_cost();
        if (j.state_messages || j.journal_messages)
            std::fprintf(stderr, "glcast slave %s: joined at frame %" PRIu64 ": %" PRIu64 " snapshot and %" PRIu64
                                 " journal messages, %" PRIu64 " bytes, in %.3f s (the keeper's state in %.3f s)\n",
                         label_.c_str(), source.joined_frame(), j.state_messages, j.journal_messages, j.bytes, j.seconds,
                         j.state_seconds);
    }

    // The tile's replayer: the one, or the left eye's of a stereo tile (its stats stand for both).
    Replayer& first() { return stereo_.pair ? stereo_.pair->left() : *replayer_; }
    void reset_replay() { stereo_.pair ? stereo_.pair->reset() : replayer_->reset(); }
    void set_frame(uint64_t frame) { stereo_.pair ? stereo_.pair->set_frame(frame) : replayer_->set_frame(frame); }

    void replay(NetworkSource& source, const std::string& out) {
        reset_replay();
        set_frame(source.joined_frame());
        say_join(source);
        source.on_restart = [this] {
            std::fprintf(stderr, "glcast slave %s: the journal no longer holds them; starting over from %s\n",
                         label_.c_str(), a_.keeper.empty() ? "the master's journal" : "the keeper");
            reset_replay();
        };
        source.on_joined = [this, &source](uint64_t frame) {
            set_frame(frame);
            say_join(source);
        };
        source.on_gap = [this, &source] {
            std::fprintf(stderr, "glcast slave %s: messages lost (%s); asking the master's journal for them\n",
                         label_.c_str(), source.gap().c_str());
        };
        source.on_idle = [this] { say_status(false); };
        // A tracked viewer: the pose the wall's run handed on with the last GO, from its frame on
        // (each eye of a stereo tile asks at its own frame's start, on its own thread); the first
        // frame's, which no GO carried, is asked for once.
        next_head_.reset();
        asked_first_head_ = false;
        auto head_at = [this, &source](uint64_t frame, HeadPose& out) {
            std::lock_guard<std::mutex> lock(head_mutex_);
            if (!next_head_ && !asked_first_head_ && link_ && a_.swap_barrier && source.live()) {
                asked_first_head_ = true;
                HeadPose first;
                if (link_->first_head(frame, kFirstHeadWaitMs, first)) next_head_ = {frame, first};
            }
            if (!next_head_ || frame < next_head_->first) return false;
            out = next_head_->second;
            return true;
        };
        Rates rates;
        rates.frames = first().stats().frames;
        if (stereo_.pair) {
            StereoPair& pair = *stereo_.pair;
            pair.head_for = head_at;
            pair.before_present = [this, &source, &rates](uint64_t frame) { before_present(source, rates, frame); };
            pair.on_frame = [this, &out](uint64_t frame, const Image& tile, const Image& left,
                                                          const Image& right) {
                if (stereo_.window) stereo_.window->show(tile, left, right);
                send_thumbnail(frame, &tile);
                std::string err;
                if (!out.empty() && !write_stereo_frame(out, frame, a_.opt.stereo, tile, left, right, err))
                    std::fprintf(stderr, "glcast slave: %s\n", err.c_str());
            };
            pair.replay(source);
            if (link_) link_->flush_timings();
            return;
        }
        Replayer& replayer = *replayer_;
        replayer.before_frame = [this, &replayer, head_at](uint64_t frame) {
            HeadPose head;
            if (head_at(frame, head)) move_head(replayer, head, frame, ("glcast slave " + label_).c_str());
        };
        // Every frame replayed is counted for the status at its present, whether it is written or
        // not (--frames A:B writes some); frames are read back only to be written.
        replayer.before_present = [this, &source, &rates](uint64_t frame) { before_present(source, rates, frame); };
        replayer.after_present = [this](uint64_t frame) { after_present(frame); };
        replayer.on_frame = nullptr;
        if (!out.empty())
            replayer.on_frame = [&out](uint64_t frame, int w, int h, const std::vector<uint8_t>& rgba) {
                write_frame(out, frame, w, h, rgba);
            };
        replayer.replay(source);
        if (link_) link_->flush_timings();
    }

    // The passes switched live (slave/live_effects.h): the newest state the run sent, applied
    // from its frame on. Called before each present, after the barrier: the change is in place
    // for the next frame's passes.
    void follow_live_effects(uint64_t frame) {
        slave::LiveEffects e;
        if (link_ && link_->take_effects(e) && e.version != report_.effects_version) pending_effects_ = e;
        if (!pending_effects_ || pending_effects_->frame > frame + 1) return;
        const slave::LiveEffects& next = *pending_effects_;
        const effects::EffectsSettings settings = next.applied_to(a_.opt.effects);
        if (stereo_.pair) {
            stereo_.pair->left().set_effects(settings);
            stereo_.pair->right().set_effects(settings);
        } else {
            replayer_->set_effects(settings);
        }
        std::fprintf(stderr, "\nglcast slave %s: effects %s from frame %" PRIu64 "%s\n", label_.c_str(),
                     next.enabled_list().c_str(), std::max(frame + 1, next.frame),
                     next.frame < frame + 1 ? " (asked from an earlier one: this tile was behind)" : "");
        report_.effects_version = next.version;
        pending_effects_.reset();
    }

    // About once a second, a small JPEG of the frame about to be shown, for the dashboard.
    void send_thumbnail(uint64_t frame, const Image* shown) {
        const auto now = std::chrono::steady_clock::now();
        if (!link_ || now - last_thumbnail_ < std::chrono::seconds(1)) return;
        last_thumbnail_ = now;
        Image image;
        if (!shown) {
            if (!replayer_->read_shown(image)) return;
            shown = &image;
        }
        std::string jpeg, error;
        if (thumbnail_jpeg(*shown, 256, 70, jpeg, error)) link_->thumbnail(frame, jpeg);
    }

    void before_present(NetworkSource& source, Rates& rates, uint64_t frame) {
        // The frame's times for the run's --timing (docs/wall.md): live frames only (one caught
        // up from the journal arrived long after the program drew it, and is not held).
        pending_timing_.reset();
        if (link_ && source.live()) pending_timing_ = FrameTiming{frame, source.arrived(), steady_seconds(), 0};
        frame_counted(source, rates, frame);
        // After one wait in vain (glcast run is gone), later frames wait briefly until a GO comes again.
        bool held = false;
        if (link_ && a_.swap_barrier && source.live()) {
            const int wait_ms = barrier_answered_ ? kBarrierWaitMs : 100;
            HeadPose head;
            bool has_head = false;
            held = barrier_answered_ = link_->barrier(frame, wait_ms, &head, &has_head);
            if (has_head) {
                std::lock_guard<std::mutex> lock(head_mutex_);
                next_head_ = {frame + 1, head};
            }
            if (!barrier_answered_ && wait_ms == kBarrierWaitMs)
                std::fprintf(stderr, "\nglcast slave %s: swap barrier: frame %" PRIu64 " went alone after %d s\n",
                             label_.c_str(), frame, kBarrierWaitMs / 1000);
        }
        if (present_log_) {
            std::fprintf(present_log_.get(), "%" PRIu64 " %.6f %d\n", frame,
                         std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(), held);
            std::fflush(present_log_.get());
        }
        follow_live_effects(frame);
        if (!stereo_.pair) send_thumbnail(frame, nullptr);
        if (a_.lockstep && source.caught_up()) source.done(frame);
        if (stereo_.pair) after_present(frame);  // (its eyes are shown together, just after)
    }

    // The frame is on the tile: its times go to the run, and the clock is sampled now, when a
    // wait delays the next frame's replay rather than this one's present.
    void after_present(uint64_t frame) {
        if (!link_) return;
        if (pending_timing_ && pending_timing_->frame == frame) {
            pending_timing_->presented = steady_seconds();
            link_->timing(*pending_timing_);
        }
        pending_timing_.reset();
        link_->sync_clock();
    }

    // Frames replayed while catching up from the journal are written too: they are the same
    // frames, only late.
    static void write_frame(const std::string& out, uint64_t frame, int width, int height,
                            const std::vector<uint8_t>& rgba) {
        char name[48];
        std::snprintf(name, sizeof name, "/frame-%06" PRIu64 ".png", frame);
        std::string err;
        if (!write_png(out + name, Image{width, height, rgba}, err)) std::fprintf(stderr, "glcast slave: %s\n", err.c_str());
    }

    void frame_counted(const NetworkSource& source, Rates& rates, uint64_t frame) {
        const auto now = std::chrono::steady_clock::now();
        const double dt = std::chrono::duration<double>(now - rates.last).count();
        report_.state = source.live() ? "live" : "joining";
        report_.frame = frame;
        report_.master_frame = source.master_frame();
        report_.lag = std::max<int64_t>(0, int64_t(source.master_frame()) - int64_t(frame));  // 0 until live
        report_.recoveries = source.recoveries();
        if (dt >= 1.0) {
            report_.fps = (first().stats().frames - rates.frames) / dt;
            report_.mbps = (source.bytes() - rates.bytes) / dt / 1e6;
            if (!a_.quiet)
                std::fprintf(stderr, "\rglcast slave %s: frame %" PRIu64 ", %.1f fps, %.2f MB/s, lag %" PRId64
                                     " frames, %" PRIu64 " recoveries   ",
                             label_.c_str(), frame, report_.fps, report_.mbps, report_.lag, report_.recoveries);
            rates.last = now;
            rates.frames = first().stats().frames;
            rates.bytes = source.bytes();
        }
        say_status(false);
    }

    SlaveArgs& a_;
    const std::string label_;  // glcast run names a config-less slave's tile "window" too
    std::unique_ptr<WallLink> link_;
    std::unique_ptr<Replayer> replayer_;  // or, for a stereo tile:
    StereoTile stereo_;
    std::unique_ptr<FILE, FileCloser> present_log_;  // test hook: "frame seconds held-by-the-barrier" a present
    TileReport report_;
    std::optional<FrameTiming> pending_timing_;  // the frame being presented
    std::chrono::steady_clock::time_point last_report_ = std::chrono::steady_clock::now() - std::chrono::seconds(10);
    bool barrier_answered_ = true;
    std::optional<std::pair<uint64_t, HeadPose>> next_head_;  // a pose from the barrier, and its frame
    bool asked_first_head_ = false;
    std::mutex head_mutex_;  // (a stereo tile's eyes ask from two threads)
    std::optional<slave::LiveEffects> pending_effects_;          // from the run, for a later frame
    std::chrono::steady_clock::time_point last_thumbnail_;
};

int slave(SlaveArgs& a) {
    int status = 0;
    if (!prepare(a, status)) return status;
    std::string error;
    std::unique_ptr<Backend> backend = a.opt.stereo == StereoMode::none ? make_backend(a.backend_kind, error) : nullptr;
    if (!backend && a.opt.stereo == StereoMode::none) {
        std::fprintf(stderr, "glcast slave: %s\n", error.c_str());
        return 1;
    }
    const ReplayOptions& opt = a.opt;
    if (backend && opt.tile.enabled && !opt.view.enabled)  // a window at its tile's place on the canvas
        backend->set_position(opt.tile.x, opt.tile.canvas_height - opt.tile.y - opt.tile.height);
    const std::string label = a.tile_name.empty() ? std::string("window") : a.tile_name;
    try {
        SlaveRun run(a, std::move(backend));
        return run.run();
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
    app->add_option("--connect", a->endpoint,
                    "the master's stream (tcp://HOST:PORT, ipc://PATH, epgm://...; default: the config's \"master\")")
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
    app->add_option("--control", a->control,
                    "glcast run's control channel: status reports, and the swap barrier with --swap-barrier\n"
                    "(a display config's \"master\" gives it, as it gives --connect, --journal and --keeper)")
        ->type_name("ENDPOINT");
    app->add_flag("--swap-barrier", a->swap_barrier,
                  "present each frame only when every tile of the wall has it (the config's \"swap_barrier\")");
    app->add_flag("--service", a->service,
                  "stay up: wait for a program, show it, and wait for the next when it ends (systemd's\n"
                  "glcast-slave@TILE.service runs this)");
    add_security_options(*app, a->keys, a->insecure);
    app->add_option("--machine", a->machine, "this machine's name in the config's tiles (default: GLCAST_MACHINE or the host name)")
        ->type_name("NAME");
    app->add_flag("--lockstep", a->lockstep, "report each replayed frame to a master that waits for its slaves");
    add_effect_options(*app, a->opt.effects);  // a display config's "effects" add to them
    add_limit_option(*app, a->opt.limits);
    return {app, [a](const std::vector<std::string>&) { return slave(*a); }};
}

}  // namespace glcast::cli
