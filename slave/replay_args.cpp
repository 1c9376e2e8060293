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
    return block.data();
}

static size_t element_bytes(const Call& c, int i) { return wire_bytes(c.info->params[i].wire); }

const void* Replayer::in(const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    switch (r.tag) {
    case PtrTag::Data: {
        const size_t bytes = r.count * element_bytes(c, i);
        void* p = arena(bytes + 1);  // + NUL: text arrays are used as C strings by some calls
        std::memcpy(p, r.data, bytes);
        return p;
    }
    case PtrTag::Offset: return reinterpret_cast<const void*>(uintptr_t(r.value));
    default: return nullptr;
    }
}

void* Replayer::out(const Call& c, int i) {
    const Arg& a = c.args[size_t(i)];
    switch (a.ptr.tag) {
    case PtrTag::Reply: {
        const ArgKind kind = c.info->params[i].kind;
        const size_t bytes = a.reply.count * (kind == ArgKind::OutString ? 1 : element_bytes(c, i));
        return arena(bytes + 4096);  // outputs the master sized by its own state: some slack
    }
    case PtrTag::Offset: return reinterpret_cast<void*>(uintptr_t(a.ptr.value));
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
    // Client memory is set up by the glcast.client_arrays tuple before each draw.
    return r.tag == PtrTag::Offset ? reinterpret_cast<const void*>(uintptr_t(r.value)) : nullptr;
}

}  // namespace glcast::slave
