// The program's GLSL as the slave's driver gets it (slave/shader_patch.h).
#include "slave/shader_patch.h"

#include <gtest/gtest.h>

using glcast::slave::patch_shader;
using glcast::slave::ShaderPatch;
using glcast::slave::window_fragcoord;

TEST(ShaderPatch, AFragmentShaderReadsTheMasterWindowsCoordinates) {
    std::string text =
        "#version 330\n"
        "uniform sampler2D tex;\nuniform int width;\nout vec4 FragColor;\n"
        "void main() { FragColor = texture(tex, gl_FragCoord.xy / vec2(width, 480)); }\n";
    ASSERT_TRUE(patch_shader(text, ShaderPatch::WindowFragCoord));
    EXPECT_EQ(text.find("#version 330\nuniform vec4 glcast_fragcoord;\n#define glcast_FragCoord "), 0u) << text;
    EXPECT_NE(text.find("texture(tex, glcast_FragCoord.xy / vec2(width, 480))"), std::string::npos) << text;
    // (only the macro reads the driver's own)
    const size_t macro = text.find("#define glcast_FragCoord"), line_end = text.find('\n', macro);
    EXPECT_GT(text.find("gl_FragCoord"), macro) << text;
    EXPECT_EQ(text.find("gl_FragCoord", line_end), std::string::npos) << text;
}

TEST(ShaderPatch, TheDeclarationComesAfterEveryExtensionOutsideTheirConditional) {
    // SuperTuxKart's header: extensions behind #ifdef, the driver refuses one after a declaration.
    std::string text =
        "#version 450\n#extension GL_ARB_explicit_attrib_location : enable\n#ifdef GL_ES\n"
        "#extension GL_EXT_frag_depth : enable\n#endif\n#define Explicit 1\nuniform sampler2D tex;\n"
        "void main() { gl_FragColor = texture2D(tex, gl_FragCoord.xy); }\n";
    ASSERT_TRUE(patch_shader(text, ShaderPatch::WindowFragCoord));
    EXPECT_EQ(text.find("#endif\nuniform vec4 glcast_fragcoord;\n"), text.find("#endif")) << text;
}

TEST(ShaderPatch, GlslEsGetsAPrecision) {
    std::string text = "#version 300 es\nprecision mediump float;\nout vec4 c;\nvoid main() { c = gl_FragCoord; }\n";
    ASSERT_TRUE(patch_shader(text, ShaderPatch::WindowFragCoord));
    EXPECT_NE(text.find("uniform highp vec4 glcast_fragcoord;"), std::string::npos) << text;
}

TEST(ShaderPatch, ShadersWithNothingToPatchAreLeftAlone) {
    const std::string plain = "#version 120\nvoid main() { gl_FragColor = vec4(1.0); }\n";
    const std::string own_layout =
        "#version 150\nlayout(origin_upper_left) in vec4 gl_FragCoord;\nout vec4 c;\nvoid main() { c = gl_FragCoord; }\n";
    for (const std::string& original : {plain, own_layout, std::string("#version 120\nfloat f;\n")}) {
        std::string text = original;
        EXPECT_FALSE(patch_shader(text, ShaderPatch::WindowFragCoord)) << original;
        EXPECT_EQ(text, original);
    }
    std::string no_main = "#version 120\nvec4 f() { return gl_Vertex; }\n";
    EXPECT_FALSE(patch_shader(no_main, ShaderPatch::Clip));
}

TEST(ShaderPatch, AVertexShaderGetsTheClipStep) {
    std::string text = "#version 120\nvoid main ( ) { gl_Position = ftransform(); }\n";
    ASSERT_TRUE(patch_shader(text, ShaderPatch::Clip));
    EXPECT_NE(text.find("void glcast_program_main("), std::string::npos) << text;
    EXPECT_NE(text.find("gl_Position = glcast_clip * gl_Position"), std::string::npos) << text;
}

TEST(ShaderPatch, TheUniformTakesATilesFragmentToTheMastersWindow) {
    // The top-right tile of a 2x2 wall over a 320x240 window, each tile 640x480: the program's
    // viewport (0, 0, 320, 240) is drawn at (-640, 0, 1280, 960).
    const double program[4] = {0, 0, 320, 240}, drawn[4] = {-640, 0, 1280, 960};
    float u[4];
    window_fragcoord(program, drawn, u);
    auto master = [&](double x, double y, int axis) { return (axis ? y : x) * (1 + u[axis]) + u[axis + 2]; };
    // The tile's pixel (0.5, 0.5) is the canvas' (640.5, 480.5): the window's (160.125, 120.125).
    EXPECT_NEAR(master(0.5, 0.5, 0), 160.125, 1e-4);
    EXPECT_NEAR(master(0.5, 0.5, 1), 0.125, 1e-4);
    EXPECT_NEAR(master(639.5, 479.5, 0), 319.875, 1e-4);
    // The program's own viewport: the identity, all zero (the uniform's default).
    window_fragcoord(program, program, u);
    for (float v : u) EXPECT_EQ(v, 0.0f);
}

// A stream's shader with a very long run of blanks where the patterns allow any (std::regex
// recurses once per character matched): left as it is, not patched.
TEST(ShaderPatch, AVeryLongRunOfBlanksIsLeftAlone) {
    for (ShaderPatch patch : {ShaderPatch::WindowFragCoord, ShaderPatch::Clip}) {
        const std::string original = "#version 150\nin" + std::string(4 << 20, ' ') + "vec4 gl_FragCoord;\nvoid" +
                                     std::string(4 << 20, ' ') + "main() { gl_Position = vec4(gl_FragCoord); }\n";
        std::string text = original;
        EXPECT_FALSE(patch_shader(text, patch));
        EXPECT_EQ(text, original);
    }
}
