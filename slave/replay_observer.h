// The narrow hook between the replay core (decode, dispatch, name maps: slave/replayer.h) and
// the parts of a slave that adapt or watch the stream: tile adaptation (slave/tile_adapter.h),
// the injected passes and their scene (slave/effects_runner.h), `--verify`
// (slave/verifier.h) and the window system (slave/window_system.h). docs/architecture.md
// shows the order in which they run for one call.
#pragma once

#include <cstddef>
#include <cstdint>

namespace glcast {
struct Call;
struct CommandInfo;
}  // namespace glcast

namespace glcast::slave {

struct SlaveContext;

class ReplayObserver {
public:
    virtual ~ReplayObserver() = default;

    // Which calls this observer sees: asked once per opcode when it is added, so that calls no
    // observer wants cost the core nothing. `info` is null for synthetic tuples.
    virtual bool wants(uint32_t opcode, const CommandInfo* info) const = 0;
    // Whether it also sees the calls the injected passes replay again (Replayer::redispatch),
    // every one of them whatever wants() says: what adapts a call to the tile does; what records
    // or checks the program's stream does not.
    virtual bool adapts_redraws() const { return false; }

    // Before the call runs, with the tuple's raw bytes (recorders keep them).
    virtual void before_call(const Call& c, const uint8_t* tuple, size_t bytes) { (void)c, (void)tuple, (void)bytes; }
    // Replays `c` itself instead of the generated replay; true when it did. The first observer
    // that takes a call replays it.
    virtual bool replace_call(const Call& c) { (void)c; return false; }
    // After the call ran on the slave's driver.
    virtual void after_call(const Call& c) { (void)c; }

    // A context was made current with its window framebuffer; `first` the first time.
    virtual void made_current(SlaveContext& ctx, bool first) { (void)ctx, (void)first; }
    // The current context's frame is drawn, before it is read back and presented.
    virtual void end_frame(SlaveContext& ctx) { (void)ctx; }
    // ... and presented: what the window holds now is what the program's next frame draws over.
    virtual void presented(SlaveContext& ctx) { (void)ctx; }
    // The context `id` was destroyed.
    virtual void context_removed(uint32_t id) { (void)id; }
    // The slave starts over (every context is gone).
    virtual void reset() {}
};

}  // namespace glcast::slave
