// The slave's replay engine: turns decoded tuples back into GL calls on the slave's own
// contexts (design.md 5). Generated per-opcode functions (glcast_slave_dispatch.cpp) use the
// argument helpers below; hand-written ones live in slave/special/.
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
#include "glcast_slave_dispatch.h"
#include "protocol/decoder.h"
#include "slave/backend.h"
#include "slave/effects/effect_params.h"
#include "slave/name_map.h"
#include "slave/tile_mapping.h"
#include "slave/view_correction.h"

namespace glcast::slave {

struct EffectsState;  // slave/effects_frame.h
namespace effects {
struct GlApi;
struct FrameView;
}  // namespace effects

class ReplayError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SlaveContext {
    uint32_t id = 0;
    uint64_t handle = 0;            // the master's driver handle
    ContextNames names;
    int width = 0, height = 0;      // its window framebuffer (the backend's default framebuffer)
    bool double_buffered = true;
    bool made_current = false;
    uint64_t drawable = 0;
    uint64_t current_program = 0;   // master name, for glUniform* locations
    uint32_t list_base = 0;         // glListBase, applied to glCallLists on the slave side
    std::map<uint32_t, std::vector<uint8_t>> client_arrays;  // by cache handle
    std::vector<uint8_t> select_buffer, feedback_buffer;
    // The program's own viewport and scissor box (window coordinates of the master), applied
    // mapped while the window framebuffer is the draw framebuffer and as they are otherwise.
    int32_t viewport[4] = {0, 0, 0, 0}, scissor[4] = {0, 0, 0, 0};
    int master_width = 0, master_height = 0;  // the master's drawable
    bool drawing_to_window = true;
    // Projection correction of rotated tiles, one entry per GL_PROJECTION stack level: whether
    // the level holds M * P_app, whether the program changed it since (relative to M * P_app),
    // and the M it holds.
    struct Projection {
        bool corrected = false, dirty = false;
        glm::dmat4 m{1.0};
    };
    std::vector<Projection> projection = std::vector<Projection>(1);
    uint32_t matrix_mode = 0x1700;  // GL_MODELVIEW
    std::unique_ptr<EffectsState> effects;  // with --effects: the passes and the frame's record
    SlaveContext();
    ~SlaveContext();  // where EffectsState is complete
};

struct ReplayOptions {
    uint64_t first_frame = 0, last_frame = UINT64_MAX;
    int width = 0, height = 0;      // window framebuffer size override (0: the master's)
    bool verify = false;            // execute reply-only calls too and compare with the replies
    TileMapping tile;               // show one tile of a wall instead of the whole window
    ViewCorrection view;            // a rotated or asymmetric tile (fixed-function programs)
    effects::EffectsSettings effects;  // injected passes run before each present (design.md 6)
};

struct ReplayStats {
    uint64_t frames = 0, calls = 0, replayed = 0, reply_only = 0, errors = 0, unserialized = 0;
    uint64_t verified = 0, mismatches = 0;
};

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
    // Forgets every context and name: the state of a slave that has seen nothing yet (a slave
    // that lost messages starts over from the master's snapshot).
    void reset();
    const ReplayStats& stats() const { return stats_; }
    Backend& backend() { return *backend_; }

    // -- helpers for generated and hand-written replay functions ---------------------
    void* proc(uint32_t opcode);
    template <class Fn>
    Fn gl(uint32_t opcode) { return reinterpret_cast<Fn>(proc(opcode)); }

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
    T name(Ns ns, const Call& c, int i) {
        return to_name<T>(map_name(ns, c.args[size_t(i)].bits, c));
    }
    uint64_t map_name(Ns ns, uint64_t master, const Call& c);
    const void* names_in(Ns ns, const Call& c, int i);
    void map_generated(Ns ns, const Call& c, int i, const void* slave_names);
    void map_created(Ns ns, uint64_t master, uint64_t slave);
    void forget(Ns ns, uint64_t master);
    void forget_names(Ns ns, const Call& c, int i);
    int32_t uniform_location(const Call& c, int i, uint64_t master_program);
    void set_uniform_location(uint64_t master_program, int32_t master, int32_t slave);

    const void* in(const Call& c, int i);
    void* out(const Call& c, int i);
    const char* string(const Call& c, int i);
    const char* const* strings(const Call& c, int i);
    const void* const* index_arrays(const Call& c, int i);
    const void* deferred(const Call& c, int i);

    // --verify: compare what the slave's call produced with the master's reply.
    void check_reply(const Call& c, int i, const void* slave_output);
    void check_return(const Call& c, uint64_t slave_value);
    void check_return_string(const Call& c, const char* slave_value);

    const TileMapping& tile() const { return options_.tile; }
    const ViewCorrection& view() const { return options_.view; }
    // Re-issues the program's viewport and scissor box for the current draw framebuffer.
    void apply_window_rects();

    SlaveContext& current();        // throws ReplayError when no context is current
    // Creates n objects of every namespace in the current context and keeps them, so that the
    // slave's names differ from the master's from then on (tests of the name maps).
    void keep_own_objects(int n);
    SlaveContext* current_or_null() { return current_; }
    uint64_t frame() const { return frame_; }
    uint64_t call_index() const { return call_index_; }

private:
    template <class T>
    static T to_name(uint64_t v) {
        if constexpr (std::is_pointer_v<T>) return reinterpret_cast<T>(uintptr_t(v));
        else return static_cast<T>(v);
    }
    void* arena(size_t bytes);
    void dispatch(const Call& c);
    void follow_context(const Call& c);
    void track_matrix_call(const Call& c);
    void correct_projection();
    void correct_shader_program(uint32_t program);
    void window_system(const Call& c);
    void synthetic(const Call& c);
    void client_arrays(const Call& c);
    void buffer_write(const Call& c);
    void make_current(uint32_t id, uint64_t drawable);
    void window_size(uint64_t drawable, int& width, int& height) const;
    void end_frame();
    // Injected passes (slave/effects_frame.cpp).
    void record_for_effects(const Call& c);
    void run_effects();
    void redraw_main_view(const glm::dmat4& correction);
    void frame_view(SlaveContext& ctx, effects::FrameView& view);
    unsigned window_copy(SlaveContext& ctx, bool depth);  // a GL texture name
    glm::dmat4 program_projection_now();
    uint32_t auto_create(Ns ns);
    void report(const std::string& what);
    void mismatch(const Call& c, const std::string& what);
    bool checking_ = false;

    std::unique_ptr<Backend> backend_;
    ReplayOptions options_;
    ReplayStats stats_;
    std::vector<void*> procs_;
    std::vector<std::vector<uint64_t>> arena_;  // per-call scratch, 8-byte aligned
    size_t arena_used_ = 0;
    std::map<uint32_t, std::unique_ptr<SlaveContext>> contexts_;
    std::map<uint64_t, ContextRequest> pending_;  // creation requests by master handle
    std::map<uint64_t, uint32_t> ids_by_handle_;
    SlaveContext* current_ = nullptr;
    std::map<uint64_t, std::pair<int, int>> drawable_sizes_;
    uint64_t frame_ = 0, call_index_ = 0;
    bool first_context_done_ = false;
    std::map<uint32_t, uint64_t> unserialized_seen_;
    std::unique_ptr<effects::GlApi> effects_gl_;  // loaded at the first frame with effects
    bool redrawing_ = false;
    glm::dmat4 redraw_correction_{1.0};
    const uint8_t* tuple_bytes_ = nullptr;  // the raw tuple being replayed, for the frame record
    size_t tuple_size_ = 0;
};

}  // namespace glcast::slave
