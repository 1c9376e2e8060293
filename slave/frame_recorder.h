// The replayer's side of the injected passes (docs/effects.md): what a slave context records
// of each frame so that passes can know the scene (the main view, the light) and re-render
// it, and running the passes before the frame is presented. An observer of the replay core.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "protocol/command_info.h"
#include "slave/effects/frame_view.h"
#include "slave/effects/pipeline.h"
#include "slave/program_camera.h"
#include "slave/replay_observer.h"

namespace glcast::slave {

// The frame's calls that re-render its geometry without side effects on objects: draws,
// immediate-mode blocks, display-list calls, matrix and vertex-array state. Kept as raw
// tuples, decoded again by redraw.
struct FrameRecord {
    struct Entry {
        size_t begin = 0, size = 0;
        bool draw = false;     // a draw or part of a glBegin/glEnd block
        bool opens = false;    // the draw call or the glBegin itself (its projection is corrected)
        bool main = false;     // ... of the main view
        bool program_state = false;  // shader-program state: replayed only in frames with shader draws
        bool offscreen = false;      // a draw into the framebuffer object that holds the scene
        // Face culling as the draw had it (GL_CULL_FACE, glCullFace, glFrontFace): a redraw culls
        // what the program culled, whatever the frame's last draws left set (neverball culls its
        // level's back faces, then draws its menu without culling: redrawn without it, the backs
        // of its rails hid the floor from the passes).
        bool cull = false;
        uint16_t cull_face = 0, front_face = 0;
    };
    std::vector<uint8_t> bytes;
    std::vector<Entry> entries;
    bool in_begin_end = false, begin_is_main = false;
    bool compiling_list = false;  // between glNewList and glEndList: nothing is drawn
    bool overflow = false;        // more than kMaxRecordBytes: this frame cannot be re-rendered
    bool shader_draws = false;    // some draw to the window used a shader program
    // The program current when the frame began (GL's name and the stream's): a redraw starts
    // from it, as the frame's first draws did.
    bool started = false;
    GLint start_program = 0;
    uint64_t start_program_stream = 0;
    // Overlays: from the first draw after the main view that is two-dimensional (an
    // orthographic projection, the depth test off, pixels at the raster position) on, the
    // frame's draws are the program's HUD and text, drawn over what the passes decorate.
    bool overlay = false;
    // A first-person view model (a game's weapon): draws after the main view squeezed into the
    // front of the depth range (glDepthRange(0, f), f < 1: Quake's depth hack, f = 0.3) so that
    // nothing in the world hides them. Not the scene: not redrawn, and the pixels whose depth is
    // below the largest such f are the program's, as an overlay's are. 0: none this frame.
    double view_model_far = 0;
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
    // A scene drawn by another context (docs/effects.md "A scene another context draws"): a
    // toolkit's GL widget (Qt's QOpenGLWidget) draws its view with a context of its own, which
    // never presents, into a framebuffer object of the widget's size, and only when the view
    // changes; the window's context draws that object's colour texture into the window every
    // frame. The lending context's record keeps the scene (its texture, depth attachment and
    // size below) until it draws the next; the presenting context's record borrows it when a
    // draw to the window samples the texture (`borrowed_from`: the lender's context id), and
    // finds where that draw put it (`placement`: x0, y0, x1, y1 in the master's window pixels).
    GLuint scene_texture = 0, scene_depth_name = 0;
    GLenum scene_depth_type = GL_NONE, scene_depth_format = 0;
    int32_t scene_size[2] = {0, 0};
    bool complete = false;  // lender: a frame was presented since it drew its scene
    uint32_t borrowed_from = 0;
    bool placement_pending = false;  // from entry placement_from on, the draw that shows it
    size_t placement_from = 0;
    int32_t placement[4] = {0, 0, 0, 0};
    glm::dmat4 projection{1.0}, modelview{1.0};
    int32_t viewport[4] = {0, 0, 0, 0};  // the program's, master window coordinates
    effects::SceneLight light;
    // The modelview the program pushed last (glPushMatrix on GL_MODELVIEW) before the main
    // view's first draw: the view transform of programs that push per object.
    bool pushed = false;
    glm::dmat4 last_push{1.0};

    void clear();
    void drop_borrowed();  // the frame shows no other context's scene after all
};
constexpr size_t kMaxRecordBytes = size_t(256) << 20;
constexpr int kMaxCameraProbes = 64;

// Per slave context: its pipeline and the copies of its window framebuffer.
struct EffectsState {
    std::unique_ptr<effects::Pipeline> pipeline;
    FrameRecord record;
    GLuint color_texture = 0, depth_texture = 0, color_fb = 0, depth_fb = 0;
    int copies_width = 0, copies_height = 0;
    // The depth of a scene drawn offscreen, in the scene framebuffer's own format (a depth blit
    // needs the same format on both sides): resolved at the program's size, then this tile's part
    // of it at the window's size.
    GLuint scene_depth_full = 0, scene_depth_full_fb = 0, scene_depth = 0, scene_depth_fb = 0;
    GLuint scene_depth_program = 0, scene_depth_vao = 0;
    GLenum scene_depth_format = 0;
    int scene_depth_sizes[4] = {0, 0, 0, 0};  // full width, height; tile width, height
    // This context has presented a frame: a context that never has may lend its scene.
    bool presents = false;
    // A borrowed scene: a framebuffer object of this context with the lender's depth attached
    // (framebuffer objects are not shared, their attachments are), and the depth-only target
    // of the master's window size on which the draw that shows the scene is drawn again to
    // find where it went.
    GLuint lender_fb = 0, placement_fb = 0, placement_depth = 0;
    int placement_sizes[2] = {0, 0};
    std::vector<uint8_t> placement_pixels;  // its depth read back, one byte a pixel
    // The last rectangle measured, and what it was measured for (place_borrowed_scene).
    bool placement_known = false;
    uint64_t placement_key = 0;
    int placement_age = 0;
    int32_t placement_rect[4] = {0, 0, 0, 0};
    bool color_copied = false, depth_copied = false;
    // The program's own picture of the frame, saved before the passes draw over it and put back
    // after present: a program that never clears draws its next frame over its own image, not
    // over the decorated one (which would pile up snow until the window is white).
    GLuint program_image = 0, program_image_fb = 0;
    bool program_image_saved = false;
    // The window as the scene left it, before the first overlay, and the program that puts the
    // overlays back over the decorated scene (slave/effects/overlays.frag).
    GLuint scene_image = 0, scene_image_fb = 0, overlay_program = 0, overlay_vao = 0;
    GLuint view_model_depth = 0;  // the depth the passes saw, for the view model's pixels
    // The program's vertex-array object and 2D textures (units 0..7) as the frame left them,
    // before any pass: redraw gives them back to the program's draws, whatever a pass bound.
    GLint program_vao = 0, program_active_texture = GL_TEXTURE0, program_textures[8] = {};
    // Shader programs' cameras, found from their matrices (slave/program_camera.h).
    std::unique_ptr<ProgramCameras> program_cameras;
    ProgramCameras& cameras(const GlApi& gl) {
        if (!program_cameras) program_cameras = std::make_unique<ProgramCameras>(gl);
        return *program_cameras;
    }
};

// The effects could not run (a shader that does not compile, a driver without GL 3.3): fatal
// for the slave, with the reason.
class EffectsError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Replayer;
class TileAdapter;

class FrameRecorder : public ReplayObserver {
public:
    FrameRecorder(Replayer& core, TileAdapter& tile) : core_(core), tile_(tile) {}
    ~FrameRecorder() override;

    bool wants(uint32_t opcode, const CommandInfo* info) const override;
    void before_call(const Call& c, const uint8_t* tuple, size_t bytes) override;
    void end_frame(SlaveContext& ctx) override;
    void presented(SlaveContext& ctx) override;
    void reset() override { states_.clear(); }
    void context_removed(uint32_t id) override { states_.erase(id); }

private:
    EffectsState& state(const SlaveContext& ctx);
    void record(const Call& c, const uint8_t* tuple, size_t bytes);
    void watch_overlays(SlaveContext& ctx, RedrawKind kind);  // before a draw to the window
    bool starts_overlays(SlaveContext& ctx, RedrawKind kind);
    void put_overlays_back(SlaveContext& ctx, bool overlays);
    void run_effects(SlaveContext& ctx);
    void redraw_main_view(SlaveContext& ctx, const glm::dmat4& correction);
    bool shader_draw_is_main(SlaveContext& ctx, FrameRecord& rec, GLuint program, GLuint framebuffer);
    // Whether a draw into the bound framebuffer object (the slave's name in `framebuffer`) can
    // be the scene's: the one the main view was found in, or, before it is known, one the program
    // draws into whole at the window's size and with a depth buffer.
    bool offscreen_scene(SlaveContext& ctx, const FrameRecord& rec, GLuint& framebuffer);
    unsigned scene_depth_copy(SlaveContext& ctx);  // the offscreen scene's depth, tile pixels
    // Another context's scene, shown by the draw about to run (a draw to the window sampling the
    // lender's colour texture): taken as this frame's main view.
    void borrow_scene(SlaveContext& ctx, FrameRecord& rec);
    void place_borrowed_scene(SlaveContext& ctx);  // after that draw ran
    // That draw (entries placement_from..end) drawn again: the rectangle it covers, master pixels.
    bool measure_placement(SlaveContext& ctx, size_t end, int32_t out[4]);
    void note_lendable_scene(SlaveContext& ctx, FrameRecord& rec);  // the main view found offscreen
    bool shares_with_another(const SlaveContext& ctx) const;  // objects with another live context
    void redispatch_entry(const FrameRecord& rec, const FrameRecord::Entry& e, Call& c);
    void note_resolved_scene(FrameRecord& rec);  // a glBlitFramebuffer from the lent scene's target
    // The record whose draws and camera are the frame's scene: the lender's for a borrowed one.
    const FrameRecord& scene_record(const SlaveContext& ctx);
    void scene_rect(SlaveContext& ctx, int32_t out[4]);  // where the scene is, tile pixels
    void frame_view(SlaveContext& ctx, effects::FrameView& view);
    unsigned window_copy(SlaveContext& ctx, bool depth);  // a GL texture name
    void size_copies(SlaveContext& ctx);                   // the copies, at the window's size
    // Blits the window's colour (or depth) into the framebuffer `copy_fb`, or back from it.
    void copy_window(SlaveContext& ctx, unsigned copy_fb, bool depth, bool back = false);

    Replayer& core_;
    TileAdapter& tile_;
    std::unordered_map<uint32_t, std::unique_ptr<EffectsState>> states_;  // by context id
    bool checked_ = false;  // the driver has every function the passes need
    bool warned_no_camera_ = false;
    bool said_borrowed_ = false;
};

}  // namespace glcast::slave
