// Arguments of a replayed call as the slave's driver takes them: pointer records copied into
// per-call scratch memory (slave/scratch_memory.h), outputs sized for the driver to write.
#include <algorithm>
#include <cstring>

#include "common/gl_headers.h"
#include "slave/replayer.h"

namespace glcast::slave {

// --- argument helpers ----------------------------------------------------------------

static size_t element_bytes(const Call& c, int i) { return wire_bytes(c.info->params[i].wire); }

static const char* param_name(const Call& c, int i) { return c.info->params[i].name; }

const void* Replayer::in(const Call& c, int i, uint32_t binding) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    switch (r.tag) {
    case PtrTag::Data: {
        const size_t bytes = r.count * element_bytes(c, i);
        // + NUL: text arrays are used as C strings by some calls. + 64: arrays sized by a pname
        // (glLightfv, glTexParameterfv: at most 16 values) are not checked against it here.
        void* p = scratch_.take(bytes + 64);
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
    // A negative count the master's driver refused without writing (Replayer::need_reply): the
    // slave's driver gets NULL and refuses it the same way.
    if (elements < 0 && a.ptr.tag == PtrTag::Reply && a.reply.count == 0) return nullptr;
    if (elements < 0)
        throw ReplayError(std::string(param_name(c, i)) + ": the slave cannot compute how much the call writes");
    if (a.ptr.tag == PtrTag::Offset) {
        check_offset(c, i, binding, a.ptr.value, elements * unit);
        return reinterpret_cast<void*>(uintptr_t(a.ptr.value));
    }
    if (uint64_t(elements) > options_.limits.buffer_bytes / uint64_t(unit))
        throw ReplayError(std::string(param_name(c, i)) + ": the call writes " + std::to_string(elements) +
                          " elements, over the limit buffer_bytes=" + std::to_string(options_.limits.buffer_bytes));
    // + 1: a string's NUL where bufSize is 0. What the call leaves unwritten (a query that
    // raised an error, an answer shorter than bufSize) is the program's own memory, which the
    // master's reply holds as the program had it: the slave's starts the same, so that
    // --verify compares what the two drivers wrote (an error only one raised shows in the
    // program's next glGetError).
    const size_t bytes = size_t(elements * unit);
    auto* p = static_cast<uint8_t*>(scratch_.take(bytes + 1));
    const size_t kept = a.reply.tag == PtrTag::Data ? std::min(bytes, size_t(a.reply.count) * size_t(unit)) : 0;
    if (kept) std::memcpy(p, a.reply.data, kept);
    std::memset(p + kept, 0, bytes + 1 - kept);
    return p;
}

const char* Replayer::string(const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    if (r.tag != PtrTag::Data) return nullptr;
    char* p = static_cast<char*>(scratch_.take(r.count + 1));
    std::memcpy(p, r.data, r.count);
    p[r.count] = 0;
    return p;
}

const char* const* Replayer::strings(const Call& c, int i, int lengths) {
    const auto& list = c.args[size_t(i)].strings;
    const PtrRecord* given = lengths >= 0 ? &c.args[size_t(lengths)].ptr : nullptr;
    if (given && given->tag == PtrTag::Data)
        for (size_t k = 0; k < list.size() && k < given->count; ++k) {
            int32_t n;
            std::memcpy(&n, given->data + 4 * k, 4);
            const uint32_t held = list[k].tag == PtrTag::Data ? list[k].count : 0;
            if (n >= 0 && uint32_t(n) > held)
                throw ReplayError("string " + std::to_string(k) + " is " +
                                  std::to_string(n) + " bytes long by its lengths, the stream holds " +
                                  std::to_string(held));
        }
    auto out = static_cast<const char**>(scratch_.take(sizeof(char*) * (list.size() + 1)));
    for (size_t k = 0; k < list.size(); ++k) {
        out[k] = nullptr;
        if (list[k].tag != PtrTag::Data) continue;
        char* p = static_cast<char*>(scratch_.take(list[k].count + 1));
        std::memcpy(p, list[k].data, list[k].count);
        p[list[k].count] = 0;
        out[k] = p;
    }
    out[list.size()] = nullptr;
    return out;
}

const void* const* Replayer::index_arrays(const Call& c, int i) {
    const auto& list = c.args[size_t(i)].strings;
    auto out = static_cast<const void**>(scratch_.take(sizeof(void*) * (list.size() + 1)));
    for (size_t k = 0; k < list.size(); ++k) {
        if (list[k].tag == PtrTag::Offset) {  // its range: Replayer::need_lists
            out[k] = reinterpret_cast<const void*>(uintptr_t(list[k].value));
        } else if (list[k].tag == PtrTag::Data) {
            void* p = scratch_.take(list[k].count);
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
