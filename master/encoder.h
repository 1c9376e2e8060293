// Encodes one tuple (u32 opcode, u32 context, u32 body length, body) into a growing byte
// buffer. Used by the generated encode_* functions; see protocol/format.h for the layout.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include <X11/Xutil.h>

#include "common/byte_vector.h"
#include "protocol/command_info.h"
#include "protocol/format.h"

namespace glcast {

using u8_t = uint8_t;
using i8_t = int8_t;
using u16_t = uint16_t;
using i16_t = int16_t;
using u32_t = uint32_t;
using i32_t = int32_t;
using u64_t = uint64_t;
using i64_t = int64_t;
using f32_t = float;
using f64_t = double;

// Largest array the encoder will read from the application: anything bigger is treated as
// an unknown size (forwarded and counted), never a giant read.
inline constexpr int64_t kMaxArrayBytes = int64_t(1) << 30;

class Encoder {
public:
    explicit Encoder(ByteVector& out) : out_(out) {}

    // Inline: every recorded call makes both, from the generated encoders in another file.
    void begin(uint32_t opcode) {
        opcode_ = opcode;
        start_ = out_.size();
        const uint32_t header[3] = {opcode, context_, 0};  // body length patched by end()
        put(header, sizeof header);
    }
    void end() {
        const uint32_t body = uint32_t(out_.size() - start_ - kTupleHeaderBytes);
        std::memcpy(out_.data() + start_ + 8, &body, 4);
    }
    void set_context(uint32_t ctx) { context_ = ctx; }
    uint32_t opcode() const { return opcode_; }

    template <class T>
    void value(T v) {
        static_assert(std::is_arithmetic_v<T>);
        put(&v, sizeof v);
    }
    void address(const void* p) { value<uint64_t>(reinterpret_cast<uintptr_t>(p)); }

    // Pointer records (PtrTag). `count` is in elements of `elem_bytes`; a negative count
    // (the application's error: GL reads nothing) encodes as zero elements.
    void data(const void* p, int64_t count, size_t elem_bytes) {
        // Inline for the common case, a few numbers (glVertex3fv, glMultMatrixf): one append of
        // tag and count, one of the data. Anything else takes the checks out of line.
        if (p && count >= 0 && count <= kInlineDataElements && elem_bytes <= 8) [[likely]] {
            uint8_t head[5] = {static_cast<uint8_t>(PtrTag::Data)};
            const uint32_t n = uint32_t(count);
            std::memcpy(head + 1, &n, 4);
            put(head, sizeof head);
            put(p, size_t(count) * elem_bytes);
            return;
        }
        data_checked(p, count, elem_bytes);
    }
    void offset(const void* p);
    void deferred(const void* p, bool in_buffer);
    void string(const char* s);
    void string_array(int64_t count, const char* const* strings, const int* lengths);
    template <class BytesOf>
    void index_arrays(const void* const* arrays, int64_t count, bool in_buffer, BytesOf&& bytes_of) {
        if (count < 0 || !arrays) count = 0;
        if (count > 1 << 20) { fail("index array list of " + std::to_string(count) + " entries"); count = 0; }
        value<uint32_t>(uint32_t(count));
        for (int64_t i = 0; i < count; ++i) {
            if (in_buffer) offset(arrays[i]);
            else data(arrays[i], bytes_of(i), 1);
        }
    }
    template <class T>
    void attrib_list(const T* list, int64_t terminator = 0);  // int or EGLAttrib key/value lists
    void visual_attribs(const int* list);
    void visualinfo(const XVisualInfo* vi);
    void reply_marker(const void* p);
    // u32 byte count, then the bytes (synthetic tuples' `bytes` fields).
    void bytes(const void* p, int64_t n) {
        if (n < 0 || n > kMaxArrayBytes) { fail("byte field of " + std::to_string(n) + " bytes"); n = 0; }
        value<uint32_t>(uint32_t(n));
        put(p, size_t(n));
    }

    // Reply part: the data of an output whose request record was PtrTag::Reply.
    void reply_data(const void* p, int64_t count, size_t elem_bytes);
    void reply_string(const char* s, int64_t capacity);

    // Set when a size could not be determined or was absurd: the tuple must be discarded.
    void fail(std::string reason) { if (failure_.empty()) failure_ = std::move(reason); }
    const std::string& failure() const { return failure_; }
    void clear_failure() { failure_.clear(); }

private:
    static constexpr int64_t kInlineDataElements = 4096;  // at most 32 KB: far inside kMaxArrayBytes
    void data_checked(const void* p, int64_t count, size_t elem_bytes);
    void put(const void* p, size_t n) { out_.append(p, n); }
    void tag(PtrTag t) { value<uint8_t>(static_cast<uint8_t>(t)); }
    bool checked_bytes(int64_t count, size_t elem_bytes, uint32_t& out_count);

    ByteVector& out_;
    size_t start_ = 0;
    uint32_t opcode_ = 0;
    uint32_t context_ = 0;
    std::string failure_;
};

template <class T>
void Encoder::attrib_list(const T* list, int64_t terminator) {
    if (!list) { tag(PtrTag::Null); return; }
    size_t n = 0;
    while (n < 512 && int64_t(list[n]) != terminator) n += 2;  // key/value pairs up to the terminating key
    if (n >= 512) { fail("attribute list without terminator"); tag(PtrTag::Null); return; }
    data(list, int64_t(n + 1), sizeof(T));
}

}  // namespace glcast
