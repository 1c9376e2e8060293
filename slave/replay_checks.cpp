// The checks the generated replay makes before each call (codegen/templates/
// slave_dispatch.cpp.j2): what the call's values and the slave's own state say the driver
// will read or write, against what the stream shipped. The stream is not trusted: a texture
// upload whose width says 1 GiB with 768 bytes shipped would have the driver read past the
// slave's scratch memory, an offset with no buffer bound would be an address the stream
// chose (docs/security.md, "The slave").
#include <algorithm>
#include <string>

#include "common/gl_headers.h"
#include "slave/replay_sizes.h"
#include "slave/replayer.h"

namespace glcast::slave {

namespace {

std::string str(int64_t v) { return std::to_string(v); }

const char* param_name(const Call& c, int i) { return c.info->params[i].name; }

size_t element_bytes(const Call& c, int i) {
    return c.info->params[i].kind == ArgKind::OutString ? 1 : wire_bytes(c.info->params[i].wire);
}

}  // namespace

SizeQueries& Replayer::sizes() {
    sizes_->clear_failure();
    return *sizes_;
}

void Replayer::sized(const Call& c) {
    (void)c;
    if (sizes_->failure().empty()) return;
    const std::string why = sizes_->failure();
    sizes_->clear_failure();
    throw ReplayError("the size of an array it reads or writes cannot be computed: " + why);
}

// Without a buffer bound the driver takes an offset for a client address: the stream would
// choose where the driver reads or writes. With one, [offset, offset + bytes) must lie in it.
void Replayer::check_offset(const Call& c, int i, uint32_t binding, uint64_t offset, int64_t bytes) {
    if (!binding)
        throw ReplayError(std::string(param_name(c, i)) + " is a buffer offset, but it takes none");
    GLint buffer = 0;
    api_.glGetIntegerv(binding, &buffer);
    const uint32_t target = binding_target(binding);
    if (!buffer || !target)
        throw ReplayError(std::string(param_name(c, i)) + " is buffer offset " + std::to_string(offset) +
                          " with no buffer bound (" + (enum_name(binding) ? enum_name(binding) : "?") + ")");
    if (bytes < 0) bytes = 0;
    GLint64 size = 0;
    if (api_.has(OP_glGetBufferParameteri64v)) {
        api_.glGetBufferParameteri64v(target, GL_BUFFER_SIZE, &size);
    } else {
        GLint size32 = 0;
        api_.glGetBufferParameteriv(target, GL_BUFFER_SIZE, &size32);
        size = size32;
    }
    if (offset > uint64_t(size) || uint64_t(bytes) > uint64_t(size) - offset)
        throw ReplayError(std::string(param_name(c, i)) + " reads or writes bytes " + std::to_string(offset) + ".." +
                          std::to_string(offset + uint64_t(bytes)) + " of the bound buffer, which has " +
                          std::to_string(size));
}

void Replayer::need(const Call& c, int i, int64_t elements, bool null_ok, uint32_t binding) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    // A negative count with NULL is an error the master's driver raised without reading (its
    // program passed NULL and lived): replayed as it is, for the same error.
    if (elements < 0 && r.tag == PtrTag::Null) return;
    if (elements < 0)
        throw ReplayError(std::string(param_name(c, i)) + ": the slave cannot compute how much the call reads");
    if (r.tag == PtrTag::Null && !null_ok && elements > 0)
        throw ReplayError(std::string(param_name(c, i)) + " is NULL, the call reads " + std::to_string(elements) +
                          " elements");
    // A client address or a reply where the call reads: the slave has no data for it (the
    // pointer becomes NULL), which is what NULL is where NULL is not allowed.
    if ((r.tag == PtrTag::ClientAddress || r.tag == PtrTag::Reply) && !null_ok && elements > 0)
        throw ReplayError(std::string(param_name(c, i)) + " is " +
                          (r.tag == PtrTag::Reply ? "a reply" : "a client address") + ", not data; the call reads " +
                          std::to_string(elements) + " elements");
    if (r.tag == PtrTag::Data && elements > int64_t(r.count))
        throw ReplayError(std::string(param_name(c, i)) + " has " + std::to_string(r.count) + " elements, the call reads " +
                          std::to_string(elements));
    if (r.tag == PtrTag::Offset) check_offset(c, i, binding, r.value, elements * int64_t(element_bytes(c, i)));
    if (r.tag == PtrTag::Data && binding) refuse_data_under_buffer(c, i, binding);
}

// With a buffer bound at the parameter's binding the driver takes the pointer for an offset into
// it: the slave's copy of shipped data would become an offset the stream's bindings chose.
void Replayer::refuse_data_under_buffer(const Call& c, int i, uint32_t binding) {
    GLint buffer = 0;
    api_.glGetIntegerv(binding, &buffer);
    if (buffer)
        throw ReplayError(std::string(param_name(c, i)) + " is data from the stream, but a buffer is bound (" +
                          (enum_name(binding) ? enum_name(binding) : "?") + "): GL would read it as an offset");
}

// A generator writes as many names as it is asked for, whatever the master's reply holds.
void Replayer::need_reply(const Call& c, int i, int64_t elements) const {
    const Arg& a = c.args[size_t(i)];
    // A negative count: the master's driver raised GL_INVALID_VALUE and generated nothing.
    if (elements < 0 && (a.ptr.tag == PtrTag::Null || (a.ptr.tag == PtrTag::Reply && a.reply.count == 0))) return;
    if (a.ptr.tag != PtrTag::Reply) {
        if (a.ptr.tag != PtrTag::Null || elements > 0)
            throw ReplayError(std::string(param_name(c, i)) + ": a generator's output must be a reply");
        return;
    }
    if (elements != int64_t(a.reply.count))
        throw ReplayError(std::string(param_name(c, i)) + ": the call generates " + std::to_string(elements) +
                          " names, the reply has " + std::to_string(a.reply.count));
}

// One index array per draw of a multi-draw: as many as drawcount, each holding what its count
// says, or an offset range inside the element buffer.
void Replayer::need_lists(const Call& c, int i, int64_t drawcount, const std::function<int64_t(int64_t)>& bytes) {
    const auto& list = c.args[size_t(i)].strings;
    if (drawcount <= 0) return;
    if (drawcount > int64_t(list.size()))
        throw ReplayError("drawcount " + str(drawcount) + " is more than the " + str(int64_t(list.size())) +
                          " index arrays of the stream");
    if (std::any_of(list.begin(), list.begin() + drawcount, [](const PtrRecord& r) { return r.tag == PtrTag::Data; }))
        refuse_data_under_buffer(c, i, GL_ELEMENT_ARRAY_BUFFER_BINDING);
    for (int64_t k = 0; k < drawcount; ++k) {
        const PtrRecord& r = list[size_t(k)];
        const int64_t n = bytes(k);
        if (n < 0) throw ReplayError("index array " + str(k) + ": the slave cannot compute its size");
        if (r.tag == PtrTag::Data && n > int64_t(r.count))
            throw ReplayError("index array " + str(k) + " has " + str(int64_t(r.count)) + " bytes, the draw reads " + str(n));
        if (r.tag == PtrTag::Offset) check_offset(c, i, GL_ELEMENT_ARRAY_BUFFER_BINDING, r.value, n);
        if (r.tag == PtrTag::Null && n > 0) throw ReplayError("index array " + str(k) + " is NULL");
    }
}

void Replayer::within(const Call& c, int i, uint64_t ReplayLimits::*limit, const char* limit_name) const {
    const size_t bytes = wire_bytes(c.info->params[i].wire);
    uint64_t bits = c.args[size_t(i)].bits;
    int64_t v = bytes >= 8 ? int64_t(bits) : int64_t(bits << (64 - 8 * bytes)) >> (64 - 8 * bytes);
    if (v > 0 && uint64_t(v) > options_.limits.*limit)
        throw ReplayError(std::string(param_name(c, i)) + " " + str(v) + " is over the limit " + limit_name + "=" +
                          str(int64_t(options_.limits.*limit)));
}

// A draw reads its client arrays over the vertices (and, per-instance arrays, the instances) it
// names: the ranges shipped just before it (Replayer::client_arrays) must hold them.
void Replayer::check_draw(const Call& c, const DrawRange& range) {
    (void)c;
    SlaveContext* ctx = current_;
    if (!ctx) return;
    if (ctx->client_arrays_refused) {
        ctx->client_arrays_refused = false;
        throw ReplayError("the client arrays of the draw were refused");
    }
    if (!ctx->client_range_pending) return;
    ctx->client_range_pending = false;
    int64_t lo = 0, hi = -1;
    sizes_->clear_failure();
    if (vertex_range(range, *sizes_, lo, hi) && (lo < ctx->client_first || hi >= ctx->client_end))
        throw ReplayError("the draw reads vertices " + str(lo) + ".." + str(hi) + ", the client arrays shipped hold " +
                          str(ctx->client_first) + ".." + str(ctx->client_end - 1));
    for (const ClientInstanceRange& a : ctx->client_instances) {
        const int64_t last = last_instance_element(range, a.divisor);
        const int64_t first = last < 0 ? 0 : std::max<int64_t>(range.baseinstance, 0);
        if (last >= 0 && (first < a.first || last >= a.end))
            throw ReplayError("the draw reads elements " + str(first) + ".." + str(last) + " of a per-instance array (divisor " +
                              str(a.divisor) + "), the stream shipped " + str(a.first) + ".." + str(a.end - 1));
    }
}

// The binding query of a texture, buffer or renderbuffer target; 0 for targets that store
// nothing (proxies) or that the stores of commands.yaml do not name.
static uint32_t binding_of(Ns ns, uint32_t target) {
    if (ns == Ns::renderbuffer) return target == GL_RENDERBUFFER ? GL_RENDERBUFFER_BINDING : 0;
    if (ns == Ns::buffer) return buffer_binding(target);
    switch (target) {
    case GL_TEXTURE_1D: return GL_TEXTURE_BINDING_1D;
    case GL_TEXTURE_2D: return GL_TEXTURE_BINDING_2D;
    case GL_TEXTURE_3D: return GL_TEXTURE_BINDING_3D;
    case GL_TEXTURE_1D_ARRAY: return GL_TEXTURE_BINDING_1D_ARRAY;
    case GL_TEXTURE_2D_ARRAY: return GL_TEXTURE_BINDING_2D_ARRAY;
    case GL_TEXTURE_RECTANGLE: return GL_TEXTURE_BINDING_RECTANGLE;
    case GL_TEXTURE_CUBE_MAP: case GL_TEXTURE_CUBE_MAP_POSITIVE_X: case GL_TEXTURE_CUBE_MAP_NEGATIVE_X:
    case GL_TEXTURE_CUBE_MAP_POSITIVE_Y: case GL_TEXTURE_CUBE_MAP_NEGATIVE_Y: case GL_TEXTURE_CUBE_MAP_POSITIVE_Z:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_Z: return GL_TEXTURE_BINDING_CUBE_MAP;
    case GL_TEXTURE_CUBE_MAP_ARRAY: return GL_TEXTURE_BINDING_CUBE_MAP_ARRAY;
    case GL_TEXTURE_2D_MULTISAMPLE: return GL_TEXTURE_BINDING_2D_MULTISAMPLE;
    case GL_TEXTURE_2D_MULTISAMPLE_ARRAY: return GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY;
    default: return 0;
    }
}

uint64_t Replayer::live_store_bytes() const {
    std::vector<const ShareGroup*> seen;
    uint64_t total = 0;
    for (const auto& [id, ctx] : contexts_) {
        const ShareGroup* g = ctx->names.shared.get();
        if (!g || std::find(seen.begin(), seen.end(), g) != seen.end()) continue;
        seen.push_back(g);
        total += g->store_bytes;
    }
    return total;
}

void Replayer::store(const Call& c, int64_t bytes, uint64_t key) {
    if (bytes < 0) throw ReplayError("the slave cannot compute the size of the data store it creates");
    SlaveContext& ctx = current();
    const CommandSemantics& s = c.info->sem;
    if (s.writes_param < 0) return;
    uint64_t object = 0;
    if (s.writes == ObjectAccess::Bound) {
        const uint32_t binding = binding_of(s.writes_ns, uint32_t(c.args[size_t(s.writes_param)].bits));
        if (!binding) return;  // a proxy, or a target GL refuses: no store
        GLint name = 0;
        api_.glGetIntegerv(binding, &name);
        object = uint32_t(name);
    } else {
        ctx.names.map(s.writes_ns).find(c.args[size_t(s.writes_param)].bits, object);
    }
    if (!object) return;  // GL raises an error and stores nothing
    ShareGroup& group = *ctx.names.shared;
    auto& images = group.stores[{int(s.writes_ns), object}];
    uint64_t old = 0;
    if (key == kWholeStore) {
        for (const auto& [k, b] : images) old += b;
    } else if (auto it = images.find(key); it != images.end()) {
        old = it->second;
    }
    const uint64_t total = live_store_bytes() - old + uint64_t(bytes);
    if (total > options_.limits.object_bytes)
        throw ReplayError("a data store of " + str(bytes) + " bytes would bring the live objects' stores to " +
                          str(int64_t(total)) + " bytes, over the limit object_bytes=" +
                          str(int64_t(options_.limits.object_bytes)));
    if (key == kWholeStore) images.clear();
    images[key] = uint64_t(bytes);
    group.store_bytes = group.store_bytes - old + uint64_t(bytes);
}

void Replayer::release_store(SlaveContext& ctx, Ns ns, uint64_t master) {
    if (kNamespaces[int(ns)].per_context) return;
    uint64_t object = 0;
    if (!ctx.names.map(ns).find(master, object)) return;
    ShareGroup& group = *ctx.names.shared;
    auto it = group.stores.find({int(ns), object});
    if (it == group.stores.end()) return;
    for (const auto& [k, b] : it->second) group.store_bytes -= b;
    group.stores.erase(it);
}

}  // namespace glcast::slave
