// Cost of the falling-snow pass at 1920x1080 on this machine's GL (llvmpipe here), in the pairs
// of the method's own measurements (docs/snow.md): the hybrid (2,000 particles + spectral snow) against particles alone at
// 2,000, 16,000 and 150,000, and the spectral composite alone (texture upload + full-screen
// blend; its synthesis runs on the worker thread, measured by spectral_snow_bench, but shares
// the machine's cores with the rasterizer). The camera is still, except in the row where it
// moves and the regions (docs/snow.md, "The pass") get their own C and theta.
// Each configuration renders `frames` frames over a cleared scene with depth; the figure is the
// median wall time per frame including glFinish. Prints a markdown table.
//
//   snow_pass_bench [frames=40] [WxH=1920x1080]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "slave/effects/gl_util.h"
#include "slave/effects/pipeline.h"
#include "tests/effects/snow/effects_test_support.h"

using namespace glcast::slave::effects;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

double frame_ms(testing::TestContext& t, const std::vector<std::string>& assignments, int frames, double* waited) {
    EffectParams params;
    std::string error;
    for (const std::string& a : assignments)
        if (!params.set_assignment(a, error)) std::fprintf(stderr, "%s\n", error.c_str()), std::exit(2);
    auto pass = make_precipitation_pass(t.gl, params, false);
    const glm::dmat4 p = glm::perspective(glm::radians(45.0), double(t.width) / t.height, 0.5, 100.0);
    std::vector<double> times;
    for (int f = 0; f < frames + 5; ++f) {
        FrameView v;
        v.frame = uint64_t(f);
        v.width = v.canvas_width = t.width;
        v.height = v.canvas_height = t.height;
        v.view_known = true;
        v.projection = v.tile_clip_from_eye = p;
        v.eye_from_tile_clip = glm::inverse(p);
        t.gl.glClearColor(0.2f, 0.3f, 0.4f, 1);
        t.gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        t.gl.glFinish();
        const auto start = std::chrono::steady_clock::now();
        {
            StateGuard guard(t.gl);
            t.gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
            t.gl.glViewport(0, 0, t.width, t.height);
            pass->run(t.gl, v);
        }
        t.gl.glFinish();
        if (f >= 5) times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    (void)waited;
    return median(times);
}

}  // namespace

int main(int argc, char** argv) {
    const int frames = argc > 1 ? std::atoi(argv[1]) : 40;
    int w = 1920, h = 1080;
    if (argc > 2 && std::sscanf(argv[2], "%dx%d", &w, &h) != 2) return 2;
    std::string error;
    auto t = testing::TestContext::create(w, h, error);
    if (!t) {
        std::fprintf(stderr, "snow_pass_bench: %s\n", error.c_str());
        return 1;
    }
    std::printf("%s, %dx%d, median of %d frames\n\n", reinterpret_cast<const char*>(t->gl.glGetString(GL_RENDERER)), w,
                h, frames);
    struct Row {
        const char* what;
        std::vector<std::string> params;
    } rows[] = {
        {"spectral composite alone (upload + blend)", {"snow.particles=0"}},
        {"particles alone, 2,000", {"snow.particles=2000", "snow.spectral=0"}},
        {"hybrid: 2,000 particles + spectral", {"snow.particles=2000"}},
        {"hybrid, camera moving forward (3x3 regions differ)",
         {"snow.particles=2000", "snow.camera_motion=0", "snow.camera_velocity_z=-10"}},
        {"particles alone, 16,000", {"snow.particles=16000", "snow.spectral=0"}},
        {"particles alone, 150,000", {"snow.particles=150000", "snow.spectral=0"}},
    };
    std::printf("| configuration | ms per frame |\n|---|---|\n");
    double hybrid = 0, p16 = 0, p150 = 0;
    for (const Row& r : rows) {
        const double ms = frame_ms(*t, r.params, frames, nullptr);
        std::printf("| %s | %.2f |\n", r.what, ms);
        std::fflush(stdout);
        if (std::string(r.what) == "hybrid: 2,000 particles + spectral") hybrid = ms;
        if (std::string(r.what).find("16,000") != std::string::npos) p16 = ms;
        if (std::string(r.what).find("150,000") != std::string::npos) p150 = ms;
    }
    std::printf("\nhybrid vs 16,000 particles: %.2fx cheaper; vs 150,000: %.2fx cheaper (goal: >= 5x vs the high count)\n",
                p16 / hybrid, p150 / hybrid);
    return 0;
}
