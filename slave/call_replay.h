// What the replay of one call may use, and all it may use: the generated functions
// (glcast_slave_dispatch.cpp) and the hand-written ones (slave/special/) see the slave through
// this, never the replay core's other parts (contexts, observers, frames). The replay core
// (slave/replayer.h) implements it; every pointer it hands out lives in the call's scratch
// memory (slave/scratch_memory.h) or in the decoded call, until the call is over.
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <type_traits>

#include "glcast_commands.h"
#include "glcast_gl_api.h"
#include "protocol/decoder.h"
#include "protocol/draw_range.h"
#include "protocol/size_queries.h"
#include "slave/name_map.h"
#include "slave/shader_patch.h"

namespace glcast::slave {

struct SlaveContext;
struct ReplayLimits;

// A call the slave refuses or cannot replay; reported with its frame and index, and skipped.
class ReplayError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// How a name argument is used: looked up, created by the slave at first use (compatibility
// GL's bind-to-create, glNewList), or released.
// How a call uses a name: AskAbout is glIs*'s, where a name never made is an answer (none), not an error.
enum class NameUse : uint8_t { Use, CreateAtFirstUse, Delete, AskAbout };

class CallReplay {
public:
    // -- the slave's driver ----------------------------------------------------------
    virtual const GlApi& api() const = 0;
    virtual void* proc(uint32_t opcode) = 0;  // throws ReplayError when the slave's driver lacks it
    virtual SlaveContext& current() = 0;      // throws ReplayError when no context is current
    virtual const ReplayLimits& limits() const = 0;
    // How this shader's source is patched before it reaches the driver: a rotated tile turns its
    // vertex positions, a tile maps its fragments' window coordinates (slave/tile_adapter.h).
    virtual ShaderPatch shader_patch(uint64_t master_shader) = 0;

    // -- values and names ------------------------------------------------------------
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
    virtual uint64_t map_name(Ns ns, uint64_t master, const Call& c, NameUse use = NameUse::Use) = 0;
    virtual const void* names_in(Ns ns, const Call& c, int i, NameUse use) = 0;
    virtual void map_generated(Ns ns, const Call& c, int i, const void* slave_names) = 0;
    virtual void map_created(Ns ns, uint64_t master, uint64_t slave) = 0;
    virtual void forget(Ns ns, uint64_t master) = 0;
    // `count` more names of `ns` would pass the limit `names`: the call is refused (every call
    // is bounded; without this their total is not: 200 glGenLists(1048576) in a 10 KB stream).
    virtual void room_for_names(Ns ns, uint64_t count) = 0;
    virtual void forget_names(Ns ns, const Call& c, int i) = 0;
    virtual int32_t uniform_location(const Call& c, int i, uint64_t master_program) = 0;
    virtual void set_uniform_location(uint64_t master_program, int32_t master, int32_t slave) = 0;

    // -- inputs and outputs ----------------------------------------------------------
    // `binding` is the buffer binding query of a parameter that may be an offset into a bound
    // buffer (commands.yaml `source`); 0: it may not, and an Offset record is refused.
    virtual const void* in(const Call& c, int i, uint32_t binding = 0) = 0;
    // An output the driver writes `elements` to, as the slave computes them (never the
    // stream's count): scratch memory of that size, or a range of the bound buffer.
    virtual void* out(const Call& c, int i, uint32_t binding, int64_t elements) = 0;
    virtual const char* string(const Call& c, int i) = 0;
    // Parameter i's strings, each NUL-terminated (null where the stream shipped none). With
    // `lengths` (the parameter of their lengths, or -1), a length over what the stream holds
    // of its string is refused (ReplayError): the driver would read that far.
    virtual const char* const* strings(const Call& c, int i, int lengths) = 0;
    virtual const void* const* index_arrays(const Call& c, int i) = 0;
    virtual const void* deferred(const Call& c, int i) = 0;

    // -- checks before the call (slave/replay_checks.cpp), generated from the length
    // expressions the shim encodes with (codegen/annotations/commands.yaml) -----------------
    // The slave's answers to `sz.` (its own driver's state); failures are collected until
    // sized() refuses the call.
    virtual SizeQueries& sizes() = 0;
    virtual void sized(const Call& c) = 0;
    // Refuses an input record shorter than `elements`, a NULL one where the driver always
    // reads (all but commands.yaml slave.may_be_null), and an offset range outside the buffer
    // bound at `binding`.
    virtual void need(const Call& c, int i, int64_t elements, bool null_ok = true, uint32_t binding = 0) = 0;
    // A generator writes `elements` names: the reply must hold exactly those.
    virtual void need_reply(const Call& c, int i, int64_t elements) const = 0;
    // A multi-draw's index arrays: drawcount of them, entry k holding bytes(k).
    virtual void need_lists(const Call& c, int i, int64_t drawcount, const std::function<int64_t(int64_t)>& bytes) = 0;
    // A value over one of the limits (commands.yaml slave.limits) is refused.
    virtual void within(const Call& c, int i, uint64_t ReplayLimits::*limit, const char* limit_name) const = 0;
    // The call (re)creates a data store of `bytes` for the object semantics.yaml `writes` names
    // (the image `key` of it, or kWholeStore): refused when the live objects' stores would pass
    // the limit object_bytes.
    virtual void store(const Call& c, int64_t bytes, uint64_t key) = 0;
    // A draw over client arrays reads only the ranges the glcast.client_arrays tuple shipped.
    virtual void check_draw(const Call& c, const DrawRange& range) = 0;

    // -- --verify: what the slave's call produced against the master's reply (no-ops unless
    // the call is being verified) ----------------------------------------------------
    virtual void check_reply(const Call& c, int i, const void* slave_output, int64_t slave_elements) = 0;
    virtual void check_return(const Call& c, uint64_t slave_value) = 0;
    virtual void check_return_string(const Call& c, const char* slave_value) = 0;

protected:
    ~CallReplay() = default;
};

}  // namespace glcast::slave
