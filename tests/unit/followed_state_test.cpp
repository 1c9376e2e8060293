// The draw state the scene classifier asks at every draw is followed from the program's calls
// (slave/scene/followed_state.h): replayed on the recording driver with a pass that needs the
// scene, the draws of a frame reach the driver with no query of what the calls already said,
// and a call that may change the state unseen (glPopAttrib, a display list) makes the slave ask
// again.
#include "tests/unit/replay_harness.h"

#include <algorithm>
#include <string>
#include <vector>

using namespace glcast;
using testing_support::ReplayHarness;

#define GL(fn, ...) encode_##fn(h.stream.e, h.stream.sz, __VA_ARGS__)
#define GL0(fn) encode_##fn(h.stream.e, h.stream.sz)

namespace {

const char* const kFollowedQueries[] = {"glIsEnabled(GL_DEPTH_TEST)", "glGetBooleanv(GL_DEPTH_WRITEMASK",
                                        "glIsEnabled(GL_CULL_FACE)",  "glGetIntegerv(GL_CULL_FACE_MODE",
                                        "glGetIntegerv(GL_FRONT_FACE", "glGetDoublev(GL_DEPTH_RANGE",
                                        "glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING", "glGetIntegerv(GL_CURRENT_PROGRAM"};

// The program's calls from the first `from` to the last glEnd(), before the frame's passes.
std::vector<std::string> program_calls(const ReplayHarness& h, const std::string& from) {
    std::vector<std::string> calls = h.calls_from(from);
    const auto last_end = std::find(calls.rbegin(), calls.rend(), "glEnd()");
    calls.erase(last_end.base(), calls.end());
    return calls;
}

size_t queries_in(const std::vector<std::string>& calls) {
    size_t n = 0;
    for (const std::string& c : calls)
        for (const char* q : kFollowedQueries) n += c.compare(0, std::string(q).size(), q) == 0;
    return n;
}

// The passes' own shaders compile and link on the recording driver.
void passes_build(ReplayHarness& h) {
    h.options.effects.cover = true;  // a pass that needs the frame's scene: the classifier runs
    h.gl->answer = [](slave::RecordedCall& c) {
        const std::string name = c.name();
        if ((name == "glGetShaderiv" && c.args[1] == GL_COMPILE_STATUS) ||
            (name == "glGetProgramiv" && c.args[1] == GL_LINK_STATUS))
            *c.pointer<GLint>(2) = 1;
    };
}

void set_state(ReplayHarness& h) {
    GL(glViewport, 0, 0, 640, 480);
    GL(glEnable, GL_DEPTH_TEST);
    GL(glDepthMask, GL_TRUE);
    GL(glEnable, GL_CULL_FACE);
    GL(glCullFace, GL_BACK);
    GL(glFrontFace, GL_CCW);
    GL(glDepthRange, 0.0, 1.0);
    GL(glBindFramebuffer, GL_FRAMEBUFFER, 0u);
    GL(glUseProgram, 0u);
    GL(glMatrixMode, GL_PROJECTION);
    GL(glFrustum, -1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    GL(glMatrixMode, GL_MODELVIEW);
}

void triangle(ReplayHarness& h, float z) {
    GL(glBegin, GL_TRIANGLES);
    GL(glVertex3f, -1.0f, 0.0f, z);
    GL(glVertex3f, 1.0f, 0.0f, z);
    GL(glVertex3f, 0.0f, 1.0f, z);
    GL0(glEnd);
}

}  // namespace

TEST(FollowedState, DrawsAskTheDriverNothingTheCallsSet) {
    ReplayHarness h;
    passes_build(h);
    set_state(h);
    for (int i = 0; i < 20; ++i) triangle(h, -5.0f - float(i));
    h.swap();
    h.replay();
    EXPECT_EQ(h.replayer->stats().errors, 0u) << h.log;
    const std::vector<std::string> calls = program_calls(h, "glEnable(GL_DEPTH_TEST)");
    ASSERT_GE(std::count(calls.begin(), calls.end(), "glEnd()"), 20);
    std::string asked;
    for (const std::string& c : calls)
        for (const char* q : kFollowedQueries)
            if (c.compare(0, std::string(q).size(), q) == 0) asked += "\n  " + c;
    EXPECT_EQ(queries_in(calls), 0u) << "draws asked the driver for state the calls had set:" << asked;
}

TEST(FollowedState, AfterGlPopAttribTheDriverIsAskedOnceAgain) {
    ReplayHarness h;
    passes_build(h);
    set_state(h);
    triangle(h, -5.0f);
    GL(glPushAttrib, GLbitfield(GL_ENABLE_BIT));
    GL(glDisable, GL_DEPTH_TEST);
    GL0(glPopAttrib);
    for (int i = 0; i < 5; ++i) triangle(h, -6.0f - float(i));
    h.swap();
    h.replay();
    const std::vector<std::string> after = program_calls(h, "glPopAttrib()");
    ASSERT_FALSE(after.empty());
    const size_t asked = size_t(std::count(after.begin(), after.end(), "glIsEnabled(GL_DEPTH_TEST)"));
    EXPECT_EQ(asked, 1u) << "the depth test after glPopAttrib is asked of the driver once, then kept";
}

TEST(FollowedState, AnIndexedBlendSwitchMakesTheDriverAskedAgain) {
    // Deferred renderers switch blending per draw buffer (glDisablei(GL_BLEND, 0)): what glEnable
    // said of GL_BLEND is no longer all of it, and the translucent-draw rule must not act on it.
    ReplayHarness h;
    passes_build(h);
    // (the recording driver answers the fixed-function projection as set_state's frustum: a view
    // is found, and its surfaces ask whether they blend)
    const auto build = h.gl->answer;
    h.gl->answer = [build](slave::RecordedCall& c) {
        build(c);
        if (std::string(c.name()) == "glGetDoublev" && c.args[0] == GL_PROJECTION_MATRIX) {
            const double frustum[16] = {1, 0, 0, 0, 0, 1.0 / 0.75, 0, 0, 0, 0, -101.0 / 99, -1, 0, 0, -200.0 / 99, 0};
            std::copy(frustum, frustum + 16, c.pointer<double>(1));
        }
    };
    set_state(h);
    GL(glEnable, GL_BLEND);
    triangle(h, -5.0f);
    GL(glDisablei, GL_BLEND, 0u);
    for (int i = 0; i < 3; ++i) triangle(h, -6.0f - float(i));
    h.swap();
    h.replay();
    // (the three triangles' calls: the passes' own queries follow them)
    std::vector<std::string> after = h.calls_from("glDisablei(");
    const auto third_end = std::find_if(after.begin(), after.end(), [n = 0](const std::string& c) mutable {
        return c == "glEnd()" && ++n == 3;
    });
    ASSERT_NE(third_end, after.end());
    after.erase(third_end + 1, after.end());
    const size_t asked = size_t(std::count(after.begin(), after.end(), "glIsEnabled(GL_BLEND)"));
    std::string seen;
    for (const std::string& c : after) seen += "\n  " + c;
    EXPECT_EQ(asked, 1u) << "blending after glDisablei is asked of the driver once, then kept:" << seen;
}
