// Which of a frame's draws are its scene: the main view (the camera the passes decorate
// through), a scene drawn offscreen into a framebuffer object, and from where on the window
// gets overlays (HUD, text, menus) that the passes leave alone. Decisions only: every fact
// about GL state comes from a DrawState (draw_state.h), every finding goes into SceneFacts, so
// each rule is tested without a driver (tests/unit/scene_classifier_test.cpp).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "protocol/command_info.h"
#include "slave/effects/frame_view.h"
#include "slave/scene/draw_state.h"

namespace glcast::slave {

// What one context's frame has shown of its scene so far; a new frame starts from SceneFacts{}.
struct SceneFacts {
    bool shader_draws = false;  // some draw to the window used a shader program
    // ... some draw of the main view did: its redraw binds the programs the frame used. (A
    // fixed-function scene shown by a GLSL blit or composite is redrawn as fixed function.)
    bool main_shader_draws = false;
    // ... some draw of the main view had the depth test off (a painter's order): the window's
    // depth lacks its surfaces, which the passes' depth gets from a redraw (EffectsRunner).
    bool painter_draws = false;
    // The window's colour was cleared whole (clears_whole_colour) before the main view: the
    // frame is a new picture (so is one whose offscreen scene is shown_whole), and the passes
    // may decorate its scene when the overlays start, under them (the program's translucent
    // menus and panels then blend over the winter).
    bool window_cleared = false;
    // Overlays: from the first draw after the main view that is two-dimensional (an
    // orthographic projection, the depth test off, pixels at the raster position) on, the
    // frame's draws are the program's HUD and text, drawn over what the passes decorate.
    bool overlay = false;
    // A first-person view model (a game's weapon): draws after the main view squeezed into the
    // front of the depth range (glDepthRange(0, f), f < 1) so that nothing in the world hides
    // them. Not the scene: not redrawn, and the pixels whose depth is below the largest such f
    // are the program's, as an overlay's are. 0: none this frame.
    double view_model_far = 0;
    // A view model drawn after a depth-only clear of the window (a voxel game's hand): the
    // clear starts the overlays, and the passes read the scene's depth as it was before it.
    bool depth_cleared = false;
    // Shader draws whose matrices were read for a camera this frame: a 2D program with
    // thousands of draws stops asking after kMaxCameraProbes.
    int camera_probes = 0;
    // The main view: the first draw to the window with a perspective projection (fixed
    // function: that also writes depth; shader programs: whose matrices split as a camera).
    bool main_known = false;
    // A scene drawn offscreen: the main view was found in the program's framebuffer object
    // `scene_framebuffer` (the slave's name; 0: the window), one the program draws into whole at
    // the window's size with a depth buffer (a post-processing engine's scene target). The first
    // draw or copy to the window after it shows it there (`presented`); later draws to the window
    // are overlays. If that first draw writes depth instead, the object was not the scene.
    GLuint scene_framebuffer = 0;
    bool presented = false;
    // ... by a draw whose viewport, or a blit whose destination, covers the whole window: the
    // frame is a new picture, as one that clears its window whole is (window_cleared).
    bool shown_whole = false;
    // ... by a blit that swaps its rows (destination y0 above y1, the source not): the window's
    // picture is the target's upside down, as a program drawing with an upper-left origin
    // (Direct3D's, under Wine) presents; the passes read it as glClipControl(GL_UPPER_LEFT)'s.
    bool shown_mirrored = false;
    // ... by a blit that swaps its columns (destination x0 right of x1, the source not): the
    // window's picture is the target's mirrored left to right (a scene drawn with glFrustum's left
    // and right swapped); the passes read it mirrored back.
    bool shown_mirrored_columns = false;
    // That target has neither the window's size nor its shape: the scene is shown in part of the
    // window (a content suite's 3D viewport), by the first flat draw to the window that samples
    // `scene_texture` (its colour texture, or the one a resolve or a post-processing draw of its
    // size copied it into; the slave's name), and placed where that draw put it (scene_lending.h).
    // Flat draws to the window before it are the interface around it.
    bool in_part = false;
    GLuint scene_texture = 0;
    GLuint scene_copy = 0;  // the framebuffer object whose colour scene_texture is, when a copy's
    // Overlays drawn into that framebuffer object after the main view, before it is shown (VTK's
    // text actors): from the first flat draw there (starts_overlays' rule) on, what the target
    // gets is the program's, as the window's overlays are.
    bool target_overlay = false;
    // A draw that writes depth into another framebuffer object holding the scene's depth, after
    // the main view (an overlay engine's wire frames and empties, drawn with the scene's camera
    // into a colour target of their own over the scene's depth, as Blender's are): from the first,
    // the passes read the scene's depth as it was before it (WindowCopies::keep_scene_depth).
    bool scene_depth_kept = false;
    // That target's colour texture (the slave's name; 0: a renderbuffer). What the engine draws
    // into it is composited over the scene before the scene is shown (Blender mixes it in by its
    // alpha in the draw that shows its viewport): its covered texels are the program's overlays,
    // kept as drawn under every pass (EffectsRunner::engine_overlays).
    GLuint overlay_texture = 0;
    // Some draw of the main view drew surfaces (not lines or points); ... one with blending off.
    bool surfaces = false, opaque_surfaces = false;
    // Marks: lines and points drawn with the main view's camera and the depth test on after its
    // surfaces (view3dscene's bounding box, a wire frame, a grid, a selection's outline, marker
    // points), which are no surfaces: not redrawn (they cast no shadow and give no normal), and
    // from the first the passes take the scene as it was before them: the window's colour and
    // depth then (or the scene's target's: target_overlay and scene_depth_kept), the marks' pixels
    // kept as drawn, as overlays are. A surface of the view after them ends them: they were among
    // its objects, and the window's depth keeps them (the copies are forgotten).
    bool marks = false;
    // A translucent draw after the view's opaque surfaces that writes depth into its target with its
    // camera (minetest's cloud layer; translucent_after_view: no caster): from the first the passes
    // read the scene's depth as it was before it (the window's kept, or the target's:
    // scene_depth_kept), so that screen-space shadows march no cloud; its colour is the scene's,
    // decorated with it. A surface of the view after it ends it, as it ends marks.
    bool translucent = false;
    glm::dmat4 projection{1.0}, modelview{1.0};
    int32_t viewport[4] = {0, 0, 0, 0};  // the program's, master window coordinates
    effects::SceneLight light;
    // The modelview the program pushed last (glPushMatrix on GL_MODELVIEW) before the main
    // view's first draw: the view transform of programs that push per object.
    bool pushed = false;
    glm::dmat4 last_push{1.0};
};

constexpr int kMaxCameraProbes = 64;

struct ClassifierSettings {
    // The display config states the shader programs' projection (program_projection): every
    // shader draw to the window before the overlays is the main view's.
    bool configured_projection = false;
    bool redraws = false;  // some pass re-renders the main view
    int window_width = 0, window_height = 0;  // the master's window; 0: unknown
};

// A draw (or glBegin) about to run.
struct DrawVerdict {
    bool main = false;        // it belongs to the main view
    bool found_view = false;  // ... and is its first: the main view was found with it
    CullState cull;           // a main draw's face culling
    AlphaTest alpha;          // ... and alpha test
    bool marks_start = false;  // the first of the view's marks (SceneFacts::marks): keep its colour now
    bool keeps_depth = false;  // the first draw over the scene (marks or translucent): keep its depth now
    bool over_end = false;     // a surface of the view after them: what was kept is not the scene
};

// What a draw to the window after the main view means for the overlays.
enum class WindowDrawMeaning {
    Scene,           // nothing changes
    StartsOverlays,  // the window as the scene left it is the passes' to decorate
    NotTheScene,     // the offscreen scene was not one: the window's draws find the main view again
    ShowsInPart,     // it shows a scene drawn in part of the window (SceneFacts::in_part): place it
};

DrawVerdict classify_draw(SceneFacts& facts, DrawState& state, GLuint framebuffer, const ClassifierSettings& settings);

// A viewport from the origin of a target at the window's shape (within 1%), from a quarter to four
// times its width: where engines draw the scene they show stretched over the window (a render
// scale; a larger viewport from a stream is refused, since the passes copy that target).
// The tile adapter turns what is drawn into such a target on rotated tiles (tile_adapter.h).
bool window_shaped(const double viewport[4], int master_width, int master_height);
// The scene is in a framebuffer object of the window's shape at another size, shown stretched
// over the window (not a borrowed scene, whose placement says where it goes).
bool stretched_scene(const SceneFacts& facts, int master_width, int master_height);

// A draw into the bound framebuffer object that may hold the scene: the one the main view was
// found in, or, before it is known, one the program draws into whole at the window's size
// (master_width x master_height) with a depth buffer, or at any other size with colour and depth:
// at the window's shape (window_shaped) shown stretched, else shown in part of the window (a
// toolkit's GL widget, a content suite's viewport). `framebuffer` is set to the bound one.
bool offscreen_scene(const SceneFacts& facts, DrawState& state, int master_width, int master_height,
                     GLuint& framebuffer);

// Engines draw their other views (a monitor's, a reflection's) before the scene that samples
// them: a main view found in a target at another size than the window's is forgotten when a
// later draw, before the window shows anything, goes into another target of the window's shape
// that could hold the scene. True: it was forgotten (the facts know no view again), and the draws
// kept for it are no longer the main view's (the caller unmarks the record's offscreen entries).
bool later_scene_target(SceneFacts& facts, DrawState& state, int master_width, int master_height);

// A scene shown in part of the window whose colour is copied on before it is shown: a draw into
// another framebuffer object at the scene's size that samples `facts.scene_texture` (a
// post-processing step), or a resolve (glBlitFramebuffer from the scene's target, kind Copy),
// makes the bound target's colour texture the one that shows it.
void follow_scene_texture(SceneFacts& facts, DrawState& state, RedrawKind kind);

// A draw of `kind` to the window while the main view is known and overlays have not started. The
// first after a scene drawn offscreen shows it (pixels, a draw without depth writes, or one
// whose depth function is GL_ALWAYS: a copy of the scene's depth), for a scene shown in part of
// the window the first such draw that samples its texture; a 3D draw instead means the
// offscreen draws were not the scene.
WindowDrawMeaning window_draw(SceneFacts& facts, DrawState& state, RedrawKind kind);

// A glBlitFramebuffer into the window of `source` (x0, y0, x1, y1 of the read framebuffer) to
// `destination` while the main view is known and overlays have not started. For a scene shown in
// part of the window, one that reads its target (or the one its colour was resolved or copied
// into) over a rectangle of the view's size, unmirrored, shows it (ShowsInPart: placed at the
// destination); for another scene drawn offscreen, any blit shows it.
WindowDrawMeaning window_blit(SceneFacts& facts, DrawState& state, const int32_t source[4],
                              const int32_t destination[4]);

// A draw of `kind` into the scene's framebuffer object (`facts.scene_framebuffer`) while its main
// view is known and it has not been shown: true when it is the first flat one (starts_overlays),
// which starts the overlays drawn into that target.
bool scene_target_overlays_start(SceneFacts& facts, DrawState& state, RedrawKind kind);

// A draw into a framebuffer object while the scene's main view is known in another one: true when
// it is the first that writes the scene's depth from another target (SceneFacts::scene_depth_kept),
// whose depth the passes must then take from before it.
bool scene_depth_overlay_starts(SceneFacts& facts, DrawState& state);

// glClear(mask) of the window while its main view is known and overlays have not started: a
// clear of the depth alone (the colour kept) ends the scene, and what follows (a view model with
// its own projection, then the HUD) lies over it. True: the overlays start with it.
bool depth_clear_starts_overlays(SceneFacts& facts, GLbitfield mask);

// A flat draw to the window after a main view drawn there: pixels at the raster position, a
// fixed-function orthographic projection, or the depth test off under another projection than
// the main view's; a draw with the main view's camera (fixed function or a shader program's) is
// scene whatever its depth test.
bool starts_overlays(const SceneFacts& facts, DrawState& state, RedrawKind kind);

// glPushMatrix before the main view is known: a push of the modelview may save the view.
void note_push(SceneFacts& facts, DrawState& state);

}  // namespace glcast::slave
