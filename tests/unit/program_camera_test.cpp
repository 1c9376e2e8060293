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

// SuperTuxKart's u_projection_view_matrix (Irrlicht's left-handed camera: w = +z, its view a
// rotation of left-handed coordinates): it splits as that camera, not as a mirrored view.
TEST(ProgramCamera, ALeftHandedProductSplitsAsALeftHandedCamera) {
    glm::dmat4 left_p = glm::perspective(glm::radians(60.0), 4.0 / 3.0, 1.0, 1000.0);
    left_p[2] = -left_p[2];  // (S mirrors z: P S is the same frustum written for z forward)
    const glm::dmat4 s = glm::scale(glm::dmat4(1.0), glm::dvec3(1, 1, -1));
    const glm::dmat4 right_v = glm::lookAt(glm::dvec3(3, 2, 5), glm::dvec3(0, 1, 0), glm::dvec3(0, 1, 0));
    const glm::dmat4 left_v = s * right_v * s;
    glm::dmat4 projection, view;
    ASSERT_TRUE(split_perspective(as_float(left_p * left_v), projection, view));
    EXPECT_NEAR(projection[2][3], 1.0, 1e-9);  // w = +z
    expect_near(projection, left_p, 1e-4);
    expect_near(view, left_v, 1e-4);
    EXPECT_GT(glm::determinant(glm::dmat3(view)), 0);
}

// What a shader's text reads: a block member it only declares is named once (std140 keeps it
// active all the same).
TEST(ProgramCamera, TheNamesAShaderReadsAreThoseItNamesTwice) {
    const auto read = glcast::slave::names_read(
        "#version 330\nlayout (std140) uniform Matrices { mat4 u_view_matrix; mat4 u_projection_matrix; };\n"
        "// u_view_matrix in a comment\n/* u_projection_matrix\n u_view_matrix */\n"
        "in vec2 Position;\nvoid main() { gl_Position = u_projection_matrix * vec4(Position, 0.0, 1.0); }\n");
    EXPECT_TRUE(read.count("u_projection_matrix"));
    EXPECT_FALSE(read.count("u_view_matrix"));
    EXPECT_TRUE(read.count("Position"));
    EXPECT_FALSE(read.count("Matrices"));
    // SuperTuxKart's header declares its sun twice, once in each branch of an #ifdef the text
    // does not define: one declaration is left, and nothing reads it.
    const auto header = glcast::slave::names_read(
        "#version 450\n#ifdef UBO_DISABLED\nuniform vec3 sun_direction;\n#else\n"
        "layout (std140) uniform LightingData { vec3 sun_direction; float sun_angle; };\n#endif\n"
        "#define USES_ANGLE 1\n#if defined(USES_ANGLE)\nfloat a() { return sun_angle; }\n#endif\n"
        "#if 0\nvec3 s() { return sun_direction; }\n#endif\n");
    EXPECT_FALSE(header.count("sun_direction"));
    EXPECT_TRUE(header.count("sun_angle"));
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

// Engines' names for their sun (SuperTuxKart, minetest, VTK and common tutorials), and names of
// the sun's other properties, which are no light vector.
TEST(ProgramCamera, LightUniformsAreKnownByTheirNames) {
    using glcast::slave::light_uniform;
    for (const char* name : {"sun_direction", "sundirection", "v_LightDirection", "u_sunDir", "lightDir", "LightPosition",
                             "sunPos", "u_light_dir_world", "shadowLightDir"}) {
        EXPECT_TRUE(light_uniform(name).light) << name;
        EXPECT_FALSE(light_uniform(name).eye_space) << name;
    }
    EXPECT_TRUE(light_uniform("LightPosition").position);
    EXPECT_FALSE(light_uniform("sun_direction").position);
    EXPECT_TRUE(light_uniform("u_lightDirView").eye_space);
    EXPECT_TRUE(light_uniform("eyeSunDir").eye_space);
    EXPECT_TRUE(light_uniform("lightDirectionVC0").eye_space);  // VTK 9
    for (const char* name : {"sun_col", "sun_color", "sunColour", "lightDirectionalIntensity", "sun_angle", "sun_scatter",
                             "LightMVP", "light", "u_time", "position", "direction"})
        EXPECT_FALSE(light_uniform(name).light) << name;
}

// A direction that could point either way is taken towards the sky the view shows: a Y-up world
// seen level and a Z-up world seen from above (its up is the eye's +y and +z mixed).
TEST(ProgramCamera, ASunOfUnknownSignLightsFromTheSky) {
    using glcast::slave::effects::SceneLight;
    using glcast::slave::effects::light_from_the_sky;
    SceneLight down{true, glm::dvec4(0.3, -1, 0.2, 0)};
    down.sign_from_up = true;
    EXPECT_EQ(light_from_the_sky(down, glm::dmat4(1.0)).eye_position, glm::dvec4(-0.3, 1, -0.2, 0));
    SceneLight up = down;
    up.eye_position = glm::dvec4(0.3, 1, 0.2, 0);
    EXPECT_EQ(light_from_the_sky(up, glm::dmat4(1.0)).eye_position, up.eye_position);
    const glm::dmat4 z_up = glm::lookAt(glm::dvec3(0, -8, 5), glm::dvec3(0), glm::dvec3(0, 0, 1));
    SceneLight z_sun{true, z_up * glm::dvec4(0.1, 0.2, -1, 0)};  // the way its light travels, in the world
    z_sun.sign_from_up = true;
    const glm::dvec4 seen = light_from_the_sky(z_sun, z_up).eye_position;
    EXPECT_GT(glm::dot(glm::dvec3(seen), glm::dmat3(z_up) * glm::dvec3(0, 0, 1)), 0.9);
    SceneLight known{true, glm::dvec4(0.3, -1, 0.2, 0)};  // a fixed-function light says its own sign
    EXPECT_EQ(light_from_the_sky(known, glm::dmat4(1.0)).eye_position, known.eye_position);
}

TEST(ProgramCamera, AnOrthographicMatrixOverPixelsDrawsFlat) {
    using glcast::slave::is_orthographic;
    EXPECT_TRUE(is_orthographic(glm::ortho(0.0, 640.0, 0.0, 480.0, -1.0, 1.0)));  // VTK's 2D actors, a HUD
    EXPECT_FALSE(is_orthographic(glm::dmat4(1.0)));                                // a full-screen pass
    EXPECT_FALSE(is_orthographic(glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, 0, 0))));
    EXPECT_FALSE(is_orthographic(glm::perspective(1.0, 1.3, 0.1, 100.0)));
    EXPECT_FALSE(is_orthographic(glm::rotate(glm::ortho(0.0, 640.0, 0.0, 480.0, -1.0, 1.0), 0.3, glm::dvec3(0, 0, 1))));
}

// A stream's shader of one very long directive line (std::regex would recurse once per character).
TEST(ProgramCamera, AShaderOfOneVeryLongLineIsReadWithoutTheStackGrowing) {
    std::string long_line = "#if " + std::string(4 << 20, '1') + "\nuniform mat4 m;\nvoid f() { m; }\n#endif\n";
    long_line += "#define X " + std::string(4 << 20, ' ') + "y\n";
    const auto read = glcast::slave::names_read(long_line);
    EXPECT_TRUE(read.count("m"));
}
