// Per call, per context: keeps in the frame's record what a pass may redraw (frame_record.h)
// and tells the scene classifier (scene_classifier.h) about each draw, so that at the frame's
// end the scene, its camera and where its overlays begin are known. Scenes lent between
// contexts go through SceneLending (scene_lending.h).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "protocol/command_info.h"
#include "slave/program_camera.h"
#include "slave/scene/frame_record.h"
#include "slave/scene/scene_classifier.h"
#include "slave/scene/scene_lending.h"

namespace glcast {
struct Call;
class GlApi;
}

namespace glcast::slave {

class Replayer;
class TileAdapter;
struct SlaveContext;

// One context's scene in the frame being replayed.
constexpr uint64_t kNeverPresented = UINT64_MAX;
constexpr uint64_t kLendsAfterFrames = 2;

struct ContextScene {
    FrameRecord record;
    SceneFacts facts;
    SceneLoan loan;
    // The frame this context presented last: one that presents may not lend its scene. A toolkit's
    // offscreen context may present once when it is made (Blender's draw manager's hidden window):
    // it lends from kLendsAfterFrames frames later.
    uint64_t last_present = kNeverPresented;
    bool presents(uint64_t frame) const { return last_present != kNeverPresented && frame <= last_present + kLendsAfterFrames; }
    BorrowerObjects borrower;  // GL objects, kept across frames
    FollowedState followed;    // the draw state the program's calls set, across frames
    void next_frame() {  // the record, the facts and the loan start over
        record.clear();
        facts = SceneFacts{};
        loan = SceneLoan{};
    }
};

class SceneRecorder {
public:
    SceneRecorder(Replayer& core, TileAdapter& tile) : core_(core), tile_(tile), lending_(core, tile, scenes_) {}

    // Called when a draw to the window, or a clear of its depth, starts the overlays, before it
    // runs: the window then holds the scene alone (the effects runner copies it, and its depth
    // when it is about to be cleared).
    std::function<void(SlaveContext&)> on_overlays_start;
    // Called before the first overlay drawn into the scene's framebuffer object (SceneFacts::target_overlay).
    std::function<void(SlaveContext&)> on_target_overlays_start;
    // Called before the first draw that writes the scene's depth from another target
    // (SceneFacts::scene_depth_kept): the scene's depth is to be kept as it is now.
    std::function<void(SlaveContext&)> on_scene_depth_shared;
    // Called before the first draw over the main view's surfaces (its marks, SceneFacts::marks, or
    // a translucent draw, ::translucent), as DrawVerdict says: the scene's depth (`keeps_depth`)
    // and, for marks, colour (`marks_start`), the window's or its target's, are to be kept as they
    // are now; and when a surface of the view ends them (`over_end`): what was kept is no longer
    // the scene.
    std::function<void(SlaveContext&, const DrawVerdict&)> on_over_scene;

    // Before each call the replay runs on the current context `ctx`.
    void record(SlaveContext& ctx, const Call& c, const uint8_t* tuple, size_t bytes);
    // After it ran: the draw state it set.
    void follow(SlaveContext& ctx, const Call& c);
    // The frame of `ctx` is drawn, before the passes run: a borrowed scene's draw is placed.
    void frame_drawn(SlaveContext& ctx);
    // ... and decorated: contexts that never present keep a scene they lend for the frames
    // that show it again (until they draw the next) and let go of anything else they
    // recorded, so that their records hold at most one frame's calls.
    void frame_decorated(SlaveContext& ctx);

    ContextScene& scene(const SlaveContext& ctx);
    const ContextScene& scene_shown(const SlaveContext& ctx) { return lending_.scene_of(scene(ctx)); }
    SceneLending& lending() { return lending_; }
    void forget(uint32_t id) { scenes_.erase(id); }
    void reset() { scenes_.clear(); }

private:
    ClassifierSettings settings(const SlaveContext& ctx) const;

    Replayer& core_;
    TileAdapter& tile_;
    ContextScenes scenes_;  // by context id
    SceneLending lending_;
};

}  // namespace glcast::slave
