// A stereo tile's two eyes (slave/stereo.h) on the recording driver: each eye's draws get its own
// eye's correction, and a head pose that holds from frame N reaches each eye at its frame N, not
// before: the eyes take turns over a message, so the left eye starts frame N while the right eye
// still has frame N - 1 of the same message to replay (each eye on its own thread).
#include "tests/unit/replay_harness.h"

#include <cstring>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "slave/stereo.h"

using namespace glcast;
using testing_support::ReplayHarness;

#define GL(fn, ...) encode_##fn(h.stream.e, h.stream.sz, __VA_ARGS__)

namespace {

// The projections one eye's driver was given for draws, in order.
struct EyeDriver {
    std::shared_ptr<slave::RecordingGl> gl = std::make_shared<slave::RecordingGl>();
    std::vector<glm::dmat4> loaded;
    GLint mode = GL_MODELVIEW;
    glm::dmat4 projection = glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    EyeDriver() {
        gl->answer = [this](slave::RecordedCall& c) {
            if (c.opcode == OP_glMatrixMode) mode = GLint(c.args[0]);
            if (c.opcode == OP_glGetIntegerv && c.args[0] == GL_MATRIX_MODE) *c.pointer<GLint>(1) = mode;
            if (c.opcode == OP_glLoadMatrixd && mode == GL_PROJECTION) {
                std::memcpy(&projection[0][0], c.pointer<GLdouble>(0), sizeof projection);
                loaded.push_back(projection);
            }
            if (c.opcode == OP_glGetDoublev && c.args[0] == GL_PROJECTION_MATRIX)
                std::memcpy(c.pointer<GLdouble>(1), &projection[0][0], sizeof projection);
        };
    }
};

}  // namespace

TEST(StereoPair, APoseFromFrameOneReachesEachEyeAtItsFrameOne) {
    ReplayHarness h;  // (its stream: one context on a 640x480 window)
    slave::ReplayOptions& o = h.options;
    o.view.enabled = o.view.screen = true;
    o.view.bottom_left = {-1.5, -1.5, -1.5}, o.view.bottom_right = {1.5, -1.5, -1.5}, o.view.top_left = {-1.5, 1.5, -1.5};
    o.stereo = slave::StereoMode::side_by_side;
    GL(glMatrixMode, GL_PROJECTION);
    GL(glFrustum, -1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    GL(glMatrixMode, GL_MODELVIEW);
    for (int frame = 0; frame < 2; ++frame) {
        GL(glDrawArrays, GL_TRIANGLES, 0, 3);
        h.swap();
    }
    EyeDriver eyes[2];
    int made = 0;
    slave::StereoPair pair([&](std::string&) { return slave::make_recording_backend(eyes[made++].gl); }, o);
    ASSERT_TRUE(pair.valid());
    slave::HeadPose moved;
    moved.position = {0.3, 0.1, 0};
    pair.head_for = [&](uint64_t frame, slave::HeadPose& out) {
        if (frame < 1) return false;
        out = moved;
        return true;
    };
    const std::vector<uint8_t> file = h.stream.file();
    CaptureReader reader(memory_source(file.data(), file.size()));
    pair.replay(reader);
    const glm::dmat4 app = glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    for (int e = 0; e < 2; ++e) {
        ASSERT_EQ(eyes[e].loaded.size(), 2u) << "eye " << e << ": frame 0's correction, then frame 1's";
        slave::Viewer viewer;
        viewer.eye = e == 0 ? slave::Eye::left : slave::Eye::right;
        for (int frame = 0; frame < 2; ++frame) {
            if (frame == 1) viewer.head.position = moved.position;
            slave::ViewCorrection v = o.view;
            ASSERT_TRUE(v.set_eye(slave::eye_position(viewer)));
            const glm::dmat4 want = v.correction(app) * app;
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j)
                    EXPECT_NEAR(eyes[e].loaded[size_t(frame)][i][j], want[i][j], 1e-6) << "eye " << e << ", frame " << frame;
        }
    }
}
