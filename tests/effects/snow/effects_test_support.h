// A real Mesa context for in-process tests of the injected passes, and the fixed-function
// calls a synthetic scene draws with (the slave links no GL library: everything is resolved
// from the backend).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "slave/backend.h"
#include "slave/effects/gl_api.h"

namespace glcast::slave::effects::testing {

struct TestContext {
    std::unique_ptr<Backend> backend;
    GlApi gl;
    int width = 0, height = 0;
    // Fixed-function drawing for synthetic scenes.
    void (*Begin)(GLenum) = nullptr;
    void (*End)() = nullptr;
    void (*Vertex3d)(double, double, double) = nullptr;
    void (*Color3d)(double, double, double) = nullptr;
    void (*LoadMatrixd)(const double*) = nullptr;
    void (*MatrixMode)(GLenum) = nullptr;

    // An EGL compatibility context with a width x height window framebuffer; empty `error` on success.
    static std::unique_ptr<TestContext> create(int width, int height, std::string& error);
    // The window framebuffer as RGB rows, bottom row first.
    std::vector<uint8_t> read_rgb();
    // A quad at eye depth z (negative) over the window's x range [x0, x1] (NDC), drawn with the
    // projection p and depth testing into the window framebuffer.
    void draw_eye_quad(const glm::dmat4& p, double x0, double x1, double z, double grey);
};

}  // namespace glcast::slave::effects::testing
