// The scene's decisions (scene_classifier.h).
#include "slave/scene/scene_classifier.h"

#include <algorithm>
#include <cmath>

namespace glcast::slave {
namespace {

void found_view(SceneFacts& f, DrawState& s, GLuint framebuffer, const glm::dmat4& projection,
                const glm::dmat4& modelview, const ClassifierSettings& settings) {
    f.main_known = true;
    f.scene_framebuffer = framebuffer;
    f.scene_depth_kept = false;  // (kept of another target)
    f.overlay_texture = 0;
    f.projection = projection;
    f.modelview = modelview;
    s.viewport(f.viewport);
    const int W = settings.window_width, H = settings.window_height;
    const double v[4] = {double(f.viewport[0]), double(f.viewport[1]), double(f.viewport[2]), double(f.viewport[3])};
    f.in_part = framebuffer && W > 0 && H > 0 && !(f.viewport[2] == W && f.viewport[3] == H) && !window_shaped(v, W, H);
    f.scene_texture = f.in_part ? s.color_texture() : 0;
}

// What was taken for the main view was not it: the facts know no view again.
void forget_view(SceneFacts& f) {
    f.main_known = false;
    f.surfaces = f.opaque_surfaces = f.marks = f.translucent = false;
    f.scene_framebuffer = 0;
    f.scene_depth_kept = false;
    f.overlay_texture = 0;
    f.target_overlay = false;
    f.in_part = false;
    f.scene_texture = 0;
    f.light = effects::SceneLight{};
}

// A blended draw after the view's opaque surfaces is translucent (minetest's cloud layer, drawn
// last, writing depth): no part of the view's redraw, so it casts no hard shadow over the world
// under it; the window's depth still has it. A program that blends every draw (openscad leaves
// GL_BLEND on) says nothing by it: until a surface of the view is drawn without blending, blended
// draws are the view's. (The draw that finds the view is the view's whatever it does.)
bool translucent_after_view(const SceneFacts& f, DrawState& s, bool found) {
    return !found && f.main_known && f.opaque_surfaces && s.blends();
}

// A fixed-function draw: the first with a perspective projection that writes depth, unless
// its modelview is mirrored, is the main view; later ones with the same projection into the
// same target belong to it, those that write depth and those drawn in a painter's order with
// the depth test off (pillars --overlay), whose surfaces the window's depth lacks: redrawn, they
// cast their shadows and give their own normals. A backdrop drawn first without depth writes (a
// star field) is neither the main view nor, after it, the start of the overlays; the window's
// depth does not have it, and the redraw leaves it out.
bool fixed_function_draw_is_main(SceneFacts& f, DrawState& s, GLuint framebuffer, const ClassifierSettings& settings,
                                  bool& found) {
    const glm::dmat4 app = s.projection();
    const bool depth = s.writes_depth();
    if (!f.main_known && is_perspective(app) && depth) {
        const glm::dmat4 modelview = s.modelview();
        if (!mirrored(modelview)) {
            // (a push made inside a reflection is not the view)
            found_view(f, s, framebuffer, app, f.pushed && !mirrored(f.last_push) ? f.last_push : modelview, settings);
            f.light = s.light();
            found = true;
        }
    }
    return f.main_known && !f.overlay && app == f.projection && (depth || !s.depth_test()) &&
           framebuffer == f.scene_framebuffer && !translucent_after_view(f, s, found);
}

// A shader program's draw belongs to the main view when its camera (found from its matrices,
// program_camera.h) has the main view's projection, the first such draw making the main view;
// with a configured projection, every draw to the window before the overlays does. Only draws
// that write depth with the depth test on, or, after the main view, draw in a painter's order
// with it off: a sky drawn without depth writes (the test on) is no caster, and the window's
// depth does not have it either.
bool shader_draw_is_main(SceneFacts& f, DrawState& s, GLuint program, GLuint framebuffer,
                         const ClassifierSettings& settings, bool& found) {
    if (f.main_known && !settings.redraws) return false;  // no pass re-renders: the camera is all we need
    if (settings.configured_projection)
        return settings.redraws && !f.overlay && s.writes_depth() && framebuffer == 0;
    if (!f.main_known && f.camera_probes >= kMaxCameraProbes) return false;
    ProgramCamera camera;
    if (!f.main_known) f.camera_probes++;
    if (!s.camera(program, camera)) return false;
    if (!f.main_known && mirrored(camera.modelview)) return false;  // a reflection's camera
    if (!f.main_known) {
        found_view(f, s, framebuffer, camera.projection, camera.modelview, settings);
        f.light = s.program_light(program, camera);
        found = true;
    }
    return !f.overlay && same_projection(camera.projection, f.projection) && (s.writes_depth() || !s.depth_test()) &&
           framebuffer == f.scene_framebuffer && !translucent_after_view(f, s, found);
}

bool lines_or_points(GLenum primitive) {
    switch (primitive) {
    case GL_POINTS: case GL_LINES: case GL_LINE_LOOP: case GL_LINE_STRIP: case GL_LINES_ADJACENCY:
    case GL_LINE_STRIP_ADJACENCY: return true;
    default: return false;
    }
}

// The draw has the main view's camera (its projection: fixed function's, or a shader program's
// found from its matrices; with a configured projection, any shader draw to the window).
bool views_camera(const SceneFacts& f, DrawState& s, const ClassifierSettings& settings) {
    const GLuint program = s.program();
    if (!program) return s.projection() == f.projection;
    if (settings.configured_projection) return !f.scene_framebuffer;
    ProgramCamera camera;
    return s.camera(program, camera) && same_projection(camera.projection, f.projection);
}

// Nothing but the view's surfaces is over the scene yet in its target: no HUD drawn into it, no
// overlay engine's depth kept (those keep what they need themselves).
bool target_free(const SceneFacts& f) {
    return f.marks || f.translucent || (!f.target_overlay && !f.scene_depth_kept);
}

// Lines or points over the view's surfaces, drawn into its target with its camera and the depth test on.
bool is_mark(const SceneFacts& f, DrawState& s, GLuint framebuffer, const ClassifierSettings& settings) {
    return f.main_known && f.surfaces && !f.overlay && target_free(f) && lines_or_points(s.primitive()) &&
           framebuffer == f.scene_framebuffer && s.depth_test() && views_camera(f, s, settings);
}

// A translucent draw (translucent_after_view) that writes depth into the view's target with its camera.
bool translucent_over_view(const SceneFacts& f, DrawState& s, GLuint framebuffer, const DrawVerdict& v,
                           const ClassifierSettings& settings) {
    return !v.main && !v.found_view && f.main_known && f.opaque_surfaces && !f.overlay && target_free(f) &&
           framebuffer == f.scene_framebuffer && s.blends() && s.writes_depth() && views_camera(f, s, settings);
}

// The scene's depth is kept from before the first draw over it (a scene target's: scene_depth_kept).
void keep_depth_before(SceneFacts& f, DrawVerdict& v) {
    v.keeps_depth = !f.marks && !f.translucent;
    if (f.scene_framebuffer) f.scene_depth_kept = true;
}

// A surface of the view after marks or translucent draws: they were among its objects.
void scene_again(SceneFacts& f, DrawVerdict& v) {
    if (f.scene_framebuffer) {
        if (f.marks) f.target_overlay = false;
        f.scene_depth_kept = false;
    }
    f.marks = f.translucent = false;
    v.over_end = true;
}

}  // namespace

DrawVerdict classify_draw(SceneFacts& f, DrawState& s, GLuint framebuffer, const ClassifierSettings& settings) {
    DrawVerdict v;
    if (const double far = s.view_model_far()) {
        // Neither the main view nor a part of it: its pixels go back as the program drew them.
        if (f.main_known && !f.overlay) f.view_model_far = std::max(f.view_model_far, far);
        if (s.program()) f.shader_draws = true;
        return v;
    }
    if (is_mark(f, s, framebuffer, settings)) {
        if (s.program()) f.shader_draws = true;
        if (!f.marks) {  // (the colour too: the marks' pixels go back as drawn)
            v.marks_start = true;
            keep_depth_before(f, v);
            f.marks = true;
            if (f.scene_framebuffer) f.target_overlay = true;
        }
        return v;
    }
    const bool over_before = f.marks || f.translucent;
    if (const GLuint program = s.program()) {
        f.shader_draws = true;
        v.main = shader_draw_is_main(f, s, program, framebuffer, settings, v.found_view);
    } else {
        v.main = fixed_function_draw_is_main(f, s, framebuffer, settings, v.found_view);
    }
    // (with no pass redrawing, a shader program's later draws are not asked for their camera: the
    // end of what is over the scene is)
    if (over_before && !f.overlay && framebuffer == f.scene_framebuffer && !lines_or_points(s.primitive()) &&
        s.writes_depth() &&
        (v.main || (!settings.redraws && s.program() && !s.blends() && views_camera(f, s, settings))))
        scene_again(f, v);
    else if (!f.translucent && translucent_over_view(f, s, framebuffer, v, settings)) {
        keep_depth_before(f, v);
        f.translucent = true;
    }
    if (v.main && lines_or_points(s.primitive())) {
        // Lines and points are no surfaces wherever they come (openscad draws its axes first): the
        // view's (they may find it), never redrawn, so no casters and no normals.
        v.main = false;
    } else if (v.main) {
        f.surfaces = true;
        if (!f.opaque_surfaces && !s.blends()) f.opaque_surfaces = true;
    }
    if (v.main) v.cull = s.cull(), v.alpha = s.alpha_test();
    if (v.main && s.program()) f.main_shader_draws = true;
    if (v.main && !s.depth_test()) f.painter_draws = true;
    return v;
}

bool window_shaped(const double v[4], int W, int H) {
    // (at most four times the window: the slave copies such a target at its size every frame)
    if (v[0] != 0 || v[1] != 0 || W <= 0 || H <= 0 || v[3] <= 0 || v[2] * 4 < W || v[2] > 4.0 * W) return false;
    return std::abs(v[2] / v[3] - double(W) / H) <= 0.01 * double(W) / H;
}

bool stretched_scene(const SceneFacts& f, int W, int H) {
    const double v[4] = {double(f.viewport[0]), double(f.viewport[1]), double(f.viewport[2]), double(f.viewport[3])};
    return f.main_known && f.scene_framebuffer && (f.viewport[2] != W || f.viewport[3] != H) && window_shaped(v, W, H);
}

bool later_scene_target(SceneFacts& f, DrawState& s, int W, int H) {
    if (!f.main_known || !f.scene_framebuffer || (f.viewport[2] == W && f.viewport[3] == H) || f.presented || f.overlay)
        return false;
    const GLuint framebuffer = s.draw_framebuffer();
    if (!framebuffer || framebuffer == f.scene_framebuffer) return false;
    int32_t viewport[4];
    s.viewport(viewport);
    const double v[4] = {double(viewport[0]), double(viewport[1]), double(viewport[2]), double(viewport[3])};
    if (!window_shaped(v, W, H) || s.color_attachment_type() == GL_NONE || s.depth_attachment_type() == GL_NONE)
        return false;
    forget_view(f);
    return true;
}

void follow_scene_texture(SceneFacts& f, DrawState& s, RedrawKind kind) {
    if (!f.in_part || f.presented || !f.scene_framebuffer) return;
    const GLuint framebuffer = s.draw_framebuffer();
    if (!framebuffer || framebuffer == f.scene_framebuffer) return;
    if (kind == RedrawKind::Copy) {
        if (s.read_framebuffer() != f.scene_framebuffer) return;
    } else {
        int32_t viewport[4];
        s.viewport(viewport);
        if (viewport[2] != f.viewport[2] || viewport[3] != f.viewport[3] || !f.scene_texture ||
            !s.samples_texture(f.scene_texture))
            return;
    }
    if (const GLuint texture = s.color_texture()) f.scene_texture = texture, f.scene_copy = framebuffer;
}

bool offscreen_scene(const SceneFacts& f, DrawState& s, int master_width, int master_height, GLuint& framebuffer) {
    framebuffer = s.draw_framebuffer();
    if (f.main_known) return f.scene_framebuffer != 0 && framebuffer == f.scene_framebuffer;
    if (f.overlay || f.presented || !framebuffer) return false;
    int32_t viewport[4];
    s.viewport(viewport);
    if (viewport[0] != 0 || viewport[1] != 0) return false;
    // At another size than the window's, a target holds a scene the window shows stretched (a
    // render scale, at the window's shape) or in part of the window (a toolkit's GL widget, a
    // content suite's viewport): one with a colour attachment the window can show. (Another view
    // drawn there first, a reflection's or a monitor's, is forgotten when the window's draws do
    // not show it: window_draw, later_scene_target.)
    if ((viewport[2] != master_width || viewport[3] != master_height) && s.color_attachment_type() == GL_NONE)
        return false;
    return s.depth_attachment_type() != GL_NONE;
}

// A scene drawn offscreen is complete when the program shows it in the window (a full-window
// draw with the depth test off, or a blit); whatever the window gets after that is overlay (a
// game's HUD, its 3D icons included). Programs draw their HUD and text last, with the depth
// test off or an orthographic projection; a 3D draw after the HUD (a weapon) is an overlay too.
WindowDrawMeaning window_draw(SceneFacts& f, DrawState& s, RedrawKind kind) {
    if (kind != RedrawKind::Draw && kind != RedrawKind::Begin && kind != RedrawKind::Pixels)
        return WindowDrawMeaning::Scene;
    if (f.scene_framebuffer && !f.presented) {
        // (a draw whose depth test passes everything copies depth: VTK copies the scene's that way)
        if (kind == RedrawKind::Pixels || !s.writes_depth() || s.depth_always()) {
            if (f.in_part) {  // the interface around it, until the draw that samples it
                if (kind == RedrawKind::Pixels || !f.scene_texture || !s.samples_texture(f.scene_texture))
                    return WindowDrawMeaning::Scene;
                f.presented = true;
                return WindowDrawMeaning::ShowsInPart;
            }
            f.presented = true;  // the scene's image drawn over the window
            return WindowDrawMeaning::Scene;
        }
        // A 3D draw to the window: what was drawn offscreen was not the scene.
        forget_view(f);
        return WindowDrawMeaning::NotTheScene;
    }
    if (!f.scene_framebuffer && !starts_overlays(f, s, kind)) return WindowDrawMeaning::Scene;
    f.overlay = true;
    return WindowDrawMeaning::StartsOverlays;
}

WindowDrawMeaning window_blit(SceneFacts& f, DrawState& s, const int32_t source[4], const int32_t destination[4]) {
    if (!f.scene_framebuffer || f.presented) return WindowDrawMeaning::Scene;
    if (!f.in_part) {
        f.presented = true;  // the scene's image copied over the window
        f.shown_mirrored = (destination[1] > destination[3]) != (source[1] > source[3]);
        f.shown_mirrored_columns = (destination[0] > destination[2]) != (source[0] > source[2]);
        return WindowDrawMeaning::Scene;
    }
    const GLuint read = s.read_framebuffer();
    if ((read != f.scene_framebuffer && (!f.scene_copy || read != f.scene_copy)) ||
        int64_t(source[2]) - source[0] != f.viewport[2] || int64_t(source[3]) - source[1] != f.viewport[3])
        return WindowDrawMeaning::Scene;  // (another picture: a thumbnail, part of the interface)
    if (destination[2] <= destination[0] || destination[3] <= destination[1])
        return WindowDrawMeaning::Scene;  // (mirrored or empty: not placed, left as drawn, as rotated tiles do)
    f.presented = true;
    return WindowDrawMeaning::ShowsInPart;
}

bool scene_target_overlays_start(SceneFacts& f, DrawState& s, RedrawKind kind) {
    // (what is drawn into the target of a scene shown in part of the window is decorated with it)
    if (!f.main_known || !f.scene_framebuffer || f.presented || f.overlay || f.target_overlay || f.in_part)
        return false;
    if (kind != RedrawKind::Draw && kind != RedrawKind::Begin) return false;
    f.target_overlay = starts_overlays(f, s, kind);
    return f.target_overlay;
}

bool scene_depth_overlay_starts(SceneFacts& f, DrawState& s) {
    // (a scene shown already, or one drawn in the window, keeps what the window's rules say)
    if (!f.main_known || !f.scene_framebuffer || f.presented || f.scene_depth_kept) return false;
    if (!s.writes_depth() || !s.shares_depth_with(f.scene_framebuffer)) return false;
    f.scene_depth_kept = true;
    f.overlay_texture = s.color_texture();
    return true;
}

bool depth_clear_starts_overlays(SceneFacts& f, GLbitfield mask) {
    // (a scene drawn offscreen keeps its own depth; a clear of the colour too starts a new picture)
    if (!f.main_known || f.overlay || f.scene_framebuffer || !(mask & GL_DEPTH_BUFFER_BIT) ||
        (mask & GL_COLOR_BUFFER_BIT))
        return false;
    f.overlay = f.depth_cleared = true;
    return true;
}

bool starts_overlays(const SceneFacts& f, DrawState& s, RedrawKind kind) {
    if (kind == RedrawKind::Pixels) return true;
    const GLuint program = s.program();
    const bool flat = !s.depth_test();
    // A fixed-function draw with the main view's projection and the depth test off is the scene's
    // too (neverball's reflection, drawn into its floor before the floor is blended over it).
    if (!program) return !is_perspective(s.projection()) || (flat && !same_projection(s.projection(), f.projection));
    // (its matrices are read only where they decide: a 3D scene's draws pay one look at them)
    ProgramCamera camera;
    // A shader program that paints its 3D scene in order with the depth test off draws it with
    // the main view's camera: scene, not overlay.
    if (flat) return !(s.camera(program, camera) && same_projection(camera.projection, f.projection));
    // One with an orthographic matrix and no camera draws flat with the depth test on too (VTK's
    // text actors).
    return s.flat_program(program) && !s.camera(program, camera);
}

void note_push(SceneFacts& f, DrawState& s) {
    if (s.matrix_mode() != GL_MODELVIEW) return;  // the value a push saves is the one on top before it
    f.last_push = s.modelview();
    f.pushed = true;
}

}  // namespace glcast::slave
