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
    case PtrTag::Offset:  // its range: Replayer::need, with the size the call reads
        if (!binding) throw ReplayError(std::string(param_name(c, i)) + " is a buffer offset, but it takes none");
        return reinterpret_cast<const void*>(uintptr_t(r.value));
    default: return nullptr;
    }
}

void* Replayer::out(const Call& c, int i, uint32_t binding, int64_t elements) {
    const Arg& a = c.args[size_t(i)];
    if (a.ptr.tag != PtrTag::Reply && a.ptr.tag != PtrTag::Offset) return nullptr;
    const ArgKind kind = c.info->params[i].kind;
    const int64_t unit = kind == ArgKind::OutString ? 1 : int64_t(element_bytes(c, i));
    if (elements < 0)
        throw ReplayError(std::string(param_name(c, i)) + ": the slave cannot compute how much the call writes");
    if (a.ptr.tag == PtrTag::Offset) {
        check_offset(c, i, binding, a.ptr.value, elements * unit);
        return reinterpret_cast<void*>(uintptr_t(a.ptr.value));
    }
    if (uint64_t(elements) > options_.limits.buffer_bytes / uint64_t(unit))
        throw ReplayError(std::string(param_name(c, i)) + ": the call writes " + std::to_string(elements) +
                          " elements, over the limit buffer_bytes=" + std::to_string(options_.limits.buffer_bytes));
    return arena(size_t(elements * unit) + 1);  // + 1: a string's NUL where bufSize is 0
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
        if (list[k].tag == PtrTag::Offset) {  // its range: Replayer::need_lists
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
