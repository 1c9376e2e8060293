// What a draw reads from client memory is found by asking the driver for the array state
// (enabled, pointer, size, type, stride, divisor) of the array kinds this context has ever
// pointed at client memory: exact, and contexts that never do (core profile, VBO-only
// programs) pay one check per draw. Index ranges come from the index array itself
// (max index + 1, honouring base vertex and primitive restart), never from the index count.
#include "interceptor/client_arrays.h"
#include "glcast_synthetic_encode.h"
#include "glcast_gl_api.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <map>
#include <tuple>
#include <mutex>
#include <vector>

#include "common/gl_headers.h"
#include "common/immortal.h"
#include "glcast_client_arrays.h"
#include "glcast_commands.h"
#include "interceptor/driver_size_queries.h"
#include "interceptor/shim.h"
#include "interceptor/shim_internal.h"
#include "master/stream.h"
#include "protocol/format.h"

namespace glcast {
namespace {

// One cached array range: a program often draws several ranges of one array per frame, so
// the cache keys on the range, not only on the array slot.
struct ShadowKey {
    uint8_t slot;
    uint32_t index;
    const void* pointer;
    uint32_t first_byte;
    uint32_t bytes;
    bool operator<(const ShadowKey& o) const {
        return std::tie(slot, index, pointer, first_byte, bytes) <
               std::tie(o.slot, o.index, o.pointer, o.first_byte, o.bytes);
    }
};
struct Shadow {
    uint32_t handle = 0;
    uint64_t last_use = 0;
    std::vector<uint8_t> bytes;
};
constexpr size_t kMaxShadowsPerContext = 1024;

struct ContextArrays {
    uint32_t kinds_used = 0;  // bit per ClientSlot that got client memory
    bool locked = false;
    int64_t lock_first = 0, lock_count = 0;
    std::map<ShadowKey, Shadow> shadows;
    uint32_t next_handle = 1;
    uint64_t clock = 0;
};

// The cache entry for `key`, evicting the least recently used one when the cache is full
// (its handle is reused: the slave overwrites that copy).
Shadow& shadow_for(ContextArrays& c, const ShadowKey& key, bool& fresh) {
    auto it = c.shadows.find(key);
    fresh = it == c.shadows.end();
    if (!fresh) return it->second;
    uint32_t handle = c.next_handle;
    if (c.shadows.size() >= kMaxShadowsPerContext) {
        auto oldest = std::min_element(c.shadows.begin(), c.shadows.end(), [](const auto& a, const auto& b) {
            return a.second.last_use < b.second.last_use;
        });
        handle = oldest->second.handle;
        c.shadows.erase(oldest);
    } else {
        c.next_handle++;
    }
    Shadow& s = c.shadows[key];
    s.handle = handle;
    return s;
}

std::mutex g_mutex;
Immortal<std::map<uint32_t, ContextArrays>> g_contexts;
// Set once any context points an array at client memory: until then a draw takes no lock.
std::atomic<bool> g_client_arrays_seen{false};

ContextArrays& arrays_of_current() {
    return (*g_contexts)[current_context_id()];
}

struct ArrayState {
    ClientSlot slot;
    uint32_t index;
    int32_t size;
    uint32_t type;
    int32_t stride;
    uint8_t normalized, integer;
    uint32_t divisor;
    const uint8_t* pointer;
};

int32_t element_bytes(const ArrayState& a) {
    const int comps = a.size == GL_BGRA ? 4 : a.size;
    switch (a.type) {
    case GL_BYTE: case GL_UNSIGNED_BYTE: return comps;
    case GL_SHORT: case GL_UNSIGNED_SHORT: case GL_HALF_FLOAT: return comps * 2;
    case GL_INT: case GL_UNSIGNED_INT: case GL_FLOAT: case GL_FIXED: return comps * 4;
    case GL_DOUBLE: return comps * 8;
    case GL_INT_2_10_10_10_REV: case GL_UNSIGNED_INT_2_10_10_10_REV: case GL_UNSIGNED_INT_10F_11F_11F_REV: return 4;
    default: return 0;
    }
}

bool read_fixed(const FixedClientArray& f, uint32_t index, ArrayState& a) {
    const GlApi& gl = real_gl();
    if (!gl.has(OP_glIsEnabled) || !gl.has(OP_glGetPointerv) || !gl.glIsEnabled(f.cap)) return false;
    if (real_get_integer(f.binding) != 0) return false;  // a buffer object: its data already travelled
    void* p = nullptr;
    gl.glGetPointerv(f.pointer, &p);
    a = ArrayState{f.slot, index, f.size_query ? real_get_integer(f.size_query) : f.size,
                   f.type_query ? uint32_t(real_get_integer(f.type_query)) : f.type, real_get_integer(f.stride),
                   uint8_t(f.normalized), 0, 0, static_cast<const uint8_t*>(p)};
    return p != nullptr;
}

bool read_attrib(uint32_t index, ArrayState& a) {
    const GlApi& gl = real_gl();
    if (!gl.has(OP_glGetVertexAttribiv) || !gl.has(OP_glGetVertexAttribPointerv)) return false;
    auto get = [&gl](GLuint i, GLenum pname, GLint* v) { gl.glGetVertexAttribiv(i, pname, v); };
    GLint v = 0;
    get(index, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &v);
    if (!v) return false;
    get(index, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &v);
    if (v) return false;
    void* p = nullptr;
    gl.glGetVertexAttribPointerv(index, GL_VERTEX_ATTRIB_ARRAY_POINTER, &p);
    GLint size = 4, type = GL_FLOAT, stride = 0, normalized = 0, integer = 0, divisor = 0;
    get(index, GL_VERTEX_ATTRIB_ARRAY_SIZE, &size);
    get(index, GL_VERTEX_ATTRIB_ARRAY_TYPE, &type);
    get(index, GL_VERTEX_ATTRIB_ARRAY_STRIDE, &stride);
    get(index, GL_VERTEX_ATTRIB_ARRAY_NORMALIZED, &normalized);
    get(index, GL_VERTEX_ATTRIB_ARRAY_INTEGER, &integer);
    get(index, GL_VERTEX_ATTRIB_ARRAY_DIVISOR, &divisor);
    a = ArrayState{ClientSlot::Attrib, index, size, uint32_t(type), stride, uint8_t(normalized), uint8_t(integer),
                   uint32_t(divisor), static_cast<const uint8_t*>(p)};
    return p != nullptr;
}

std::vector<ArrayState> enabled_client_arrays(uint32_t kinds) {
    std::vector<ArrayState> out;
    ArrayState a{};
    for (const FixedClientArray& f : kFixedClientArrays) {
        if (!(kinds & (1u << unsigned(f.slot)))) continue;
        if (f.slot != ClientSlot::TexCoord) {
            if (read_fixed(f, 0, a)) out.push_back(a);
            continue;
        }
        const GlApi& gl = real_gl();
        const bool active = gl.has(OP_glClientActiveTexture);
        const GLint units = active ? real_get_integer(GL_MAX_TEXTURE_COORDS) : 1;
        const GLint saved = active ? real_get_integer(GL_CLIENT_ACTIVE_TEXTURE) : GL_TEXTURE0;
        for (GLint u = 0; u < std::max(units, 1); ++u) {
            if (active) gl.glClientActiveTexture(GL_TEXTURE0 + u);
            if (read_fixed(f, uint32_t(u), a)) out.push_back(a);
        }
        if (active) gl.glClientActiveTexture(saved);
    }
    if (kinds & (1u << unsigned(ClientSlot::Attrib))) {
        const GLint n = std::min(real_get_integer(GL_MAX_VERTEX_ATTRIBS), 64);
        for (GLint i = 0; i < n; ++i)
            if (read_attrib(uint32_t(i), a)) out.push_back(a);
    }
    return out;
}

}  // namespace

void note_client_pointer(uint32_t opcode) {
    g_client_arrays_seen.store(true, std::memory_order_relaxed);
    std::lock_guard lock(g_mutex);
    arrays_of_current().kinds_used |= client_arrays_set_by(opcode);
}

uint32_t thread_state_opcode() { return thread_state().opcode; }

void lock_client_arrays(int64_t first, int64_t count) {
    std::lock_guard lock(g_mutex);
    ContextArrays& c = arrays_of_current();
    c.locked = count > 0;
    c.lock_first = first;
    c.lock_count = count;
}

void unlock_client_arrays() {
    std::lock_guard lock(g_mutex);
    arrays_of_current().locked = false;
}

void CallScope::ship_client_arrays(const DrawRange& range) {
    ship_mapped_writes(*this);
    if (!g_client_arrays_seen.load(std::memory_order_relaxed)) return;
    uint32_t kinds;
    bool locked;
    int64_t lock_first, lock_count;
    {
        std::lock_guard lock(g_mutex);
        ContextArrays& c = arrays_of_current();
        kinds = c.kinds_used;
        locked = c.locked;
        lock_first = c.lock_first;
        lock_count = c.lock_count;
    }
    if (!kinds) return;
    const std::vector<ArrayState> arrays = enabled_client_arrays(kinds);
    if (arrays.empty()) return;
    int64_t lo = 0, hi = -1;
    DriverSizeQueries sz;
    const bool any = vertex_range(range, sz, lo, hi);
    if (locked) {
        lo = any ? std::min(lo, lock_first) : lock_first;
        hi = any ? std::max(hi, lock_first + lock_count - 1) : lock_first + lock_count - 1;
    } else if (!any) {
        return;
    }
    if (lo < 0) lo = 0;

    Encoder& e = begin_synthetic(kSynthClientArrays);
    encode_synth_client_arrays(e, uint32_t(arrays.size()));
    Stream* s = stream();
    std::lock_guard lock(g_mutex);
    ContextArrays& c = arrays_of_current();
    for (const ArrayState& a : arrays) {
        const int32_t elem = element_bytes(a);
        const int64_t stride = a.stride ? a.stride : elem;
        int64_t first = lo, last = hi;
        if (a.divisor) {  // per-instance array: from element 0 to the last instance's
            first = 0;
            last = std::max<int64_t>(last_instance_element(range, a.divisor), 0);
        }
        const int64_t bytes = elem ? (last - first) * stride + elem : 0;
        if (bytes < 0 || bytes > kMaxArrayBytes) {
            e.fail("client array range of " + std::to_string(bytes) + " bytes");
            break;
        }
        const uint32_t first_byte = uint32_t(first * stride);
        bool fresh = false;
        Shadow& sh = shadow_for(c, ShadowKey{uint8_t(a.slot), a.index, a.pointer, first_byte, uint32_t(bytes)}, fresh);
        sh.last_use = ++c.clock;
        const uint8_t* data = a.pointer + first_byte;
        const bool hit = !fresh && std::memcmp(sh.bytes.data(), data, size_t(bytes)) == 0;
        encode_synth_client_arrays_item(e, uint8_t(a.slot), a.index, a.size, a.type, int32_t(stride), a.normalized,
                                        a.integer, sh.handle, first_byte, hit, data, bytes);
        if (!hit) sh.bytes.assign(data, data + bytes);
        if (s) s->count_cache(hit);
    }
    if (!thread_state().synthetic_encoder.failure().empty()) {
        unserialized(thread_state().synthetic_encoder.failure().c_str());
        thread_state().synthetic_encoder.clear_failure();
        return;
    }
    commit_synthetic();
}

}  // namespace glcast
