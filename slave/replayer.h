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
#include "protocol/decoder.h"
#include "protocol/draw_range.h"
#include "protocol/size_queries.h"
#include "slave/backend.h"
#include "slave/effects/effect_params.h"
#include "slave/name_map.h"
#include "slave/replay_observer.h"
#include "slave/tile_mapping.h"
#include "slave/view_correction.h"

namespace glcast::slave {

namespace effects {
struct FrameView;
}  // namespace effects
class WindowSystem;
class TileAdapter;
class EffectsRunner;
class Verifier;

class ReplayError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The elements [first, end) a per-instance client array (divisor > 0) of the last
// glcast.client_arrays tuple holds.
struct ClientInstanceRange {
    uint32_t divisor = 1;
    int64_t first = 0, end = 0;
};

// One of the master's contexts on the slave: its names and what its window framebuffer is.
struct SlaveContext {
    uint32_t id = 0;
    uint64_t handle = 0;            // the master's driver handle
    ContextNames names;
    int width = 0, height = 0;      // its window framebuffer (the backend's default framebuffer)
    int master_width = 0, master_height = 0;  // the master's drawable
    bool double_buffered = true;
    bool made_current = false;
    uint64_t drawable = 0;
    bool drawing_to_window = true;  // the draw framebuffer is the window (tracked by TileAdapter)
    uint64_t current_program = 0;   // master name, for glUniform* locations
    uint32_t list_base = 0;         // glListBase, applied to glCallLists on the slave side
    // The window's draw and read buffers as the master named them (GL_BACK, ...; 0: never set):
    // the slave's driver holds its own window's (slave/special/framebuffers.cpp).
    uint32_t window_draw_buffer = 0, window_read_buffer = 0;
    std::map<uint32_t, std::vector<uint8_t>> client_arrays;  // by cache handle
    uint64_t client_array_bytes = 0;  // in client_arrays
    // The vertices [client_first, client_end) that every client array of the last
    // glcast.client_arrays tuple holds: the draw that follows it may read only those.
    bool client_range_pending = false;
    // The last glcast.client_arrays tuple was refused: the arrays may point at copies that are
    // gone, so the draw after it is refused too.
    bool client_arrays_refused = false;
    int64_t client_first = 0, client_end = 0;
    std::vector<ClientInstanceRange> client_instances;  // its per-instance arrays
    std::vector<uint8_t> select_buffer, feedback_buffer;
};

// What one stream may make the slave allocate or loop over (docs/slave.md "Limits of a
// stream", docs/security.md). A call over a limit is refused like any bad call: reported,
// counted, skipped. The defaults are far above what the committed captures and the test
// programs use, and far below what exhausts a slave.
struct ReplayLimits {
    uint64_t list_range = 1u << 20;          // glGenLists / glDeleteLists range
    uint64_t texture_dimension = 16384;      // width, height, depth of one texture image
    uint64_t buffer_bytes = 1ull << 30;      // size of one buffer's data store
    uint64_t client_array_bytes = 256u << 20;  // client-array copies kept per context
    uint64_t arena_retain_bytes = 16u << 20; // scratch blocks above this are freed after their call
    uint64_t drawable_dimension = 16384;     // width, height of a window framebuffer
    uint64_t contexts = 256;                 // contexts alive at once
    uint64_t list_entries = 1u << 20;        // pointer records of one string or index-array list
    uint64_t object_bytes = 4ull << 30;      // data stores of all live textures, buffers, renderbuffers
    uint64_t names = 1u << 22;               // live names of one kind in one share group (or context)
};

// The image of a texture a call replaces (commands.yaml slave.stores `image`), or its whole store.
constexpr uint64_t kWholeStore = ~0ull;
inline uint64_t store_key(uint32_t target, int32_t level) { return uint64_t(target) << 32 | uint32_t(level); }

// Sets one limit from "NAME=VALUE" (--limit); false with a message naming the limits, or the
// closest name, on an unknown NAME or a bad VALUE.
bool set_replay_limit(ReplayLimits& limits, const std::string& spec, std::string& error);
std::string replay_limit_names();  // "list_range=1048576, ..." with the current values' defaults

struct ReplayOptions {
    uint64_t first_frame = 0, last_frame = UINT64_MAX;
    int width = 0, height = 0;      // window framebuffer size override (0: the master's)
    bool verify = false;            // execute reply-only calls too and compare with the replies
    TileMapping tile;               // show one tile of a wall instead of the whole window
    ViewCorrection view;            // a rotated or asymmetric tile
    effects::EffectsSettings effects;  // injected passes run before each present (docs/effects.md)
    ReplayLimits limits;
};

struct ReplayStats {
    uint64_t frames = 0, calls = 0, replayed = 0, reply_only = 0, errors = 0, unserialized = 0;
    uint64_t verified = 0, mismatches = 0;
};

// How a name argument is used: looked up, created by the slave at first use (compatibility
// GL's bind-to-create, glNewList), or released.
enum class NameUse : uint8_t { Use, CreateAtFirstUse, Delete };

class Replayer {
public:
    Replayer(std::unique_ptr<Backend> backend, ReplayOptions options);
    ~Replayer();

    // Called after each swap with the finished window framebuffer (RGBA, rows top to bottom).
    std::function<void(uint64_t frame, int width, int height, const std::vector<uint8_t>& rgba)> on_frame;
    // Called once before the first call, with the slave current: lets tests allocate names.
    std::function<void(Replayer&)> on_first_context;
    // Called just before each frame is presented (the swap barrier waits here).
    std::function<void(uint64_t frame)> before_present;
    // Called after the injected passes of each frame, with the frame's view (tests of redraw).
    std::function<void(const effects::FrameView& view)> after_effects;

    void replay(MessageSource& source);  // throws DecodeError on a bad stream
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
    const GlApi& api() const { return api_; }

    // -- helpers for generated and hand-written replay functions ---------------------
    void* proc(uint32_t opcode);  // throws ReplayError when the slave's driver lacks it

    template <class T>
    T value(const Call& c, int i) const {
        const uint64_t bits = c.args[size_t(i)].bits;
        if constexpr (std::is_pointer_v<T>) {
            return reinterpret_cast<T>(uintptr_t(bits));
        } else if constexpr (std::is_floating_point_v<T>) {
            T v;
            std::memcpy(&v, &bits, sizeof v);
            return v;
        } else {
            return static_cast<T>(bits);
        }
    }
    template <class T>
    T name(Ns ns, const Call& c, int i, NameUse use = NameUse::Use) {
        const uint64_t v = map_name(ns, c.args[size_t(i)].bits, c, use);
        if constexpr (std::is_pointer_v<T>) return reinterpret_cast<T>(uintptr_t(v));
        else return static_cast<T>(v);
    }
    uint64_t map_name(Ns ns, uint64_t master, const Call& c, NameUse use = NameUse::Use);
    const void* names_in(Ns ns, const Call& c, int i, NameUse use);
    void map_generated(Ns ns, const Call& c, int i, const void* slave_names);
    void map_created(Ns ns, uint64_t master, uint64_t slave);
    void forget(Ns ns, uint64_t master);
    // `count` more names of `ns` would pass the limit `names`: the call is refused (every call
    // is bounded; without this their total is not: 200 glGenLists(1048576) in a 10 KB stream).
    void room_for_names(Ns ns, uint64_t count);
    void forget_names(Ns ns, const Call& c, int i);
    int32_t uniform_location(const Call& c, int i, uint64_t master_program);
    void set_uniform_location(uint64_t master_program, int32_t master, int32_t slave);

    // `binding` is the buffer binding query of a parameter that may be an offset into a bound
    // buffer (commands.yaml `source`); 0: it may not, and an Offset record is refused.
    const void* in(const Call& c, int i, uint32_t binding = 0);
    // An output the driver writes `elements` to, as the slave computes them (never the
    // stream's count): scratch memory of that size, or a range of the bound buffer.
    void* out(const Call& c, int i, uint32_t binding, int64_t elements);

    // -- checks before the call (slave/replay_checks.cpp), generated from the length
    // expressions the shim encodes with (codegen/annotations/commands.yaml) -----------------
    // The slave's answers to `sz.` (its own driver's state); failures are collected until
    // sized() refuses the call.
    SizeQueries& sizes();
    void sized(const Call& c);
    // Refuses an input record shorter than `elements`, a NULL one where the driver always
    // reads (all but commands.yaml slave.may_be_null), and an offset range outside the buffer bound at
    // `binding`.
    void need(const Call& c, int i, int64_t elements, bool null_ok = true, uint32_t binding = 0);
    // A generator writes `elements` names: the reply must hold exactly those.
    void need_reply(const Call& c, int i, int64_t elements) const;
    // A multi-draw's index arrays: drawcount of them, entry k holding bytes(k).
    void need_lists(const Call& c, int i, int64_t drawcount, const std::function<int64_t(int64_t)>& bytes);
    // A value over one of options().limits (commands.yaml slave.limits) is refused.
    void within(const Call& c, int i, uint64_t ReplayLimits::*limit, const char* limit_name) const;
    // The call (re)creates a data store of `bytes` for the object semantics.yaml `writes` names
    // (the image `key` of it, or kWholeStore): refused when the live objects' stores would pass
    // the limit object_bytes.
    void store(const Call& c, int64_t bytes, uint64_t key);
    // A draw over client arrays reads only the ranges the glcast.client_arrays tuple shipped.
    void check_draw(const Call& c, const DrawRange& range);
    // An offset record of argument i is used as a pointer only inside the buffer bound at
    // `binding`, [offset, offset + bytes) within its size.
    void check_offset(const Call& c, int i, uint32_t binding, uint64_t offset, int64_t bytes);
    void refuse_data_under_buffer(const Call& c, int i, uint32_t binding);

    const char* string(const Call& c, int i);
    const char* const* strings(const Call& c, int i);
    const void* const* index_arrays(const Call& c, int i);
    const void* deferred(const Call& c, int i);

    // --verify: compare what the slave's call produced with the master's reply (no-ops unless
    // the Verifier is checking this call).
    void check_reply(const Call& c, int i, const void* slave_output, int64_t slave_elements);
    void check_return(const Call& c, uint64_t slave_value);
    void check_return_string(const Call& c, const char* slave_value);

    // -- contexts (driven by the WindowSystem) -----------------------------------------
    SlaveContext& current();        // throws ReplayError when no context is current
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
    void* arena(size_t bytes);
    void release_arena();
    static void* resolve(void* self, uint32_t opcode);

    std::unique_ptr<Backend> backend_;
    ReplayOptions options_;
    ReplayStats stats_;
    GlApi api_;
    std::unique_ptr<SizeQueries> sizes_;  // ReplaySizeQueries over api_
    std::vector<std::vector<uint64_t>> arena_;  // per-call scratch, 8-byte aligned
    size_t arena_used_ = 0;
    bool arena_grown_ = false;          // a block above limits.arena_retain_bytes was used
    std::map<uint32_t, std::unique_ptr<SlaveContext>> contexts_;
    SlaveContext* current_ = nullptr;
    uint64_t frame_ = 0, call_index_ = 0;
    bool first_context_done_ = false;
    std::map<uint32_t, uint64_t> unserialized_seen_;

    // Observers, in the order they see a call; interest_[opcode] has bit i for observers_[i].
    std::unique_ptr<WindowSystem> window_system_;
    std::unique_ptr<TileAdapter> tile_;
    std::unique_ptr<EffectsRunner> effects_;
    std::unique_ptr<Verifier> verifier_;
    std::vector<ReplayObserver*> observers_;
    std::vector<uint8_t> interest_;       // by opcode
    uint8_t redraw_observers_ = 0;        // the bits of those that adapt redraws
    std::vector<uint8_t> synth_interest_;  // by synthetic opcode - kSynthBase
};

}  // namespace glcast::slave
