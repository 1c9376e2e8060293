// What a snapshot of live state cannot read back from the keeper's driver, kept from the stream
// as the tuples that made it (docs/keeper.md): the calls that created each live context and made
// it current on its drawable, and the contents of each live display list (GL has no query for
// either). What it holds is bounded by the live contexts, drawables and lists, never by the
// length of the run: a list deleted or compiled again, a context destroyed, frees its tuples.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "slave/replay_observer.h"

namespace glcast::slave {
class Replayer;
struct ShareGroup;
}  // namespace glcast::slave

namespace glcast::keeper {

using Tuple = std::vector<uint8_t>;

struct ContextCalls {
    Tuple create;        // glXCreateContext*, eglCreateContext: the request the slave follows
    Tuple context;       // glcast.context: id, handle, share group
    Tuple make_current;  // the last call that made it current (empty: never made current)
    uint64_t handle = 0;
};

// Display lists of one share group: master name -> the tuples between glNewList and glEndList.
using ListBodies = std::map<uint64_t, Tuple>;

// The shaders a program was last linked with (type, source): programs often detach or delete
// their shaders after linking, and GL keeps no source for the executable it linked.
struct LinkedShader {
    uint32_t type = 0;
    std::string source;
};
using LinkedPrograms = std::map<uint64_t, std::vector<LinkedShader>>;  // by master program name

class KeptCalls : public slave::ReplayObserver {
public:
    explicit KeptCalls(slave::Replayer& core) : core_(core) {}

    bool wants(uint32_t opcode, const CommandInfo* info) const override;
    void before_call(const Call& c, const uint8_t* tuple, size_t bytes) override;
    void after_call(const Call& c) override;
    void reset() override;

    const std::map<uint32_t, ContextCalls>& contexts() const { return contexts_; }
    const std::map<uint64_t, Tuple>& drawable_sizes() const { return drawable_sizes_; }
    const ListBodies* lists(const slave::ShareGroup* group) const;
    const std::vector<LinkedShader>* linked(const slave::ShareGroup* group, uint64_t program) const;
    uint64_t bytes() const;  // held for the snapshot

private:
    struct Recording {
        uint64_t list = 0;
        Tuple body;
    };
    slave::Replayer& core_;
    std::map<uint32_t, ContextCalls> contexts_;
    std::map<uint64_t, Tuple> pending_create_;  // by the driver handle it returned
    std::map<uint64_t, Tuple> drawable_sizes_;  // by drawable
    std::map<std::shared_ptr<slave::ShareGroup>, ListBodies> lists_;
    std::map<std::shared_ptr<slave::ShareGroup>, LinkedPrograms> linked_;
    std::map<uint32_t, Recording> recording_;   // by context id: a list being compiled
    const uint8_t* last_tuple_ = nullptr;
    size_t last_bytes_ = 0;
};

}  // namespace glcast::keeper
