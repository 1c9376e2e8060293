// The slave's replay core: turns decoded tuples back into GL calls on the slave's own contexts.
// It decodes, dispatches (generated per-opcode functions, glcast_slave_dispatch.cpp, and the
// hand-written ones of slave/special/) and maps object names; everything that adapts the
// stream to a tile or watches it hooks in as a ReplayObserver (slave/replay_observer.h):
//
//   WindowSystem   contexts, drawables, frames (slave/window_system.h)
//   TileAdapter    viewports, pixel sizes and projections on a tile (slave/tile_adapter.h)
//   EffectsRunner  the frame's scene for the injected passes, and running them (slave/effects_runner.h)
//   Verifier       `--verify`: reply-only calls re-asked and compared (slave/verifier.h)
//
// Errors in one call (a name never generated, a deferred array never sent, a context that
// does not exist) throw ReplayError; the loop reports it with frame and call index, counts
// it, and goes on with the next call.
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "glcast_commands.h"
#include "glcast_gl_api.h"
#include "glcast_slave_dispatch.h"
#include "common/image.h"
#include "slave/call_replay.h"
#include "slave/replay_limits.h"
#include "slave/slave_context.h"
#include "protocol/decoder.h"
#include "protocol/draw_range.h"
#include "protocol/size_queries.h"
#include "slave/replay_sizes.h"
#include "slave/backend.h"
#include "slave/effects/effect_params.h"
#include "slave/name_map.h"
#include "slave/projector_warp.h"
#include "slave/replay_observer.h"
#include "slave/scratch_memory.h"
#include "slave/tile_mapping.h"
#include "slave/view_correction.h"
#include "slave/viewer.h"

namespace glcast::slave {

namespace effects {
struct FrameView;
}  // namespace effects
class WindowSystem;
class TileAdapter;
class EffectsRunner;
class Verifier;

struct ReplayOptions {
    uint64_t first_frame = 0, last_frame = UINT64_MAX;
    int width = 0, height = 0;      // window framebuffer size override (0: the master's)
    bool verify = false;            // execute reply-only calls too and compare with the replies
    TileMapping tile;               // show one tile of a wall instead of the whole window
    ViewCorrection view;            // a rotated or asymmetric tile
    Viewer viewer;                  // an immersive wall's viewer: view.eye is its eye
    StereoMode stereo = StereoMode::none;  // both eyes in one output: replayed by a StereoPair
    effects::EffectsSettings effects;  // injected passes run before each present (docs/effects.md)
    std::shared_ptr<const ProjectorMaps> projector;  // a projector's warp and blend, last before present
    ReplayLimits limits;
    std::string scene_report_dir;  // write what the passes took each frame for here (scene_report.h)
};

struct ReplayStats {
    uint64_t frames = 0, calls = 0, replayed = 0, reply_only = 0, errors = 0, unserialized = 0;
    uint64_t verified = 0, mismatches = 0;
};

class Replayer final : public CallReplay {
public:
    Replayer(std::unique_ptr<Backend> backend, ReplayOptions options);
    ~Replayer();

    // Called after each swap with the finished window framebuffer (RGBA, rows top to bottom). The
    // buffer is the replayer's: a callback may swap it for one of the same size to keep the image.
    std::function<void(uint64_t frame, int width, int height, std::vector<uint8_t>& rgba)> on_frame;
    // Called once before the first call, with the slave current: lets tests allocate names.
    std::function<void(Replayer&)> on_first_context;
    // Instead of on_frame: called with the frame drawn and its context current, to read it back
    // itself (a stereo tile's eye, straight into its half of the tile's image).
    std::function<void(uint64_t frame, int width, int height, GLenum buffer)> on_frame_drawn;
    // Called just before each frame is presented (the swap barrier waits here).
    std::function<void(uint64_t frame)> before_present;
    // Called just after each frame was presented (when it was shown: docs/wall.md's timing).
    std::function<void(uint64_t frame)> after_present;
    // Called before the first call of each frame, with its number (a tracked viewer's pose).
    std::function<void(uint64_t frame)> before_frame;
    // Called after the injected passes of each frame, with the frame's view (tests of redraw).
    std::function<void(const effects::FrameView& view)> after_effects;

    void replay(MessageSource& source);  // throws DecodeError on a bad stream
    // One message of it; false once past options().last_frame. Two replayers may take turns on
    // one thread (the two eyes of a stereo tile, slave/stereo.h): each resume()s first, which
    // makes its current context current again.
    bool replay_message(const Message& m);
    void resume();
    // Adds an observer after the slave's own (at most kMaxObservers in all; one more throws
    // std::logic_error): a keeper's (keeper/kept_calls.h).
    void watch(ReplayObserver* observer) { add_observer(observer); }
    static constexpr size_t kMaxObservers = 8;  // the bits of an opcode's interest mask
    const std::map<uint32_t, std::unique_ptr<SlaveContext>>& contexts() const { return contexts_; }
    // Forgets every context and name: the state of a slave that has seen nothing yet (a slave
    // that lost messages starts over from the master's snapshot).
    void reset();
    const ReplayStats& stats() const { return stats_; }
    ReplayStats& stats() { return stats_; }
    Backend& backend() { return *backend_; }
    const ReplayOptions& options() const { return options_; }
    // Switches passes and parameters between two frames (slave/live_effects.h); needs a replay
    // started with effects.live or some pass on.
    void set_effects(const effects::EffectsSettings& settings);
    // The current context's frame as it will be shown (rows top to bottom); false: nothing drawn.
    bool read_shown(Image& out);
    // Moves the viewer (head pose, eye separation): the tile's eye follows from the next draw.
    // False, nothing changed, for an eye the tile cannot have (behind its screen, not finite).
    bool set_viewer(const Viewer& viewer);
    // Moves the viewer's head (and eye separation, when the pose gives one) to `head`; nothing to
    // do when it is there already. False: refused, as set_viewer.
    bool move_head(const HeadPose& head);
    const GlApi& api() const override { return api_; }
    const ReplayLimits& limits() const override { return options_.limits; }
    ShaderPatch shader_patch(uint64_t master_shader) override;

    // -- CallReplay: what generated and hand-written replay functions use (slave/call_replay.h)
    void* proc(uint32_t opcode) override;
    uint64_t map_name(Ns ns, uint64_t master, const Call& c, NameUse use = NameUse::Use) override;
    const void* names_in(Ns ns, const Call& c, int i, NameUse use) override;
    void map_generated(Ns ns, const Call& c, int i, const void* slave_names) override;
    void map_created(Ns ns, uint64_t master, uint64_t slave) override;
    void forget(Ns ns, uint64_t master) override;
    void room_for_names(Ns ns, uint64_t count) override;
    void forget_names(Ns ns, const Call& c, int i) override;
    int32_t uniform_location(const Call& c, int i, uint64_t master_program) override;
    void set_uniform_location(uint64_t master_program, int32_t master, int32_t slave) override;
    const void* in(const Call& c, int i, uint32_t binding = 0) override;
    void* out(const Call& c, int i, uint32_t binding, int64_t elements) override;
    const char* string(const Call& c, int i) override;
    const char* const* strings(const Call& c, int i, int lengths) override;
    const void* const* index_arrays(const Call& c, int i) override;
    const void* deferred(const Call& c, int i) override;
    SizeQueries& sizes() override;
    void sized(const Call& c) override;
    void need(const Call& c, int i, int64_t elements, bool null_ok = true, uint32_t binding = 0) override;
    void need_reply(const Call& c, int i, int64_t elements) const override;
    void need_lists(const Call& c, int i, int64_t drawcount, const std::function<int64_t(int64_t)>& bytes) override;
    void within(const Call& c, int i, uint64_t ReplayLimits::*limit, const char* limit_name) const override;
    void store(const Call& c, int64_t bytes, uint64_t key) override;
    void check_draw(const Call& c, const DrawRange& range) override;
    void check_reply(const Call& c, int i, const void* slave_output, int64_t slave_elements) override;
    void check_return(const Call& c, uint64_t slave_value) override;
    void check_return_string(const Call& c, const char* slave_value) override;

    // -- contexts (driven by the WindowSystem) -----------------------------------------
    SlaveContext& current() override;  // throws ReplayError when no context is current
    SlaveContext* current_or_null() { return current_; }
    SlaveContext* context(uint32_t id);
    SlaveContext& add_context(uint32_t id, uint64_t handle, uint32_t share_id, const ContextRequest& request);
    void remove_context(uint32_t id);
    // Makes context `id` current with a window framebuffer of width x height (0: release).
    void make_current(uint32_t id, uint64_t drawable, int width, int height);
    // The current context's frame is complete: observers, readback, present, next frame.
    void finish_frame();

    // Creates n objects of every namespace in the current context and keeps them, so that the
    // slave's names differ from the master's from then on (tests of the name maps).
    void keep_own_objects(int n);
    uint64_t frame() const { return frame_; }
    // The name a call gets for one the stream never made: no object of the slave's driver has it.
    static constexpr uint64_t kNoObjectName = 0xffffffffu;
    // The frame the next swap ends: a slave that joined from a snapshot of the master's frame N
    // counts from N, as the master does.
    void set_frame(uint64_t frame) { frame_ = frame; }
    uint64_t call_index() const { return call_index_; }
    void report(const std::string& what);

    TileAdapter& tile_adapter() { return *tile_; }
    // Replays one call through the generated or hand-written function and the observers that
    // adapt redraws (ReplayObserver::adapts_redraws: tile adaptation), without recording or
    // verifying it: the injected passes' redraw of recorded calls.
    void redispatch(const Call& c);

private:
    // An offset record of argument i is used as a pointer only inside the buffer bound at
    // `binding`, [offset, offset + bytes) within its size.
    void check_offset(const Call& c, int i, uint32_t binding, uint64_t offset, int64_t bytes);
    void refuse_data_under_buffer(const Call& c, int i, uint32_t binding);
    void add_observer(ReplayObserver* o);
    void dispatch(const Call& c, const uint8_t* tuple, size_t bytes);
    // The observers of `mask` before, instead of (first taker) and after `run`.
    template <class Run>
    void observe(const Call& c, const uint8_t* tuple, size_t bytes, uint8_t mask, Run&& run);
    void run_default(const Call& c);
    void follow_context(const Call& c);
    void synthetic(const Call& c);
    void client_arrays(const Call& c);
    void release_store(SlaveContext& ctx, Ns ns, uint64_t master);  // the object is deleted
    uint64_t live_store_bytes() const;
    void buffer_write(const Call& c);
    static void* resolve(void* self, uint32_t opcode);

    std::unique_ptr<Backend> backend_;
    ReplayOptions options_;
    ReplayStats stats_;
    GlApi api_;
    void used_program(uint64_t master);  // glUseProgram's: a program deleted in use goes now
    bool said_name_never_made_ = false;
    bool redrawing_ = false;  // running recorded calls again for the passes (redispatch)
    std::unique_ptr<ReplaySizeQueries> sizes_;  // over api_
    ScratchMemory scratch_;               // the current call's
    std::map<uint32_t, std::unique_ptr<SlaveContext>> contexts_;
    SlaveContext* current_ = nullptr;
    uint64_t frame_ = 0, call_index_ = 0;
    uint64_t frame_begun_ = UINT64_MAX;  // the frame before_frame was last called for
    std::vector<uint8_t> frame_rgba_, frame_scratch_;  // the frame read back for on_frame, kept for the next
    bool first_context_done_ = false;
    std::map<uint32_t, uint64_t> unserialized_seen_;

    // Observers, in the order they see a call; interest_[opcode] has bit i for observers_[i].
    std::unique_ptr<WindowSystem> window_system_;
    std::unique_ptr<TileAdapter> tile_;
    std::unique_ptr<EffectsRunner> effects_;
    std::unique_ptr<ProjectorWarp> projector_;
    std::unique_ptr<Verifier> verifier_;
    std::vector<ReplayObserver*> observers_;
    std::vector<uint8_t> interest_;       // by opcode
    uint8_t redraw_observers_ = 0;        // the bits of those that adapt redraws
    std::vector<uint8_t> synth_interest_;  // by synthetic opcode - kSynthBase
};

}  // namespace glcast::slave
