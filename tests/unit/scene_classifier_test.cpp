// The scene classifier's rules, each on a draw state given as values: no driver, no stream.
// Which draw is the main view, where the overlays begin, what an offscreen scene target is.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "slave/scene/frame_record.h"
#include "slave/scene/scene_classifier.h"

using namespace glcast;
using namespace glcast::slave;

namespace {

// A draw state as a test states it; counts what the classifier asked.
struct Given final : DrawState {
    GLuint framebuffer = 0, read = 0, current_program = 0;
    bool depth_on = true, depth_mask = true;
    double far = 0;
    glm::dmat4 proj = glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    glm::dmat4 mv = glm::translate(glm::dmat4(1.0), glm::dvec3(0, -1, -5));
    GLenum mode = GL_MODELVIEW;
    effects::SceneLight lit;
    effects::SceneLight sun;  // a shader program's
    bool flat = false;        // ... an orthographic matrix among its own
    CullState culling{true, GL_BACK, GL_CCW};
    AlphaTest alpha;
    bool always = false;
    bool blending = false;
    int32_t vp[4] = {0, 0, 640, 480};
    bool has_camera = false;
    ProgramCamera cam;
    GLenum color = GL_TEXTURE, depth = GL_RENDERBUFFER;
    GLuint texture = 0;  // the bound target's colour texture
    GLuint sampled = 0;  // the texture the draw samples
    int asked = 0;

    GLuint draw_framebuffer() override { return asked++, framebuffer; }
    GLuint read_framebuffer() override { return asked++, read; }
    GLuint program() override { return asked++, current_program; }
    bool depth_test() override { return asked++, depth_on; }
    bool writes_depth() override { return asked++, depth_on && depth_mask; }
    bool blends() override { return asked++, blending; }
    double view_model_far() override { return asked++, far; }
    glm::dmat4 projection() override { return asked++, proj; }
    glm::dmat4 modelview() override { return asked++, mv; }
    GLenum matrix_mode() override { return asked++, mode; }
    effects::SceneLight light() override { return asked++, lit; }
    CullState cull() override { return asked++, culling; }
    AlphaTest alpha_test() override { return alpha; }
    bool depth_always() override { return always; }
    void viewport(int32_t out[4]) override { asked++, std::copy(vp, vp + 4, out); }
    bool camera(GLuint, ProgramCamera& out) override {
        asked++;
        if (has_camera) out = cam;
        return has_camera;
    }
    effects::SceneLight program_light(GLuint, const ProgramCamera&) override { return asked++, sun; }
    bool flat_program(GLuint) override { return asked++, flat; }
    GLenum color_attachment_type() override { return asked++, color; }
    GLenum depth_attachment_type() override { return asked++, depth; }
    GLuint color_texture() override { return asked++, texture; }
    bool samples_texture(GLuint t) override { return asked++, t != 0 && t == sampled; }
    bool shares_depth_with(GLuint f) override { return asked++, f != 0 && f != framebuffer && f == depth_of; }
    GLenum primitive() override { return drawn; }  // (the call's argument: nothing to ask)
    GLuint depth_of = 0;  // the framebuffer whose depth the bound one holds
    GLenum drawn = GL_TRIANGLES;
};

const ClassifierSettings kPasses{false, true};  // a pass redraws the scene

// A 400x300 window's scene drawn into multisampled renderbuffers (framebuffer 3) of its
// 320x260 viewport: shown in part of the window.
bool found_in_part_of_400x300(SceneFacts& facts, Given& s) {
    s.framebuffer = 3, s.texture = 0, s.color = GL_RENDERBUFFER;
    s.vp[2] = 320, s.vp[3] = 260;
    return classify_draw(facts, s, 3, ClassifierSettings{false, true, 400, 300}).found_view && facts.in_part;
}
const glm::dmat4 kOrtho = glm::ortho(0.0, 640.0, 0.0, 480.0, -1.0, 1.0);

}  // namespace

TEST(SceneClassifier, TheFirstPerspectiveDrawThatWritesDepthIsTheMainView) {
    SceneFacts facts;
    Given s;
    s.lit = effects::SceneLight{true, glm::dvec4(1, 2, 3, 0)};
    s.vp[0] = 10;
    const DrawVerdict v = classify_draw(facts, s, 0, kPasses);
    EXPECT_TRUE(v.main);
    EXPECT_TRUE(v.found_view);
    EXPECT_TRUE(facts.main_known);
    EXPECT_EQ(facts.projection, s.proj);
    EXPECT_EQ(facts.modelview, s.mv);
    EXPECT_EQ(facts.viewport[0], 10);
    EXPECT_TRUE(facts.light.known);
    EXPECT_EQ(facts.light.eye_position, glm::dvec4(1, 2, 3, 0));
    EXPECT_EQ(facts.scene_framebuffer, 0u);
}

TEST(SceneClassifier, LaterDrawsWithTheViewsProjectionBelongToIt) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);
    s.mv = glm::rotate(s.mv, 0.5, glm::dvec3(0, 1, 0));  // another object
    const DrawVerdict v = classify_draw(facts, s, 0, kPasses);
    EXPECT_TRUE(v.main);
    EXPECT_FALSE(v.found_view);
    EXPECT_NE(facts.modelview, s.mv);  // the view stays the first draw's
}

TEST(SceneClassifier, ADrawWithAnotherProjectionIsNotTheMainViews) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);
    s.proj = glm::frustum(-0.5, 0.5, -0.5, 0.5, 1.0, 10.0);
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
}

TEST(SceneClassifier, ABackdropWithoutDepthWritesIsNeitherTheViewNorInIt) {
    SceneFacts facts;
    Given s;
    s.depth_mask = false;
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_FALSE(facts.main_known);
    s.depth_mask = true;
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).found_view);
}

TEST(SceneClassifier, AnOrthographicDrawIsNoView) {
    SceneFacts facts;
    Given s;
    s.proj = kOrtho;
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_FALSE(facts.main_known);
}

TEST(SceneClassifier, AMirroredModelviewIsAReflectionNotTheView) {
    SceneFacts facts;
    Given s;
    const glm::dmat4 view = s.mv;
    s.mv = glm::scale(view, glm::dvec3(1, -1, 1));
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_FALSE(facts.main_known);
    s.mv = view;
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).found_view);
    EXPECT_EQ(facts.modelview, view);
}

TEST(SceneClassifier, TheModelviewPushedBeforeTheFirstDrawIsTheView) {
    SceneFacts facts;
    Given s;
    const glm::dmat4 view = s.mv;
    note_push(facts, s);  // glPushMatrix with the view on top, then a model transform
    s.mv = glm::translate(view, glm::dvec3(3, 0, 0));
    classify_draw(facts, s, 0, kPasses);
    EXPECT_EQ(facts.modelview, view);
}

TEST(SceneClassifier, APushOfAnotherStackOrOfAReflectionIsNotTheView) {
    SceneFacts facts;
    Given s;
    s.mode = GL_PROJECTION;
    note_push(facts, s);
    EXPECT_FALSE(facts.pushed);
    s.mode = GL_MODELVIEW;
    const glm::dmat4 view = s.mv;
    s.mv = glm::scale(view, glm::dvec3(1, -1, 1));
    note_push(facts, s);  // pushed inside the reflection
    s.mv = view;
    classify_draw(facts, s, 0, kPasses);
    EXPECT_EQ(facts.modelview, view);
}

TEST(SceneClassifier, AViewModelInTheFrontOfTheDepthRangeIsNotTheScene) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);
    s.far = 0.3;  // glDepthRange(0, 0.3): a weapon
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_DOUBLE_EQ(facts.view_model_far, 0.3);
}

TEST(SceneClassifier, MainDrawsKeepTheirFaceCulling) {
    SceneFacts facts;
    Given s;
    s.culling = CullState{true, GL_FRONT, GL_CW};
    const DrawVerdict v = classify_draw(facts, s, 0, kPasses);
    EXPECT_TRUE(v.cull.enabled);
    EXPECT_EQ(v.cull.cull_face, GLenum(GL_FRONT));
    EXPECT_EQ(v.cull.front_face, GLenum(GL_CW));
}

TEST(SceneClassifier, AnOrthographicHudAfterTheMainViewStartsTheOverlays) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::Scene);  // more of the scene
    s.proj = kOrtho;  // glOrtho: the HUD
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::StartsOverlays);
    EXPECT_TRUE(facts.overlay);
}

TEST(SceneClassifier, ADrawWithTheDepthTestOffUnderAnotherProjectionStartsTheOverlays) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);
    s.depth_on = false;
    s.proj = glm::perspective(1.2, 4.0 / 3.0, 0.1, 10.0);  // a HUD's 3D icon, its own projection
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Begin), WindowDrawMeaning::StartsOverlays);
}

TEST(SceneClassifier, ADrawWithTheMainProjectionAndTheDepthTestOffIsTheScenes) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);
    s.depth_on = false;  // a reflection drawn into the floor (neverball's mirror)
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Begin), WindowDrawMeaning::Scene);
    EXPECT_FALSE(facts.overlay);
    s.depth_on = true;  // the floor over it, then the level: still the main view's
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).main);
}

TEST(SceneClassifier, PixelsAtTheRasterPositionStartTheOverlays) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Pixels), WindowDrawMeaning::StartsOverlays);
}

TEST(SceneClassifier, ADepthOnlyClearAfterTheMainViewStartsAViewModel) {
    SceneFacts facts;
    EXPECT_FALSE(depth_clear_starts_overlays(facts, GL_DEPTH_BUFFER_BIT));  // no view yet: the frame's own clear
    Given s;
    classify_draw(facts, s, 0, kPasses);
    EXPECT_FALSE(depth_clear_starts_overlays(facts, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT));  // a new picture
    EXPECT_FALSE(depth_clear_starts_overlays(facts, GL_STENCIL_BUFFER_BIT));
    EXPECT_FALSE(facts.overlay);
    EXPECT_TRUE(depth_clear_starts_overlays(facts, GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT));
    EXPECT_TRUE(facts.overlay && facts.depth_cleared);
    // The hand, drawn with the main view's projection or not, is not the scene's.
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_FALSE(depth_clear_starts_overlays(facts, GL_DEPTH_BUFFER_BIT));  // once a frame
}

TEST(SceneClassifier, ADepthClearOfAnOffscreenSceneIsNotAViewModel) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 7, kPasses);  // found in framebuffer object 7
    EXPECT_FALSE(depth_clear_starts_overlays(facts, GL_DEPTH_BUFFER_BIT));
}

TEST(SceneClassifier, StateCallsNeverStartTheOverlays) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);
    s.depth_on = false;
    EXPECT_EQ(window_draw(facts, s, RedrawKind::State), WindowDrawMeaning::Scene);
    EXPECT_FALSE(facts.overlay);
}

TEST(SceneClassifier, AShaderDrawWhoseMatricesHoldACameraIsTheMainView) {
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);  // no camera among its matrices
    EXPECT_TRUE(facts.shader_draws);
    s.has_camera = true;
    s.cam.projection = s.proj;
    s.cam.modelview = s.mv;
    EXPECT_FALSE(facts.main_shader_draws);
    const DrawVerdict v = classify_draw(facts, s, 0, kPasses);
    EXPECT_TRUE(v.main);
    EXPECT_TRUE(v.found_view);
    EXPECT_EQ(facts.projection, s.proj);
    EXPECT_TRUE(facts.main_shader_draws);  // its redraw binds the programs
}

TEST(SceneClassifier, APaintersDrawAfterTheViewIsTheViewsToo) {
    // pillars --overlay: the pillars drawn after the floor with the depth test off.
    SceneFacts facts;
    Given s;
    s.depth_on = false;
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);  // a backdrop before the view: no part of it
    EXPECT_FALSE(facts.main_known);
    s.depth_on = true;
    ASSERT_TRUE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_FALSE(facts.painter_draws);
    s.depth_on = false;
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_TRUE(facts.painter_draws);
    s.depth_on = true, s.depth_mask = false;  // the test on, no writes (a translucent draw): not a caster
    SceneFacts glass;
    classify_draw(glass, s, 0, kPasses);
    s.depth_mask = true;
    classify_draw(glass, s, 0, kPasses);
    s.depth_mask = false;
    EXPECT_FALSE(classify_draw(glass, s, 0, kPasses).main);
    EXPECT_FALSE(glass.painter_draws);
}

TEST(SceneClassifier, ABlendedDrawAfterTheViewIsNoPartOfIt) {
    // minetest's cloud layer: drawn last, blended, writing depth: no caster.
    SceneFacts facts;
    Given s;
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).found_view);  // the world, opaque
    s.blending = true;
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
    s.blending = false;
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).main);
}

TEST(SceneClassifier, ATranslucentDrawWritingDepthKeepsTheScenesDepthBeforeIt) {
    // minetest's cloud layer writes depth: screen-space shadows must not march it.
    SceneFacts facts;
    Given s;
    ASSERT_TRUE(classify_draw(facts, s, 0, kPasses).found_view);
    s.blending = true;
    DrawVerdict v = classify_draw(facts, s, 0, kPasses);
    EXPECT_FALSE(v.main);
    EXPECT_TRUE(v.keeps_depth);
    EXPECT_FALSE(v.marks_start);  // its colour is the scene's
    EXPECT_TRUE(facts.translucent);
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).keeps_depth);  // the first only
    s.drawn = GL_LINES;  // marks after it keep the colour; the depth is kept already
    v = classify_draw(facts, s, 0, kPasses);
    EXPECT_TRUE(v.marks_start);
    EXPECT_FALSE(v.keeps_depth);
    s.drawn = GL_TRIANGLES;
    s.blending = false;  // an opaque surface: all of it was the scene
    v = classify_draw(facts, s, 0, kPasses);
    EXPECT_TRUE(v.main);
    EXPECT_TRUE(v.over_end);
    EXPECT_FALSE(facts.translucent || facts.marks);
    s.blending = true;
    s.depth_mask = false;  // translucent without depth writes: the depth is the scene's as it is
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).keeps_depth);
}

TEST(SceneClassifier, BlendingOnForTheWholeSceneSaysNothing) {
    // openscad leaves GL_BLEND on for every draw: its surfaces are opaque and cast their shadows.
    // Blending says a draw is translucent only after an opaque surface of the view.
    SceneFacts facts;
    Given s;
    s.blending = true;
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).found_view);
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).main);
    s.blending = false;  // an opaque surface ...
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).main);
    s.blending = true;  // ... then a blended one is translucent
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
}

TEST(SceneClassifier, AFixedFunctionSceneShownByAShaderProgramIsRedrawnAsFixedFunction) {
    // pillars --fbo --region --wire: the scene by fixed function into its target, then one GLSL
    // draw to the window mixes the scene's texture and the overlay engine's.
    SceneFacts facts;
    Given s;
    s.framebuffer = 3;
    ASSERT_TRUE(classify_draw(facts, s, 3, kPasses).main);
    s.framebuffer = 0;
    s.current_program = 4;
    s.depth_on = false;
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_TRUE(facts.shader_draws);
    EXPECT_FALSE(facts.main_shader_draws);
}

TEST(SceneClassifier, AShaderProgramPaintingInOrderWithTheViewsCameraIsScene) {
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    s.has_camera = true;
    s.cam.projection = s.proj;
    classify_draw(facts, s, 0, kPasses);
    s.depth_on = false;  // painter's order, the same camera
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::Scene);
    s.cam.projection = kOrtho;  // its HUD program
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::StartsOverlays);
}

TEST(SceneClassifier, CameraProbesStopAfterTheirBound) {
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    for (int i = 0; i < kMaxCameraProbes; ++i) classify_draw(facts, s, 0, kPasses);
    EXPECT_EQ(facts.camera_probes, kMaxCameraProbes);
    s.has_camera = true;
    s.cam.projection = s.proj;
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);  // a 2D program: no longer asked
    EXPECT_FALSE(facts.main_known);
}

TEST(SceneClassifier, AReflectionsShaderCameraIsNotTheView) {
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    s.has_camera = true;
    s.cam.projection = s.proj;
    s.cam.modelview = glm::scale(s.mv, glm::dvec3(1, -1, 1));
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
    EXPECT_FALSE(facts.main_known);
}

TEST(SceneClassifier, AConfiguredProjectionMakesEveryDepthWritingShaderDrawToTheWindowMain) {
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    const ClassifierSettings configured{true, true};
    EXPECT_TRUE(classify_draw(facts, s, 0, configured).main);
    EXPECT_FALSE(classify_draw(facts, s, 3, configured).main);  // into a framebuffer object
    s.depth_mask = false;
    EXPECT_FALSE(classify_draw(facts, s, 0, configured).main);
    EXPECT_EQ(s.asked > 0, true);
    EXPECT_FALSE(classify_draw(facts, s, 0, ClassifierSettings{true, false}).main);  // nothing redraws
}

TEST(SceneClassifier, WithoutARedrawingPassOnlyTheCameraIsLookedFor) {
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    s.has_camera = true;
    s.cam.projection = s.proj;
    const ClassifierSettings camera_only{false, false};
    EXPECT_TRUE(classify_draw(facts, s, 0, camera_only).found_view);
    const int asked = s.asked;
    EXPECT_FALSE(classify_draw(facts, s, 0, camera_only).main);
    EXPECT_LT(s.asked - asked, 4);  // no camera asked for again
}

TEST(SceneClassifier, AWindowSizedTargetWithDepthMayHoldTheScene) {
    SceneFacts facts;
    Given s;
    s.framebuffer = 3;
    GLuint bound = 0;
    EXPECT_TRUE(offscreen_scene(facts, s, 640, 480, bound));
    EXPECT_EQ(bound, 3u);
    s.depth = GL_NONE;
    EXPECT_FALSE(offscreen_scene(facts, s, 640, 480, bound));  // no depth: a post-process target
    s.depth = GL_TEXTURE;
    s.vp[2] = 256, s.vp[3] = 256;  // a shadow map: depth alone
    s.color = GL_NONE;
    EXPECT_FALSE(offscreen_scene(facts, s, 640, 480, bound));
    s.color = GL_TEXTURE;
    s.vp[0] = 8, s.vp[2] = 640, s.vp[3] = 480;
    EXPECT_FALSE(offscreen_scene(facts, s, 640, 480, bound));  // not drawn whole
    s.framebuffer = 0;
    s.vp[0] = 0;
    EXPECT_FALSE(offscreen_scene(facts, s, 640, 480, bound));  // the window is no offscreen target
}

TEST(SceneClassifier, ATargetOfTheWindowsShapeAtAnotherSizeHoldsTheScene) {
    // A render scale: half the window (and twice it), colour and depth, shown stretched.
    SceneFacts facts;
    Given s;
    s.framebuffer = 3;
    GLuint bound = 0;
    for (const int scale2 : {1, 4}) {
        s.vp[2] = 320 * scale2, s.vp[3] = 240 * scale2;
        EXPECT_TRUE(offscreen_scene(facts, s, 640, 480, bound)) << s.vp[2];
    }
    s.vp[2] = 320, s.vp[3] = 240;
    s.color = GL_NONE;  // depth alone: a shadow map of the window's shape
    EXPECT_FALSE(offscreen_scene(facts, s, 640, 480, bound));
    s.color = GL_TEXTURE;
    s.vp[2] = 128, s.vp[3] = 96;  // a thumbnail: under a quarter of the window's width
    const double thumbnail[4] = {0, 0, 128, 96};
    EXPECT_FALSE(window_shaped(thumbnail, 640, 480));  // (in part of the window, if the window shows it)
    const double shaped[4] = {0, 0, 322, 241.5};  // within 1% of the window's shape
    EXPECT_TRUE(window_shaped(shaped, 640, 480));
    // A stream's viewport is no render scale past four times the window (supersampling): the
    // slave would copy that target, at that size, every frame.
    const double supersampled[4] = {0, 0, 2560, 1920}, huge[4] = {0, 0, 16000, 12000};
    EXPECT_TRUE(window_shaped(supersampled, 640, 480));
    EXPECT_FALSE(window_shaped(huge, 640, 480));
    s.vp[2] = 320, s.vp[3] = 240;
    classify_draw(facts, s, 3, kPasses);
    EXPECT_TRUE(stretched_scene(facts, 640, 480));
    facts.viewport[2] = 640, facts.viewport[3] = 480;
    EXPECT_FALSE(stretched_scene(facts, 640, 480));  // the window's size: not stretched
}

TEST(SceneClassifier, ALaterTargetReplacesAScaledScene) {
    // A monitor's view of the window's shape drawn first, the scene's target after it: the view
    // found in the monitor's target is forgotten for the later one.
    SceneFacts facts;
    Given s;
    s.framebuffer = 3;
    s.vp[2] = 256, s.vp[3] = 192;
    GLuint bound = 0;
    ASSERT_TRUE(offscreen_scene(facts, s, 640, 480, bound));
    ASSERT_TRUE(classify_draw(facts, s, bound, kPasses).found_view);
    s.framebuffer = 5;
    s.vp[2] = 640, s.vp[3] = 480;
    EXPECT_TRUE(later_scene_target(facts, s, 640, 480));
    EXPECT_FALSE(facts.main_known);
    ASSERT_TRUE(offscreen_scene(facts, s, 640, 480, bound));
    EXPECT_TRUE(classify_draw(facts, s, bound, kPasses).found_view);
    EXPECT_EQ(facts.scene_framebuffer, 5u);
    // A scene found at the window's size is not replaced; nor one the window already shows.
    s.framebuffer = 7;
    EXPECT_FALSE(later_scene_target(facts, s, 640, 480));
    SceneFacts shown;
    s.framebuffer = 3, s.vp[2] = 256, s.vp[3] = 192;
    classify_draw(shown, s, 3, kPasses);
    shown.presented = true;
    s.framebuffer = 5, s.vp[2] = 640, s.vp[3] = 480;
    EXPECT_FALSE(later_scene_target(shown, s, 640, 480));
}

TEST(SceneClassifier, ASmallerTargetWithColourAndDepthMayHoldASceneShownInPartOfTheWindow) {
    // A toolkit's GL widget, a content suite's viewport: another shape, colour and depth.
    SceneFacts facts;
    Given s;
    s.framebuffer = 3;
    s.vp[2] = 200, s.vp[3] = 250;
    GLuint bound = 0;
    EXPECT_TRUE(offscreen_scene(facts, s, 640, 480, bound));
    s.color = GL_NONE;  // a shadow map
    EXPECT_FALSE(offscreen_scene(facts, s, 640, 480, bound));
    s.color = GL_TEXTURE;
    s.texture = 11;
    const ClassifierSettings window{false, true, 640, 480};
    ASSERT_TRUE(classify_draw(facts, s, 3, window).found_view);
    EXPECT_TRUE(facts.in_part);
    EXPECT_EQ(facts.scene_texture, 11u);
    EXPECT_FALSE(stretched_scene(facts, 640, 480));
    SceneFacts stretched;  // the window's shape: shown stretched, not in part
    s.vp[2] = 320, s.vp[3] = 240;
    classify_draw(stretched, s, 3, window);
    EXPECT_FALSE(stretched.in_part);
    EXPECT_EQ(stretched.scene_texture, 0u);
}

TEST(SceneClassifier, TheDrawThatSamplesASceneShownInPartShowsItAndTheInterfaceBeforeItIsNotTheScene) {
    SceneFacts facts;
    Given s;
    s.framebuffer = 3, s.texture = 11;
    s.vp[2] = 320, s.vp[3] = 260;
    ASSERT_TRUE(classify_draw(facts, s, 3, ClassifierSettings{false, true, 400, 300}).found_view);
    ASSERT_TRUE(facts.in_part);
    s.framebuffer = 0, s.depth_on = false, s.proj = kOrtho;
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::Scene);  // a toolbar
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Pixels), WindowDrawMeaning::Scene);
    EXPECT_FALSE(facts.presented);
    s.sampled = 11;  // the viewport's quad
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::ShowsInPart);
    EXPECT_TRUE(facts.presented);
    s.sampled = 0;  // the header after it
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::StartsOverlays);
    // A 3D draw to the window that samples it (a monitor in the program's own scene) is no showing.
    SceneFacts monitor;
    s.framebuffer = 3, s.depth_on = true, s.proj = glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    classify_draw(monitor, s, 3, ClassifierSettings{false, true, 400, 300});
    s.framebuffer = 0, s.sampled = 11;
    EXPECT_EQ(window_draw(monitor, s, RedrawKind::Draw), WindowDrawMeaning::NotTheScene);
    EXPECT_FALSE(monitor.main_known || monitor.in_part || monitor.scene_texture);
}

TEST(SceneClassifier, ASceneShownInPartFollowsItsColourThroughAResolveAndAPostProcessingCopy) {
    SceneFacts facts;
    Given s;
    ASSERT_TRUE(found_in_part_of_400x300(facts, s));
    EXPECT_EQ(facts.scene_texture, 0u);
    s.framebuffer = 4, s.read = 3, s.texture = 12;  // resolved into a texture
    follow_scene_texture(facts, s, RedrawKind::Copy);
    EXPECT_EQ(facts.scene_texture, 12u);
    s.framebuffer = 5, s.texture = 13;
    s.vp[2] = 160, s.vp[3] = 130, s.sampled = 12;  // a bloom's smaller target: not the picture
    follow_scene_texture(facts, s, RedrawKind::Draw);
    EXPECT_EQ(facts.scene_texture, 12u);
    s.vp[2] = 320, s.vp[3] = 260, s.sampled = 0;  // the scene's size, another texture
    follow_scene_texture(facts, s, RedrawKind::Draw);
    EXPECT_EQ(facts.scene_texture, 12u);
    s.sampled = 12;  // a post-processing copy
    follow_scene_texture(facts, s, RedrawKind::Draw);
    EXPECT_EQ(facts.scene_texture, 13u);
}

TEST(SceneClassifier, ABlitFromASceneShownInPartAtTheViewsSizeShowsIt) {
    SceneFacts facts;
    Given s;
    ASSERT_TRUE(found_in_part_of_400x300(facts, s));
    s.framebuffer = 0;
    const int32_t view[4] = {0, 0, 320, 260}, half[4] = {0, 0, 160, 130}, at[4] = {80, 0, 400, 260};
    const int32_t mirrored[4] = {80, 260, 400, 0};
    s.read = 7;  // another target's picture (an icon, a thumbnail)
    EXPECT_EQ(window_blit(facts, s, view, at), WindowDrawMeaning::Scene);
    s.read = 3;
    EXPECT_EQ(window_blit(facts, s, half, at), WindowDrawMeaning::Scene);  // part of it
    EXPECT_EQ(window_blit(facts, s, view, mirrored), WindowDrawMeaning::Scene);  // upside down: not placed
    EXPECT_FALSE(facts.presented);
    EXPECT_EQ(window_blit(facts, s, view, at), WindowDrawMeaning::ShowsInPart);  // the resolve into the window
    EXPECT_TRUE(facts.presented);
    EXPECT_EQ(window_blit(facts, s, view, at), WindowDrawMeaning::Scene);  // once
    // Resolved into a texture first, that target's blit shows it.
    SceneFacts copied;
    s.framebuffer = 3;
    classify_draw(copied, s, 3, ClassifierSettings{false, true, 400, 300});
    s.framebuffer = 4, s.read = 3, s.texture = 12;
    follow_scene_texture(copied, s, RedrawKind::Copy);
    s.framebuffer = 0, s.read = 4;
    EXPECT_EQ(window_blit(copied, s, view, at), WindowDrawMeaning::ShowsInPart);
    // A scene of the window's size is shown by any blit.
    SceneFacts whole;
    s.framebuffer = 3, s.vp[2] = 400, s.vp[3] = 300;
    classify_draw(whole, s, 3, ClassifierSettings{false, true, 400, 300});
    ASSERT_TRUE(whole.scene_framebuffer && !whole.in_part);
    s.framebuffer = 0, s.read = 9;
    EXPECT_EQ(window_blit(whole, s, half, at), WindowDrawMeaning::Scene);
    EXPECT_TRUE(whole.presented);
    EXPECT_FALSE(whole.shown_mirrored);
    // ... upside down too (a scene drawn with Direct3D's origin, Wine's present): the window's
    // picture is the target's with its rows swapped; or mirrored left to right.
    auto shown_by_blit = [&](const int32_t source[4], const int32_t destination[4]) {
        SceneFacts f;
        s.framebuffer = 3;
        classify_draw(f, s, 3, ClassifierSettings{false, true, 400, 300});
        s.framebuffer = 0;
        EXPECT_EQ(window_blit(f, s, source, destination), WindowDrawMeaning::Scene);
        EXPECT_TRUE(f.presented);
        return f;
    };
    const int32_t window[4] = {0, 0, 400, 300}, rows_swapped[4] = {0, 300, 400, 0}, columns_swapped[4] = {400, 0, 0, 300};
    const SceneFacts flipped = shown_by_blit(window, rows_swapped);
    EXPECT_TRUE(flipped.shown_mirrored);
    EXPECT_FALSE(flipped.shown_mirrored_columns);
    const SceneFacts both = shown_by_blit(rows_swapped, rows_swapped);  // source and destination swapped: upright
    EXPECT_FALSE(both.shown_mirrored);
    EXPECT_FALSE(both.shown_mirrored_columns);
    const SceneFacts left_right = shown_by_blit(window, columns_swapped);
    EXPECT_TRUE(left_right.shown_mirrored_columns);
    EXPECT_FALSE(left_right.shown_mirrored);
}

TEST(SceneClassifier, ALaterTargetOfTheWindowsShapeReplacesASceneFoundInPart) {
    // A reflection of another shape drawn first, the scene's window-sized target after it.
    SceneFacts facts;
    Given s;
    s.framebuffer = 3, s.texture = 11;
    s.vp[2] = 256, s.vp[3] = 256;
    ASSERT_TRUE(classify_draw(facts, s, 3, ClassifierSettings{false, true, 640, 480}).found_view);
    s.framebuffer = 5, s.vp[2] = 640, s.vp[3] = 480;
    EXPECT_TRUE(later_scene_target(facts, s, 640, 480));
    EXPECT_FALSE(facts.main_known || facts.in_part || facts.scene_texture);
}

TEST(SceneClassifier, OnceTheSceneIsFoundOffscreenOnlyItsTargetCounts) {
    SceneFacts facts;
    Given s;
    s.framebuffer = 3;
    GLuint bound = 0;
    ASSERT_TRUE(offscreen_scene(facts, s, 640, 480, bound));
    EXPECT_TRUE(classify_draw(facts, s, bound, kPasses).found_view);
    EXPECT_EQ(facts.scene_framebuffer, 3u);
    s.framebuffer = 5;
    EXPECT_FALSE(offscreen_scene(facts, s, 640, 480, bound));
    s.framebuffer = 3;
    EXPECT_TRUE(offscreen_scene(facts, s, 640, 480, bound));
}

TEST(SceneClassifier, AFlatDrawToTheWindowShowsTheOffscreenSceneAndWhatFollowsIsOverlay) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 3, kPasses);
    ASSERT_EQ(facts.scene_framebuffer, 3u);
    s.depth_on = false;  // the post-processed picture drawn over the window
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::Scene);
    EXPECT_TRUE(facts.presented);
    s.depth_on = true;  // a 3D icon of the HUD
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::StartsOverlays);
}

TEST(SceneClassifier, A3DDrawToTheWindowMeansTheOffscreenTargetWasNotTheScene) {
    SceneFacts facts;
    Given s;
    s.lit.known = true;
    classify_draw(facts, s, 3, kPasses);
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::NotTheScene);
    EXPECT_FALSE(facts.main_known);
    EXPECT_EQ(facts.scene_framebuffer, 0u);
    EXPECT_FALSE(facts.light.known);
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).found_view);  // the window's draws find it again
}

TEST(SceneClassifier, ADepthCopyToTheWindowShowsTheOffscreenScene) {
    // VTK copies its scene's depth into the window with a full-window draw, colour masked, the
    // depth test on with GL_ALWAYS: that shows the scene, it is no 3D draw.
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 3, kPasses);
    s.always = true;
    EXPECT_EQ(window_draw(facts, s, RedrawKind::Draw), WindowDrawMeaning::Scene);
    EXPECT_TRUE(facts.presented && facts.main_known);
}

TEST(SceneClassifier, AFlatDrawIntoTheSceneTargetBeforeItIsShownStartsItsOverlays) {
    // VTK draws its text actors into the scene's framebuffer object, after the 3D view.
    SceneFacts facts;
    Given s;
    EXPECT_FALSE(scene_target_overlays_start(facts, s, RedrawKind::Draw));  // no view yet
    classify_draw(facts, s, 3, kPasses);
    EXPECT_FALSE(scene_target_overlays_start(facts, s, RedrawKind::Draw));  // another 3D draw of the view
    s.proj = kOrtho;
    EXPECT_FALSE(scene_target_overlays_start(facts, s, RedrawKind::State));
    EXPECT_TRUE(scene_target_overlays_start(facts, s, RedrawKind::Draw));
    EXPECT_TRUE(facts.target_overlay);
    EXPECT_FALSE(scene_target_overlays_start(facts, s, RedrawKind::Draw));  // started once
    SceneFacts shown;
    s.proj = glm::frustum(-1.0, 1.0, -0.75, 0.75, 1.0, 100.0);
    classify_draw(shown, s, 3, kPasses);
    shown.presented = true;  // after the scene is shown, its target is no longer the picture's
    s.proj = kOrtho;
    EXPECT_FALSE(scene_target_overlays_start(shown, s, RedrawKind::Draw));
}

TEST(SceneClassifier, AnotherTargetWritingTheScenesDepthKeepsThatDepthOnce) {
    // Blender's overlay engine draws wire frames with the scene's camera into a colour target of
    // its own that holds the scene's depth texture, writing depth.
    SceneFacts facts;
    Given s;
    s.framebuffer = 3;
    classify_draw(facts, s, 3, kPasses);
    ASSERT_TRUE(facts.main_known);
    EXPECT_FALSE(scene_depth_overlay_starts(facts, s));  // the scene's own target
    s.framebuffer = 5;
    EXPECT_FALSE(scene_depth_overlay_starts(facts, s));  // a target with a depth of its own
    s.depth_of = 3;
    s.depth_mask = false;
    EXPECT_FALSE(scene_depth_overlay_starts(facts, s));  // tests the depth, writes none
    s.depth_mask = true;
    s.texture = 12;  // its colour: the overlays composited over the scene
    EXPECT_TRUE(scene_depth_overlay_starts(facts, s));
    EXPECT_TRUE(facts.scene_depth_kept);
    EXPECT_EQ(facts.overlay_texture, 12u);
    s.texture = 13;
    EXPECT_FALSE(scene_depth_overlay_starts(facts, s));  // kept once
    EXPECT_EQ(facts.overlay_texture, 12u);
    s.framebuffer = 3;
    s.texture = 0;
    facts.main_known = false;  // a new main view forgets it
    classify_draw(facts, s, 3, kPasses);
    EXPECT_EQ(facts.overlay_texture, 0u);
    SceneFacts shown;
    s.framebuffer = 3;
    classify_draw(shown, s, 3, kPasses);
    shown.presented = true;  // shown already: the window's rules
    s.framebuffer = 5;
    EXPECT_FALSE(scene_depth_overlay_starts(shown, s));
    SceneFacts window;  // a scene drawn in the window has no target to share
    s.framebuffer = 0;
    classify_draw(window, s, 0, kPasses);
    s.framebuffer = 5;
    EXPECT_FALSE(scene_depth_overlay_starts(window, s));
}

TEST(SceneClassifier, AShaderDrawWithAnOrthographicMatrixIsFlatWithTheDepthTestOn) {
    SceneFacts facts;
    Given s;
    classify_draw(facts, s, 0, kPasses);  // the view, fixed function
    s.current_program = 6;               // VTK's text actor: depth test on, no camera, an ortho matrix
    EXPECT_FALSE(starts_overlays(facts, s, RedrawKind::Draw));
    s.flat = true;
    EXPECT_TRUE(starts_overlays(facts, s, RedrawKind::Draw));
    s.has_camera = true;  // a camera among its matrices: a 3D draw, whatever else it holds
    s.cam.projection = s.proj;
    EXPECT_FALSE(starts_overlays(facts, s, RedrawKind::Draw));
}

TEST(FrameRecord, AppendKeepsTuplesInOrderAndClearStartsOverWithTheMemoryKept) {
    FrameRecord rec;
    const uint8_t a[3] = {1, 2, 3}, b[2] = {4, 5};
    RecordEntry e;
    e.main = true;
    ASSERT_TRUE(rec.append(a, 3, e));
    e.begin = 3;
    ASSERT_TRUE(rec.append(b, 2, e));
    EXPECT_EQ(rec.bytes, (std::vector<uint8_t>{1, 2, 3, 4, 5}));
    EXPECT_EQ(rec.entries.size(), 2u);
    rec.in_begin_end = rec.started = rec.overflow = true;
    rec.start_program = 7;
    const size_t capacity = rec.bytes.capacity();
    rec.clear();
    EXPECT_TRUE(rec.bytes.empty());
    EXPECT_TRUE(rec.entries.empty());
    EXPECT_FALSE(rec.in_begin_end || rec.started || rec.overflow);
    EXPECT_EQ(rec.start_program, 0);
    EXPECT_EQ(rec.bytes.capacity(), capacity);
}

TEST(FrameRecord, ATupleBeyondTheFramesLimitIsRefusedAndTheFrameMarked) {
    FrameRecord rec;
    const uint8_t a[1] = {1};
    ASSERT_TRUE(rec.append(a, 1, RecordEntry{}));
    // (the size alone is checked: the tuple is never read)
    EXPECT_FALSE(rec.append(a, kMaxRecordBytes, RecordEntry{}));
    EXPECT_TRUE(rec.overflow);
    EXPECT_FALSE(rec.append(a, 1, RecordEntry{}));
    EXPECT_EQ(rec.entries.size(), 1u);
}

TEST(SceneClassifier, ADrawsProjectionSplitFromAnotherProductIsStillTheViews) {
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    s.has_camera = true;
    s.cam.projection = s.proj;
    classify_draw(facts, s, 0, kPasses);
    // The next draw's projection * view * model split alone: the same camera, other last bits.
    s.cam.projection = s.proj;
    s.cam.projection[0][0] *= 1 + 1e-7;
    s.cam.projection[3][2] *= 1 - 1e-7;
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).main);
    s.cam.projection[0][0] *= 1.01;  // another lens
    EXPECT_FALSE(classify_draw(facts, s, 0, kPasses).main);
}

// The shader program that gives the main view gives its light (its sun, ProgramCameras::light).
TEST(SceneClassifier, TheMainViewsShaderProgramGivesItsSun) {
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    s.has_camera = true;
    s.cam.projection = s.proj;
    s.cam.modelview = s.mv;
    s.sun = effects::SceneLight{true, glm::dvec4(0.2, 1, 0.1, 0)};
    s.lit = effects::SceneLight{true, glm::dvec4(9, 9, 9, 0)};  // a fixed-function light: not this draw's
    ASSERT_TRUE(classify_draw(facts, s, 0, kPasses).found_view);
    EXPECT_TRUE(facts.light.known);
    EXPECT_EQ(facts.light.eye_position, glm::dvec4(0.2, 1, 0.1, 0));
}

TEST(SceneClassifier, LinesDrawnWithTheViewsCameraAfterItsSurfacesAreMarks) {
    // view3dscene's bounding box: GL_LINE_STRIPs with the scene's camera, the depth test on, after
    // its surfaces. Not redrawn (no shadow, no normals); from the first, the passes read the scene
    // as it was before them.
    SceneFacts facts;
    Given s;
    ASSERT_TRUE(classify_draw(facts, s, 0, kPasses).found_view);
    s.drawn = GL_LINE_STRIP;
    DrawVerdict v = classify_draw(facts, s, 0, kPasses);
    EXPECT_FALSE(v.main);
    EXPECT_TRUE(v.marks_start);
    EXPECT_TRUE(facts.marks);
    s.drawn = GL_POINTS;  // marker points too; the marks go on
    v = classify_draw(facts, s, 0, kPasses);
    EXPECT_FALSE(v.main);
    EXPECT_FALSE(v.marks_start);
    // A surface after them: they were among the scene's objects, which the window's depth keeps.
    s.drawn = GL_TRIANGLES;
    v = classify_draw(facts, s, 0, kPasses);
    EXPECT_TRUE(v.main);
    EXPECT_TRUE(v.over_end);
    EXPECT_FALSE(facts.marks);
    EXPECT_FALSE(facts.overlay);
}

TEST(SceneClassifier, AShaderProgramsLinesAreMarksAlsoWhenNoPassRedraws) {
    // (snow and screen-space shadows read the depth only: the lines must not be in it)
    SceneFacts facts;
    Given s;
    s.current_program = 4;
    s.has_camera = true;
    s.cam.projection = s.proj;
    const ClassifierSettings depth_only{false, false};
    ASSERT_TRUE(classify_draw(facts, s, 0, depth_only).found_view);
    s.drawn = GL_LINES;
    EXPECT_TRUE(classify_draw(facts, s, 0, depth_only).marks_start);
    s.drawn = GL_TRIANGLE_STRIP;
    const DrawVerdict v = classify_draw(facts, s, 0, depth_only);
    EXPECT_FALSE(v.main);  // (nothing is redrawn)
    EXPECT_TRUE(v.over_end);
    // Lines under another camera (a HUD's, a gizmo's) are no marks of this view.
    s.drawn = GL_LINES;
    s.cam.projection = kOrtho;
    EXPECT_FALSE(classify_draw(facts, s, 0, depth_only).marks_start);
    EXPECT_FALSE(facts.marks);
}

TEST(SceneClassifier, LinesThatAreNoMarks) {
    SceneFacts facts;
    Given s;
    s.drawn = GL_LINES;  // openscad's axes, drawn first: they find the view, as any draw does ...
    DrawVerdict v = classify_draw(facts, s, 0, kPasses);
    EXPECT_TRUE(v.found_view);
    EXPECT_FALSE(v.main);  // ... but are never redrawn: no casters, no normals
    v = classify_draw(facts, s, 0, kPasses);  // no surface before them: no marks either
    EXPECT_FALSE(v.main);
    EXPECT_FALSE(v.marks_start);
    s.drawn = GL_TRIANGLES;
    classify_draw(facts, s, 0, kPasses);
    s.drawn = GL_LINES;
    EXPECT_TRUE(classify_draw(facts, s, 0, kPasses).marks_start);  // over its first surface
    SceneFacts flat;
    s.drawn = GL_TRIANGLES;
    classify_draw(flat, s, 0, kPasses);
    s.drawn = GL_LINES;
    s.depth_on = false;  // drawn in a painter's order: the scene's (or, flat, the overlays')
    EXPECT_FALSE(classify_draw(flat, s, 0, kPasses).marks_start);
    s.depth_on = true;
    s.proj = kOrtho;  // another projection
    EXPECT_FALSE(classify_draw(flat, s, 0, kPasses).marks_start);
    EXPECT_FALSE(flat.marks);
}

TEST(SceneClassifier, MarksInTheScenesTargetKeepItsColourAndDepth) {
    // A scene drawn offscreen: its target's picture and depth from before the marks are the scene's.
    SceneFacts facts;
    Given s;
    s.framebuffer = 3;
    ASSERT_TRUE(classify_draw(facts, s, 3, kPasses).found_view);
    s.drawn = GL_LINE_LOOP;
    EXPECT_TRUE(classify_draw(facts, s, 3, kPasses).marks_start);
    EXPECT_TRUE(facts.target_overlay);
    EXPECT_TRUE(facts.scene_depth_kept);
    EXPECT_EQ(facts.overlay_texture, 0u);  // (no overlay engine's)
    s.drawn = GL_TRIANGLES;
    EXPECT_TRUE(classify_draw(facts, s, 3, kPasses).over_end);
    EXPECT_FALSE(facts.target_overlay);
    EXPECT_FALSE(facts.scene_depth_kept);
}
