// Context backends (slave/backends/) and image utilities (common/image.*).
//
// A backend's default framebuffer is the program's window framebuffer (slave/backend.h): the
// tests draw into it, not into FBOs, and check its size, its buffers, its life across
// make-currents and resizes, and that EGL and OSMesa rasterize the same scene identically.
//
// Headless backends (egl, osmesa) run everywhere with Mesa; tests named Window* need an X
// display and skip without DISPLAY (ctest runs them again under a private Xvfb). The program
// links no GL library: every GL call goes through the backend's proc_address, as in the slave.
//
//   build:  the backend_tests target (tests/backends/CMakeLists.txt)
//   run:    ./backend_tests   (GLCAST_TEST_OUT=dir to choose where the scene PNGs go)
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>
#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "common/gl_state.h"
#include "common/image.h"
#include "slave/backend.h"
#include "tests/backends/x11_grab.h"

using namespace glcast::slave;

namespace {

// ---- GL through the backend -----------------------------------------------------------------

#define GLCAST_TEST_GL(X)                                                                          \
    X(glGetString) X(glGetIntegerv) X(glGetBooleanv) X(glGetError) X(glIsEnabled) X(glEnable)     \
    X(glDisable) X(glViewport) X(glScissor) X(glClearColor) X(glClearDepth) X(glClear)            \
    X(glFinish) X(glReadPixels) X(glPixelStorei) X(glReadBuffer) X(glDrawBuffer)                  \
    X(glGenFramebuffers) X(glDeleteFramebuffers) X(glBindFramebuffer) X(glCheckFramebufferStatus) \
    X(glGenRenderbuffers) X(glDeleteRenderbuffers) X(glBindRenderbuffer) X(glRenderbufferStorage) \
    X(glFramebufferRenderbuffer) X(glFramebufferTexture2D) X(glGetFramebufferAttachmentParameteriv) \
    X(glGenTextures) X(glDeleteTextures) X(glBindTexture) X(glTexImage2D) X(glTexParameteri)      \
    X(glIsTexture) X(glTexEnvi)                                                                   \
    X(glCreateShader) X(glShaderSource) X(glCompileShader) X(glGetShaderiv) X(glGetShaderInfoLog) \
    X(glCreateProgram) X(glAttachShader) X(glLinkProgram) X(glGetProgramiv) X(glUseProgram)       \
    X(glDeleteShader) X(glDeleteProgram)                                                          \
    X(glGenVertexArrays) X(glBindVertexArray) X(glDeleteVertexArrays) X(glGenBuffers)             \
    X(glBindBuffer) X(glBufferData) X(glDeleteBuffers) X(glVertexAttribPointer)                   \
    X(glEnableVertexAttribArray) X(glDrawArrays) X(glDepthFunc)                                   \
    X(glBegin) X(glEnd) X(glVertex3f) X(glColor3f) X(glNormal3f) X(glTexCoord2f) X(glLightfv)     \
    X(glLightModelfv) X(glMaterialfv) X(glColorMaterial) X(glShadeModel) X(glMatrixMode)          \
    X(glLoadIdentity) X(glFrustum) X(glTranslatef) X(glRotatef) X(glPushMatrix) X(glPopMatrix)

struct Gl {
#define GLCAST_DECLARE(name) decltype(&::name) name = nullptr;
    GLCAST_TEST_GL(GLCAST_DECLARE)
#undef GLCAST_DECLARE

    // Call with a context of `backend` current. Empty string: all found.
    std::string load(Backend& backend) {
        std::string missing;
#define GLCAST_LOAD(fn)                                                     \
    fn = reinterpret_cast<decltype(fn)>(backend.proc_address(#fn)); \
    if (!fn) missing += #fn " ";
        GLCAST_TEST_GL(GLCAST_LOAD)
#undef GLCAST_LOAD
        return missing;
    }
    std::string version() { return reinterpret_cast<const char*>(glGetString(GL_VERSION)); }
    std::array<int, 4> viewport() {
        std::array<int, 4> v{};
        glGetIntegerv(GL_VIEWPORT, v.data());
        return v;
    }
    bool double_buffered() {
        GLboolean db = GL_FALSE;
        glGetBooleanv(GL_DOUBLEBUFFER, &db);
        return db;
    }
};

std::string out_dir() {
    const char* d = std::getenv("GLCAST_TEST_OUT");
    std::string dir = d && *d ? d : ::testing::TempDir();
    if (!dir.empty() && dir.back() != '/') dir += '/';
    return dir;
}

// The bound read framebuffer's w x h pixels, top row first.
Image read_pixels(Gl& gl, int w, int h) {
    Image img;
    img.width = w;
    img.height = h;
    img.rgba.resize(size_t(w) * h * 4);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
    return flip_rows(img);
}

// The default framebuffer's drawn buffer (back if double-buffered, else front), w x h, top row
// first: what the slave reads for a frame (Replayer::end_frame).
Image read_default(Gl& gl, int w, int h) {
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl.glReadBuffer(gl.double_buffered() ? GL_BACK : GL_FRONT);
    return read_pixels(gl, w, h);
}

// Pixel (x, y) of a top-down image, y counted from the top.
std::array<int, 4> px(const Image& img, int x, int y) {
    const uint8_t* p = &img.rgba[(size_t(y) * img.width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
}

::testing::AssertionResult near(const std::array<int, 4>& got, const std::array<int, 4>& want, int tol = 1) {
    for (int i = 0; i < 4; ++i)
        if (std::abs(got[i] - want[i]) > tol)
            return ::testing::AssertionFailure() << "pixel (" << got[0] << "," << got[1] << "," << got[2] << ","
                                                 << got[3] << ") != (" << want[0] << "," << want[1] << ","
                                                 << want[2] << "," << want[3] << ")";
    return ::testing::AssertionSuccess();
}

const std::array<int, 4> kClear = {51, 102, 153, 255};  // glClearColor(0.2, 0.4, 0.6, 1)

void clear(Gl& gl, float r = 0.2f, float g = 0.4f, float b = 0.6f) {
    gl.glClearColor(r, g, b, 1.0f);
    gl.glClearDepth(1.0);
    gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
}

// The default framebuffer is exactly w x h and cleared to `want`: a (w+1) x (h+1) read of it
// fills w x h pixels with `want` and leaves the extra column and row of the destination alone
// (Mesa clips reads to the framebuffer; the spec leaves those pixels undefined).
::testing::AssertionResult default_framebuffer_is(Gl& gl, int w, int h, const std::array<int, 4>& want = kClear) {
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl.glReadBuffer(gl.double_buffered() ? GL_BACK : GL_FRONT);
    const int W = w + 1, H = h + 1;
    std::vector<uint8_t> data(size_t(W) * H * 4, 0xee);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, data.data());
    int64_t wrong_inside = 0, written_outside = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const uint8_t* p = &data[(size_t(y) * W + x) * 4];
            if (x < w && y < h) {
                wrong_inside += !near({p[0], p[1], p[2], p[3]}, want, 0);
            } else {
                written_outside += p[0] != 0xee || p[1] != 0xee || p[2] != 0xee || p[3] != 0xee;
            }
        }
    const GLenum err = gl.glGetError();
    if (wrong_inside || written_outside || err != GL_NO_ERROR)
        return ::testing::AssertionFailure() << "expected a " << w << "x" << h << " default framebuffer: "
                                             << wrong_inside << " pixels inside differ from the clear colour, "
                                             << written_outside << " pixels outside were written, GL error 0x"
                                             << std::hex << err;
    return ::testing::AssertionSuccess();
}

GLuint compile(Gl& gl, GLenum type, const char* source) {
    GLuint s = gl.glCreateShader(type);
    gl.glShaderSource(s, 1, &source, nullptr);
    gl.glCompileShader(s);
    GLint ok = 0;
    gl.glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = {};
        gl.glGetShaderInfoLog(s, sizeof log, nullptr, log);
        ADD_FAILURE() << "shader: " << log;
    }
    return s;
}

// A triangle over the middle of the framebuffer in (255, 128, 0), by shader (core profile).
void draw_core_triangle(Gl& gl) {
    const GLuint vs = compile(gl, GL_VERTEX_SHADER,
                              "#version 330 core\nlayout(location = 0) in vec2 p;\n"
                              "void main() { gl_Position = vec4(p, 0.5, 1.0); }\n");
    const GLuint fs = compile(gl, GL_FRAGMENT_SHADER,
                              "#version 330 core\nout vec4 color;\n"
                              "void main() { color = vec4(1.0, 0.5, 0.0, 1.0); }\n");
    const GLuint prog = gl.glCreateProgram();
    gl.glAttachShader(prog, vs);
    gl.glAttachShader(prog, fs);
    gl.glLinkProgram(prog);
    GLint linked = 0;
    gl.glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    EXPECT_TRUE(linked);
    const float verts[] = {-0.8f, -0.8f, 0.8f, -0.8f, 0.0f, 0.8f};
    GLuint vao = 0, vbo = 0;
    gl.glGenVertexArrays(1, &vao);
    gl.glBindVertexArray(vao);
    gl.glGenBuffers(1, &vbo);
    gl.glBindBuffer(GL_ARRAY_BUFFER, vbo);
    gl.glBufferData(GL_ARRAY_BUFFER, sizeof verts, verts, GL_STATIC_DRAW);
    gl.glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.glEnableVertexAttribArray(0);
    gl.glUseProgram(prog);
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDrawArrays(GL_TRIANGLES, 0, 3);
    gl.glDisable(GL_DEPTH_TEST);
    gl.glUseProgram(0);
    gl.glBindVertexArray(0);
    gl.glDeleteBuffers(1, &vbo);
    gl.glDeleteVertexArrays(1, &vao);
    gl.glDeleteProgram(prog);
    gl.glDeleteShader(vs);
    gl.glDeleteShader(fs);
}

// The same triangle in immediate mode (compatibility profile).
void draw_compat_triangle(Gl& gl) {
    gl.glEnable(GL_DEPTH_TEST);
    gl.glBegin(GL_TRIANGLES);
    gl.glColor3f(1.0f, 0.5f, 0.0f);
    gl.glVertex3f(-0.8f, -0.8f, 0.0f);
    gl.glVertex3f(0.8f, -0.8f, 0.0f);
    gl.glVertex3f(0.0f, 0.8f, 0.0f);
    gl.glEnd();
    gl.glDisable(GL_DEPTH_TEST);
}

// The triangle in a 64 x 48 framebuffer (top-down image): apex up, base down.
void expect_triangle_scene(const Image& img) {
    ASSERT_EQ(img.width, 64);
    ASSERT_EQ(img.height, 48);
    EXPECT_TRUE(near(px(img, 32, 28), {255, 128, 0, 255})) << "triangle centre";
    EXPECT_TRUE(near(px(img, 10, 41), {255, 128, 0, 255})) << "near the base, left";
    EXPECT_TRUE(near(px(img, 10, 6), kClear)) << "beside the apex, left (an upside-down image fails here)";
    EXPECT_TRUE(near(px(img, 0, 0), kClear)) << "top-left corner";
    EXPECT_TRUE(near(px(img, 63, 0), kClear)) << "top-right corner";
    EXPECT_TRUE(near(px(img, 2, 2), kClear)) << "beside the apex";
}

// ---- the comparison scene: fixed function, compatibility profile ----------------------------

// Three parts, depth tested in perspective: an unlit smooth-shaded triangle (colour
// interpolation), two lit smooth-shaded crossing triangles (per-vertex lighting with specular,
// depth on their intersection), and a textured triangle (perspective-correct texture
// coordinates, bilinear filtering, repeat, GL_MODULATE). Leaves the texture bound to the caller
// to delete.
GLuint draw_comparison_scene(Gl& gl, int w, int h) {
    gl.glViewport(0, 0, w, h);
    clear(gl);
    gl.glMatrixMode(GL_PROJECTION);
    gl.glLoadIdentity();
    gl.glFrustum(-1.0, 1.0, -0.75, 0.75, 1.5, 20.0);
    gl.glMatrixMode(GL_MODELVIEW);
    gl.glLoadIdentity();
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_LESS);
    gl.glShadeModel(GL_SMOOTH);

    // Unlit, smooth: top left.
    gl.glPushMatrix();
    gl.glTranslatef(-1.7f, 0.9f, -4.5f);
    gl.glRotatef(20.0f, 0.0f, 0.0f, 1.0f);
    gl.glBegin(GL_TRIANGLES);
    gl.glColor3f(1.0f, 0.0f, 0.0f); gl.glVertex3f(-0.9f, -0.7f, 0.0f);
    gl.glColor3f(0.0f, 1.0f, 0.0f); gl.glVertex3f(0.9f, -0.6f, 0.2f);
    gl.glColor3f(0.0f, 0.0f, 1.0f); gl.glVertex3f(0.1f, 0.8f, -0.3f);
    gl.glEnd();
    gl.glPopMatrix();

    // Lit, smooth: the middle.
    const float light_pos[] = {2.0f, 3.0f, 4.0f, 0.0f};
    const float ambient[] = {0.15f, 0.15f, 0.15f, 1.0f};
    const float specular[] = {0.8f, 0.8f, 0.8f, 1.0f};
    const float shininess[] = {24.0f};
    gl.glLightfv(GL_LIGHT0, GL_POSITION, light_pos);
    gl.glLightfv(GL_LIGHT0, GL_SPECULAR, specular);
    gl.glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
    gl.glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, specular);
    gl.glMaterialfv(GL_FRONT_AND_BACK, GL_SHININESS, shininess);
    gl.glEnable(GL_LIGHTING);
    gl.glEnable(GL_LIGHT0);
    gl.glEnable(GL_COLOR_MATERIAL);
    gl.glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    gl.glEnable(GL_NORMALIZE);
    gl.glPushMatrix();
    gl.glTranslatef(0.0f, 0.0f, -4.0f);
    gl.glRotatef(-30.0f, 1.0f, 0.0f, 0.0f);
    gl.glRotatef(25.0f, 0.0f, 1.0f, 0.0f);
    gl.glBegin(GL_TRIANGLES);
    gl.glNormal3f(-0.3f, 0.2f, 1.0f); gl.glColor3f(1.0f, 0.1f, 0.1f); gl.glVertex3f(-1.6f, -1.0f, 0.0f);
    gl.glNormal3f(0.4f, 0.1f, 1.0f);  gl.glColor3f(0.1f, 1.0f, 0.1f); gl.glVertex3f(1.6f, -1.0f, 0.3f);
    gl.glNormal3f(0.0f, 0.6f, 0.8f);  gl.glColor3f(0.1f, 0.2f, 1.0f); gl.glVertex3f(0.0f, 1.5f, -0.4f);
    gl.glNormal3f(0.8f, 0.0f, 0.6f);  gl.glColor3f(1.0f, 1.0f, 0.2f); gl.glVertex3f(-1.2f, 0.8f, -0.8f);
    gl.glNormal3f(-0.5f, 0.5f, 0.7f); gl.glColor3f(0.2f, 1.0f, 1.0f); gl.glVertex3f(1.0f, 1.0f, 0.6f);
    gl.glNormal3f(0.0f, -0.7f, 0.7f); gl.glColor3f(1.0f, 0.3f, 1.0f); gl.glVertex3f(0.2f, -1.3f, 0.2f);
    gl.glEnd();
    gl.glPopMatrix();
    gl.glDisable(GL_LIGHTING);
    gl.glDisable(GL_COLOR_MATERIAL);

    // Textured: bottom right, tilted away so that the texture is perspective-mapped.
    uint8_t texels[8 * 8 * 4];
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            uint8_t* t = &texels[(y * 8 + x) * 4];
            const bool dark = (x / 2 + y / 2) % 2;
            t[0] = uint8_t(dark ? 30 + x * 9 : 250 - y * 11);
            t[1] = uint8_t(dark ? 40 + y * 17 : 220);
            t[2] = uint8_t(dark ? 200 - x * 13 : 60 + x * y * 2);
            t[3] = 255;
        }
    GLuint tex = 0;
    gl.glGenTextures(1, &tex);
    gl.glBindTexture(GL_TEXTURE_2D, tex);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 8, 8, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    gl.glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    gl.glEnable(GL_TEXTURE_2D);
    gl.glPushMatrix();
    gl.glTranslatef(1.5f, -0.9f, -3.6f);
    gl.glRotatef(-55.0f, 1.0f, 0.0f, 0.0f);
    gl.glRotatef(15.0f, 0.0f, 0.0f, 1.0f);
    gl.glBegin(GL_TRIANGLES);
    gl.glColor3f(0.9f, 0.8f, 0.7f);
    gl.glTexCoord2f(0.0f, 0.0f); gl.glVertex3f(-1.1f, -1.0f, 0.0f);
    gl.glTexCoord2f(2.5f, 0.0f); gl.glVertex3f(1.2f, -0.9f, 0.0f);
    gl.glTexCoord2f(1.0f, 2.0f); gl.glVertex3f(0.0f, 1.3f, 0.0f);
    gl.glEnd();
    gl.glPopMatrix();
    gl.glDisable(GL_TEXTURE_2D);
    gl.glDisable(GL_DEPTH_TEST);
    gl.glFinish();
    return tex;
}

// ---- headless backends ----------------------------------------------------------------------

ContextRequest core33() {
    ContextRequest r;
    r.major = 3;
    r.minor = 3;
    r.core = true;
    return r;
}

class Headless : public ::testing::TestWithParam<std::string> {
protected:
    void SetUp() override {
        std::string error;
        backend_ = make_backend(GetParam(), error);
        ASSERT_TRUE(backend_) << error;
        EXPECT_STREQ(backend_->name(), GetParam().c_str());
    }
    void TearDown() override {
        if (backend_) {
            std::string error;
            backend_->make_current(0, 0, 0, error);
        }
    }
    // Creates context `id`, makes it current with a w x h default framebuffer and loads GL
    // through the backend.
    void start(uint32_t id, const ContextRequest& request, uint32_t share = 0, int w = 64, int h = 48) {
        std::string error;
        ASSERT_TRUE(backend_->create_context(id, share, request, error)) << error;
        ASSERT_TRUE(backend_->make_current(id, w, h, error)) << error;
        const std::string missing = gl_.load(*backend_);
        ASSERT_EQ(missing, "") << "entry points missing";
    }
    std::unique_ptr<Backend> backend_;
    Gl gl_;
};

// First make-current with 64 x 48: viewport and scissor box cover it (as GLX does for the
// window a context is first made current to), the default framebuffer is bound with its
// window-format buffers, and it is exactly 64 x 48.
TEST_P(Headless, DefaultFramebufferOfTheRequestedSize) {
    ASSERT_NO_FATAL_FAILURE(start(1, ContextRequest{}));
    EXPECT_EQ(gl_.viewport(), (std::array<int, 4>{0, 0, 64, 48}));
    std::array<int, 4> scissor{};
    gl_.glGetIntegerv(GL_SCISSOR_BOX, scissor.data());
    EXPECT_EQ(scissor, (std::array<int, 4>{0, 0, 64, 48}));
    GLint draw_fb = -1, read_fb = -1, draw_buffer = 0, read_buffer = 0;
    gl_.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fb);
    gl_.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb);
    EXPECT_EQ(draw_fb, 0);
    EXPECT_EQ(read_fb, 0);

    // GL_DOUBLEBUFFER decides which buffer the slave reads a frame from (default_framebuffer_is
    // below reads that one after drawing with the initial draw buffer). Mesa's headless buffers
    // are single-buffered, the front and back names the same buffer (an EGL pbuffer starts with
    // draw buffer GL_BACK, read buffer GL_FRONT); both names must be accepted, since the
    // captured program's window had both.
    const bool db = gl_.double_buffered();
    gl_.glGetIntegerv(GL_DRAW_BUFFER, &draw_buffer);
    gl_.glGetIntegerv(GL_READ_BUFFER, &read_buffer);
    for (GLenum buffer : {GL_BACK, GL_FRONT}) {
        gl_.glDrawBuffer(buffer);
        gl_.glReadBuffer(buffer);
        EXPECT_EQ(gl_.glGetError(), GLenum(GL_NO_ERROR)) << "glDrawBuffer/glReadBuffer 0x" << std::hex << buffer;
    }
    gl_.glDrawBuffer(GLenum(draw_buffer));
    gl_.glReadBuffer(GLenum(read_buffer));

    // Window format: 8-bit RGB, 24-bit depth, 8-bit stencil.
    GLint bits[6] = {};
    const GLenum pnames[6] = {GL_RED_BITS, GL_GREEN_BITS, GL_BLUE_BITS, GL_ALPHA_BITS, GL_DEPTH_BITS, GL_STENCIL_BITS};
    for (int i = 0; i < 6; ++i) gl_.glGetIntegerv(pnames[i], &bits[i]);
    EXPECT_EQ(bits[0], 8);
    EXPECT_EQ(bits[1], 8);
    EXPECT_EQ(bits[2], 8);
    EXPECT_EQ(bits[4], 24);
    EXPECT_EQ(bits[5], 8);
    if (GetParam() == "egl") {
        EXPECT_EQ(bits[3], 0) << "the XRGB8888 config has no alpha";
    }
    auto buffer_name = [](GLint b) { return b == GL_BACK ? "GL_BACK" : b == GL_FRONT ? "GL_FRONT" : "other"; };
    std::printf("[ %s ] default framebuffer: GL_DOUBLEBUFFER %s, draw buffer %s, read buffer %s, "
                "R%dG%dB%dA%d D%d S%d\n",
                GetParam().c_str(), db ? "true" : "false", buffer_name(draw_buffer), buffer_name(read_buffer),
                bits[0], bits[1], bits[2], bits[3], bits[4], bits[5]);

    clear(gl_);
    EXPECT_TRUE(default_framebuffer_is(gl_, 64, 48));
    EXPECT_EQ(gl_.glGetError(), GLenum(GL_NO_ERROR));
}

TEST_P(Headless, Core33Triangle) {
    ASSERT_NO_FATAL_FAILURE(start(1, core33()));
    const std::string version = gl_.version();
    int major = 0, minor = 0, profile = 0;
    gl_.glGetIntegerv(GL_MAJOR_VERSION, &major);
    gl_.glGetIntegerv(GL_MINOR_VERSION, &minor);
    gl_.glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_GE(major * 10 + minor, 33) << version;
    EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT) << version;
    EXPECT_EQ(gl_.viewport(), (std::array<int, 4>{0, 0, 64, 48}));
    const bool db = gl_.double_buffered();
    std::printf("[ %s ] core context: %s, GL_DOUBLEBUFFER %s\n", GetParam().c_str(), version.c_str(),
                db ? "true" : "false");

    // The default framebuffer's colour buffer, as a core context sees it.
    GLint red = 0, alpha = -1;
    gl_.glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, db ? GL_BACK_LEFT : GL_FRONT_LEFT,
                                              GL_FRAMEBUFFER_ATTACHMENT_RED_SIZE, &red);
    gl_.glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, db ? GL_BACK_LEFT : GL_FRONT_LEFT,
                                              GL_FRAMEBUFFER_ATTACHMENT_ALPHA_SIZE, &alpha);
    EXPECT_EQ(red, 8);
    if (GetParam() == "egl") {
        EXPECT_EQ(alpha, 0);
    }

    clear(gl_);
    EXPECT_TRUE(default_framebuffer_is(gl_, 64, 48));
    draw_core_triangle(gl_);
    expect_triangle_scene(read_default(gl_, 64, 48));
    EXPECT_EQ(gl_.glGetError(), GLenum(GL_NO_ERROR));
}

TEST_P(Headless, CompatibilityTriangle) {
    ASSERT_NO_FATAL_FAILURE(start(1, ContextRequest{}));
    const std::string version = gl_.version();
    int profile = 0;
    gl_.glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_FALSE(profile & GL_CONTEXT_CORE_PROFILE_BIT) << version;
    EXPECT_GE(std::atof(version.c_str()), 3.0) << "highest compatibility version expected: " << version;
    std::printf("[ %s ] compatibility context: %s\n", GetParam().c_str(), version.c_str());

    clear(gl_);
    draw_compat_triangle(gl_);
    expect_triangle_scene(read_default(gl_, 64, 48));
    EXPECT_EQ(gl_.glGetError(), GLenum(GL_NO_ERROR));
}

// make_current with another size replaces the default framebuffer; with the same size it keeps
// it (and its contents: programs make contexts current every frame). The viewport is the
// program's, as with a resized GLX window: not reset.
TEST_P(Headless, ResizeByMakeCurrent) {
    ASSERT_NO_FATAL_FAILURE(start(1, ContextRequest{}));
    const bool db = gl_.double_buffered();
    clear(gl_);
    EXPECT_TRUE(default_framebuffer_is(gl_, 64, 48));

    std::string error;
    ASSERT_TRUE(backend_->make_current(1, 96, 80, error)) << error;
    EXPECT_EQ(gl_.viewport(), (std::array<int, 4>{0, 0, 64, 48})) << "a resize does not move the viewport";
    EXPECT_EQ(gl_.double_buffered(), db);
    gl_.glViewport(0, 0, 96, 80);
    clear(gl_, 1.0f, 0.0f, 0.0f);
    EXPECT_TRUE(default_framebuffer_is(gl_, 96, 80, {255, 0, 0, 255}));

    ASSERT_TRUE(backend_->make_current(1, 40, 30, error)) << error;  // smaller
    gl_.glViewport(0, 0, 40, 30);
    clear(gl_, 0.0f, 1.0f, 0.0f);
    EXPECT_TRUE(default_framebuffer_is(gl_, 40, 30, {0, 255, 0, 255}));

    // Same size again, after a release: the same framebuffer, contents kept.
    ASSERT_TRUE(backend_->make_current(0, 0, 0, error)) << error;
    ASSERT_TRUE(backend_->make_current(1, 40, 30, error)) << error;
    EXPECT_TRUE(default_framebuffer_is(gl_, 40, 30, {0, 255, 0, 255}));

    // And back to 64 x 48, drawn into.
    ASSERT_TRUE(backend_->make_current(1, 64, 48, error)) << error;
    gl_.glViewport(0, 0, 64, 48);
    clear(gl_);
    EXPECT_TRUE(default_framebuffer_is(gl_, 64, 48));
    draw_compat_triangle(gl_);
    expect_triangle_scene(read_default(gl_, 64, 48));
    EXPECT_EQ(gl_.glGetError(), GLenum(GL_NO_ERROR));
}

// Two contexts of the same size each have their own default framebuffer (as two windows).
TEST_P(Headless, ContextsHaveTheirOwnDefaultFramebuffers) {
    ASSERT_NO_FATAL_FAILURE(start(1, ContextRequest{}));
    std::string error;
    ASSERT_TRUE(backend_->create_context(2, 1, ContextRequest{}, error)) << error;
    clear(gl_, 1.0f, 0.0f, 0.0f);
    gl_.glFinish();
    ASSERT_TRUE(backend_->make_current(2, 64, 48, error)) << error;
    EXPECT_EQ(gl_.viewport(), (std::array<int, 4>{0, 0, 64, 48}));
    clear(gl_, 0.0f, 0.0f, 1.0f);
    gl_.glFinish();
    ASSERT_TRUE(backend_->make_current(1, 64, 48, error)) << error;
    EXPECT_TRUE(default_framebuffer_is(gl_, 64, 48, {255, 0, 0, 255})) << "context 1";
    ASSERT_TRUE(backend_->make_current(2, 64, 48, error)) << error;
    EXPECT_TRUE(default_framebuffer_is(gl_, 64, 48, {0, 0, 255, 255})) << "context 2";
    backend_->destroy_context(2);
}

TEST_P(Headless, SharedTextureVisibleInSecondContext) {
    ASSERT_NO_FATAL_FAILURE(start(1, ContextRequest{}));
    const uint8_t texels[2 * 2 * 4] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 10, 20, 30, 40};
    GLuint tex = 0;
    gl_.glGenTextures(1, &tex);
    gl_.glBindTexture(GL_TEXTURE_2D, tex);
    gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl_.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 2, 2, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    gl_.glFinish();

    std::string error;
    ASSERT_TRUE(backend_->create_context(2, 1, ContextRequest{}, error)) << error;
    ASSERT_TRUE(backend_->create_context(3, 0, ContextRequest{}, error)) << error;  // not sharing
    ASSERT_TRUE(backend_->make_current(3, 64, 48, error)) << error;
    EXPECT_FALSE(gl_.glIsTexture(tex)) << "an unshared context sees the texture";
    ASSERT_TRUE(backend_->make_current(2, 32, 32, error)) << error;
    EXPECT_TRUE(gl_.glIsTexture(tex));

    // Read back through an FBO...
    GLuint fbo = 0;
    gl_.glGenFramebuffers(1, &fbo);
    gl_.glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl_.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    ASSERT_EQ(gl_.glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    uint8_t back[16] = {};
    gl_.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl_.glReadPixels(0, 0, 2, 2, GL_RGBA, GL_UNSIGNED_BYTE, back);
    EXPECT_EQ(std::memcmp(back, texels, 16), 0);
    gl_.glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_.glDeleteFramebuffers(1, &fbo);

    // ...and drawn into the second context's default framebuffer: a quad of 2 x 2 texels
    // over its 32 x 32 pixels.
    gl_.glViewport(0, 0, 32, 32);
    clear(gl_);
    gl_.glBindTexture(GL_TEXTURE_2D, tex);
    gl_.glEnable(GL_TEXTURE_2D);
    gl_.glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    gl_.glBegin(GL_TRIANGLES);
    gl_.glTexCoord2f(0, 0); gl_.glVertex3f(-1, -1, 0);
    gl_.glTexCoord2f(1, 0); gl_.glVertex3f(1, -1, 0);
    gl_.glTexCoord2f(1, 1); gl_.glVertex3f(1, 1, 0);
    gl_.glTexCoord2f(0, 0); gl_.glVertex3f(-1, -1, 0);
    gl_.glTexCoord2f(1, 1); gl_.glVertex3f(1, 1, 0);
    gl_.glTexCoord2f(0, 1); gl_.glVertex3f(-1, 1, 0);
    gl_.glEnd();
    gl_.glDisable(GL_TEXTURE_2D);
    const Image drawn = read_default(gl_, 32, 32);
    EXPECT_TRUE(near(px(drawn, 4, 27), {255, 0, 0, 255}, 0)) << "bottom left: texel (0, 0)";
    EXPECT_TRUE(near(px(drawn, 27, 27), {0, 255, 0, 255}, 0)) << "bottom right: texel (1, 0)";
    EXPECT_TRUE(near(px(drawn, 4, 4), {0, 0, 255, 255}, 0)) << "top left: texel (0, 1)";
    EXPECT_EQ(gl_.glGetError(), GLenum(GL_NO_ERROR));

    backend_->destroy_context(2);  // current: released first
    ASSERT_TRUE(backend_->make_current(1, 64, 48, error)) << error;
    EXPECT_TRUE(gl_.glIsTexture(tex));
    backend_->destroy_context(3);
}

TEST_P(Headless, ContextCurrentOnAnotherThread) {
    ASSERT_NO_FATAL_FAILURE(start(1, core33()));
    std::string error;
    ASSERT_TRUE(backend_->make_current(0, 0, 0, error)) << error;
    Image img;
    std::string thread_error;
    std::thread worker([&] {
        if (!backend_->make_current(1, 64, 48, thread_error)) return;
        clear(gl_);
        draw_core_triangle(gl_);
        img = read_default(gl_, 64, 48);
        backend_->make_current(0, 0, 0, thread_error);
    });
    worker.join();
    ASSERT_EQ(thread_error, "");
    expect_triangle_scene(img);
    ASSERT_TRUE(backend_->make_current(1, 64, 48, error)) << error;  // free again after release
    expect_triangle_scene(read_default(gl_, 64, 48));  // the same framebuffer, the worker's frame
}

TEST_P(Headless, DebugAndForwardCompatibleRequests) {
    ContextRequest r = core33();
    r.forward_compatible = true;
    r.debug = true;
    ASSERT_NO_FATAL_FAILURE(start(1, r));
    int flags = 0;
    gl_.glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    if (GetParam() == "egl") {
        EXPECT_TRUE(flags & GL_CONTEXT_FLAG_DEBUG_BIT);
        EXPECT_TRUE(flags & GL_CONTEXT_FLAG_FORWARD_COMPATIBLE_BIT);
    }
    // osmesa has no attributes for these: the context is created without them.
}

TEST_P(Headless, Errors) {
    std::string error;
    EXPECT_FALSE(backend_->make_current(7, 64, 48, error));
    EXPECT_NE(error.find(GetParam() + ": "), std::string::npos) << error;
    EXPECT_NE(error.find("7"), std::string::npos) << error;

    error.clear();
    EXPECT_FALSE(backend_->create_context(1, 42, ContextRequest{}, error));
    EXPECT_NE(error.find("share context 42"), std::string::npos) << error;

    ContextRequest impossible;
    impossible.major = 9;
    impossible.minor = 9;
    impossible.core = true;
    error.clear();
    EXPECT_FALSE(backend_->create_context(1, 0, impossible, error));
    EXPECT_NE(error.find(GetParam() + ": "), std::string::npos) << error;
    EXPECT_NE(error.find("9.9 core"), std::string::npos) << error;
    std::printf("[ %s ] expected error: %s\n", GetParam().c_str(), error.c_str());

    ASSERT_TRUE(backend_->create_context(1, 0, ContextRequest{}, error)) << error;
    error.clear();
    EXPECT_FALSE(backend_->create_context(1, 0, ContextRequest{}, error));
    EXPECT_NE(error.find("already exists"), std::string::npos) << error;
    backend_->present();  // headless, nothing current: nothing, no crash
    ASSERT_TRUE(backend_->make_current(1, 64, 48, error)) << error;
    backend_->present();  // headless: nothing
    backend_->destroy_context(1);
    backend_->destroy_context(1);  // unknown: ignored
}

// What glcast does inside a program's frame (a depth copy before an overlay engine's draw, a
// pass) runs under GlStateGuard, and the program draws on with what it left: a framebuffer object
// with several draw buffers keeps every one (Blender's overlay engine draws its wires into a
// colour and a line-data attachment at once; restoring only the first left its anti-aliasing
// pass without line data, and its wires drawn aliased).
TEST_P(Headless, StateGuardKeepsEveryDrawBuffer) {
    start(1, core33());
    glcast::GlApi api;
    std::string error;
    ASSERT_TRUE(api.load([this](const char* name) { return backend_->proc_address(name); }, error)) << error;
    GLuint fb = 0, colour[3] = {};
    api.glGenFramebuffers(1, &fb);
    api.glBindFramebuffer(GL_FRAMEBUFFER, fb);
    api.glGenRenderbuffers(3, colour);
    for (int i = 0; i < 3; ++i) {
        api.glBindRenderbuffer(GL_RENDERBUFFER, colour[i]);
        api.glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 16, 16);
        api.glFramebufferRenderbuffer(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + i), GL_RENDERBUFFER, colour[i]);
    }
    const GLenum program_buffers[] = {GL_COLOR_ATTACHMENT2, GL_NONE, GL_COLOR_ATTACHMENT0};
    api.glDrawBuffers(3, program_buffers);
    ASSERT_EQ(api.glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    {
        glcast::GlStateGuard guard(api, glcast::kGuardPass);
        api.glBindFramebuffer(GL_FRAMEBUFFER, 0);  // (what runs inside draws elsewhere)
    }
    GLint bound = 0;
    api.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    EXPECT_EQ(GLuint(bound), fb);
    for (int i = 0; i < 3; ++i) {
        GLint buffer = -1;
        api.glGetIntegerv(GLenum(GL_DRAW_BUFFER0 + i), &buffer);
        EXPECT_EQ(GLenum(buffer), program_buffers[i]) << "draw buffer " << i;
    }
    {  // and the window's single buffer, as before
        api.glBindFramebuffer(GL_FRAMEBUFFER, 0);
        GLint window_buffer = 0;
        api.glGetIntegerv(GL_DRAW_BUFFER, &window_buffer);
        { glcast::GlStateGuard guard(api, glcast::kGuardPass); }
        GLint after = 0;
        api.glGetIntegerv(GL_DRAW_BUFFER, &after);
        EXPECT_EQ(after, window_buffer);
    }
    EXPECT_EQ(api.glGetError(), GLenum(GL_NO_ERROR));
    api.glDeleteRenderbuffers(3, colour);
    api.glDeleteFramebuffers(1, &fb);
}

INSTANTIATE_TEST_SUITE_P(Backends, Headless, ::testing::Values("egl", "osmesa"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(Factory, UnknownKind) {
    std::string error;
    EXPECT_EQ(make_backend("vulkan", error), nullptr);
    EXPECT_NE(error.find("vulkan"), std::string::npos) << error;
}

TEST(Factory, WindowWithoutDisplayFails) {
    if (std::getenv("DISPLAY")) GTEST_SKIP() << "DISPLAY is set";
    std::string error;
    EXPECT_EQ(make_backend("window", error), nullptr);
    EXPECT_NE(error.find("window: "), std::string::npos) << error;
    std::printf("[ window ] expected error: %s\n", error.c_str());
}

// ---- egl vs osmesa --------------------------------------------------------------------------

// The comparison scene in the default framebuffer of a fresh compatibility context of `kind`
// (fbo false), or in an RGBA8 FBO of the same context (fbo true, for comparison only).
Image render_comparison(const std::string& kind, int w, int h, std::string& version, bool fbo = false) {
    std::string error;
    auto backend = make_backend(kind, error);
    if (!backend) {
        ADD_FAILURE() << error;
        return {};
    }
    if (!backend->create_context(1, 0, ContextRequest{}, error) || !backend->make_current(1, w, h, error)) {
        ADD_FAILURE() << error;
        return {};
    }
    Gl gl;
    EXPECT_EQ(gl.load(*backend), "");
    version = gl.version();
    GLuint fb = 0, rb[2] = {};
    if (fbo) {
        gl.glGenFramebuffers(1, &fb);
        gl.glBindFramebuffer(GL_FRAMEBUFFER, fb);
        gl.glGenRenderbuffers(2, rb);
        gl.glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
        gl.glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
        gl.glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
        gl.glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
        gl.glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
        gl.glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
        EXPECT_EQ(gl.glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    }
    GLuint tex = draw_comparison_scene(gl, w, h);
    Image img = fbo ? read_pixels(gl, w, h) : read_default(gl, w, h);
    EXPECT_EQ(gl.glGetError(), GLenum(GL_NO_ERROR));
    gl.glDeleteTextures(1, &tex);
    if (fbo) {
        gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
        gl.glDeleteRenderbuffers(2, rb);
        gl.glDeleteFramebuffers(1, &fb);
    }
    backend->make_current(0, 0, 0, error);
    return img;
}

constexpr int kSceneW = 320, kSceneH = 240;

// Pixels that are not the clear colour, per part of the scene.
struct Coverage {
    int64_t total = 0, left = 0, middle = 0, right_bottom = 0;
};
Coverage coverage(const Image& img) {
    Coverage c;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            if (near(px(img, x, y), kClear, 0)) continue;
            ++c.total;
            if (x < img.width / 4 && y < img.height / 3) ++c.left;
            if (x > img.width * 3 / 8 && x < img.width * 5 / 8 && y > img.height / 3 && y < img.height * 2 / 3) ++c.middle;
            if (x > img.width * 3 / 4 && y > img.height * 2 / 3) ++c.right_bottom;
        }
    return c;
}

// The project wants replays pixel-identical on both software paths: the same scene in the
// default framebuffers of egl and osmesa (both Mesa llvmpipe here), compared exactly.
TEST(CrossBackend, EglAndOsmesaDefaultFramebuffersIdentical) {
    const int w = kSceneW, h = kSceneH;
    std::string egl_version, osmesa_version;
    const Image egl = render_comparison("egl", w, h, egl_version);
    const Image osmesa = render_comparison("osmesa", w, h, osmesa_version);
    ASSERT_EQ(egl.width, w);
    ASSERT_EQ(osmesa.width, w);
    std::string error;
    EXPECT_TRUE(write_png(out_dir() + "backend_egl.png", egl, error)) << error;
    EXPECT_TRUE(write_png(out_dir() + "backend_osmesa.png", osmesa, error)) << error;

    // The scene must have drawn all three parts, not just the clear colour.
    const Coverage c = coverage(egl);
    EXPECT_GT(c.total, w * h / 8);
    EXPECT_GT(c.left, 500) << "unlit triangle, top left";
    EXPECT_GT(c.middle, 2000) << "lit triangles, middle";
    EXPECT_GT(c.right_bottom, 500) << "textured triangle, bottom right";

    const ImageDiff d = compare(egl, osmesa);
    std::printf("[ cross ] egl (%s) vs osmesa (%s), default framebuffers: %lld of %d pixels differ, max channel "
                "diff %d (scene covers %lld pixels)\n",
                egl_version.c_str(), osmesa_version.c_str(), static_cast<long long>(d.differing_pixels), w * h,
                d.max_channel_diff, static_cast<long long>(c.total));
    ::testing::Test::RecordProperty("differing_pixels", std::to_string(d.differing_pixels));
    ::testing::Test::RecordProperty("max_channel_diff", d.max_channel_diff);
    EXPECT_FALSE(d.size_mismatch);
    EXPECT_EQ(d.differing_pixels, 0);
    EXPECT_EQ(d.max_channel_diff, 0);

    // For the record only: the same scene in an RGBA8 FBO, which is why the window
    // framebuffer is the default framebuffer (slave/backend.h).
    std::string ignored;
    const Image egl_fbo = render_comparison("egl", w, h, ignored, true);
    const ImageDiff f = compare(egl, egl_fbo);
    std::printf("[ cross ] egl default framebuffer vs egl RGBA8 FBO: %lld pixels differ, max channel diff %d\n",
                static_cast<long long>(f.differing_pixels), f.max_channel_diff);
}

// ---- window backend -------------------------------------------------------------------------

class Window : public ::testing::Test {
protected:
    void SetUp() override {
        if (!std::getenv("DISPLAY")) GTEST_SKIP() << "needs an X display (DISPLAY unset); ctest runs it under Xvfb";
        std::string error;
        backend_ = make_backend("window", error);
        ASSERT_TRUE(backend_) << error;
    }
    void TearDown() override {
        std::string error;
        if (backend_) backend_->make_current(0, 0, 0, error);
    }
    // Presents what was drawn into the current window's w x h default framebuffer and returns
    // what the window then shows (read from the X server), with the back buffer's own pixels,
    // read before the swap, in `expected`.
    Image present_and_grab(Gl& gl, int w, int h, Image& expected) {
        EXPECT_TRUE(gl.double_buffered()) << "the window is double-buffered";
        expected = read_default(gl, w, h);

        // Program state present() must leave alone: framebuffer bindings, the scissor.
        GLuint other[2] = {};
        gl.glGenFramebuffers(2, other);
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, other[0]);
        gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, other[1]);
        gl.glEnable(GL_SCISSOR_TEST);
        gl.glScissor(0, 0, 1, 1);
        backend_->present();
        GLint read = 0, draw = 0;
        gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
        gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
        EXPECT_EQ(GLuint(read), other[0]);
        EXPECT_EQ(GLuint(draw), other[1]);
        EXPECT_TRUE(gl.glIsEnabled(GL_SCISSOR_TEST));
        gl.glDisable(GL_SCISSOR_TEST);
        gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
        gl.glDeleteFramebuffers(2, other);
        EXPECT_EQ(gl.glGetError(), GLenum(GL_NO_ERROR));

        // Mesa's software GLX does not read GL_FRONT back from the X window, so ask X.
        Image shown;
        std::string error;
        EXPECT_TRUE(glcast::test::grab_current_window(shown, error)) << error;
        return shown;
    }
    std::unique_ptr<Backend> backend_;
};

TEST_F(Window, DefaultFramebufferIsTheWindow) {
    std::string error;
    ASSERT_TRUE(backend_->create_context(1, 0, core33(), error)) << error;
    ASSERT_TRUE(backend_->create_context(2, 1, core33(), error)) << error;  // hidden, shared
    ASSERT_TRUE(backend_->make_current(1, 64, 48, error)) << error;
    Gl gl;
    ASSERT_EQ(gl.load(*backend_), "");
    // GLFW makes the context current once while creating its window (at 640 x 480), so the
    // initial viewport is the creation size, not the size of the first make_current; the
    // slave sets viewport and scissor itself at a context's first make-current
    // (Replayer::make_current), as done here.
    std::printf("[ window ] core context: %s, initial viewport %dx%d\n", gl.version().c_str(), gl.viewport()[2],
                gl.viewport()[3]);
    gl.glViewport(0, 0, 64, 48);
    EXPECT_TRUE(gl.double_buffered());

    clear(gl);
    EXPECT_TRUE(default_framebuffer_is(gl, 64, 48));
    draw_core_triangle(gl);
    Image expected;
    Image shown = present_and_grab(gl, 64, 48, expected);
    expect_triangle_scene(expected);
    ImageDiff d = compare(shown, expected);  // also checks the window is 64 x 48
    EXPECT_EQ(d.differing_pixels, 0) << "window " << shown.width << "x" << shown.height
                                     << ", max channel diff " << d.max_channel_diff;
    if (d.differing_pixels) write_png(out_dir() + "backend_window_shown.png", shown, error);

    // A new size resizes the window and its default framebuffer; the viewport is the program's.
    ASSERT_TRUE(backend_->make_current(1, 96, 80, error)) << error;
    EXPECT_EQ(gl.viewport(), (std::array<int, 4>{0, 0, 64, 48})) << "a resize does not move the viewport";
    gl.glViewport(0, 0, 96, 80);
    clear(gl);
    EXPECT_TRUE(default_framebuffer_is(gl, 96, 80));
    draw_core_triangle(gl);
    shown = present_and_grab(gl, 96, 80, expected);
    EXPECT_TRUE(near(px(expected, 48, 45), {255, 128, 0, 255}));
    d = compare(shown, expected);
    EXPECT_EQ(d.differing_pixels, 0) << "after resize: window " << shown.width << "x" << shown.height
                                     << ", max channel diff " << d.max_channel_diff;

    // The shared context has its own (hidden) window; the program's texture names are shared.
    ASSERT_TRUE(backend_->make_current(2, 1, 1, error)) << error;
    EXPECT_EQ(gl.viewport(), (std::array<int, 4>{0, 0, 1, 1}));
    backend_->destroy_context(2);
    backend_->destroy_context(1);
}

TEST_F(Window, CompatibilityContext) {
    std::string error;
    ASSERT_TRUE(backend_->create_context(5, 0, ContextRequest{}, error)) << error;
    ASSERT_TRUE(backend_->make_current(5, 64, 48, error)) << error;
    Gl gl;
    ASSERT_EQ(gl.load(*backend_), "");
    std::printf("[ window ] compatibility context: %s\n", gl.version().c_str());
    gl.glViewport(0, 0, 64, 48);  // as the slave does (see DefaultFramebufferIsTheWindow)
    clear(gl);
    EXPECT_TRUE(default_framebuffer_is(gl, 64, 48));
    draw_compat_triangle(gl);
    Image expected;
    const Image shown = present_and_grab(gl, 64, 48, expected);
    expect_triangle_scene(expected);
    const ImageDiff d = compare(shown, expected);
    EXPECT_EQ(d.differing_pixels, 0) << "window " << shown.width << "x" << shown.height;
    EXPECT_FALSE(backend_->make_current(6, 64, 48, error));
    EXPECT_NE(error.find("window: "), std::string::npos) << error;
}

// The comparison scene in a real window (GLX on the X server's TrueColor visual: what the
// captured program drew into) against the headless backends' default framebuffers.
TEST_F(Window, SameSceneAsHeadlessBackends) {
    const int w = kSceneW, h = kSceneH;
    // The headless renders first: glvnd lets no EGL context become current on a thread with a
    // current GLX context.
    std::string egl_version, osmesa_version;
    const Image egl = render_comparison("egl", w, h, egl_version);
    const Image osmesa = render_comparison("osmesa", w, h, osmesa_version);

    std::string error;
    ASSERT_TRUE(backend_->create_context(1, 0, ContextRequest{}, error)) << error;
    ASSERT_TRUE(backend_->make_current(1, w, h, error)) << error;
    Gl gl;
    ASSERT_EQ(gl.load(*backend_), "");
    const std::string version = gl.version();
    gl.glViewport(0, 0, w, h);
    clear(gl);
    EXPECT_TRUE(default_framebuffer_is(gl, w, h));
    const GLuint tex = draw_comparison_scene(gl, w, h);
    Image drawn;
    const Image shown = present_and_grab(gl, w, h, drawn);
    gl.glDeleteTextures(1, &tex);
    EXPECT_EQ(compare(shown, drawn).differing_pixels, 0) << "the window shows its back buffer";

    const ImageDiff de = compare(shown, egl), dm = compare(shown, osmesa);
    std::printf("[ window ] window (%s) vs egl (%s): %lld of %d pixels differ, max channel diff %d\n",
                version.c_str(), egl_version.c_str(), static_cast<long long>(de.differing_pixels), w * h,
                de.max_channel_diff);
    std::printf("[ window ] window vs osmesa (%s): %lld of %d pixels differ, max channel diff %d\n",
                osmesa_version.c_str(), static_cast<long long>(dm.differing_pixels), w * h, dm.max_channel_diff);
    if (de.differing_pixels) write_png(out_dir() + "backend_window_scene.png", shown, error);
    EXPECT_EQ(de.differing_pixels, 0);
    EXPECT_EQ(dm.differing_pixels, 0);
}

// ---- images ---------------------------------------------------------------------------------

Image gradient(int w, int h, uint8_t seed) {
    Image img;
    img.width = w;
    img.height = h;
    img.rgba.resize(size_t(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* p = &img.rgba[(size_t(y) * w + x) * 4];
            p[0] = uint8_t(x * 7 + seed);
            p[1] = uint8_t(y * 13 + seed);
            p[2] = uint8_t((x ^ y) + seed);
            p[3] = uint8_t(255 - x);
        }
    return img;
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Png, RoundTrip) {
    const Image img = gradient(37, 21, 5);
    const std::string path = out_dir() + "glcast_png_roundtrip.png";
    std::string error;
    ASSERT_TRUE(write_png(path, img, error)) << error;
    Image back;
    ASSERT_TRUE(read_png(path, back, error)) << error;
    EXPECT_EQ(back.width, 37);
    EXPECT_EQ(back.height, 21);
    EXPECT_EQ(back.rgba, img.rgba);
    std::remove(path.c_str());
}

TEST(Png, CorruptAndTruncatedFilesFailCleanly) {
    const std::string good = out_dir() + "glcast_png_good.png", bad = out_dir() + "glcast_png_bad.png";
    std::string error;
    ASSERT_TRUE(write_png(good, gradient(50, 40, 1), error)) << error;
    const std::string bytes = read_bytes(good);
    ASSERT_GT(bytes.size(), 100u);
    Image img;

    write_bytes(bad, bytes.substr(0, bytes.size() / 2));  // truncated in the image data
    EXPECT_FALSE(read_png(bad, img, error));
    EXPECT_NE(error.find(bad), std::string::npos) << error;
    std::printf("[ png ] truncated: %s\n", error.c_str());

    write_bytes(bad, bytes.substr(0, 20));  // truncated in the header
    EXPECT_FALSE(read_png(bad, img, error));

    std::string flipped = bytes;  // garbage in the middle: CRC or zlib errors
    for (size_t i = 60; i < flipped.size() - 20; i += 7) flipped[i] = char(flipped[i] ^ 0x5a);
    write_bytes(bad, flipped);
    EXPECT_FALSE(read_png(bad, img, error));
    std::printf("[ png ] corrupt: %s\n", error.c_str());

    write_bytes(bad, "this is not a png at all");
    EXPECT_FALSE(read_png(bad, img, error));
    EXPECT_NE(error.find("not a PNG"), std::string::npos) << error;

    EXPECT_FALSE(read_png(out_dir() + "glcast_no_such_file.png", img, error));
    EXPECT_FALSE(write_png("/nonexistent-dir/x.png", gradient(2, 2, 0), error));
    EXPECT_FALSE(write_png(bad, Image{}, error));
    std::remove(good.c_str());
    std::remove(bad.c_str());
}

// A PNG written by libpng directly in another format, to check conversion and refusal.
bool write_raw_png(const std::string& path, int w, int h, int color_type, int depth, const std::vector<uint8_t>& data) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return false;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        std::fclose(f);
        return false;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, w, h, depth, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (color_type == PNG_COLOR_TYPE_PALETTE) {
        png_color palette[2] = {{0, 0, 0}, {255, 255, 255}};
        png_set_PLTE(png, info, palette, 2);
    }
    png_write_info(png, info);
    const size_t stride = data.size() / h;
    for (int y = 0; y < h; ++y) png_write_row(png, const_cast<png_bytep>(&data[y * stride]));
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    return true;
}

TEST(Png, GrayAndRgbConvertOthersRefused) {
    const std::string path = out_dir() + "glcast_png_formats.png";
    std::string error;
    Image img;
    ASSERT_TRUE(write_raw_png(path, 2, 1, PNG_COLOR_TYPE_GRAY, 8, {10, 200}));
    ASSERT_TRUE(read_png(path, img, error)) << error;
    EXPECT_EQ(img.rgba, (std::vector<uint8_t>{10, 10, 10, 255, 200, 200, 200, 255}));

    ASSERT_TRUE(write_raw_png(path, 2, 1, PNG_COLOR_TYPE_RGB, 8, {1, 2, 3, 4, 5, 6}));
    ASSERT_TRUE(read_png(path, img, error)) << error;
    EXPECT_EQ(img.rgba, (std::vector<uint8_t>{1, 2, 3, 255, 4, 5, 6, 255}));

    ASSERT_TRUE(write_raw_png(path, 2, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, {7, 8, 9, 10}));
    ASSERT_TRUE(read_png(path, img, error)) << error;
    EXPECT_EQ(img.rgba, (std::vector<uint8_t>{7, 7, 7, 8, 9, 9, 9, 10}));

    ASSERT_TRUE(write_raw_png(path, 2, 1, PNG_COLOR_TYPE_RGB, 16, std::vector<uint8_t>(12, 1)));
    EXPECT_FALSE(read_png(path, img, error));
    EXPECT_NE(error.find("8-bit"), std::string::npos) << error;

    ASSERT_TRUE(write_raw_png(path, 8, 1, PNG_COLOR_TYPE_PALETTE, 1, {0xa5}));
    EXPECT_FALSE(read_png(path, img, error));
    EXPECT_NE(error.find("palette"), std::string::npos) << error;
    std::remove(path.c_str());
}

TEST(ImageUtil, Compare) {
    Image a = gradient(8, 6, 0), b = a;
    ImageDiff d = compare(a, b);
    EXPECT_EQ(d.differing_pixels, 0);
    EXPECT_EQ(d.max_channel_diff, 0);
    EXPECT_FALSE(d.size_mismatch);

    b.rgba[(2 * 8 + 3) * 4 + 1] += 9;
    b.rgba[(5 * 8 + 7) * 4 + 3] -= 2;
    b.rgba[(5 * 8 + 7) * 4 + 0] -= 1;
    d = compare(a, b);
    EXPECT_EQ(d.differing_pixels, 2);
    EXPECT_EQ(d.max_channel_diff, 9);

    d = compare(a, gradient(6, 8, 0));
    EXPECT_TRUE(d.size_mismatch);
    EXPECT_EQ(d.differing_pixels, 48);
    EXPECT_EQ(d.max_channel_diff, 255);
}

TEST(ImageUtil, FlipRows) {
    const Image a = gradient(5, 3, 0);
    const Image f = flip_rows(a);
    ASSERT_EQ(f.rgba.size(), a.rgba.size());
    for (int y = 0; y < 3; ++y)
        EXPECT_EQ(std::memcmp(&f.rgba[y * 20], &a.rgba[(2 - y) * 20], 20), 0);
    EXPECT_EQ(flip_rows(f).rgba, a.rgba);
}

TEST(ImageUtil, Mosaic) {
    const Image a = gradient(4, 3, 1), b = gradient(2, 2, 50), c = gradient(3, 5, 100);
    // Row 0: a b ; row 1: (none) c. Columns: max(4, -)=4, max(2, 3)=3. Rows: 3, 5.
    const Image m = mosaic({{&a, &b}, {nullptr, &c}});
    ASSERT_EQ(m.width, 7);
    ASSERT_EQ(m.height, 8);
    EXPECT_EQ(px(m, 0, 0), px(a, 0, 0));
    EXPECT_EQ(px(m, 3, 2), px(a, 3, 2));
    EXPECT_EQ(px(m, 4, 0), px(b, 0, 0));
    EXPECT_EQ(px(m, 5, 1), px(b, 1, 1));
    EXPECT_EQ(px(m, 6, 0), (std::array<int, 4>{0, 0, 0, 255}));  // b is narrower than its column
    EXPECT_EQ(px(m, 4, 2), (std::array<int, 4>{0, 0, 0, 255}));  // and shorter than its row
    EXPECT_EQ(px(m, 0, 3), (std::array<int, 4>{0, 0, 0, 255}));  // the empty cell
    EXPECT_EQ(px(m, 4, 3), px(c, 0, 0));
    EXPECT_EQ(px(m, 6, 7), px(c, 2, 4));

    // The usual wall: equal tiles, 2 x 2.
    const Image t = gradient(16, 9, 3);
    const Image wall = mosaic({{&t, &t}, {&t, &t}});
    EXPECT_EQ(wall.width, 32);
    EXPECT_EQ(wall.height, 18);
    EXPECT_EQ(px(wall, 16 + 5, 9 + 4), px(t, 5, 4));
    EXPECT_EQ(mosaic({}).width, 0);
}

}  // namespace
