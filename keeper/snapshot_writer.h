// The snapshot writer's shared parts (keeper/snapshot.cpp orders the work; snapshot_objects.cpp
// reads objects, snapshot_context.cpp a context's state). Not for use outside keeper/.
#pragma once

#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "glcast_gl_api.h"
#include "keeper/kept_calls.h"
#include "keeper/snapshot.h"
#include "keeper/snapshot_sizes.h"
#include "master/encoder.h"
#include "slave/replayer.h"

namespace glcast::keeper {

class SnapshotWriter {
public:
    SnapshotWriter(slave::Replayer& keeper, const KeptCalls& kept, const TupleOut& out);
    SnapshotReport write();

private:
    // -- output -------------------------------------------------------------------------
    void flush();                                        // hands the encoded tuples to out_
    void raw(const Tuple& tuples, uint32_t context = 0); // kept tuples; context != 0 rewrites theirs
    void missing(const std::string& what) { report_.missing.push_back(what); }

    // -- the keeper's side ----------------------------------------------------------------
    void read_in(slave::SlaveContext& ctx);  // the keeper reads ctx's state; tuples go to ctx
    uint64_t master_name(slave::SlaveContext& ctx, Ns ns, uint64_t slave_name);  // 0: none
    GLint integer(GLenum pname);                // glGetIntegerv; 0 when the driver refuses it
    bool query(GLenum pname, GLint& out);        // false when the driver refuses it
    bool asked();  // the last query was accepted (clears the error)

    // -- objects of a share group (snapshot_objects.cpp) --------------------------------------
    void share_group(slave::SlaveContext& ctx);
    void buffers(slave::SlaveContext& ctx);
    void textures(slave::SlaveContext& ctx);
    void texture_images(GLenum target, uint64_t master);  // of the bound texture
    void renderbuffers(slave::SlaveContext& ctx);
    void renderbuffer_contents(GLuint slave_name, GLuint master, GLenum internal, GLint w, GLint h);
    void samplers(slave::SlaveContext& ctx);
    void programs(slave::SlaveContext& ctx);
    void program(slave::SlaveContext& ctx, GLuint slave_name, uint64_t master);
    void uniforms(slave::SlaveContext& ctx, GLuint slave_name, uint64_t master);
    void lists(slave::SlaveContext& ctx);
    void syncs(slave::SlaveContext& ctx);

    // -- one context (snapshot_context.cpp) -----------------------------------------------
    void window_contents(slave::SlaveContext& ctx);
    void context_objects(slave::SlaveContext& ctx);
    void objects_not_held(slave::SlaveContext& ctx);  // reported missing by name
    void framebuffer(slave::SlaveContext& ctx);  // the bound one
    void vertex_arrays(slave::SlaveContext& ctx);  // of the bound vertex array object
    void context_state(slave::SlaveContext& ctx);
    bool compatibility();
    void matrices(slave::SlaveContext& ctx);
    void bindings(slave::SlaveContext& ctx);
    void window_buffers(slave::SlaveContext& ctx);
    void client_array_cache(slave::SlaveContext& ctx);
    void upload_state();  // the unpack state the snapshot's uploads assume

    slave::Replayer& keeper_;
    const GlApi& gl_;
    const KeptCalls& kept_;
    const TupleOut& out_;
    ByteVector buf_;
    Encoder e_;
    SnapshotSizeQueries sz_;
    SnapshotReport report_;
    // slave name -> master name, per namespace, of the share group or context being written
    std::map<std::pair<const void*, int>, std::unordered_map<uint64_t, uint64_t>> reverse_;
    std::map<std::pair<const void*, GLuint>, GLenum> texture_targets_;  // share group, keeper's name
    uint32_t next_temporary_ = 0;
};

// Master names the snapshot uses for objects the program no longer names (a shader deleted
// while attached): created and deleted again within the snapshot, above any name GL hands out
// in practice.
inline constexpr uint32_t kTemporaryNameBase = 0xFFF00000u;

}  // namespace glcast::keeper
