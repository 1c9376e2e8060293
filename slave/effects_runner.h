// The injected passes' observer of the replay (docs/effects.md): before each call it hands the
// call to the scene recorder (slave/scene/scene_recorder.h), which keeps what a pass may redraw
// and finds the frame's scene; at the end of each frame it describes the frame to the passes
// (effects::FrameView), runs them (slave/effects/pipeline.h) and puts the program's overlays
// back over what they drew.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <unordered_map>

#include <glm/glm.hpp>

#include "slave/effects/frame_view.h"
#include "slave/effects/pipeline.h"
#include "slave/replay_observer.h"
#include "slave/scene/depth_convention.h"
#include "slave/scene/scene_recorder.h"
#include "slave/scene/window_copies.h"

namespace glcast::slave {

// The effects could not run (a shader that does not compile, a driver without GL 3.3): fatal
// for the slave, with the reason.
class EffectsError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Replayer;
class TileAdapter;

class EffectsRunner : public ReplayObserver {
public:
    EffectsRunner(Replayer& core, TileAdapter& tile);
    ~EffectsRunner() override;

    bool wants(uint32_t opcode, const CommandInfo* info) const override;
    void before_call(const Call& c, const uint8_t* tuple, size_t bytes) override;
    void after_call(const Call& c) override;
    void end_frame(SlaveContext& ctx) override;
    void presented(SlaveContext& ctx) override;
    void reset() override;
    void context_removed(uint32_t id) override;

    SceneRecorder& scenes() { return scenes_; }
    // The replay's effect settings changed (passes switched live): pipelines are built anew.
    void settings_changed();

private:
    // Per slave context: its pipeline, the copies of its window, the overlays' program, and the
    // program's vertex-array object and 2D textures (units 0..7) as the frame left them, before
    // any pass: a redraw gives them back to the program's draws, whatever a pass bound.
    // A frame decorated when its overlays started (decorates_under_overlays), the window's
    // copy scene_image then holding the decorated scene: what its end still owes.
    struct UnderOverlays {
        bool decorated = false;
        bool report = false;           // --scene-report wants the frame
        bool target_overlays = false;  // the scene's own target had overlays (put back then)
        effects::FrameView view;
    };
    struct ContextPasses {
        explicit ContextPasses(Replayer& core) : copies(core) {}
        std::unique_ptr<effects::Pipeline> pipeline;
        WindowCopies copies;
        GLuint overlay_program = 0, overlay_vao = 0;
        GLuint view_model_depth = 0;  // the depth the passes saw, for the view model's pixels
        // The vertex array and textures bound as this frame's record started (a redraw starts there).
        GLint program_vao = 0, program_active_texture = GL_TEXTURE0, program_textures[8] = {};
        DepthConvention depth;  // this frame's: the program's depth as the passes read it
        glm::dmat4 pass_clip_from_program_clip{1.0};  // the depth conversion's, with the tile's map
        GLuint report_mask = 0, report_mask_fb = 0;   // --scene-report: the kept pixels
        GLuint painter_depth_fb = 0;  // the passes' depth completed by a painter's draws, once a frame
        // An overlay engine's colour, copied for the put-back (engine_overlay_texture).
        GLuint engine_fb = 0, engine_copy = 0, engine_copy_fb = 0;
        GLint engine_copy_format = 0;
        int engine_copy_size[2] = {0, 0};
        bool painter_depth_done = false;
        int report_size[2] = {0, 0};
        UnderOverlays under_overlays;
    };
    ContextPasses& passes(const SlaveContext& ctx);
    void run_effects(SlaveContext& ctx);  // at the frame's end
    void keep_frame_start(SlaveContext& ctx);
    // The frame's passes, run over the window as it is (under_overlays: when its overlays start)
    // and the program's own pixels put back.
    void decorate(SlaveContext& ctx, bool under_overlays);
    bool decorates_under_overlays(SlaveContext& ctx);
    // The scene report of a frame decorated under its overlays: the pixels they changed are kept.
    void report_under_overlays(SlaveContext& ctx);
    void frame_view(SlaveContext& ctx, effects::FrameView& view);
    // A program whose depth is not the passes' (depth_convention.h): the view in the passes'
    // projection, the window's depth converted, redraws corrected.
    void convert_depth(SlaveContext& ctx, effects::FrameView& v, const glm::dmat4& planar);
    void redraw_main_view(SlaveContext& ctx, const glm::dmat4& correction);
    // A frame with draws of the main view made with the depth test off (SceneFacts::painter_draws):
    // `depth` (the passes' depth texture, this tile's size) gets their surfaces from a depth-only
    // `redraw` of the main view (FrameView::redraw) with the depth test on, `correction` putting
    // it on the tile.
    void complete_painter_depth(SlaveContext& ctx, const std::function<void(const glm::dmat4&)>& redraw,
                                bool binds_programs, GLuint depth, const glm::dmat4& correction);
    // Draws the program's own pixels back over the passes' into `target` (0: the window).
    void put_overlays_back(SlaveContext& ctx, bool overlays, bool target_overlays, GLuint target = 0);
    void report_scene(SlaveContext& ctx, const effects::FrameView& view, bool overlays, bool target_overlays, bool kept);
    void scene_rect(SlaveContext& ctx, int32_t out[4]);  // where the scene is, tile pixels
    // The colour texture an overlay engine composited over the frame's scene before it was shown
    // (SceneFacts::overlay_texture, the lender's for a borrowed scene); 0: none.
    GLuint engine_overlays(SlaveContext& ctx);
    // That texture's picture in a 2D texture of ours the put-back can sample, at `size` (the scene's
    // target's), whatever its target, resolved where it is multisampled; 0: none.
    GLuint engine_overlay_texture(SlaveContext& ctx, const int size[2]);
    GLuint copy_engine_overlay(ContextPasses& st, GLenum format, const int size[2]);

    Replayer& core_;
    TileAdapter& tile_;
    SceneRecorder scenes_;
    std::unordered_map<uint32_t, std::unique_ptr<ContextPasses>> passes_;  // by context id
    bool checked_ = false;  // the driver has every function the passes need
    bool warned_no_camera_ = false;
    bool said_borrowed_ = false;
    bool said_depth_convention_ = false;
};

}  // namespace glcast::slave
