// The tile adapter's per-context and per-share-group state (tile_adapter.h), shared by its two
// files: tile_adapter.cpp (rectangles, calls, redraws) and tile_turn.cpp (rotated tiles).
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "slave/program_camera.h"
#include "slave/scaled_blit.h"
#include "slave/shown_scene.h"
#include "slave/tile_adapter.h"

namespace glcast::slave {

// Per context: the program's rectangles as it set them, and the projection-correction state
// of rotated tiles, one entry per GL_PROJECTION stack level: whether the level holds
// M * P_app, whether the program changed it since (relative to M * P_app), and the M it holds.
struct TileAdapter::State {
    double viewport[kViewports][4] = {};
    int32_t scissor[kViewports][4] = {};
    bool indexed = false;  // the program used GL_ARB_viewport_array: all rectangles are applied
    double line_width = 0, point_size = 0;  // as the program set them (0: it did not)
    int mapped_for[2] = {0, 0};  // the master's window size the rectangles were last mapped for
    struct Projection {
        bool corrected = false, dirty = false;
        glm::dmat4 m{1.0};
        bool left = false;  // not perspective: shown as the program drew it
    };
    std::vector<Projection> projection = std::vector<Projection>(1);
    uint32_t matrix_mode = GL_MODELVIEW;
    bool in_begin_end = false;  // GL refuses queries between glBegin and glEnd
    uint64_t draw_framebuffer = 0;  // the master's name of the bound draw framebuffer (0: the window)
    // What framebuffer objects (by the master's name) hold, colour and depth (kHoldsColour,
    // kHoldsDepth): a scene may be drawn where both are. Asked of the driver at the first draw into
    // each, forgotten when attachments change.
    std::unordered_map<uint64_t, uint8_t> attachments;
    // Engines draw their other views (a monitor's, a reflection's) first and their scene last
    // before showing it: the last such target drawn with a perspective view before the window
    // in a frame (not a post-processing target its full-screen quads fill after it) held the
    // scene, unless the window itself got a perspective view (then none did), and from the next
    // frame on only it is turned (until then, every one); with it, the targets of the window's
    // shape drawn with the same projection that frame (a deferred renderer draws its geometry,
    // its lights and its colours into several: SuperTuxKart).
    uint64_t scene_target = 0;  // 0: the window
    std::vector<uint64_t> scene_targets;  // ... and those drawn with its projection
    bool scene_target_known = false;
    uint64_t frame_scene_target = 0;  // this frame's, so far
    // This frame's targets of the window's shape drawn with a perspective view, and its projection
    // (the last), at most kFrameViews.
    static constexpr size_t kFrameViews = 16;
    std::vector<std::pair<uint64_t, glm::dmat4>> frame_views;
    bool presented = false;           // the context presented a frame (its frames end)
    uint64_t presented_frame = 0;     // ... the last
    bool window_drawn = false;        // this frame has drawn to the window
    bool window_view = false;         // ... with a perspective view
    glm::dmat4 window_projection{1.0};  // that view's projection (the program's, unturned)
    bool scene_view = false;          // this frame drew a perspective view into the scene target
    glm::dmat4 scene_projection{1.0};  // that view's projection
    // ... as the window shows it, upright: a scene drawn upside down into its target is shown
    // flipped (Wine's way), and the window's flat draws after it (a HUD) lie on an upright screen.
    glm::dmat4 scene_screen{1.0};
    bool scene_shown = false;         // ... and the window's first flat draw, which shows it, went by
    bool frame_shaped_view = false;   // this frame drew a view into a target of the window's shape

    // A scene target that is not of the window's shape, shown in part of the window (shown_scene.h):
    // once a frame's view went only there, it is the scene target and turned from the next frame
    // on; the draw that shows it samples a texture of its view's size.
    bool scene_in_part = false;       // the scene target is such a one
    bool part_refused = false;        // one was turned and then not found shown: left alone since
    uint64_t frame_part_target = 0;   // this frame's candidate, drawn with a perspective view
    int32_t part_viewport[4] = {0, 0, 0, 0};  // that view's viewport in its target
    bool part_turned = false;         // this frame drew the scene target turned
    bool part_found = false;          // ... and the draw to the window that shows it was found
    GLuint showing_texture = 0;       // the texture the draw that shows it samples, and its size
    bool showing_repeatable = false;  // that draw is one call (not glBegin/glEnd's)
    int32_t showing_size[2] = {0, 0};
    // The program's window on its screen: the frustum of the scene's view extended by where in the
    // window the program showed it (the frame before's until this frame's is measured).
    bool window_screen_known = false;
    glm::dmat4 window_screen{1.0};
    // The scene the window shows this frame, as the draw that shows it found it (the context's own
    // or its lender's: the projection of its view and that view's viewport).
    glm::dmat4 shown_projection{1.0};
    int32_t shown_viewport[4] = {0, 0, 0, 0};
    uint32_t lender = 0;              // the context (id) whose scene the window shows, if not its own
    uint64_t shown_in_frame = 0;      // the frame (+ 1) whose scene was last shown over the tile
    std::shared_ptr<ShownScene> shown;  // (shared with the copy a redraw keeps)
    std::shared_ptr<ScaledBlit> scaled_blit;  // a multisampled blit into the window, scaled (scaled_blit.h)
};

// Per share group: what the shader patch needs to know of shaders and programs.
struct TileAdapter::Shared {
    std::unordered_map<uint64_t, uint32_t> shader_types;  // master shader name -> GL_VERTEX_SHADER, ...
    // glcast_clip's location in each slave program (-1: not patched) and what it holds now.
    struct Clip {
        int32_t location = -1;
        glm::mat4 value{0.0f};
    };
    std::unordered_map<uint32_t, Clip> clip_uniforms;
    // glcast_fragcoord's location in each slave program (-1: none) and what it holds now.
    struct FragCoord {
        int32_t location = -1;
        float value[4] = {0, 0, 0, 0};
    };
    std::unordered_map<uint32_t, FragCoord> fragcoord_uniforms;
    explicit Shared(const GlApi& gl) : cameras(gl) {}
    ProgramCameras cameras;  // shader programs' projections, without program_projection
};

}  // namespace glcast::slave
