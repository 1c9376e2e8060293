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

#include "glcast_gl_api.h"
#include "slave/replay_observer.h"

namespace glcast::slave {
class Replayer;
struct ShareGroup;
}  // namespace glcast::slave

namespace glcast::keeper {

using Tuple = std::vector<uint8_t>;

struct ContextCalls {
    Tuple create;        // glXCreateContext*, eglCreateContext: the request the slave follows
    Tuple format;        // glcast.context_format and glcast.context_bits where sent, one after the other
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

// A shader's type and its source as the driver holds it (for the keeper's own shader names).
LinkedShader read_shader(const GlApi& gl, uint32_t shader);

// The calls since the last glLoadIdentity or glLoadMatrix that made one entry of a matrix
// stack: replayed after glLoadIdentity they give the same numbers and, for a driver that keeps
// what kind of matrix it holds (Mesa multiplies rotations, perspectives and general matrices
// by different code, rounding differently), the same kind; glLoadMatrix would not.
struct MatrixRecipe {
    Tuple calls;
    bool known = true;  // false: a display list changed it, or too many calls to keep
};

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
    // The modelview or projection stack of a context, bottom first; null: not followed.
    const std::vector<MatrixRecipe>* matrices(uint32_t context, uint32_t mode) const;
    uint64_t bytes() const;  // held for the snapshot

private:
    struct Recording {
        uint64_t list = 0;
        bool execute = false;  // GL_COMPILE_AND_EXECUTE
        Tuple body;
    };
    struct Matrices {
        uint32_t mode = GL_MODELVIEW;
        std::vector<MatrixRecipe> modelview = std::vector<MatrixRecipe>(1), projection = std::vector<MatrixRecipe>(1);
        std::vector<MatrixRecipe>* stack() { return mode == GL_MODELVIEW ? &modelview : mode == GL_PROJECTION ? &projection : nullptr; }
    };
    void follow_matrices(const Call& c, uint32_t context);
    static constexpr size_t kDrawablesKept = 16;  // sizes kept of drawables no context is on
    slave::Replayer& core_;
    std::map<uint32_t, ContextCalls> contexts_;
    std::map<uint64_t, Tuple> pending_create_;  // by the driver handle it returned
    std::map<uint64_t, Tuple> pending_format_;  // glcast.context_format, by handle
    std::map<uint64_t, Tuple> pending_bits_;    // glcast.context_bits, by handle
    std::map<uint64_t, Tuple> drawable_sizes_;  // by drawable
    std::map<std::shared_ptr<slave::ShareGroup>, ListBodies> lists_;
    std::map<std::shared_ptr<slave::ShareGroup>, LinkedPrograms> linked_;
    std::map<uint32_t, Recording> recording_;   // by context id: a list being compiled
    std::map<uint32_t, Matrices> matrices_;     // by context id
    std::map<std::shared_ptr<slave::ShareGroup>, std::map<uint64_t, bool>> list_matrices_;  // lists that touch matrices
    const uint8_t* last_tuple_ = nullptr;
    size_t last_bytes_ = 0;
};

}  // namespace glcast::keeper
