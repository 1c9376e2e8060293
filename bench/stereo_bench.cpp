// Stereo's cost per frame (docs/performance.md): a capture replayed as one eye of a screen tile
// and as both eyes of a stereo tile (slave/stereo.h), each frame read back as a wall tile does
// when it writes or composes it. Per frame: from the 20th frame shown to the last (the contexts'
// creation and first shader compiles left out), in wall time and in the process's CPU time (the
// eyes replay on two threads). Runs alternate, R rounds; prints the medians, their ratios, and
// how many messages each run read (one read per message, whatever the eyes).
//
//   stereo_bench CAPTURE [WIDTHxHEIGHT] [ROUNDS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <string>
#include <vector>

#include "protocol/decoder.h"
#include "slave/stereo.h"

using namespace glcast;
using namespace glcast::slave;

namespace {

// A source that counts the messages it hands out.
class Counted : public MessageSource {
public:
    explicit Counted(MessageSource& inner) : inner_(inner) {}
    bool next(Message& m) override {
        const bool more = inner_.next(m);
        messages += more;
        return more;
    }
    uint64_t messages = 0;

private:
    MessageSource& inner_;
};

ReplayOptions screen_tile(int width, int height, StereoMode stereo) {
    ReplayOptions o;
    o.tile.enabled = true;
    o.tile.canvas_width = o.tile.width = width;
    o.tile.canvas_height = o.tile.height = height;
    o.tile.place_canvas_width = width, o.tile.place_canvas_height = height;
    o.view.enabled = o.view.screen = true;
    const double half_h = 1.5 * height / width;
    o.view.bottom_left = {-1.5, -half_h, -1.5}, o.view.bottom_right = {1.5, -half_h, -1.5}, o.view.top_left = {-1.5, half_h, -1.5};
    o.viewer.eye = Eye::left;
    o.view.set_eye(eye_position(o.viewer));
    o.stereo = stereo;
    return o;
}

struct Run {
    double seconds, cpu_seconds;
    uint64_t frames, messages;
};

double cpu_now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

Run run(const std::string& path, const ReplayOptions& options) {
    std::string error;
    CaptureReader reader(open_file_source(path));
    Counted source(reader);
    uint64_t frames = 0, checksum = 0;
    std::chrono::steady_clock::time_point t0, t1;
    double cpu0 = 0, cpu1 = 0;
    auto shown = [&] {
        if (++frames == 20) t0 = std::chrono::steady_clock::now(), cpu0 = cpu_now();
        t1 = std::chrono::steady_clock::now(), cpu1 = cpu_now();
    };
    if (options.stereo == StereoMode::none) {
        std::unique_ptr<Backend> backend = make_backend("egl", error);
        if (!backend) throw std::runtime_error(error);
        Replayer one(std::move(backend), options);
        one.on_frame = [&](uint64_t, int, int, const std::vector<uint8_t>& rgba) { shown(), checksum += rgba[rgba.size() / 2]; };
        one.replay(source);
    } else {
        StereoPair pair([](std::string& e) { return make_backend("egl", e); }, options);
        if (!pair.valid()) throw std::runtime_error(pair.error());
        pair.on_frame = [&](uint64_t, const Image& tile, const Image&, const Image&) {
            shown(), checksum += tile.rgba[tile.rgba.size() / 2];
        };
        pair.replay(source);
    }
    if (frames <= 21) throw std::runtime_error("the capture has too few frames (at least 22)");
    const double seconds = std::chrono::duration<double>(t1 - t0).count();
    if (checksum == 1) std::fputc(' ', stderr);  // (the images are used)
    return {seconds, cpu1 - cpu0, frames - 20, source.messages};
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: stereo_bench CAPTURE [WIDTHxHEIGHT] [ROUNDS]\n");
        return 2;
    }
    int width = 1024, height = 768;
    if (argc > 2 && std::sscanf(argv[2], "%dx%d", &width, &height) != 2) return 2;
    const int rounds = argc > 3 ? std::atoi(argv[3]) : 5;
    // Each stereo mode against one eye of the same size: anaglyph's eyes are the tile's size,
    // side by side's half its width.
    const StereoMode modes[] = {StereoMode::none, StereoMode::anaglyph, StereoMode::none, StereoMode::side_by_side};
    const char* names[] = {"one eye, tile size", "anaglyph (two eyes, tile size)", "one eye, half width",
                           "side-by-side (two eyes, half width)"};
    constexpr int kModes = 4;
    std::vector<double> ms[kModes], cpu[kModes];
    uint64_t messages[kModes] = {}, frames[kModes] = {};
    for (int r = 0; r < rounds; ++r)
        for (int m = 0; m < kModes; ++m) {
            ReplayOptions o = screen_tile(width, height, modes[m]);
            if (m >= 2) eye_size(StereoMode::side_by_side, width, height, o.tile.width, o.tile.height);
            o.tile.canvas_width = o.tile.width, o.tile.canvas_height = o.tile.height;
            const Run x = run(argv[1], o);
            ms[m].push_back(1000 * x.seconds / std::max<uint64_t>(1, x.frames));
            cpu[m].push_back(1000 * x.cpu_seconds / std::max<uint64_t>(1, x.frames));
            messages[m] = x.messages, frames[m] = x.frames;
        }
    std::printf("| replay of %s, %dx%d per tile | ms per frame (median of %d) | x one eye of its size | CPU ms per "
                "frame | x one eye's CPU | frames timed | messages read |\n", argv[1], width, height, rounds);
    std::printf("|---|---|---|---|---|---|---|\n");
    for (int m = 0; m < kModes; ++m)
        std::printf("| %s | %.2f | %.2f | %.2f | %.2f | %llu | %llu |\n", names[m], median(ms[m]),
                    median(ms[m]) / median(ms[m & ~1]), median(cpu[m]), median(cpu[m]) / median(cpu[m & ~1]),
                    (unsigned long long)frames[m], (unsigned long long)messages[m]);
    return 0;
}
