// The order of a snapshot (docs/keeper.md "What a snapshot holds"): contexts and their window
// framebuffers first, then the objects of each share group, then each context's own objects and
// state, the program's pixel store and current context last, so that nothing the snapshot does
// to upload an object is left behind in the state it recreates.
#include "keeper/snapshot.h"

#include <algorithm>
#include <cstring>

#include "glcast_encode.h"

#include "keeper/snapshot_writer.h"
#include "protocol/format.h"

namespace glcast::keeper {

namespace {

// The keeper's pack state, set clean while it reads back and restored after.
constexpr GLenum kPackState[] = {GL_PACK_SWAP_BYTES,  GL_PACK_LSB_FIRST,   GL_PACK_ROW_LENGTH, GL_PACK_IMAGE_HEIGHT,
                                 GL_PACK_SKIP_ROWS,   GL_PACK_SKIP_PIXELS, GL_PACK_SKIP_IMAGES, GL_PACK_ALIGNMENT};

}  // namespace

SnapshotReport write_snapshot(slave::Replayer& keeper, const KeptCalls& kept, const TupleOut& out) {
    return SnapshotWriter(keeper, kept, out).write();
}

SnapshotWriter::SnapshotWriter(slave::Replayer& keeper, const KeptCalls& kept, const TupleOut& out)
    : keeper_(keeper), gl_(keeper.api()), kept_(kept), out_(out), e_(buf_) {}

void SnapshotWriter::flush() {
    size_t at = 0;
    while (at + kTupleHeaderBytes <= buf_.size()) {
        uint32_t body = 0;
        std::memcpy(&body, buf_.data() + at + 8, 4);
        const size_t bytes = kTupleHeaderBytes + body;
        out_(buf_.data() + at, bytes);
        report_.tuples++;
        report_.bytes += bytes;
        at += bytes;
    }
    buf_.clear();
}

void SnapshotWriter::raw(const Tuple& tuples, uint32_t context) {
    flush();
    Tuple copy;
    const Tuple* from = &tuples;
    if (context) {
        copy = tuples;
        for (size_t at = 0; at + kTupleHeaderBytes <= copy.size();) {
            uint32_t body = 0;
            std::memcpy(&body, copy.data() + at + 8, 4);
            std::memcpy(copy.data() + at + 4, &context, 4);
            at += kTupleHeaderBytes + body;
        }
        from = &copy;
    }
    buf_.assign(from->data(), from->data() + from->size());
    flush();
}

void SnapshotWriter::read_in(slave::SlaveContext& ctx) {
    flush();
    std::string error;
    if (!keeper_.backend().make_current(ctx.id, ctx.width, ctx.height, error))
        throw slave::ReplayError("snapshot: the keeper cannot make context " + std::to_string(ctx.id) +
                                 " current: " + error);
    e_.set_context(ctx.id);
}

bool SnapshotWriter::asked() { return gl_.glGetError() == GL_NO_ERROR; }

bool SnapshotWriter::query(GLenum pname, GLint& out) {
    for (int i = 0; i < 16 && gl_.glGetError() != GL_NO_ERROR; ++i) {  // bounded: a lost context errs forever
    }
    GLint v[16] = {};
    gl_.glGetIntegerv(pname, v);
    out = v[0];
    return asked();
}

GLint SnapshotWriter::integer(GLenum pname) {
    GLint v = 0;
    return query(pname, v) ? v : 0;
}

uint64_t SnapshotWriter::master_name(slave::SlaveContext& ctx, Ns ns, uint64_t slave_name) {
    if (!slave_name) return 0;
    const bool own = kNamespaces[int(ns)].per_context;
    const void* scope = own ? static_cast<const void*>(&ctx) : static_cast<const void*>(ctx.names.shared.get());
    auto key = std::make_pair(scope, int(ns));
    auto it = reverse_.find(key);
    if (it == reverse_.end()) {
        it = reverse_.emplace(key, std::unordered_map<uint64_t, uint64_t>()).first;
        ctx.names.map(ns).each([&](uint64_t master, uint64_t slave) { it->second[slave] = master; });
    }
    auto found = it->second.find(slave_name);
    return found == it->second.end() ? 0 : found->second;
}

void SnapshotWriter::upload_state() {
    for (GLenum pname : {GL_UNPACK_SWAP_BYTES, GL_UNPACK_LSB_FIRST, GL_UNPACK_ROW_LENGTH, GL_UNPACK_IMAGE_HEIGHT,
                         GL_UNPACK_SKIP_ROWS, GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_IMAGES})
        encode_glPixelStorei(e_, sz_, pname, 0);
    encode_glPixelStorei(e_, sz_, GL_UNPACK_ALIGNMENT, 1);
    if (gl_.has(OP_glBindBuffer)) encode_glBindBuffer(e_, sz_, GL_PIXEL_UNPACK_BUFFER, 0);
    sz_.set_bound(GL_PIXEL_UNPACK_BUFFER_BINDING, false);
}

SnapshotReport SnapshotWriter::write() {
    slave::SlaveContext* was_current = keeper_.current_or_null();
    // 1. Contexts, in the order the master made them (a context shares with an older one).
    for (const auto& [id, calls] : kept_.contexts()) {
        if (!keeper_.context(id)) continue;
        raw(calls.create);
        if (!calls.format.empty()) raw(calls.format);
        raw(calls.context);
        report_.contexts++;
    }
    // 2. Their window framebuffers: the drawables' sizes, and each context made current once.
    for (const auto& [drawable, size] : kept_.drawable_sizes()) raw(size);
    std::vector<slave::SlaveContext*> drawn;
    for (const auto& [id, calls] : kept_.contexts()) {
        slave::SlaveContext* ctx = keeper_.context(id);
        if (!ctx || !ctx->made_current || calls.make_current.empty()) continue;
        raw(calls.make_current);
        drawn.push_back(ctx);
    }
    // 3. The objects of each share group, written through its first context with a window.
    std::vector<const slave::ShareGroup*> groups_done;
    std::vector<GLint> pack(std::size(kPackState));
    for (slave::SlaveContext* ctx : drawn) {
        read_in(*ctx);
        for (size_t i = 0; i < pack.size(); ++i) {
            pack[i] = integer(kPackState[i]);
            gl_.glPixelStorei(kPackState[i], kPackState[i] == GL_PACK_ALIGNMENT ? 1 : 0);
        }
        const GLint pack_buffer = gl_.has(OP_glBindBuffer) ? integer(GL_PIXEL_PACK_BUFFER_BINDING) : 0;
        if (pack_buffer) gl_.glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        upload_state();
        const slave::ShareGroup* group = ctx->names.shared.get();
        if (std::find(groups_done.begin(), groups_done.end(), group) == groups_done.end()) {
            groups_done.push_back(group);
            share_group(*ctx);
        }
        for (size_t i = 0; i < pack.size(); ++i) gl_.glPixelStorei(kPackState[i], pack[i]);
        if (pack_buffer) gl_.glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(pack_buffer));
        flush();
    }
    // 4. Each context's own objects and state.
    for (slave::SlaveContext* ctx : drawn) {
        read_in(*ctx);
        upload_state();
        window_contents(*ctx);
        context_objects(*ctx);
        context_state(*ctx);
        flush();
    }
    // 5. The context that was current last, current again.
    std::string error;
    if (was_current) {
        keeper_.backend().make_current(was_current->id, was_current->width, was_current->height, error);
        auto calls = kept_.contexts().find(was_current->id);
        if (calls != kept_.contexts().end()) raw(calls->second.make_current);
    } else {
        keeper_.backend().make_current(0, 0, 0, error);
    }
    flush();
    return report_;
}

}  // namespace glcast::keeper
