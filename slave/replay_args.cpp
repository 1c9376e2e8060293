// Arguments of a replayed call as the slave's driver takes them: pointer records copied into
// per-call scratch memory (the arena), outputs sized for the driver to write.
#include <cstring>

#include "common/gl_headers.h"
#include "slave/replayer.h"

namespace glcast::slave {

// --- argument helpers ----------------------------------------------------------------

void* Replayer::arena(size_t bytes) {
    if (arena_used_ == arena_.size()) arena_.emplace_back();
    std::vector<uint64_t>& block = arena_[arena_used_++];
    block.assign(bytes / 8 + 2, 0);
    if (bytes > options_.limits.arena_retain_bytes) arena_grown_ = true;
    return block.data();
}

// One large upload must not keep its scratch for the rest of the replay.
void Replayer::release_arena() {
    arena_grown_ = false;
    const size_t keep = options_.limits.arena_retain_bytes / 8 + 2;
    for (std::vector<uint64_t>& block : arena_)
        if (block.capacity() > keep) std::vector<uint64_t>().swap(block);
}

static size_t element_bytes(const Call& c, int i) { return wire_bytes(c.info->params[i].wire); }

static const char* param_name(const Call& c, int i) { return c.info->params[i].name; }

static uint32_t binding_target(uint32_t binding) {
    switch (binding) {
    case GL_ARRAY_BUFFER_BINDING: return GL_ARRAY_BUFFER;
    case GL_ELEMENT_ARRAY_BUFFER_BINDING: return GL_ELEMENT_ARRAY_BUFFER;
    case GL_PIXEL_PACK_BUFFER_BINDING: return GL_PIXEL_PACK_BUFFER;
    case GL_PIXEL_UNPACK_BUFFER_BINDING: return GL_PIXEL_UNPACK_BUFFER;
    case GL_DRAW_INDIRECT_BUFFER_BINDING: return GL_DRAW_INDIRECT_BUFFER;
    case GL_DISPATCH_INDIRECT_BUFFER_BINDING: return GL_DISPATCH_INDIRECT_BUFFER;
    case GL_PARAMETER_BUFFER_BINDING: return GL_PARAMETER_BUFFER;
    case GL_QUERY_BUFFER_BINDING: return GL_QUERY_BUFFER;
    case GL_COPY_READ_BUFFER_BINDING: return GL_COPY_READ_BUFFER;
    case GL_COPY_WRITE_BUFFER_BINDING: return GL_COPY_WRITE_BUFFER;
    case GL_TEXTURE_BUFFER_BINDING: return GL_TEXTURE_BUFFER;
    default: return 0;
    }
}

// Without a buffer bound the driver takes an offset for a client address: the stream would
// choose where the driver reads or writes.
int64_t Replayer::check_offset(const Call& c, int i, uint32_t binding, uint64_t offset) {
    if (!binding)
        throw ReplayError(std::string(param_name(c, i)) + " is a buffer offset, but it takes none");
    GLint buffer = 0;
    api_.glGetIntegerv(binding, &buffer);
    const uint32_t target = binding_target(binding);
    if (!buffer || !target)
        throw ReplayError(std::string(param_name(c, i)) + " is buffer offset " + std::to_string(offset) +
                          " with no buffer bound (" + (enum_name(binding) ? enum_name(binding) : "?") + ")");
    GLint size = 0;
    if (!offset) return 0;  // inside any buffer; most draws start there, and a query per draw costs
    api_.glGetBufferParameteriv(target, GL_BUFFER_SIZE, &size);
    if (offset > uint64_t(size))
        throw ReplayError(std::string(param_name(c, i)) + " is buffer offset " + std::to_string(offset) +
                          " past the end of the bound buffer (" + std::to_string(size) + " bytes)");
    return size;
}

void Replayer::need(const Call& c, int i, int64_t elements, bool null_ok) const {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    if (r.tag == PtrTag::Null && !null_ok && elements > 0)
        throw ReplayError(std::string(param_name(c, i)) + " is NULL, the call reads " + std::to_string(elements) +
                          " elements");
    if (r.tag == PtrTag::Data && elements > int64_t(r.count))
        throw ReplayError(std::string(param_name(c, i)) + " has " + std::to_string(r.count) + " elements, the call reads " +
                          std::to_string(elements));
}

// A generator writes as many names as it is asked for, whatever the master's reply holds.
void Replayer::need_reply(const Call& c, int i, int64_t elements) const {
    const Arg& a = c.args[size_t(i)];
    if (a.ptr.tag != PtrTag::Reply) {
        if (a.ptr.tag != PtrTag::Null || elements > 0)
            throw ReplayError(std::string(param_name(c, i)) + ": a generator's output must be a reply");
        return;
    }
    if (elements != int64_t(a.reply.count))
        throw ReplayError(std::string(param_name(c, i)) + ": the call generates " + std::to_string(elements) +
                          " names, the reply has " + std::to_string(a.reply.count));
}

const void* Replayer::in(const Call& c, int i, uint32_t binding) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    switch (r.tag) {
    case PtrTag::Data: {
        const size_t bytes = r.count * element_bytes(c, i);
        // + NUL: text arrays are used as C strings by some calls. + 64: arrays sized by a pname
        // (glLightfv, glTexParameterfv: at most 16 values) are not checked against it here.
        void* p = arena(bytes + 64);
        std::memcpy(p, r.data, bytes);
        return p;
    }
    case PtrTag::Offset:
        check_offset(c, i, binding, r.value);
        return reinterpret_cast<const void*>(uintptr_t(r.value));
    default: return nullptr;
    }
}

void* Replayer::out(const Call& c, int i, uint32_t binding) {
    const Arg& a = c.args[size_t(i)];
    switch (a.ptr.tag) {
    case PtrTag::Reply: {
        const ArgKind kind = c.info->params[i].kind;
        const size_t bytes = a.reply.count * (kind == ArgKind::OutString ? 1 : element_bytes(c, i));
        return arena(bytes + 4096);  // outputs the master sized by its own state: some slack
    }
    case PtrTag::Offset:
        check_offset(c, i, binding, a.ptr.value);
        return reinterpret_cast<void*>(uintptr_t(a.ptr.value));
    default: return nullptr;
    }
}

const char* Replayer::string(const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    if (r.tag != PtrTag::Data) return nullptr;
    char* p = static_cast<char*>(arena(r.count + 1));
    std::memcpy(p, r.data, r.count);
    p[r.count] = 0;
    return p;
}

const char* const* Replayer::strings(const Call& c, int i) {
    const auto& list = c.args[size_t(i)].strings;
    auto out = static_cast<const char**>(arena(sizeof(char*) * (list.size() + 1)));
    for (size_t k = 0; k < list.size(); ++k) {
        if (list[k].tag != PtrTag::Data) continue;
        char* p = static_cast<char*>(arena(list[k].count + 1));
        std::memcpy(p, list[k].data, list[k].count);
        out[k] = p;
    }
    return out;
}

const void* const* Replayer::index_arrays(const Call& c, int i) {
    const auto& list = c.args[size_t(i)].strings;
    auto out = static_cast<const void**>(arena(sizeof(void*) * (list.size() + 1)));
    for (size_t k = 0; k < list.size(); ++k) {
        if (list[k].tag == PtrTag::Offset) {
            check_offset(c, i, GL_ELEMENT_ARRAY_BUFFER_BINDING, list[k].value);
            out[k] = reinterpret_cast<const void*>(uintptr_t(list[k].value));
        } else if (list[k].tag == PtrTag::Data) {
            void* p = arena(list[k].count);
            std::memcpy(p, list[k].data, list[k].count);
            out[k] = p;
        }
    }
    return out;
}

const void* Replayer::deferred(const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    // Client memory is set up by the glcast.client_arrays tuple before each draw. An offset
    // is kept by the driver and read at draws: a buffer must be bound, its size may come later.
    if (r.tag != PtrTag::Offset) return nullptr;
    GLint buffer = 0;
    api_.glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &buffer);
    if (!buffer)
        throw ReplayError(std::string(param_name(c, i)) + " is buffer offset " + std::to_string(r.value) +
                          " with no GL_ARRAY_BUFFER bound");
    return reinterpret_cast<const void*>(uintptr_t(r.value));
}

}  // namespace glcast::slave
