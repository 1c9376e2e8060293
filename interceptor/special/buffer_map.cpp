// Mapped buffer objects.
//
// The application writes into driver memory between map and unmap, outside any GL call, so
// the stream learns the contents only when GL is told they are ready:
//  - glUnmapBuffer: the whole mapped range travels (kSynthBufferWrite), unless the map was
//    GL_MAP_FLUSH_EXPLICIT_BIT, in which case only glFlushMappedBufferRange ranges do;
//  - the memory must be read *before* the real unmap, after which the pointer is invalid;
//    this is the one place where the driver is called after encoding;
//  - persistent maps (GL_MAP_PERSISTENT_BIT) stay mapped while the program draws and writes,
//    so their changes travel at every point where GL may read them (ship_mapped_writes: draws,
//    compute, commands that read a bound buffer, syncs, flushes, swaps), found against a shadow
//    copy taken at map time. The whole pages of a large mapping are write-tracked
//    (interceptor/write_tracking.h): only the pages written since the last point are compared,
//    so the cost follows what the program wrote, not the mapping's size. The partial pages at
//    its ends (they may share memory with other data), small mappings, and mappings that cannot
//    be tracked are compared whole. The changed spans of each page travel, not whole pages.
//  - a mapping's tracking ends before the driver may free its memory: before the real unmap,
//    before the buffer's deletion, before its context's destruction.
// Read-only maps change nothing and are only recorded.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <map>
#include <mutex>
#include <vector>

#include "glcast_commands.h"
#include "glcast_gl_api.h"
#include "glcast_synthetic_encode.h"
#include "glcast_encode.h"
#include "glcast_special.h"
#include "common/immortal.h"
#include "interceptor/driver_size_queries.h"
#include "interceptor/shim.h"
#include "interceptor/write_tracking.h"
#include "protocol/format.h"

namespace glcast {
namespace {

struct Mapping {
    uint8_t* pointer = nullptr;
    int64_t offset = 0, length = 0;
    GLbitfield access = 0;
    std::vector<uint8_t> shadow;  // persistent maps only
    int tracked = -1;             // write_tracking slot of the whole pages [tracked_from, tracked_to)
    int64_t tracked_from = 0, tracked_to = 0;
};

// Below this a mapping is compared whole: a few pages cost less than their faults.
constexpr int64_t kTrackMinBytes = 64 * 1024;
// Changed spans of neighbouring pages closer than this travel as one write (a tuple costs about as much).
constexpr int64_t kMergeGap = 64;

std::mutex g_mutex;
Immortal<std::map<std::pair<uint32_t, GLuint>, Mapping>> g_maps;  // (context id, buffer name)
std::atomic<int> g_persistent_maps{0};  // draws take the lock only while some exist
Immortal<std::vector<std::pair<size_t, size_t>>> g_runs;  // ship_persistent's scratch, under g_mutex

void start_tracking(Mapping& m) {
    const uintptr_t p = reinterpret_cast<uintptr_t>(m.pointer);
    const uintptr_t from = (p + kTrackedPage - 1) / kTrackedPage * kTrackedPage;
    const uintptr_t to = (p + uintptr_t(m.length)) / kTrackedPage * kTrackedPage;
    if (m.length < kTrackMinBytes || to <= from) return;
    m.tracked = track_writes(reinterpret_cast<uint8_t*>(from), to - from);
    if (m.tracked < 0) return;
    m.tracked_from = int64_t(from - p);
    m.tracked_to = int64_t(to - p);
}

void stop_tracking(Mapping& m) {
    untrack_writes(m.tracked);
    m.tracked = -1;
}

// Forgets a mapping whose memory the driver may free next.
void forget(std::map<std::pair<uint32_t, GLuint>, Mapping>::iterator it) {
    stop_tracking(it->second);
    g_persistent_maps -= int(!it->second.shadow.empty());
    g_maps->erase(it);
}

GLenum binding_of(GLenum target) {
    switch (target) {
    case GL_ARRAY_BUFFER: return GL_ARRAY_BUFFER_BINDING;
    case GL_ELEMENT_ARRAY_BUFFER: return GL_ELEMENT_ARRAY_BUFFER_BINDING;
    case GL_PIXEL_PACK_BUFFER: return GL_PIXEL_PACK_BUFFER_BINDING;
    case GL_PIXEL_UNPACK_BUFFER: return GL_PIXEL_UNPACK_BUFFER_BINDING;
    case GL_UNIFORM_BUFFER: return GL_UNIFORM_BUFFER_BINDING;
    case GL_TEXTURE_BUFFER: return GL_TEXTURE_BUFFER_BINDING;
    case GL_TRANSFORM_FEEDBACK_BUFFER: return GL_TRANSFORM_FEEDBACK_BUFFER_BINDING;
    case GL_COPY_READ_BUFFER: return GL_COPY_READ_BUFFER_BINDING;
    case GL_COPY_WRITE_BUFFER: return GL_COPY_WRITE_BUFFER_BINDING;
    case GL_DRAW_INDIRECT_BUFFER: return GL_DRAW_INDIRECT_BUFFER_BINDING;
    case GL_DISPATCH_INDIRECT_BUFFER: return GL_DISPATCH_INDIRECT_BUFFER_BINDING;
    case GL_SHADER_STORAGE_BUFFER: return GL_SHADER_STORAGE_BUFFER_BINDING;
    case GL_ATOMIC_COUNTER_BUFFER: return GL_ATOMIC_COUNTER_BUFFER_BINDING;
    case GL_QUERY_BUFFER: return GL_QUERY_BUFFER_BINDING;
    default: return 0;
    }
}

GLuint bound_buffer(GLenum target) {
    const GLenum binding = binding_of(target);
    return binding ? GLuint(real_get_integer(binding)) : 0;
}

int64_t buffer_size(GLenum target) {
    GLint64 v = 0;
    if (real_gl().has(OP_glGetBufferParameteri64v)) real_gl().glGetBufferParameteri64v(target, GL_BUFFER_SIZE, &v);
    return v;
}

GLbitfield access_bits(GLenum access) {  // glMapBuffer's enum to glMapBufferRange's bits
    switch (access) {
    case GL_READ_ONLY: return GL_MAP_READ_BIT;
    case GL_WRITE_ONLY: return GL_MAP_WRITE_BIT;
    default: return GL_MAP_READ_BIT | GL_MAP_WRITE_BIT;
    }
}

void emit_write(CallScope& scope, GLuint buffer, int64_t offset, const uint8_t* data, int64_t bytes) {
    if (bytes <= 0) return;
    encode_synth_buffer_write(scope.begin_synthetic(kSynthBufferWrite), buffer, uint64_t(offset), data, bytes);
    scope.commit_synthetic();
}

void mapped(CallScope& scope, GLuint buffer, void* pointer, int64_t offset, int64_t length, GLbitfield access) {
    if (!pointer || !buffer) return;
    Mapping m{static_cast<uint8_t*>(pointer), offset, length, access, {}};
    if ((access & GL_MAP_PERSISTENT_BIT) && (access & GL_MAP_WRITE_BIT)) {
        m.shadow.assign(m.pointer, m.pointer + length);
        start_tracking(m);
    }
    (void)scope;
    std::lock_guard lock(g_mutex);
    Mapping& slot = (*g_maps)[{current_context_id(), buffer}];
    stop_tracking(slot);
    g_persistent_maps += int(!m.shadow.empty()) - int(!slot.shadow.empty());
    slot = std::move(m);
}

// Narrows [lo, hi) to its first and last byte that differ from the shadow; false when none do.
bool changed_span(const Mapping& m, int64_t& lo, int64_t& hi) {
    const uint8_t *now = m.pointer, *was = m.shadow.data();
    if (lo >= hi || !std::memcmp(now + lo, was + lo, size_t(hi - lo))) return false;
    constexpr int64_t kBlock = 64;  // a block at a time, then bytes
    while (hi - lo > kBlock && !std::memcmp(now + lo, was + lo, kBlock)) lo += kBlock;
    while (hi - lo > kBlock && !std::memcmp(now + hi - kBlock, was + hi - kBlock, kBlock)) hi -= kBlock;
    while (now[lo] == was[lo]) ++lo;
    while (now[hi - 1] == was[hi - 1]) --hi;
    return true;
}

// Ships what the program wrote into a mapping; for persistent maps only the changed span.
void ship_changes(CallScope& scope, GLuint buffer, Mapping& m, int64_t from, int64_t bytes) {
    if (!(m.access & GL_MAP_WRITE_BIT)) return;
    from = std::clamp<int64_t>(from, 0, m.length);
    bytes = std::clamp<int64_t>(bytes, 0, m.length - from);
    if (m.shadow.empty()) {
        emit_write(scope, buffer, m.offset + from, m.pointer + from, bytes);
        return;
    }
    int64_t lo = from, hi = from + bytes;
    if (!changed_span(m, lo, hi)) return;
    std::memcpy(m.shadow.data() + lo, m.pointer + lo, size_t(hi - lo));
    emit_write(scope, buffer, m.offset + lo, m.pointer + lo, hi - lo);
}

// The written pages [from, to) of a tracked mapping: each page's changed span, neighbours merged.
void ship_pages(CallScope& scope, GLuint buffer, Mapping& m, int64_t from, int64_t to) {
    int64_t lo = -1, hi = -1;  // the span waiting to travel
    auto flush = [&] {
        if (lo < 0) return;
        std::memcpy(m.shadow.data() + lo, m.pointer + lo, size_t(hi - lo));
        emit_write(scope, buffer, m.offset + lo, m.pointer + lo, hi - lo);
        lo = hi = -1;
    };
    for (int64_t page = from; page < to; page += int64_t(kTrackedPage)) {
        int64_t a = page, b = std::min<int64_t>(page + int64_t(kTrackedPage), to);
        if (!changed_span(m, a, b)) continue;
        if (lo >= 0 && a - hi > kMergeGap) flush();
        if (lo < 0) lo = a;
        hi = b;
    }
    flush();
}

// Everything the program wrote into a persistent mapping since the last time.
void ship_persistent(CallScope& scope, GLuint buffer, Mapping& m, bool frame_end = false) {
    if (m.tracked < 0) return ship_changes(scope, buffer, m, 0, m.length);
    ship_changes(scope, buffer, m, 0, m.tracked_from);
    std::vector<std::pair<size_t, size_t>>& runs = *g_runs;  // under g_mutex
    take_written_pages(m.tracked, runs, frame_end);
    for (const auto& [first, end] : runs)
        ship_pages(scope, buffer, m, m.tracked_from + int64_t(first * kTrackedPage),
                   m.tracked_from + int64_t(end * kTrackedPage));
    ship_changes(scope, buffer, m, m.tracked_to, m.length - m.tracked_to);
}

// Before glUnmapBuffer: the data goes out first, then the real unmap, then its tuple.
template <class Unmap, class Encode>
GLboolean unmap(CallScope& scope, GLuint buffer, Unmap&& real_unmap, Encode&& encode) {
    if (scope.recording()) {
        std::lock_guard lock(g_mutex);
        auto it = g_maps->find({current_context_id(), buffer});
        if (it != g_maps->end()) {
            Mapping& m = it->second;
            if (!m.shadow.empty())
                ship_persistent(scope, buffer, m);
            else if (!(m.access & GL_MAP_FLUSH_EXPLICIT_BIT))
                ship_changes(scope, buffer, m, 0, m.length);
        }
    }
    if (g_recording) {  // a forked child touches nothing of the shim's
        std::lock_guard lock(g_mutex);
        auto it = g_maps->find({current_context_id(), buffer});
        if (it != g_maps->end()) forget(it);
    }
    const GLboolean ret = real_unmap();
    if (scope.recording()) scope.record([&](Encoder& e, SizeQueries& sz) { encode(e, sz, ret); });
    return ret;
}

void flushed(CallScope& scope, GLuint buffer, int64_t offset, int64_t length) {
    std::lock_guard lock(g_mutex);
    auto it = g_maps->find({current_context_id(), buffer});
    if (it == g_maps->end()) return;
    if (it->second.shadow.empty())
        ship_changes(scope, buffer, it->second, offset, length);
    else
        ship_persistent(scope, buffer, it->second);
}

template <class Delete, class Encode>
void delete_buffers(CallScope& scope, GLsizei n, const GLuint* buffers, Delete&& real_delete, Encode&& encode) {
    if (g_recording && n > 0 && buffers) {  // deleting a mapped buffer unmaps it
        std::lock_guard lock(g_mutex);
        const uint32_t ctx = current_context_id();
        for (GLsizei i = 0; i < n; ++i) {
            auto it = g_maps->find({ctx, buffers[i]});
            if (it != g_maps->end()) forget(it);
        }
    }
    real_delete();
    if (scope.recording()) scope.record([&](Encoder& e, SizeQueries& sz) { encode(e, sz); });
}

}  // namespace

namespace {
void ship_current_context(CallScope& scope, bool frame_end) {
    std::lock_guard lock(g_mutex);
    const uint32_t ctx = current_context_id();
    for (auto& [key, m] : *g_maps)
        if (key.first == ctx && !m.shadow.empty()) ship_persistent(scope, key.second, m, frame_end);
}
}  // namespace

void ship_mapped_writes(CallScope& scope) {
    if (g_persistent_maps.load(std::memory_order_relaxed) == 0) return;
    ship_current_context(scope, false);
}

void ship_mapped_writes_at_frame_end(CallScope& scope) {
    if (g_persistent_maps.load(std::memory_order_relaxed) == 0) return;
    if (!check_handler()) {  // every mapping compared whole from its next ship on
        std::lock_guard lock(g_mutex);
        for (auto& entry : *g_maps) stop_tracking(entry.second);
    }
    ship_current_context(scope, true);
}

void forget_mappings_of_context(uint32_t context) {
    if (!g_recording || g_persistent_maps.load() == 0) return;
    std::lock_guard lock(g_mutex);
    for (auto it = g_maps->begin(); it != g_maps->end();) {
        auto next = std::next(it);
        if (it->first.first == context) forget(it);
        it = next;
    }
}

void* special::glMapBuffer(glMapBuffer_fn real, CallScope& scope, GLenum target, GLenum access) {
    void* ret = real(target, access);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) { encode_glMapBuffer(e, sz, target, access, ret); });
    mapped(scope, bound_buffer(target), ret, 0, buffer_size(target), access_bits(access));
    return ret;
}

void* special::glMapBufferARB(glMapBufferARB_fn real, CallScope& scope, GLenum target, GLenum access) {
    void* ret = real(target, access);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) { encode_glMapBufferARB(e, sz, target, access, ret); });
    mapped(scope, bound_buffer(target), ret, 0, buffer_size(target), access_bits(access));
    return ret;
}

void* special::glMapBufferRange(glMapBufferRange_fn real, CallScope& scope, GLenum target, GLintptr offset,
                                GLsizeiptr length, GLbitfield access) {
    void* ret = real(target, offset, length, access);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) { encode_glMapBufferRange(e, sz, target, offset, length, access, ret); });
    mapped(scope, bound_buffer(target), ret, offset, length, access);
    return ret;
}

void* special::glMapNamedBuffer(glMapNamedBuffer_fn real, CallScope& scope, GLuint buffer, GLenum access) {
    void* ret = real(buffer, access);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) { encode_glMapNamedBuffer(e, sz, buffer, access, ret); });
    GLint64 size = 0;
    if (real_gl().has(OP_glGetNamedBufferParameteri64v))
        real_gl().glGetNamedBufferParameteri64v(buffer, GL_BUFFER_SIZE, &size);
    mapped(scope, buffer, ret, 0, size, access_bits(access));
    return ret;
}

void* special::glMapNamedBufferRange(glMapNamedBufferRange_fn real, CallScope& scope, GLuint buffer,
                                     GLintptr offset, GLsizeiptr length, GLbitfield access) {
    void* ret = real(buffer, offset, length, access);
    if (!scope.recording()) return ret;
    scope.record([&](Encoder& e, SizeQueries& sz) {
        encode_glMapNamedBufferRange(e, sz, buffer, offset, length, access, ret);
    });
    mapped(scope, buffer, ret, offset, length, access);
    return ret;
}

GLboolean special::glUnmapBuffer(glUnmapBuffer_fn real, CallScope& scope, GLenum target) {
    return unmap(scope, bound_buffer(target), [&] { return real(target); },
                 [&](Encoder& e, SizeQueries& sz, GLboolean ret) { encode_glUnmapBuffer(e, sz, target, ret); });
}

GLboolean special::glUnmapBufferARB(glUnmapBufferARB_fn real, CallScope& scope, GLenum target) {
    return unmap(scope, bound_buffer(target), [&] { return real(target); },
                 [&](Encoder& e, SizeQueries& sz, GLboolean ret) { encode_glUnmapBufferARB(e, sz, target, ret); });
}

GLboolean special::glUnmapNamedBuffer(glUnmapNamedBuffer_fn real, CallScope& scope, GLuint buffer) {
    return unmap(scope, buffer, [&] { return real(buffer); },
                 [&](Encoder& e, SizeQueries& sz, GLboolean ret) { encode_glUnmapNamedBuffer(e, sz, buffer, ret); });
}

void special::glFlushMappedBufferRange(glFlushMappedBufferRange_fn real, CallScope& scope, GLenum target,
                                       GLintptr offset, GLsizeiptr length) {
    if (scope.recording()) flushed(scope, bound_buffer(target), offset, length);
    real(target, offset, length);
    if (scope.recording())
        scope.record([&](Encoder& e, SizeQueries& sz) { encode_glFlushMappedBufferRange(e, sz, target, offset, length); });
}

void special::glFlushMappedNamedBufferRange(glFlushMappedNamedBufferRange_fn real, CallScope& scope, GLuint buffer,
                                            GLintptr offset, GLsizeiptr length) {
    if (scope.recording()) flushed(scope, buffer, offset, length);
    real(buffer, offset, length);
    if (scope.recording())
        scope.record([&](Encoder& e, SizeQueries& sz) {
            encode_glFlushMappedNamedBufferRange(e, sz, buffer, offset, length);
        });
}

void special::glDeleteBuffers(glDeleteBuffers_fn real, CallScope& scope, GLsizei n, const GLuint* buffers) {
    delete_buffers(scope, n, buffers, [&] { real(n, buffers); },
                   [&](Encoder& e, SizeQueries& sz) { encode_glDeleteBuffers(e, sz, n, buffers); });
}

void special::glDeleteBuffersARB(glDeleteBuffersARB_fn real, CallScope& scope, GLsizei n, const GLuint* buffers) {
    delete_buffers(scope, n, buffers, [&] { real(n, buffers); },
                   [&](Encoder& e, SizeQueries& sz) { encode_glDeleteBuffersARB(e, sz, n, buffers); });
}

}  // namespace glcast
