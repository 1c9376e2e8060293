// Bad streams on the slave: a draw with a client array never sent, a context that does not
// exist. Each is reported for its call, counted, and the replay goes on: the frame after them is
// still rendered. A name never generated is said once and given to the driver as no object
// (the master's call raised its error). Runs headless on the EGL backend.
#include <gtest/gtest.h>  // before the X11 headers, whose None and Bool macros it cannot take
#include <zlib.h>

#include <GL/gl.h>
#include <GL/glx.h>

#include <cstring>

#include "glcast_commands.h"
#include "glcast_encode.h"
#include "master/encoder.h"
#include "master/stream.h"
#include "protocol/decoder.h"
#include "protocol/format.h"
#include "slave/replayer.h"
#include "tests/roundtrip_support.h"
#include "tests/unit/stream_builder.h"

using namespace glcast;

using testing_support::open_window;
using testing_support::StreamBuilder;

TEST(ReplayErrors, ReportedCountedAndSkipped) {
    std::string error;
    auto backend = slave::make_backend("egl", error);
    if (!backend) GTEST_SKIP() << "no EGL backend here: " << error;

    StreamBuilder s;
    auto* handle = reinterpret_cast<GLXContext>(uintptr_t(0xc0de));
    open_window(s, handle);
    encode_glUseProgram(s.e, s.sz, 77);  // never created: error 1
    s.client_array_never_sent();  // a cached array never sent: error 2
    s.context(5);
    encode_glXMakeCurrent(s.e, s.sz, nullptr, 7, reinterpret_cast<GLXContext>(uintptr_t(0xbad)), True);  // error 3
    s.context(1);
    encode_glBindTexture(s.e, s.sz, GL_TEXTURE_2D, 9);  // created at first bind: legal, no error
    encode_glClearColor(s.e, s.sz, 1.0f, 0.0f, 0.0f, 1.0f);
    encode_glClear(s.e, s.sz, GL_COLOR_BUFFER_BIT);
    encode_glXSwapBuffers(s.e, s.sz, nullptr, 7);

    const std::vector<uint8_t> file = s.file();
    slave::Replayer replayer(std::move(backend), slave::ReplayOptions{});
    int frames = 0;
    uint8_t red = 0;
    replayer.on_frame = [&](uint64_t, int w, int h, const std::vector<uint8_t>& rgba) {
        frames++;
        EXPECT_EQ(w, 32);
        EXPECT_EQ(h, 16);
        red = rgba[0];
    };
    CaptureReader reader(memory_source(file.data(), file.size()));
    testing::internal::CaptureStderr();
    replayer.replay(reader);
    const std::string log = testing::internal::GetCapturedStderr();
    EXPECT_EQ(replayer.stats().errors, 2u) << log;  // a name never made is no object, not an error
    EXPECT_NE(log.find("program 77 was never made by the stream"), std::string::npos) << log;
    EXPECT_NE(log.find("never sent"), std::string::npos) << log;
    EXPECT_NE(log.find("context 5, which does not exist"), std::string::npos) << log;
    EXPECT_NE(log.find("frame 0, call"), std::string::npos) << log;
    EXPECT_EQ(frames, 1);
    EXPECT_EQ(red, 255);  // the calls after the errors still ran
}

// A context format claiming more samples than any GL has (a pbuffer of 2^30 samples would be
// asked of the driver): refused for its tuple; the context is made single-sampled and the
// frame is still rendered.
TEST(ReplayErrors, ContextFormatSamplesAreBounded) {
    std::string error;
    auto backend = slave::make_backend("egl", error);
    if (!backend) GTEST_SKIP() << "no EGL backend here: " << error;
    StreamBuilder s;
    auto* handle = reinterpret_cast<GLXContext>(uintptr_t(0xc0de));
    open_window(s, handle, 1 << 30);
    encode_glClearColor(s.e, s.sz, 0.0f, 1.0f, 0.0f, 1.0f);
    encode_glClear(s.e, s.sz, GL_COLOR_BUFFER_BIT);
    encode_glXSwapBuffers(s.e, s.sz, nullptr, 7);
    const std::vector<uint8_t> file = s.file();
    slave::Replayer replayer(std::move(backend), slave::ReplayOptions{});
    uint8_t green = 0;
    replayer.on_frame = [&](uint64_t, int, int, const std::vector<uint8_t>& rgba) { green = rgba[1]; };
    CaptureReader reader(memory_source(file.data(), file.size()));
    testing::internal::CaptureStderr();
    replayer.replay(reader);
    const std::string log = testing::internal::GetCapturedStderr();
    EXPECT_NE(log.find("a context format of 1073741824 samples (at most 64)"), std::string::npos) << log;
    EXPECT_EQ(replayer.stats().errors, 1u) << log;
    EXPECT_EQ(green, 255);
}

// Context creations whose glcast.context tuple never comes: the slave waits for at most as
// many as contexts may live (limit contexts), then refuses the next.
TEST(ReplayErrors, CreationsWaitingForTheirContextTupleAreBounded) {
    std::string error;
    auto backend = slave::make_backend("egl", error);
    if (!backend) GTEST_SKIP() << "no EGL backend here: " << error;
    StreamBuilder s;
    s.context(0);
    for (uintptr_t k = 1; k <= 300; ++k)
        encode_glXCreateContext(s.e, s.sz, nullptr, nullptr, nullptr, True, reinterpret_cast<GLXContext>(k << 4));
    const std::vector<uint8_t> file = s.file();
    slave::Replayer replayer(std::move(backend), slave::ReplayOptions{});
    CaptureReader reader(memory_source(file.data(), file.size()));
    testing::internal::CaptureStderr();
    replayer.replay(reader);
    const std::string log = testing::internal::GetCapturedStderr();
    EXPECT_NE(log.find("more than 256 context creations wait for their glcast.context tuple"), std::string::npos)
        << log.substr(0, 2000);
    EXPECT_EQ(replayer.stats().errors, 300u - 256u);
}

// --limit NAME=VALUE: a typo is refused with the closest name, a bad value with the limit's.
TEST(ReplayLimits, SetByName) {
    glcast::slave::ReplayLimits limits;
    std::string error;
    EXPECT_TRUE(glcast::slave::set_replay_limit(limits, "list_range=4096", error)) << error;
    EXPECT_EQ(limits.list_range, 4096u);
    EXPECT_TRUE(glcast::slave::set_replay_limit(limits, "buffer_bytes=0x1000", error)) << error;
    EXPECT_EQ(limits.buffer_bytes, 4096u);
    EXPECT_FALSE(glcast::slave::set_replay_limit(limits, "list_rang=1", error));
    EXPECT_NE(error.find("did you mean \"list_range\""), std::string::npos) << error;
    EXPECT_FALSE(glcast::slave::set_replay_limit(limits, "contexts=-1", error));
    EXPECT_NE(error.find("contexts"), std::string::npos) << error;
    EXPECT_FALSE(glcast::slave::set_replay_limit(limits, "contexts=", error));
}
