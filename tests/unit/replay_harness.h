// Replays a stream written call by call (stream_builder.h) on the recording driver
// (slave/backends/recording/recording_gl.h): what the slave's core and observers hand the driver,
// call by call, with no GL, no window and no Xvfb. The unit tests of the replay use it.
#pragma once

#include <functional>

#include <gtest/gtest.h>  // before the X11 headers, whose None and Bool macros it cannot take

#include <memory>
#include <string>
#include <vector>

#include "protocol/decoder.h"
#include "slave/backends/recording/recording_gl.h"
#include "slave/replayer.h"
#include "tests/unit/stream_builder.h"

namespace glcast::testing_support {

class ReplayHarness {
public:
    StreamBuilder stream;
    slave::ReplayOptions options;
    std::shared_ptr<slave::RecordingGl> gl = std::make_shared<slave::RecordingGl>();
    std::unique_ptr<slave::Replayer> replayer;
    std::string log;  // what the replay said on stderr
    std::function<void(slave::Replayer&)> prepare;  // called on the new Replayer before it replays

    // Context 1 current on a window of width x height.
    explicit ReplayHarness(int32_t width = 640, int32_t height = 480) : width_(width), height_(height) {
        open_window(stream, handle(1), 0, width, height);
    }
    static GLXContext handle(uintptr_t k) { return reinterpret_cast<GLXContext>(k << 8); }
    StreamBuilder* operator->() { return &stream; }
    Encoder& e() { return stream.e; }
    roundtrip::FakeSizes& sz() { return stream.sz; }
    void swap(uint64_t drawable = 7) { encode_glXSwapBuffers(stream.e, stream.sz, nullptr, drawable); }

    // Tile (column, row) of a columns x rows wall of the master's window size, row 0 at the top.
    void tile(int column, int row, int columns, int rows) {
        slave::TileMapping& t = options.tile;
        t.enabled = true;
        t.canvas_width = width_, t.canvas_height = height_;
        t.width = width_ / columns, t.height = height_ / rows;
        t.x = column * t.width;
        t.y = (rows - 1 - row) * t.height;  // GL's origin is the bottom left
        t.place_x = t.x, t.place_y = t.y, t.place_canvas_width = width_, t.place_canvas_height = height_;
        options.width = t.width, options.height = t.height;
    }

    // Replays everything written so far on a new Replayer; what reached the driver is in gl.
    slave::Replayer& replay() {
        gl->clear();
        replayer = std::make_unique<slave::Replayer>(slave::make_recording_backend(gl), options);
        if (prepare) prepare(*replayer);
        file_ = stream.file();
        CaptureReader reader(memory_source(file_.data(), file_.size()));
        ::testing::internal::CaptureStderr();
        try {
            replayer->replay(reader);
        } catch (...) {
            log = ::testing::internal::GetCapturedStderr();
            throw;
        }
        log = ::testing::internal::GetCapturedStderr();
        return *replayer;
    }
    std::vector<std::string> calls(const std::string& prefix = "") const { return gl->texts(prefix); }
    // The recorded calls from the first that starts with `from` on (the program's own, after the
    // replay's set-up).
    std::vector<std::string> calls_from(const std::string& from) const {
        std::vector<std::string> all = gl->texts(), out;
        bool on = false;
        for (const std::string& c : all) {
            on = on || c.compare(0, from.size(), from) == 0;
            if (on) out.push_back(c);
        }
        return out;
    }

private:
    int32_t width_, height_;
    std::vector<uint8_t> file_;
};

}  // namespace glcast::testing_support
