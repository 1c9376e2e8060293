// `glcast replay FILE [options]`: a capture back to pixels, one PNG per swapped frame,
// optionally compared with reference PNGs (the program's own frames from GLCAST_SNAPSHOT_DIR,
// or goldens).
#include <sys/stat.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "cli/tile_options.h"
#include "cli/stereo_tile.h"
#include "display_configs/head_poses.h"
#include "protocol/decoder.h"
#include "common/image.h"
#include "slave/replayer.h"

namespace glcast::cli {

using namespace glcast::slave;

namespace {

struct ReplayArgs {
    std::string path, backend_kind = "egl", out_dir, compare_dir, config_path, tile_name, head_poses_path;
    uint64_t offset_names = 0;
    std::vector<int> tile_rect;  // X,Y,W,H on the canvas, from the top left
    ReplayOptions opt;
};

std::string frame_file(const std::string& dir, uint64_t frame) {
    char name[32];
    std::snprintf(name, sizeof name, "/frame-%06" PRIu64 ".png", frame);
    return dir + name;
}

// A stereo tile: both eyes, each message read once (slave/stereo.h); the composed frames to
// --out (quad-buffer: each eye's, as frame-N-left.png and frame-N-right.png).
int replay_stereo(ReplayArgs& a, const HeadPoseTrack& head_poses) {
    StereoTile tile;
    std::string error;
    if (!open_stereo_tile(a.backend_kind, a.opt, tile, error)) {
        std::fprintf(stderr, "glcast replay: %s\n", error.c_str());
        return 1;
    }
    StereoPair& pair = *tile.pair;
    if (head_poses.size()) pair.head_for = [&](uint64_t frame, HeadPose& out) {
        const HeadPose* pose = head_poses.at(frame);
        if (pose) out = *pose;
        return pose != nullptr;
    };
    pair.on_frame = [&](uint64_t frame, const Image& composed, const Image& left, const Image& right) {
        if (tile.window) tile.window->show(composed, left, right);
        std::string err;
        if (!a.out_dir.empty() && !write_stereo_frame(a.out_dir, frame, a.opt.stereo, composed, left, right, err))
            std::fprintf(stderr, "glcast replay: %s\n", err.c_str());
    };
    try {
        CaptureReader reader(open_file_source(a.path));
        pair.replay(reader);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast replay: %s: %s\n", a.path.c_str(), e.what());
        return 1;
    }
    const ReplayStats& l = pair.left().stats();
    const ReplayStats& r = pair.right().stats();
    std::printf("replayed %" PRIu64 " frames per eye, %" PRIu64 " calls (%" PRIu64 " executed per eye), %" PRIu64
                " errors\n", l.frames, l.calls, l.replayed, l.errors + r.errors);
    return (l.errors || r.errors) ? 1 : 0;
}

int replay(ReplayArgs& a) {
    ReplayOptions& opt = a.opt;
    const std::string &path = a.path, &out_dir = a.out_dir, &compare_dir = a.compare_dir;
    if (!a.config_path.empty()) {  // --config and --tile come together (CLI11 checks)
        std::string error;
        if (!tile_options(a.config_path, a.tile_name, opt, error)) {
            std::fprintf(stderr, "glcast replay: %s\n", error.c_str());
            return 1;
        }
    } else if (!a.tile_rect.empty()) {  // --canvas/--tile-rect
        if (!opt.tile.canvas_width) usage_error("--tile-rect", "needs --canvas");
        TileMapping& t = opt.tile;
        t.enabled = true;
        t.x = a.tile_rect[0], t.y = a.tile_rect[1], t.width = a.tile_rect[2], t.height = a.tile_rect[3];
        if (t.width < 1 || t.height < 1 || t.width > 16384 || t.height > 16384)
            usage_error("--tile-rect", "W and H take 1..16384");
        if (t.x + t.width > t.canvas_width || t.y + t.height > t.canvas_height)
            usage_error("--tile-rect", "lies outside the canvas");
        t.y = t.canvas_height - t.y - t.height;  // GL's origin is the bottom left
        t.place_x = t.x, t.place_y = t.y;
        t.place_canvas_width = t.canvas_width, t.place_canvas_height = t.canvas_height;
    }
    HeadPoseTrack head_poses;
    if (!a.head_poses_path.empty()) {
        std::string error;
        if (!head_poses.load(a.head_poses_path, error)) {
            std::fprintf(stderr, "glcast replay: --head-poses: %s\n", error.c_str());
            return 1;
        }
    }
    std::string mkdir_error;
    if (!out_dir.empty() && !make_directories(out_dir, mkdir_error)) {
        std::fprintf(stderr, "glcast replay: --out: %s\n", mkdir_error.c_str());
        return 1;
    }
    if (!opt.scene_report_dir.empty() && !make_directories(opt.scene_report_dir, mkdir_error)) {
        std::fprintf(stderr, "glcast replay: --scene-report: %s\n", mkdir_error.c_str());
        return 1;
    }
    if (opt.stereo != StereoMode::none) return replay_stereo(a, head_poses);
    std::string error;
    std::unique_ptr<Backend> backend = make_backend(a.backend_kind, error);
    if (!backend) {
        std::fprintf(stderr, "glcast replay: %s\n", error.c_str());
        return 1;
    }

    uint64_t mismatched = 0, compared = 0, missing = 0;
    Replayer replayer(std::move(backend), opt);
    if (head_poses.size()) replayer.before_frame = [&](uint64_t frame) {
        if (const HeadPose* pose = head_poses.at(frame)) move_head(replayer, *pose, frame, "glcast replay");
    };
    if (a.offset_names) replayer.on_first_context = [&](Replayer& r) { r.keep_own_objects(int(a.offset_names)); };
    if (!out_dir.empty() || !compare_dir.empty()) replayer.on_frame = [&](uint64_t frame, int w, int h, const std::vector<uint8_t>& rgba) {
        Image image{w, h, rgba};
        std::string err;
        if (!out_dir.empty() && !write_png(frame_file(out_dir, frame), image, err))
            std::fprintf(stderr, "glcast replay: %s\n", err.c_str());
        if (compare_dir.empty()) return;
        Image reference;
        if (!read_png(frame_file(compare_dir, frame), reference, err)) {
            std::fprintf(stderr, "glcast replay: frame %" PRIu64 ": no reference: %s\n", frame, err.c_str());
            missing++;
            return;
        }
        compared++;
        const ImageDiff d = compare(image, reference);
        if (d.size_mismatch || d.differing_pixels) {
            mismatched++;
            if (d.size_mismatch)
                std::printf("frame %" PRIu64 ": size %dx%d, reference %dx%d\n", frame, w, h, reference.width,
                            reference.height);
            else
                std::printf("frame %" PRIu64 ": %" PRId64 " pixels differ, max channel difference %d\n", frame,
                            d.differing_pixels, d.max_channel_diff);
        }
    };
    try {
        CaptureReader reader(open_file_source(path));
        replayer.replay(reader);
    } catch (const DecodeError& e) {
        std::fprintf(stderr, "glcast replay: %s: %s\n", path.c_str(), e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast replay: %s\n", e.what());
        return 1;
    }
    const ReplayStats& s = replayer.stats();
    std::printf("replayed %" PRIu64 " frames, %" PRIu64 " calls (%" PRIu64 " executed, %" PRIu64
                " answered by the master's replies), %" PRIu64 " errors, %" PRIu64 " unserialized on the master\n",
                s.frames, s.calls, s.replayed, s.reply_only, s.errors, s.unserialized);
    if (opt.verify)
        std::printf("verified %" PRIu64 " replies: %" PRIu64 " differ\n", s.verified, s.mismatches);
    if (!compare_dir.empty())
        std::printf("compared %" PRIu64 " frames: %" PRIu64 " differ, %" PRIu64 " without reference\n", compared,
                    mismatched, missing);
    return (mismatched || missing || s.errors || s.mismatches) ? 1 : 0;
}

}  // namespace

Command add_replay(CLI::App& glcast) {
    auto a = std::make_shared<ReplayArgs>();
    CLI::App* app = glcast.add_subcommand("replay", "replay a capture on the slave engine, to PNGs or a window");
    app->add_option("FILE", a->path, "the capture file")->required();
    add_frame_range(*app, "--frames", LoneFrame::only_that_frame, a->opt.first_frame, a->opt.last_frame,
                    "only frames A through B (either may be omitted; N alone: frame N)");
    app->add_option("--backend", a->backend_kind, "egl (headless, the default), osmesa or window")
        ->type_name("egl|osmesa|window");
    app->add_option("--out", a->out_dir, "write frame-NNNNNN.png into DIR per swap")->type_name("DIR");
    app->add_option("--compare", a->compare_dir,
                    "check each frame against DIR/frame-NNNNNN.png (exit 1 on a mismatch)")
        ->type_name("DIR");
    add_size(*app, "--size", 16384, a->opt.width, a->opt.height, "the window's framebuffer size (default: the master's)");
    add_u64(*app, "--offset-names", a->offset_names, 0, 10000,
            "keep N objects of each kind of the slave's own first, so that its names\n"
            "differ from the master's (a test of the name maps)");
    app->add_flag("--verify", a->opt.verify,
                  "also execute the calls that only answered the program (glGet*, glReadPixels,\n"
                  "glGetError, ...) and report where the slave's answer differs from the master's");
    CLI::Option* config = app->add_option("--config", a->config_path, "a display config: with --tile, show one tile of it,\n"
                                                                    "as glcast slave does")
                              ->type_name("FILE");
    CLI::Option* tile = app->add_option("--tile", a->tile_name, "the tile of --config to show")->type_name("NAME");
    config->needs(tile);
    tile->needs(config);
    app->add_option("--head-poses", a->head_poses_path,
                    "with --config: play a recorded viewer's head poses, JSON lines\n"
                    "{\"frame\": N, \"position\": [x,y,z], \"orientation\": [w,x,y,z]}, each holding from its frame on\n"
                    "(docs/immersive.md)")
        ->type_name("FILE")
        ->needs(config);
    add_size(*app, "--canvas", 65536, a->opt.tile.canvas_width, a->opt.tile.canvas_height,
             "stretch the program's window over a canvas of WxH (with --tile-rect)");
    add_ints(*app, "--tile-rect", 4, 0, 65536, "X,Y,W,H", a->tile_rect,
             "show one rectangle of the canvas (pixels from the top left), as one tile of a wall does");
    add_effect_options(*app, a->opt.effects);
    app->add_flag("--live-effects", a->opt.effects.live,
                  "follow the scene as a wall's slave does, ready for passes switched while the program\n"
                  "runs (glcast ctl): to measure what that costs (docs/performance.md)");
    app->add_option("--scene-report", a->opt.scene_report_dir,
                    "with --effects: write what the passes took each frame of --frames for into DIR\n"
                    "(its depth, its view, the program's pixels kept; slave/scene_report.h)")
        ->type_name("DIR");
    add_limit_option(*app, a->opt.limits);
    return {app, [a](const std::vector<std::string>&) { return replay(*a); }};
}

}  // namespace glcast::cli
