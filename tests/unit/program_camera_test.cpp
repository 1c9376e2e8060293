// Splitting a shader program's matrix into a perspective projection and a view
// (slave/program_camera.h): what the slave finds without a display config's program_projection.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "slave/program_camera.h"

using glcast::slave::is_rigid;
using glcast::slave::split_perspective;

namespace {

void expect_near(const glm::dmat4& a, const glm::dmat4& b, double tolerance) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[c][r], b[c][r], tolerance) << "column " << c << ", row " << r;
}

glm::dmat4 as_float(const glm::dmat4& m) { return glm::dmat4(glm::mat4(m)); }  // what a uniform holds

}  // namespace

TEST(ProgramCamera, AProjectionAloneSplitsIntoItselfAndTheIdentity) {
    const glm::dmat4 p = glm::perspective(glm::radians(50.0), 4.0 / 3.0, 0.5, 200.0);
    glm::dmat4 projection, view;
    ASSERT_TRUE(split_perspective(as_float(p), projection, view));
    expect_near(projection, p, 1e-5);
    expect_near(view, glm::dmat4(1.0), 1e-6);
}

TEST(ProgramCamera, AnOffCentreProjectionTimesAViewSplitsIntoBoth) {
    const glm::dmat4 p = glm::frustum(-0.3, 0.5, -0.2, 0.25, 0.5, 100.0);
    const glm::dmat4 v = glm::scale(glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(1, -2, -7)), 0.7,
                                                glm::normalize(glm::dvec3(0.3, 1, 0.2))),
                                    glm::dvec3(2.5));
    glm::dmat4 projection, view;
    ASSERT_TRUE(split_perspective(as_float(p * v), projection, view));
    expect_near(projection, p, 1e-4);
    expect_near(view, v, 1e-4);
}

TEST(ProgramCamera, OrthographicAndModelMatricesAreNoCamera) {
    glm::dmat4 projection, view;
    EXPECT_FALSE(split_perspective(glm::ortho(0.0, 640.0, 0.0, 480.0, -1.0, 1.0), projection, view));
    EXPECT_FALSE(split_perspective(glm::translate(glm::dmat4(1.0), glm::dvec3(1, 2, 3)), projection, view));
    EXPECT_FALSE(split_perspective(glm::dmat4(1.0), projection, view));
}

TEST(ProgramCamera, RigidMatricesAreViews) {
    EXPECT_TRUE(is_rigid(glm::lookAt(glm::dvec3(3, 4, 5), glm::dvec3(0), glm::dvec3(0, 1, 0))));
    EXPECT_TRUE(is_rigid(glm::scale(glm::dmat4(1.0), glm::dvec3(2.0))));
    EXPECT_FALSE(is_rigid(glm::scale(glm::dmat4(1.0), glm::dvec3(1, 2, 1))));
    EXPECT_FALSE(is_rigid(glm::perspective(1.0, 1.0, 0.1, 10.0)));
}

// VTK 9's MCDCMatrix as a VTK program uploaded it (tests/data would hold the capture; the numbers
// are its frame 59's): VTK keeps its matrices row-major and multiplies row vectors, so the upload
// is GL's column-major P * V as it stands.
TEST(ProgramCamera, VtksModelToClipMatrixSplits) {
    const float uploaded[16] = {1.0542f, -1.50208f, -0.836032f, -0.834362f, 0, 3.3614f, -0.435344f, -0.434474f,
                                -2.59293f, -0.610695f, -0.339903f, -0.339224f, 0, -1.6807f, 12.8448f, 12.8762f};
    glm::dmat4 m;
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = uploaded[i];
    glm::dmat4 p, v;
    EXPECT_TRUE(glcast::slave::split_perspective(m, p, v));
}
