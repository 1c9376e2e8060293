// The replay core on the recording driver: what reaches the driver for each call of a stream,
// with no GL. Names mapped and unmapped, calls in order and on their context, replies not
// re-asked, bad calls refused before the driver.
#include "tests/unit/replay_harness.h"

#include <algorithm>

using namespace glcast;
using testing_support::ReplayHarness;

#define GL(fn, ...) encode_##fn(h.stream.e, h.stream.sz, __VA_ARGS__)
#define GL0(fn) encode_##fn(h.stream.e, h.stream.sz)

TEST(ReplayCore, ACallReachesTheDriverAsTheProgramMadeIt) {
    ReplayHarness h;
    GL(glClearColor, 0.25f, 0.5f, 1.0f, 1.0f);
    GL(glClear, GL_COLOR_BUFFER_BIT);
    h.swap();
    h.replay();
    EXPECT_EQ(h.calls("glClearColor"), std::vector<std::string>{"glClearColor(0.25, 0.5, 1, 1)"});
    EXPECT_EQ(h.calls("glClear("), std::vector<std::string>{"glClear(16384)"});
    EXPECT_EQ(h.replayer->stats().frames, 1u);
    EXPECT_EQ(h.replayer->stats().errors, 0u) << h.log;
}

TEST(ReplayCore, CallsReachTheDriverInTheStreamsOrder) {
    ReplayHarness h;
    GL(glEnable, GL_DEPTH_TEST);
    GL(glDepthFunc, GL_LEQUAL);
    GL(glDisable, GL_DEPTH_TEST);
    h.replay();
    const std::vector<std::string> calls = h.calls_from("glEnable(GL_DEPTH_TEST)");
    ASSERT_GE(calls.size(), 3u);
    EXPECT_EQ(calls[0], "glEnable(GL_DEPTH_TEST)");
    EXPECT_EQ(calls[1], "glDepthFunc(GL_LEQUAL)");
    EXPECT_EQ(calls[2], "glDisable(GL_DEPTH_TEST)");
}

TEST(ReplayCore, AGeneratedTexturesNameIsMappedToTheSlaves) {
    ReplayHarness h;
    GLuint master[2] = {5, 6};
    GL(glGenTextures, 2, master);
    GL(glBindTexture, GL_TEXTURE_2D, 6);
    h.replay();
    const std::vector<std::string> gens = h.calls("glGenTextures");
    ASSERT_EQ(gens.size(), 1u);
    // The recording driver hands out names from one counter: find what it gave for the second.
    const slave::RecordedCall* gen = nullptr;
    for (const auto& c : h.gl->calls)
        if (c.text.rfind("glGenTextures", 0) == 0) gen = &c;
    ASSERT_NE(gen, nullptr);
    const GLuint* slave_names = gen->pointer<GLuint>(1);
    (void)slave_names;  // the scratch memory is the replay's; the bind says which name it got
    const std::vector<std::string> binds = h.calls("glBindTexture");
    ASSERT_EQ(binds.size(), 1u);
    EXPECT_NE(binds[0], "glBindTexture(GL_TEXTURE_2D, 6)");  // the slave's name, not the master's
    EXPECT_EQ(h.replayer->stats().errors, 0u) << h.log;
}

TEST(ReplayCore, ACreatedProgramsNameIsMappedAndADeletedOneUnmapped) {
    ReplayHarness h;
    GL(glCreateProgram, 9);
    GL(glUseProgram, 9);
    GL(glDeleteProgram, 9);
    GL(glUseProgram, 9);  // deleted while in use: its name lives until it is not (GL 4.6, 7.3)
    GL(glUseProgram, 0);
    GL(glUseProgram, 9);  // now no longer a name of the stream
    h.replay();
    const std::vector<std::string> uses = h.calls("glUseProgram");
    ASSERT_EQ(uses.size(), 4u) << h.log;
    const uint64_t slave_name = h.gl->calls[0].reply;  // placeholder, replaced below
    (void)slave_name;
    std::string created;
    for (const auto& c : h.gl->calls)
        if (c.text == "glCreateProgram()") created = std::to_string(c.reply);
    EXPECT_EQ(uses[0], "glUseProgram(" + created + ")");
    EXPECT_EQ(uses[1], "glUseProgram(" + created + ")");
    EXPECT_EQ(h.calls("glDeleteProgram"), std::vector<std::string>{"glDeleteProgram(" + created + ")"});
    // deleted: no object on the master, none on the slave (the driver raises the master's error)
    EXPECT_EQ(uses[3], "glUseProgram(4294967295)");
    EXPECT_EQ(h.replayer->stats().errors, 0u);
    EXPECT_NE(h.log.find("program 9 was never made by the stream"), std::string::npos) << h.log;
}

// A program may use a name it never made (Mesa's piglit does, for the error): the slave's driver
// gets a name that is no object, and raises the same error.
TEST(ReplayCore, ANameNeverGeneratedIsNoObjectOnTheSlave) {
    ReplayHarness h;
    GL(glUseProgram, 77);
    GL(glClear, GL_COLOR_BUFFER_BIT);
    h.swap();
    h.replay();
    EXPECT_EQ(h.calls("glUseProgram"), std::vector<std::string>{"glUseProgram(4294967295)"});
    EXPECT_EQ(h.calls("glClear("), std::vector<std::string>{"glClear(16384)"});
    EXPECT_EQ(h.replayer->stats().errors, 0u);
    EXPECT_NE(h.log.find("glUseProgram: program 77 was never made"), std::string::npos) << h.log;
}

TEST(ReplayCore, AReplyOnlyQueryIsNotAskedAgain) {
    ReplayHarness h;
    GLint viewport[4] = {0, 0, 640, 480};
    GL(glGetIntegerv, GL_VIEWPORT, viewport);
    h.replay();
    EXPECT_TRUE(h.calls("glGetIntegerv(GL_VIEWPORT").empty());
    EXPECT_EQ(h.replayer->stats().reply_only, 1u);
}
