// `glcast replay`: a capture back to pixels, one PNG per swapped frame, optionally compared
// with reference PNGs (the program's own frames from GLCAST_SNAPSHOT_DIR, or goldens).
#include "cli/commands.h"

#include <sys/stat.h>

#include <cinttypes>
#include <cstdio>
#include <cstdlib>

#include "protocol/decoder.h"
#include "slave/image.h"
#include "slave/replayer.h"
#include "cli/tile_options.h"

namespace glcast::slave {

const char* kReplayUsage =
    "  replay FILE [--frames A:B] [--backend egl|osmesa|window] [--out DIR] [--compare DIR]\n"
    "         [--size WxH] [--offset-names N] [--verify] [--config FILE --tile NAME]\n"
    "         [--canvas WxH --tile-rect X,Y,W,H] [--effects LIST] [--effect-param NAME=VALUE]...\n"
    "        replay a capture on the slave engine; --out writes frame-NNNNNN.png per swap,\n"
    "        --compare checks each frame against DIR/frame-NNNNNN.png (exit 1 on a mismatch);\n"
    "        --config/--tile show one tile of a display config, as `glcast slave` does;\n"
    "        --canvas/--tile-rect stretch the program's window over a canvas and show one rectangle\n"
    "        of it (from the top left), as one tile of a wall does;\n"
    "        --verify also executes the calls that only answered the program (glGet*, glReadPixels,\n"
    "        glGetError, ...) and reports where the slave's answer differs from the master's;\n"
    "        --offset-names makes the slave keep N objects of each kind of its own first, so its\n"
    "        names differ from the master's (a test of the name maps);\n"
    "        --effects runs injected passes before each present: a comma-separated list of snow,\n"
    "        rain, cover, icicles, shadows; --effect-param sets one of their parameters (docs/effects.md)\n";

namespace {

int usage(const std::string& msg) {
    std::fprintf(stderr, "glcast replay: %s\nusage: glcast\n%s", msg.c_str(), kReplayUsage);
    return 2;
}

bool parse_u64(const std::string& s, uint64_t& out) {
    if (s.empty() || s.size() > 19 || s.find_first_not_of("0123456789") != std::string::npos) return false;
    out = std::strtoull(s.c_str(), nullptr, 10);
    return true;
}

std::string frame_file(const std::string& dir, uint64_t frame) {
    char name[32];
    std::snprintf(name, sizeof name, "/frame-%06" PRIu64 ".png", frame);
    return dir + name;
}

}  // namespace

int replay_main(const std::vector<std::string>& args) {
    std::string path, backend_kind = "egl", out_dir, compare_dir;
    uint64_t offset_names = 0;
    std::string config_path, tile_name;
    ReplayOptions opt;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const bool has_value = i + 1 < args.size();
        if (a == "--frames" && has_value) {
            const std::string r = args[++i];
            const size_t colon = r.find(':');
            const std::string lo = colon == std::string::npos ? r : r.substr(0, colon);
            const std::string hi = colon == std::string::npos ? r : r.substr(colon + 1);
            if ((!lo.empty() && !parse_u64(lo, opt.first_frame)) || (!hi.empty() && !parse_u64(hi, opt.last_frame)) ||
                opt.first_frame > opt.last_frame)
                return usage("--frames takes A:B with A <= B, got '" + r + "'");
        } else if (a == "--backend" && has_value) {
            backend_kind = args[++i];
        } else if (a == "--out" && has_value) {
            out_dir = args[++i];
        } else if (a == "--canvas" && has_value) {
            if (std::sscanf(args[++i].c_str(), "%dx%d", &opt.tile.canvas_width, &opt.tile.canvas_height) != 2 ||
                opt.tile.canvas_width <= 0 || opt.tile.canvas_height <= 0 || opt.tile.canvas_width > 65536 ||
                opt.tile.canvas_height > 65536)
                return usage("--canvas takes WxH, got '" + args[i] + "'");
        } else if (a == "--tile-rect" && has_value) {
            int x, y, w, h;
            if (std::sscanf(args[++i].c_str(), "%d,%d,%d,%d", &x, &y, &w, &h) != 4 || w <= 0 || h <= 0 || w > 16384 ||
                h > 16384)
                return usage("--tile-rect takes X,Y,W,H (canvas pixels from the top left), got '" + args[i] + "'");
            opt.tile.enabled = true;
            opt.tile.x = x;
            opt.tile.width = w;
            opt.tile.height = h;
            opt.tile.y = y;  // converted to GL's bottom-left origin once the canvas is known
        } else if (a == "--config" && has_value) {
            config_path = args[++i];
        } else if (a == "--tile" && has_value) {
            tile_name = args[++i];
        } else if (a == "--effects" && has_value) {
            std::string error;
            if (!opt.effects.enable(args[++i], error)) return usage("--effects: " + error);
        } else if (a == "--effect-param" && has_value) {
            std::string error;
            if (!opt.effects.params.set_assignment(args[++i], error)) return usage(error);
        } else if (a == "--verify") {
            opt.verify = true;
        } else if (a == "--offset-names" && has_value) {
            if (!parse_u64(args[++i], offset_names) || offset_names > 10000)
                return usage("--offset-names takes 0..10000, got '" + args[i] + "'");
        } else if (a == "--compare" && has_value) {
            compare_dir = args[++i];
        } else if (a == "--size" && has_value) {
            if (std::sscanf(args[++i].c_str(), "%dx%d", &opt.width, &opt.height) != 2 || opt.width <= 0 ||
                opt.height <= 0 || opt.width > 16384 || opt.height > 16384)
                return usage("--size takes WxH (1..16384), got '" + args[i] + "'");
        } else if (!a.empty() && a[0] == '-') {
            return usage("unknown option '" + a + "'");
        } else if (path.empty()) {
            path = a;
        } else {
            return usage("one capture at a time");
        }
    }
    if (path.empty()) return usage("which capture?");
    if (!config_path.empty() || !tile_name.empty()) {
        std::string error;
        if (config_path.empty() || tile_name.empty()) return usage("--config and --tile go together");
        if (!tile_options(config_path, tile_name, opt, error)) {
            std::fprintf(stderr, "glcast replay: %s\n", error.c_str());
            return 1;
        }
    }
    if (opt.tile.enabled && config_path.empty()) {  // --canvas/--tile-rect (tile_options did a config's tile)
        if (!opt.tile.canvas_width) return usage("--tile-rect needs --canvas");
        if (opt.tile.x < 0 || opt.tile.y < 0 || opt.tile.x + opt.tile.width > opt.tile.canvas_width ||
            opt.tile.y + opt.tile.height > opt.tile.canvas_height)
            return usage("--tile-rect lies outside the canvas");
        opt.tile.y = opt.tile.canvas_height - opt.tile.y - opt.tile.height;
        opt.tile.place_x = opt.tile.x, opt.tile.place_y = opt.tile.y;
        opt.tile.place_canvas_width = opt.tile.canvas_width, opt.tile.place_canvas_height = opt.tile.canvas_height;
    }
    if (!out_dir.empty() && mkdir(out_dir.c_str(), 0755) != 0 && errno != EEXIST) {
        std::fprintf(stderr, "glcast replay: cannot create %s: %s\n", out_dir.c_str(), std::strerror(errno));
        return 1;
    }
    std::string error;
    std::unique_ptr<Backend> backend = make_backend(backend_kind, error);
    if (!backend) {
        std::fprintf(stderr, "glcast replay: %s\n", error.c_str());
        return 1;
    }

    uint64_t mismatched = 0, compared = 0, missing = 0;
    Replayer replayer(std::move(backend), opt);
    if (offset_names) replayer.on_first_context = [&](Replayer& r) { r.keep_own_objects(int(offset_names)); };
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

}  // namespace glcast::slave
