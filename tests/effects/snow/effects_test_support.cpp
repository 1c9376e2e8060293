#include "tests/effects/snow/effects_test_support.h"

namespace glcast::slave::effects::testing {

std::unique_ptr<TestContext> TestContext::create(int width, int height, std::string& error) {
    auto t = std::make_unique<TestContext>();
    t->backend = make_backend("egl", error);
    if (!t->backend) return nullptr;
    if (!t->backend->create_context(1, 0, ContextRequest{}, error) || !t->backend->make_current(1, width, height, error))
        return nullptr;
    Backend* b = t->backend.get();
    if (!t->gl.load([b](const char* name) { return b->proc_address(name); }, error)) return nullptr;
    t->width = width, t->height = height;
    auto load = [b](auto& fn, const char* name) { fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(b->proc_address(name)); };
    load(t->Begin, "glBegin");
    load(t->End, "glEnd");
    load(t->Vertex3d, "glVertex3d");
    load(t->Color3d, "glColor3d");
    load(t->LoadMatrixd, "glLoadMatrixd");
    load(t->MatrixMode, "glMatrixMode");
    return t;
}

std::vector<uint8_t> TestContext::read_rgb() {
    std::vector<uint8_t> rgb(size_t(width) * height * 3);
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    return rgb;
}

void TestContext::draw_eye_quad(const glm::dmat4& p, double x0, double x1, double z, double grey) {
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_LESS);
    gl.glDepthMask(GL_TRUE);
    MatrixMode(GL_PROJECTION);
    LoadMatrixd(&p[0][0]);
    MatrixMode(GL_MODELVIEW);
    const glm::dmat4 identity(1.0);
    LoadMatrixd(&identity[0][0]);
    // Eye-space corners that project to NDC x0..x1 and the whole height at depth z.
    const double sx = -z / p[0][0], sy = -z / p[1][1];
    Color3d(grey, grey, grey);
    Begin(GL_QUADS);
    Vertex3d(x0 * sx, -sy, z);
    Vertex3d(x1 * sx, -sy, z);
    Vertex3d(x1 * sx, sy, z);
    Vertex3d(x0 * sx, sy, z);
    End();
}

}  // namespace glcast::slave::effects::testing
