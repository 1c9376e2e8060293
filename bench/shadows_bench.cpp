// Soft shadows (docs/shadows.md): the cost of each step of erosion/PCF and erosion/direct and
// the totals against PCSS 8/32/64 (the layout of the erosion method's own tables, docs/shadows.md), with each
// method's error against the area-light reference, on the test scenes of
// tests/effects/shadows/. EGL, headless, Mesa llvmpipe here; each step ends in glFinish and is
// timed with a steady clock; medians over frames (the scene is redrawn before each, untimed).
//
//   shadows_bench [--size WxH] [--map N] [--frames N] [--reference-samples N] [--max-penumbra PX]
//   shadows_bench --pictures DIR     pictures for docs/shadows.md (640x480, docs/images/)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "common/image.h"
#include "slave/effects/gl_util.h"
#include "slave/effects/shadows/shadow_renderer.h"
#include "tests/effects/shadows/shadow_scene.h"

using namespace glcast::slave::effects;
using glcast::slave::Image;
using shadow_test::Scene;
using shadow_test::SceneContext;
using shadow_test::Tile;

namespace {

const ShadowMethod kCompared[] = {ShadowMethod::ErosionPcf, ShadowMethod::ErosionDirect, ShadowMethod::Pcss8,
                                  ShadowMethod::Pcss32, ShadowMethod::Pcss64, ShadowMethod::ScreenSpace};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
}

int g_max_penumbra = 24;  // --max-penumbra

ShadowSettings settings_for(const Scene& scene, int map_size, int reference_samples) {
    ShadowSettings s;
    s.max_penumbra_px = g_max_penumbra;
    s.map_size = map_size;
    s.light_size = scene.light_size;
    s.light_angle_deg = scene.light_angle_deg;
    s.reference_samples = reference_samples;
    s.max_distance = 20;
    return s;
}

// Draws the frame, runs `method` (and the darkening when `frame` is given); the visibility.
std::vector<float> run_method(SceneContext& ctx, ShadowRenderer& r, const Scene& scene, const Tile& tile,
                              ShadowMethod method, Image* frame) {
    ctx.draw_frame(scene, tile);
    const FrameView view = ctx.frame_view(scene, tile);
    r.set_method(method);
    std::string why;
    {
        StateGuard guard(ctx.gl());
        if (!r.render(view, why)) {
            std::fprintf(stderr, "shadows_bench: %s\n", why.c_str());
            std::exit(1);
        }
        r.composite(view);
    }
    if (frame) *frame = ctx.read_color(tile);
    return r.read_tile(r.visibility_texture(), 0);
}

void write(const std::string& path, const Image& img) {
    std::string error;
    if (!glcast::slave::write_png(path, img, error)) {
        std::fprintf(stderr, "shadows_bench: %s\n", error.c_str());
        std::exit(1);
    }
}

// A strip of `images`, each cut to the rectangle (x, y, w, h) and scaled by `scale` (nearest),
// separated by 4 white columns.
Image strip(const std::vector<Image>& images, int x, int y, int w, int h, int scale) {
    Image out;
    out.width = int(images.size()) * (w * scale + 4) - 4;
    out.height = h * scale;
    out.rgba.assign(size_t(out.width) * out.height * 4, 255);
    for (size_t k = 0; k < images.size(); ++k)
        for (int j = 0; j < out.height; ++j)
            for (int i = 0; i < w * scale; ++i) {
                const uint8_t* s = &images[k].rgba[(size_t(y + j / scale) * images[k].width + x + i / scale) * 4];
                std::copy(s, s + 4, &out.rgba[(size_t(j) * out.width + k * (w * scale + 4) + i) * 4]);
            }
    return out;
}

int pictures(const std::string& dir) {
    SceneContext ctx;
    const Tile tile{0, 0, 640, 480, 640, 480};
    for (const Scene& scene : {shadow_test::blocks_scene(), shadow_test::fence_scene(), shadow_test::ramp_scene()}) {
        ShadowRenderer r(ctx.gl(), settings_for(scene, 2048, 512));
        ctx.draw_frame(scene, tile);
        std::vector<Image> frames{ctx.read_color(tile)};  // [0]: the frame without shadows
        for (ShadowMethod m : {ShadowMethod::ErosionPcf, ShadowMethod::ErosionDirect, ShadowMethod::Pcss8,
                               ShadowMethod::Pcss32, ShadowMethod::Reference, ShadowMethod::ScreenSpace}) {
            frames.emplace_back();
            run_method(ctx, r, scene, tile, m, &frames.back());
        }
        // Crops around the most telling shadows: the floating cube's wide penumbra, the
        // slats (fine structure), the plank's shadow from contact to its raised end.
        struct Crop {
            int x, y, w, h, scale;
        };
        const Crop c = scene.name == "fence" ? Crop{200, 190, 128, 96, 2}
                     : scene.name == "ramp"  ? Crop{185, 195, 380, 120, 1}
                                             : Crop{340, 150, 128, 96, 2};
        write(dir + "/shadows-" + scene.name + "-methods.png",
              strip({frames[1], frames[2], frames[3], frames[4], frames[5], frames[6]}, c.x, c.y, c.w, c.h, c.scale));
    }
    return 0;
}

struct Row {
    std::vector<ShadowStepTimes> frames;
    std::vector<double> totals;
    double error = 0;
};

ShadowStepTimes median_steps(const std::vector<ShadowStepTimes>& frames) {
    auto pick = [&](double ShadowStepTimes::*step) {
        std::vector<double> v;
        for (const auto& f : frames) v.push_back(f.*step);
        return median(v);
    };
    ShadowStepTimes m;
    m.shadow_map = pick(&ShadowStepTimes::shadow_map);
    m.hard_shadows = pick(&ShadowStepTimes::hard_shadows);
    m.edge_detection = pick(&ShadowStepTimes::edge_detection);
    m.erosion = pick(&ShadowStepTimes::erosion);
    m.shading = pick(&ShadowStepTimes::shading);
    return m;
}

int benchmark(int width, int height, int map_size, int frames, int reference_samples) {
    SceneContext ctx;
    const Tile tile{0, 0, width, height, width, height};
    const std::vector<Scene> scenes{shadow_test::blocks_scene(), shadow_test::fence_scene(), shadow_test::ramp_scene()};
    std::map<std::string, std::map<ShadowMethod, Row>> rows;
    for (const Scene& scene : scenes) {
        ShadowRenderer r(ctx.gl(), settings_for(scene, map_size, reference_samples));
        const auto reference = run_method(ctx, r, scene, tile, ShadowMethod::Reference, nullptr);
        r.set_profiling(true);
        // Interleaved: every method once per round, so drifts of the machine hit all alike.
        for (int round = 0; round <= frames; ++round)
            for (ShadowMethod m : kCompared) {
                const auto v = run_method(ctx, r, scene, tile, m, nullptr);
                Row& row = rows[scene.name][m];
                if (round == 0) {  // warm-up (programs, targets); its output gives the error
                    row.error = shadow_test::visibility_error(v, reference, width, height).shadows;
                    continue;
                }
                row.frames.push_back(r.last_times());
                row.totals.push_back(r.last_times().total());
            }
        std::fprintf(stderr, "shadows_bench: %s done\n", scene.name.c_str());
    }
    std::printf("Soft shadows at %dx%d, %d^2 shadow map, shadows.max_penumbra %d, median of %d frames (ms); RMSE "
                "of the visibility against the %d-sample reference over the shadows\n\n",
                width, height, map_size, g_max_penumbra, frames, reference_samples);
    std::printf("Table 1: total cost of the pass (ms) and error\n\n| method |");
    for (const Scene& s : scenes) std::printf(" %s ms | %s RMSE |", s.name.c_str(), s.name.c_str());
    std::printf("\n|---|");
    for (size_t i = 0; i < scenes.size(); ++i) std::printf("---|---|");
    std::printf("\n");
    for (ShadowMethod m : kCompared) {
        std::printf("| %s |", method_name(m));
        for (const Scene& s : scenes) {
            const Row& row = rows[s.name][m];
            std::printf(" %.1f | %.4f |", median(row.totals), row.error);
        }
        std::printf("\n");
    }
    for (ShadowMethod m : kCompared) {
        std::printf("\nTable 2: steps of %s (ms)%s\n\n| step |", method_name(m),
                    pcss_blocker_samples(m) ? " (hard shadows: the camera depth only; shading: blocker search, PCF, darkening)"
                    : m == ShadowMethod::ScreenSpace ? " (hard shadows: the march; shading: the softening, darkening)"
                                                     : "");
        for (const Scene& s : scenes) std::printf(" %s |", s.name.c_str());
        std::printf("\n|---|");
        for (size_t i = 0; i < scenes.size(); ++i) std::printf("---|");
        std::printf("\n");
        const char* names[] = {"shadow map", "hard shadows", "edge detection", "erosion", "shading"};
        double ShadowStepTimes::*steps[] = {&ShadowStepTimes::shadow_map, &ShadowStepTimes::hard_shadows,
                                            &ShadowStepTimes::edge_detection, &ShadowStepTimes::erosion,
                                            &ShadowStepTimes::shading};
        for (int k = 0; k < 5; ++k) {
            std::printf("| %s |", names[k]);
            for (const Scene& s : scenes) std::printf(" %.1f |", median_steps(rows[s.name][m].frames).*steps[k]);
            std::printf("\n");
        }
    }
    std::printf("\nGoal (erosion/PCF no slower than PCSS-32 at equal or lower error):\n");
    for (const Scene& s : scenes) {
        const Row& e = rows[s.name][ShadowMethod::ErosionPcf];
        const Row& p = rows[s.name][ShadowMethod::Pcss32];
        const bool met = median(e.totals) <= median(p.totals) && e.error <= p.error;
        std::printf("  %s: %.1f ms vs %.1f ms, RMSE %.4f vs %.4f: %s\n", s.name.c_str(), median(e.totals),
                    median(p.totals), e.error, p.error, met ? "met" : "not met");
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    int width = 1920, height = 1080, map_size = 2048, frames = 5, reference_samples = 512;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
        if (a == "--pictures" && v) return pictures(v);
        if (a == "--size" && v && std::sscanf(v, "%dx%d", &width, &height) == 2) ++i;
        else if (a == "--map" && v) map_size = std::atoi(argv[++i]);
        else if (a == "--max-penumbra" && v) g_max_penumbra = std::max(1, std::atoi(argv[++i]));
        else if (a == "--frames" && v) frames = std::max(1, std::atoi(argv[++i]));
        else if (a == "--reference-samples" && v) reference_samples = std::max(1, std::atoi(argv[++i]));
        else {
            std::fprintf(stderr,
                         "usage: shadows_bench [--size WxH] [--map N] [--frames N] [--reference-samples N] "
                         "[--max-penumbra PX]\n"
                         "       shadows_bench --pictures DIR\n");
            return 2;
        }
    }
    if (width < 64 || height < 64 || map_size < 256) {
        std::fprintf(stderr, "shadows_bench: size at least 64x64, map at least 256\n");
        return 2;
    }
    return benchmark(width, height, map_size, frames, reference_samples);
}
