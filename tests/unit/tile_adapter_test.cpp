// The tile adapter on the recording driver: window coordinates and pixel sizes of the program's
// calls as they reach the driver of one tile of a wall, and the program's own framebuffer
// objects left alone.
#include "tests/unit/replay_harness.h"

#include <algorithm>
#include <cstring>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

using namespace glcast;
using testing_support::ReplayHarness;

#define GL(fn, ...) encode_##fn(h.stream.e, h.stream.sz, __VA_ARGS__)
#define GL0(fn) encode_##fn(h.stream.e, h.stream.sz)

namespace {

std::vector<std::string> last(const std::vector<std::string>& calls, size_t n) {
    return std::vector<std::string>(calls.end() - std::ptrdiff_t(std::min(n, calls.size())), calls.end());
}

// Tile (1, 0) of a 2x2 wall whose canvas is twice the program's 640x480 window each way: every
// window pixel is 2x2 canvas pixels, and the tile shows the canvas' top-right quarter.
void scaled_top_right(ReplayHarness& h) {
    slave::TileMapping& t = h.options.tile;
    t.enabled = true;
    t.canvas_width = 1280, t.canvas_height = 960;
    t.width = 640, t.height = 480, t.x = 640, t.y = 480;
    t.place_x = t.x, t.place_y = t.y, t.place_canvas_width = 1280, t.place_canvas_height = 960;
}

}  // namespace

TEST(TileAdapter, AViewportOnTheTopRightTileOfATwoByTwoWallReachesTheDriverShifted) {
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    GL(glViewport, 0, 0, 640, 480);
    h.replay();
    EXPECT_EQ(h.calls("glViewport").back(), "glViewport(-320, -240, 640, 480)");
}

TEST(TileAdapter, TheBottomLeftTileSharesTheWindowsOrigin) {
    ReplayHarness h;
    h.tile(0, 1, 2, 2);
    GL(glViewport, 10, 20, 300, 200);
    h.replay();
    EXPECT_EQ(h.calls("glViewport").back(), "glViewport(10, 20, 300, 200)");
}

TEST(TileAdapter, AScissorBoxIsMappedAsTheViewportIs) {
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    GL(glScissor, 400, 300, 100, 50);
    h.replay();
    EXPECT_EQ(h.calls("glScissor").back(), "glScissor(80, 60, 100, 50)");
}

TEST(TileAdapter, ANewContextsViewportCoversTheWindowOnTheTile) {
    ReplayHarness h;
    h.tile(1, 1, 2, 2);
    h.replay();
    // Before any call of the program: GLX's initial viewport, the window, mapped.
    EXPECT_EQ(h.calls("glViewport"), std::vector<std::string>{"glViewport(-320, 0, 640, 480)"});
}

TEST(TileAdapter, WithoutAWallTheViewportIsTheProgramsOwn) {
    ReplayHarness h;
    GL(glViewport, 5, 6, 70, 80);
    h.replay();
    EXPECT_EQ(h.calls("glViewport").back(), "glViewport(5, 6, 70, 80)");
}

TEST(TileAdapter, InsideAFramebufferObjectTheViewportIsLeftAsTheProgramSetIt) {
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    GLuint fb[1] = {3};
    GL(glGenFramebuffers, 1, fb);
    GL(glBindFramebuffer, GL_FRAMEBUFFER, 3);
    GL(glViewport, 0, 0, 256, 256);
    h.replay();
    EXPECT_EQ(h.calls("glViewport").back(), "glViewport(0, 0, 256, 256)");
}

TEST(TileAdapter, BackInTheWindowTheProgramsViewportIsMappedAgain) {
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    GLuint fb[1] = {3};
    GL(glGenFramebuffers, 1, fb);
    GL(glBindFramebuffer, GL_FRAMEBUFFER, 3);
    GL(glViewport, 0, 0, 256, 256);
    GL(glBindFramebuffer, GL_FRAMEBUFFER, 0);
    h.replay();
    EXPECT_EQ(last(h.calls_from("glBindFramebuffer(GL_FRAMEBUFFER, 0)"), 2),
              (std::vector<std::string>{"glViewport(-320, -240, 256, 256)", "glScissor(-320, -240, 640, 480)"}));
}

TEST(TileAdapter, OnAScaledCanvasWindowCoordinatesAndPixelSizesScale) {
    ReplayHarness h;
    scaled_top_right(h);
    GL(glViewport, 0, 0, 640, 480);
    GL(glLineWidth, 2.0f);
    GL(glPointSize, 3.0f);
    GL(glPixelZoom, 1.0f, -1.0f);
    h.replay();
    EXPECT_EQ(h.calls("glViewport").back(), "glViewport(-640, -480, 1280, 960)");
    EXPECT_EQ(h.calls("glLineWidth"), std::vector<std::string>{"glLineWidth(4)"});
    EXPECT_EQ(h.calls("glPointSize"), std::vector<std::string>{"glPointSize(6)"});
    EXPECT_EQ(h.calls("glPixelZoom"), std::vector<std::string>{"glPixelZoom(2, -2)"});
}

TEST(TileAdapter, LineWidthAndPointSizeAreScaledOnlyWhileTheWindowIsBound) {
    // Context state, set with the window bound (Blender does it with a hidden 1x1 window): the
    // framebuffer object's draws get the program's own values, the window's the scaled ones.
    ReplayHarness h;
    scaled_top_right(h);
    GL(glLineWidth, 2.0f);
    GL(glPointSize, 3.0f);
    GLuint fb[1] = {3};
    GL(glGenFramebuffers, 1, fb);
    GL(glBindFramebuffer, GL_FRAMEBUFFER, 3);
    GL(glBindFramebuffer, GL_FRAMEBUFFER, 0);
    h.replay();
    const std::vector<std::string> widths = h.calls("glLineWidth"), sizes = h.calls("glPointSize");
    EXPECT_EQ(widths, (std::vector<std::string>{"glLineWidth(4)", "glLineWidth(2)", "glLineWidth(4)"})) << h.log;
    EXPECT_EQ(sizes, (std::vector<std::string>{"glPointSize(6)", "glPointSize(3)", "glPointSize(6)"}));
}

namespace {

// The scaled top-right tile, the program's framebuffer 3 bound for reading, and a driver that
// says the read framebuffer (slave name 3) is multisampled RGBA8 renderbuffers, at most 16384 a
// side.
void reading_multisampled_on_scaled_tile(ReplayHarness& h) {
    scaled_top_right(h);
    GLuint fb[1] = {3};
    GL(glGenFramebuffers, 1, fb);
    GL(glBindFramebuffer, GL_READ_FRAMEBUFFER, 3);
    h.gl->answer = [](slave::RecordedCall& c) {
        if (c.opcode == OP_glGetIntegerv) {
            GLint* out = c.pointer<GLint>(1);
            switch (GLenum(c.args[0])) {
            case GL_READ_FRAMEBUFFER_BINDING: *out = 3; break;
            case GL_SAMPLES: *out = 4; break;
            case GL_READ_BUFFER: *out = GL_COLOR_ATTACHMENT0; break;
            case GL_MAX_RENDERBUFFER_SIZE: *out = 16384; break;
            default: break;
            }
        } else if (c.opcode == OP_glGetFramebufferAttachmentParameteriv &&
                   GLenum(c.args[2]) == GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE) {
            *c.pointer<GLint>(3) = GL_RENDERBUFFER;
        } else if (c.opcode == OP_glGetRenderbufferParameteriv &&
                   GLenum(c.args[1]) == GL_RENDERBUFFER_INTERNAL_FORMAT) {
            *c.pointer<GLint>(2) = GL_RGBA8;
        }
    };
}

}  // namespace

TEST(TileAdapter, AMultisampledBlitIntoTheWindowIsResolvedAtItsOwnSizeBeforeTheTileScalesIt) {
    ReplayHarness h;
    reading_multisampled_on_scaled_tile(h);
    GL(glBlitFramebuffer, 0, 0, 320, 240, 0, 0, 320, 240, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    h.replay();
    EXPECT_EQ(h.calls("glRenderbufferStorage"),
              std::vector<std::string>{"glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 320, 240)"}) << h.log;
    const std::vector<std::string> blits = h.calls("glBlitFramebuffer");
    ASSERT_EQ(blits.size(), 2u) << h.log;
    EXPECT_EQ(blits[0], "glBlitFramebuffer(0, 0, 320, 240, 0, 0, 320, 240, 16384, GL_NEAREST)");  // the resolve
    EXPECT_EQ(blits[1], "glBlitFramebuffer(0, 0, 320, 240, -640, -480, 0, 0, 16384, GL_NEAREST)");  // scaled
}

TEST(TileAdapter, AMultisampledBlitOfAnImpossibleRectangleIsRefusedBeforeAnythingIsMade) {
    // The stream's rectangle: INT_MIN to INT_MAX wide would have overflowed, then asked the
    // driver for a renderbuffer of that size.
    ReplayHarness h;
    reading_multisampled_on_scaled_tile(h);
    GL(glBlitFramebuffer, INT32_MIN, 0, INT32_MAX, 240, 0, 0, 320, 240, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    GL(glBlitFramebuffer, 0, 0, 20000, 240, 0, 0, 320, 240, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    h.replay();
    EXPECT_TRUE(h.calls("glRenderbufferStorage").empty());
    EXPECT_TRUE(h.calls("glBlitFramebuffer").empty());
    EXPECT_NE(h.log.find("a source rectangle of 4294967295x240"), std::string::npos) << h.log;
    EXPECT_NE(h.log.find("a source rectangle of 20000x240 at 0,0 is beyond the driver's largest renderbuffer (16384)"),
              std::string::npos) << h.log;
}

TEST(TileAdapter, ABlitToTheWindowLandsWhereTheTileShowsIt) {
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    GLuint fb[1] = {3};
    GL(glGenFramebuffers, 1, fb);
    GL(glBindFramebuffer, GL_READ_FRAMEBUFFER, 3);
    GL(glBlitFramebuffer, 0, 0, 640, 480, 0, 0, 640, 480, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    h.replay();
    const std::vector<std::string> blits = h.calls("glBlitFramebuffer");
    ASSERT_EQ(blits.size(), 1u) << h.log;
    EXPECT_EQ(blits[0], "glBlitFramebuffer(0, 0, 640, 480, -320, -240, 320, 240, 16384, GL_NEAREST)");
}

TEST(TileAdapter, AnIndexedViewportIsMappedByItsIndex) {
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    std::vector<float> sent;  // the driver's array, read while the call is made
    h.gl->answer = [&sent](slave::RecordedCall& c) {
        if (c.opcode == OP_glViewportArrayv) sent.assign(c.pointer<const float>(2), c.pointer<const float>(2) + 4 * c.args[1]);
    };
    GL(glViewportIndexedf, 2u, 320.0f, 240.0f, 100.0f, 100.0f);
    h.replay();
    EXPECT_TRUE(h.calls("glViewportIndexedf").empty());  // every viewport, mapped, in one array
    ASSERT_EQ(sent.size(), 4u * 16);
    EXPECT_EQ(std::vector<float>(sent.begin() + 8, sent.begin() + 12), (std::vector<float>{0, 0, 100, 100}));
    EXPECT_EQ(std::vector<float>(sent.begin(), sent.begin() + 4), (std::vector<float>{-320, -240, 640, 480}));
}

TEST(TileAdapter, ADrawOnARotatedTileGetsTheCorrectedProjectionFirst) {
    ReplayHarness h;
    h.options.view.enabled = true;
    h.options.view.yaw_deg = 60;
    // The driver's matrix mode, as the program left it, and its projection.
    GLint mode = GL_MODELVIEW;
    h.gl->answer = [&mode](slave::RecordedCall& c) {
        if (c.opcode == OP_glMatrixMode) mode = GLint(c.args[0]);
        if (c.opcode == OP_glGetIntegerv && c.args[0] == GL_MATRIX_MODE) *c.pointer<GLint>(1) = mode;
        if (c.opcode == OP_glGetDoublev && c.args[0] == GL_PROJECTION_MATRIX) {
            const glm::dmat4 p = glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
            std::memcpy(c.pointer<GLdouble>(1), &p[0][0], sizeof p);
        }
    };
    GL(glMatrixMode, GL_PROJECTION);
    GL(glFrustum, -1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    GL(glMatrixMode, GL_MODELVIEW);
    GL(glDrawArrays, GL_TRIANGLES, 0, 3);
    h.replay();
    const std::vector<std::string> calls = h.calls_from("glFrustum");
    auto at = [&calls](const std::string& call) {
        return std::find(calls.begin(), calls.end(), call) - calls.begin();
    };
    const auto draw = at("glDrawArrays(GL_TRIANGLES, 0, 3)");
    ASSERT_LT(size_t(draw), calls.size());
    // glMatrixMode(GL_PROJECTION), glLoadMatrixd(corrected), glMatrixMode(GL_MODELVIEW), the draw.
    EXPECT_EQ(calls[size_t(draw) - 3], "glMatrixMode(GL_PROJECTION)");
    EXPECT_EQ(calls[size_t(draw) - 2].rfind("glLoadMatrixd(", 0), 0u);
    EXPECT_EQ(calls[size_t(draw) - 1], "glMatrixMode(GL_MODELVIEW)");
}

TEST(TileAdapter, AnOrthographicDrawOnARotatedTileIsLeftAsDrawn) {
    // With no perspective view in the window before it (a backdrop, the full-window quad that
    // shows a scene drawn offscreen): no camera to turn.
    ReplayHarness h;
    h.options.view.enabled = true;
    h.options.view.yaw_deg = 60;
    h.gl->answer = [](slave::RecordedCall& c) {
        if (c.opcode == OP_glGetDoublev && c.args[0] == GL_PROJECTION_MATRIX) {
            const glm::dmat4 p = glm::ortho(0.0, 640.0, 0.0, 480.0, -1.0, 1.0);
            std::memcpy(c.pointer<GLdouble>(1), &p[0][0], sizeof p);
        }
    };
    GL(glMatrixMode, GL_PROJECTION);
    GL(glOrtho, 0.0, 640.0, 0.0, 480.0, -1.0, 1.0);
    GL(glMatrixMode, GL_MODELVIEW);
    GL(glDrawArrays, GL_TRIANGLES, 0, 3);
    GL(glDrawArrays, GL_TRIANGLES, 0, 3);
    h.replay();
    const std::vector<std::string> calls = h.calls_from("glOrtho");
    EXPECT_EQ(std::count_if(calls.begin(), calls.end(), [](const std::string& c) { return c.rfind("glLoadMatrixd(", 0) == 0; }), 0)
        << "an orthographic projection was replaced";
    EXPECT_EQ(std::count_if(calls.begin(), calls.end(),
                            [](const std::string& c) { return c.rfind("glGetDoublev(GL_PROJECTION_MATRIX", 0) == 0; }),
              1)
        << "the projection is looked at once, until the program changes it";
}

TEST(TileAdapter, AnOrthographicDrawOverTheWindowsViewIsTurnedOntoTheProgramsScreen) {
    // A HUD drawn over the scene the window's perspective view showed lies on the program's
    // screen: turned by that view's correction, so that a tile looking elsewhere does not show
    // it (wall_cylinder_hud measures where it lands).
    ReplayHarness h;
    h.options.view.enabled = true;
    h.options.view.yaw_deg = 60;
    GLint mode = GL_MODELVIEW;
    bool ortho = false;
    h.gl->answer = [&](slave::RecordedCall& c) {
        if (c.opcode == OP_glMatrixMode) mode = GLint(c.args[0]);
        if (c.opcode == OP_glFrustum) ortho = false;
        if (c.opcode == OP_glOrtho) ortho = true;
        if (c.opcode == OP_glGetIntegerv && c.args[0] == GL_MATRIX_MODE) *c.pointer<GLint>(1) = mode;
        if (c.opcode == OP_glGetDoublev && c.args[0] == GL_PROJECTION_MATRIX) {
            const glm::dmat4 p = ortho ? glm::ortho(0.0, 640.0, 0.0, 480.0, -1.0, 1.0)
                                       : glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
            std::memcpy(c.pointer<GLdouble>(1), &p[0][0], sizeof p);
        }
    };
    GL(glMatrixMode, GL_PROJECTION);
    GL(glFrustum, -1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    GL(glMatrixMode, GL_MODELVIEW);
    GL(glDrawArrays, GL_TRIANGLES, 0, 3);  // the scene
    GL(glMatrixMode, GL_PROJECTION);
    GL0(glLoadIdentity);
    GL(glOrtho, 0.0, 640.0, 0.0, 480.0, -1.0, 1.0);
    GL(glMatrixMode, GL_MODELVIEW);
    GL(glDrawArrays, GL_TRIANGLES, 0, 6);  // the HUD
    h.replay();
    const std::vector<std::string> calls = h.calls_from("glOrtho");
    EXPECT_EQ(std::count_if(calls.begin(), calls.end(), [](const std::string& c) { return c.rfind("glLoadMatrixd(", 0) == 0; }), 1)
        << "the HUD's orthographic projection was not turned by the view's correction";
}

TEST(TileAdapter, AFlatTileLeavesTheProjectionAlone) {
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    GL(glMatrixMode, GL_PROJECTION);
    GL(glFrustum, -1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    GL(glDrawArrays, GL_TRIANGLES, 0, 3);
    h.replay();
    EXPECT_TRUE(h.calls("glLoadMatrixd").empty());
}

TEST(TileAdapter, AViewportSetBeforeTheWindowGrewIsMappedForItsNewSize) {
    // The window made at 32x32, its viewport set once for 640x480, then the window grown to
    // 640x480 without another glViewport (apitrace's retrace does this).
    ReplayHarness h(32, 32);
    h.tile(1, 0, 2, 2);
    h.options.tile.canvas_width = 640, h.options.tile.canvas_height = 480;
    h.options.tile.width = 320, h.options.tile.height = 240, h.options.tile.x = 320, h.options.tile.y = 240;
    h.options.width = 320, h.options.height = 240;
    GL(glViewport, 0, 0, 640, 480);
    h.stream.synthetic(kSynthDrawableSize, [](Encoder& e) {
        e.value<uint64_t>(7);
        e.value<int32_t>(640);
        e.value<int32_t>(480);
    });
    h.swap();  // the resize applies from the next frame on
    GL(glClear, GL_COLOR_BUFFER_BIT);
    h.replay();
    EXPECT_EQ(h.calls_from("glClear(").size(), 1u);
    EXPECT_EQ(h.calls("glViewport").back(), "glViewport(-320, -240, 640, 480)");  // before: (-320, -240, 12800, 7200)
}

TEST(TileAdapter, AViewerWhoMovesGetsAProjectionTheProgramSetOnceCorrectedAgain) {
    // A tracked head: the eye moves between frames while the program keeps the projection it set
    // at its start (as glxgears does); the next frame's draws must see the new eye.
    ReplayHarness h;
    slave::ViewCorrection& v = h.options.view;
    v.enabled = v.screen = true;
    v.bottom_left = {-1.5, -1.5, -1.5}, v.bottom_right = {1.5, -1.5, -1.5}, v.top_left = {-1.5, 1.5, -1.5};
    GLint mode = GL_MODELVIEW;
    glm::dmat4 projection = glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    std::vector<glm::dmat4> loaded;
    h.gl->answer = [&](slave::RecordedCall& c) {
        if (c.opcode == OP_glMatrixMode) mode = GLint(c.args[0]);
        if (c.opcode == OP_glGetIntegerv && c.args[0] == GL_MATRIX_MODE) *c.pointer<GLint>(1) = mode;
        if (c.opcode == OP_glLoadMatrixd && mode == GL_PROJECTION) {
            std::memcpy(&projection[0][0], c.pointer<GLdouble>(0), sizeof projection);
            loaded.push_back(projection);
        }
        if (c.opcode == OP_glGetDoublev && c.args[0] == GL_PROJECTION_MATRIX)
            std::memcpy(c.pointer<GLdouble>(1), &projection[0][0], sizeof projection);
    };
    GL(glMatrixMode, GL_PROJECTION);
    GL(glFrustum, -1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    GL(glMatrixMode, GL_MODELVIEW);
    for (int frame = 0; frame < 3; ++frame) {
        GL(glDrawArrays, GL_TRIANGLES, 0, 3);
        h.swap();
    }
    h.prepare = [](slave::Replayer& r) {
        r.before_frame = [&r](uint64_t frame) {
            if (frame != 1) return;
            slave::Viewer viewer = r.options().viewer;
            viewer.head.position = {0.3, 0.1, 0};
            EXPECT_TRUE(r.set_viewer(viewer));
        };
    };
    h.replay();
    ASSERT_EQ(loaded.size(), 2u) << "frame 0 corrects the projection, frame 1 again for the moved eye, frame 2 keeps it";
    // The second is the program's projection corrected for the moved eye, not the first corrected twice.
    slave::ViewCorrection moved = v;
    moved.eye = {0.3, 0.1, 0};
    const glm::dmat4 app = glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    const glm::dmat4 want = moved.correction(app) * app;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(loaded[1][i][j], want[i][j], 1e-9) << i << j;
}
