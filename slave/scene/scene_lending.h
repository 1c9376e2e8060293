// A scene shown in part of the window (docs/effects.md "A scene shown in part of the window"):
// a toolkit's GL widget (Qt's QOpenGLWidget) draws its view with a context of its own, which
// never presents, into a framebuffer object of the widget's size, and only when the view
// changes; the window's context draws that object's colour texture into the window every
// frame. The lending context's record keeps its scene (texture, depth attachment, size) until
// it draws the next; the presenting context borrows it when a draw to the window samples the
// texture, and finds where that draw put it by drawing it again in the master's window
// coordinates into a depth-only target. A content suite's viewport is the same with one
// context: it lends its scene to itself (SceneFacts::in_part).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <memory>
#include <vector>

#include "common/gl_headers.h"
#include "slave/draw_footprint.h"

namespace glcast::slave {

class Replayer;
class TileAdapter;
struct SlaveContext;
struct ContextScene;
class DrawState;

// This frame's side of a loan; a new frame starts from SceneLoan{}.
struct SceneLoan {
    // Lender: its scene's colour texture, depth attachment and size.
    GLuint scene_texture = 0, scene_depth_name = 0;
    GLenum scene_depth_type = GL_NONE, scene_depth_format = 0;
    int32_t scene_size[2] = {0, 0};
    bool complete = false;  // a frame was presented since it drew its scene
    // Borrower: the lender's context id (its own for a scene of its own shown in part of the
    // window), and where the draw that shows the scene put it (x0, y0, x1, y1 in the master's
    // window pixels) once measured.
    uint32_t borrowed_from = 0;
    bool placement_pending = false;  // from entry placement_from on, the draw that shows it
    size_t placement_from = 0;
    bool placement_given = false;  // a blit showed it: placement is its destination, of this source
    int32_t placement_source[4] = {0, 0, 0, 0};
    int32_t placement[4] = {0, 0, 0, 0};
};

// A borrower's GL objects and its last measured placement; they outlive frames.
struct BorrowerObjects {
    // A framebuffer object of this context with the lender's depth attached (framebuffer objects
    // are not shared, their attachments are), and the footprint of the draw that shows the
    // scene, drawn again.
    GLuint lender_fb = 0;
    DrawFootprint placement;
    bool placement_known = false;
    uint64_t placement_key = 0;  // what the last rectangle was measured for
    int placement_age = 0;
    int32_t placement_rect[4] = {0, 0, 0, 0};
};

using ContextScenes = std::unordered_map<uint32_t, std::unique_ptr<ContextScene>>;

class SceneLending {
public:
    SceneLending(Replayer& core, TileAdapter& tile, ContextScenes& scenes) : core_(core), tile_(tile), scenes_(scenes) {}

    // The main view was just found in a framebuffer object of a context that never presented, or
    // in one shown in part of the window: what it lends, read from that framebuffer's attachments.
    void note_lendable_scene(SlaveContext& ctx, ContextScene& scene);
    // A lender's multisampled scene resolved (glBlitFramebuffer) into a framebuffer object whose
    // colour is a texture: that texture shows the scene.
    void note_resolved_scene(ContextScene& scene, DrawState& state);
    // Another context's scene, shown by the draw about to run (a draw to the window sampling the
    // lender's colour texture: DrawState::samples_texture): taken as this frame's main view.
    void borrow_scene(SlaveContext& ctx, ContextScene& scene, DrawState& state);
    // The draw about to run shows the context's own scene in part of the window (window_draw's
    // ShowsInPart): placed as a borrowed one.
    void show_own_scene(SlaveContext& ctx, ContextScene& scene);
    // ... by a blit of `source` (x0, y0, x1, y1 of its target) into `destination` of the window
    // (the master's pixels): placed there, with no draw to measure.
    void show_own_scene(SlaveContext& ctx, ContextScene& scene, const int32_t source[4],
                        const int32_t destination[4]);
    // After that draw ran: where it put the scene, and the scene's viewport in the window.
    void place_borrowed_scene(SlaveContext& ctx, ContextScene& scene);
    // The scene whose draws and camera are this context's frame's: the lender's when borrowed.
    const ContextScene& scene_of(const ContextScene& scene) const;

private:
    bool measured_placement(SlaveContext& ctx, ContextScene& scene, int32_t rect[4]);  // kept or measured
    bool measure_placement(SlaveContext& ctx, ContextScene& scene, size_t end, int32_t out[4]);

    Replayer& core_;
    TileAdapter& tile_;
    ContextScenes& scenes_;
};

// The frame shows no scene placed in part of the window after all.
void drop_borrowed(ContextScene& scene);

}  // namespace glcast::slave
