// Inter-frame coding of messages (message_coder.h).
#include "master/message_coder.h"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>

#include "common/xor_bytes.h"
#include "protocol/format.h"

namespace glcast {

namespace {
// The least zstd level an XOR residual is compressed at.
constexpr int kXorResidualLevel = 5;
constexpr uint64_t kXorProbeInterval = 16;
}  // namespace

MessageCoder::MessageCoder(int zstd_level, bool inter_frame)
    : zstd_level_(zstd_level), inter_frame_(inter_frame), lazy_level_(std::max(zstd_level, kXorResidualLevel)),
      xor_level_(lazy_level_), cctx_(ZSTD_createCCtx()) {}

MessageCoder::~MessageCoder() { ZSTD_freeCCtx(cctx_); }

size_t MessageCoder::compress(uint8_t* dst, size_t capacity, const ByteVector& src, bool with_prefix, int level) {
    compressions_++;
    ZSTD_CCtx_reset(cctx_, ZSTD_reset_session_and_parameters);
    ZSTD_CCtx_setParameter(cctx_, ZSTD_c_compressionLevel, level);
    if (with_prefix) {
        // The window spans the prefix and the message, so that any of the prefix can be matched.
        int window_log = 10;
        while (window_log < 27 && (size_t(1) << window_log) < previous_.size() + src.size()) window_log++;
        ZSTD_CCtx_setParameter(cctx_, ZSTD_c_windowLog, window_log);
        ZSTD_CCtx_refPrefix(cctx_, previous_.data(), previous_.size());
    }
    return ZSTD_compress2(cctx_, dst, capacity, src.data(), src.size());
}

size_t MessageCoder::code(uint64_t sequence, const ByteVector& raw, uint32_t& flags) {
    compressions_ = 0;
    flags = 0;
    if (zstd_level_ <= 0 || raw.empty()) return raw.size();
    body_.resize(ZSTD_compressBound(raw.size()) + 4);
    const bool coded = inter_frame_ && sequence % kKeyIntervalMessages != 0 && !previous_.empty();
    // A frame of the same calls as the last, with numbers that moved (animated vertices): XORed
    // with the last, what stayed is zeros and what moved keeps its high bytes alike. Tried, and
    // kept when smaller, where the prefix left more than 1/64 of the frame: a frame that mostly
    // repeats the last gains nothing from it.
    const bool same_length = coded && previous_.size() == raw.size();
    const bool xor_only = same_length && xor_mode_ && coded_messages_++ % kXorProbeInterval != 0;
    size_t n = xor_only ? static_cast<size_t>(-1)  // not tried: an error code for ZSTD_isError
                        : compress(body_.data(), body_.size(), raw, coded, zstd_level_);
    uint32_t how = coded ? uint32_t(kMsgDelta) : 0u;
    if (same_length && (xor_only || (!ZSTD_isError(n) && n > raw.size() / 64))) {
        n = try_xor(raw, n, xor_only, how);
    } else if (coded && !xor_only) {
        xor_mode_ = false;  // the prefix coding left too little for XOR to be tried
    }
    if (ZSTD_isError(n)) return raw.size();
    if (how) {  // bound to the message it is coded against
        if (n + 4 >= raw.size()) return raw.size();
        std::memmove(body_.data() + 4, body_.data(), n);
        for (int i = 0; i < 4; ++i) body_[size_t(i)] = uint8_t(previous_crc_ >> (8 * i));
        n += 4;
        how |= kMsgBound;
    }
    if (n >= raw.size()) return raw.size();
    flags = kMsgCompressed | how;
    return n;
}

void MessageCoder::next_prefix(ByteVector& raw) {
    previous_.swap(raw);
    previous_crc_ = uint32_t(crc32(0, previous_.data(), uInt(previous_.size())));
}

// The XOR residual is mostly runs of zeros between a few changed bytes, where zstd's lazy match
// finder often finds far more than the greedy one at level 1, and sometimes not: the writer
// probes both levels now and then and keeps the lazy one only while it saves a tenth.
size_t MessageCoder::try_xor(const ByteVector& raw, size_t n, bool xor_only, uint32_t& how) {
    xored_.resize(raw.size());
    xor_bytes(xored_.data(), raw.data(), previous_.data(), xored_.size());
    alternative_.resize(ZSTD_compressBound(xored_.size()));
    size_t x = compress(alternative_.data(), alternative_.size(), xored_, false, xor_level_);
    if (lazy_level_ != zstd_level_ && xored_messages_++ % kXorProbeInterval == 0 && !ZSTD_isError(x)) {
        const int other = xor_level_ == lazy_level_ ? zstd_level_ : lazy_level_;
        probe_.resize(alternative_.size());
        const size_t y = compress(probe_.data(), probe_.size(), xored_, false, other);
        if (!ZSTD_isError(y)) {
            const size_t lazy = other == lazy_level_ ? y : x, greedy = other == lazy_level_ ? x : y;
            xor_level_ = lazy * 10 < greedy * 9 ? lazy_level_ : zstd_level_;
            if (y < x) alternative_.swap(probe_), x = y;
        }
    }
    if (xor_only && (ZSTD_isError(x) || x > raw.size() / 8 || 2 * x > 3 * last_xor_bytes_))  // both
        n = compress(body_.data(), body_.size(), raw, true, zstd_level_);
    if (!ZSTD_isError(x)) last_xor_bytes_ = x;
    if (!ZSTD_isError(n) && !ZSTD_isError(x)) xor_mode_ = x * 4 <= n * 3;  // both tried
    if (!ZSTD_isError(x) && (ZSTD_isError(n) || x < n)) {
        std::memcpy(body_.data(), alternative_.data(), x);
        how = kMsgXor;
        return x;
    }
    return n;
}

}  // namespace glcast
