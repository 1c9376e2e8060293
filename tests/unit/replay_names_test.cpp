// Object names on the recording driver: the master's names mapped to the slave's for every kind
// of object, per share group, created at first use where compatibility GL does, and forgotten
// when deleted.
#include "tests/unit/replay_harness.h"

using namespace glcast;
using testing_support::ReplayHarness;

#define GL(fn, ...) encode_##fn(h.stream.e, h.stream.sz, __VA_ARGS__)
#define GL0(fn) encode_##fn(h.stream.e, h.stream.sz)

namespace {

// The value the recording driver returned for the first call whose text is `text`.
uint64_t returned(const ReplayHarness& h, const std::string& text) {
    for (const auto& c : h.gl->calls)
        if (c.text == text) return c.reply;
    ADD_FAILURE() << "no call " << text;
    return 0;
}

// A second context, `id` on drawable `drawable`, sharing objects with context `share` (0: none).
void second_context(ReplayHarness& h, uint32_t id, uint32_t share, uint64_t drawable) {
    testing_support::open_window(h.stream, ReplayHarness::handle(id), 0, 640, 480, id, drawable, share);
}

}  // namespace

TEST(ReplayNames, ADisplayListRangeIsMappedFromItsBase) {
    ReplayHarness h;
    GL(glGenLists, 2, 10);  // the master got lists 10 and 11
    GL(glNewList, 11u, GLenum(GL_COMPILE));
    GL0(glEndList);
    GL(glCallList, 11u);
    h.replay();
    const uint64_t base = returned(h, "glGenLists(2)");
    EXPECT_EQ(h.calls("glNewList"), std::vector<std::string>{"glNewList(" + std::to_string(base + 1) + ", GL_COMPILE)"});
    EXPECT_EQ(h.calls("glCallList("), std::vector<std::string>{"glCallList(" + std::to_string(base + 1) + ")"});
    EXPECT_EQ(h.replayer->stats().errors, 0u) << h.log;
}

TEST(ReplayNames, DeletedListsAreForgotten) {
    ReplayHarness h;
    GL(glGenLists, 2, 10);
    GL(glDeleteLists, 10u, 2);
    GL(glCallList, 10u);
    h.replay();
    const uint64_t base = returned(h, "glGenLists(2)");
    // (one by one: the slave's names of a master range need not be a range)
    EXPECT_EQ(h.calls("glDeleteLists"), (std::vector<std::string>{"glDeleteLists(" + std::to_string(base) + ", 1)",
                                                                  "glDeleteLists(" + std::to_string(base + 1) + ", 1)"}));
    // deleted: no list on the master, none on the slave (calling it does nothing in GL)
    EXPECT_EQ(h.calls("glCallList("), std::vector<std::string>{"glCallList(4294967295)"});
    EXPECT_EQ(h.replayer->stats().errors, 0u) << h.log;
}

TEST(ReplayNames, AListRangeOverTheLimitIsRefusedBeforeTheDriver) {
    ReplayHarness h;
    h.options.limits.list_range = 16;
    GL(glGenLists, 1000, 1);
    h.replay();
    EXPECT_TRUE(h.calls("glGenLists").empty());
    EXPECT_EQ(h.replayer->stats().errors, 1u);
    EXPECT_NE(h.log.find("list_range"), std::string::npos) << h.log;
}

TEST(ReplayNames, ABufferBoundWithoutGenerationIsCreatedByTheSlave) {
    ReplayHarness h;
    GL(glBindBuffer, GL_ARRAY_BUFFER, 4u);
    h.replay();
    const std::vector<std::string> calls = h.calls_from("glGenBuffers");
    ASSERT_EQ(calls.size(), 2u) << h.log;
    EXPECT_EQ(calls[0].rfind("glGenBuffers(1, ", 0), 0u);
    EXPECT_EQ(calls[1].rfind("glBindBuffer(GL_ARRAY_BUFFER, ", 0), 0u);
    EXPECT_NE(calls[1], "glBindBuffer(GL_ARRAY_BUFFER, 4)");
}

TEST(ReplayNames, NameZeroIsAlwaysZero) {
    ReplayHarness h;
    GL(glBindTexture, GL_TEXTURE_2D, 0u);
    GL(glUseProgram, 0u);
    GL(glBindFramebuffer, GL_FRAMEBUFFER, 0u);
    h.replay();
    EXPECT_EQ(h.calls("glBindTexture"), std::vector<std::string>{"glBindTexture(GL_TEXTURE_2D, 0)"});
    EXPECT_EQ(h.calls("glUseProgram"), std::vector<std::string>{"glUseProgram(0)"});
    EXPECT_EQ(h.replayer->stats().errors, 0u) << h.log;
}

TEST(ReplayNames, ADeletedTexturesNameIsUnmappedAndANewOneMadeAtItsNextBind) {
    ReplayHarness h;
    GLuint master[1] = {5};
    GL(glGenTextures, 1, master);
    GL(glBindTexture, GL_TEXTURE_2D, 5u);
    GL(glDeleteTextures, 1, master);
    GL(glBindTexture, GL_TEXTURE_2D, 5u);  // compatibility GL: a new texture of that name
    h.replay();
    const std::vector<std::string> binds = h.calls("glBindTexture");
    ASSERT_EQ(binds.size(), 2u) << h.log;
    EXPECT_NE(binds[0], binds[1]);
    EXPECT_EQ(h.calls("glGenTextures").size(), 2u);
    EXPECT_EQ(h.calls("glDeleteTextures").size(), 1u);
}

TEST(ReplayNames, ContextsOfOneShareGroupSeeTheSameObjects) {
    ReplayHarness h;
    GLuint master[1] = {5};
    GL(glGenTextures, 1, master);
    GL(glBindTexture, GL_TEXTURE_2D, 5u);
    second_context(h, 2, 1, 8);
    GL(glBindTexture, GL_TEXTURE_2D, 5u);
    h.replay();
    const std::vector<std::string> binds = h.calls("glBindTexture");
    ASSERT_EQ(binds.size(), 2u) << h.log;
    EXPECT_EQ(binds[0], binds[1]);
    EXPECT_EQ(h.calls("glGenTextures").size(), 1u);
}

TEST(ReplayNames, AContextOfAnotherShareGroupHasItsOwnObjects) {
    ReplayHarness h;
    GLuint master[1] = {5};
    GL(glGenTextures, 1, master);
    GL(glBindTexture, GL_TEXTURE_2D, 5u);
    second_context(h, 2, 0, 8);
    GL(glBindTexture, GL_TEXTURE_2D, 5u);  // another texture that has the same name there
    h.replay();
    const std::vector<std::string> binds = h.calls("glBindTexture");
    ASSERT_EQ(binds.size(), 2u) << h.log;
    EXPECT_NE(binds[0], binds[1]);
}

TEST(ReplayNames, AUniformLocationIsTheSlavesOwn) {
    ReplayHarness h;
    h.gl->answer = [](slave::RecordedCall& c) {
        if (c.opcode == OP_glGetUniformLocation) c.reply = 7;  // the slave's driver puts it elsewhere
    };
    GL(glCreateProgram, 9u);
    GL(glUseProgram, 9u);
    GL(glGetUniformLocation, 9u, "exposure", 3);
    GL(glUniform1f, 3, 0.5f);
    h.replay();
    EXPECT_EQ(h.calls("glUniform1f"), std::vector<std::string>{"glUniform1f(7, 0.5)"});
    EXPECT_EQ(h.replayer->stats().errors, 0u) << h.log;
}

TEST(ReplayNames, ShadersAndProgramsShareOneNameSpace) {
    ReplayHarness h;
    GL(glCreateShader, GL_VERTEX_SHADER, 2u);
    GL(glCreateProgram, 3u);
    GL(glAttachShader, 3u, 2u);
    h.replay();
    const uint64_t shader = returned(h, "glCreateShader(GL_VERTEX_SHADER)");
    const uint64_t program = returned(h, "glCreateProgram()");
    EXPECT_EQ(h.calls("glAttachShader"),
              std::vector<std::string>{"glAttachShader(" + std::to_string(program) + ", " + std::to_string(shader) + ")"});
}

TEST(ReplayNames, LiveNamesOfOneKindAreBoundedInAll) {
    ReplayHarness h;
    h.options.limits.names = 10;
    GL(glGenLists, 8, 1);
    GL(glGenLists, 8, 9);  // 16 lists would live: refused before the driver
    GLuint textures[12] = {};
    for (GLuint k = 0; k < 12; ++k) textures[k] = 100 + k;
    GL(glGenTextures, 12, textures);  // the names the master got are more than may live
    GL(glBindTexture, GL_TEXTURE_2D, 200u);  // one created at first bind still fits
    h.replay();
    EXPECT_EQ(h.calls("glGenLists"), std::vector<std::string>{"glGenLists(8)"});
    EXPECT_EQ(h.replayer->stats().errors, 2u) << h.log;
    EXPECT_NE(h.log.find("over the limit names=10"), std::string::npos) << h.log;
    EXPECT_EQ(h.calls("glBindTexture").size(), 1u);
}
