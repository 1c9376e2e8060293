// Inter-frame coding of the stream's messages on the writer thread (docs/stream-format.md,
// version 2): most messages are compressed with the previous message's payload as a zstd
// prefix, or XORed with it, so a frame that repeats the last one costs what changed. Every
// kKeyIntervalMessages-th message (and the first) is a key, compressed alone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/byte_vector.h"

typedef struct ZSTD_CCtx_s ZSTD_CCtx;

namespace glcast {

class MessageCoder {
public:
    MessageCoder(int zstd_level, bool inter_frame);
    ~MessageCoder();
    MessageCoder(const MessageCoder&) = delete;
    MessageCoder& operator=(const MessageCoder&) = delete;

    // Codes message `sequence`'s payload `raw`; returns the bytes stored and sets `flags`
    // (kMsgCompressed, and kMsgDelta or kMsgXor with kMsgBound, the stored bytes then starting with
    // the previous payload's CRC-32) when they are coded, else stores `raw` as it is (flags 0).
    // The stored bytes are coded(), or `raw` itself when not coded.
    size_t code(uint64_t sequence, const ByteVector& raw, uint32_t& flags);
    const uint8_t* coded() const { return body_.data(); }
    // `raw` was the message just written: the next one's prefix (taken, not copied; the buffer
    // given back is the older prefix, for reuse).
    void next_prefix(ByteVector& raw);
    uint64_t compressions() const { return compressions_; }  // since the last call of code()

private:
    size_t compress(uint8_t* dst, size_t capacity, const ByteVector& src, bool with_prefix, int level);
    // Tries the XOR residual against the prefix coding's `n` bytes; returns the better size,
    // with the residual's bytes moved into body_ and `how` set when it wins.
    size_t try_xor(const ByteVector& raw, size_t n, bool xor_only, uint32_t& how);

    const int zstd_level_;
    const bool inter_frame_;
    // The level XOR residuals are compressed at: the lazy level where it pays, re-decided on
    // every kXorProbeInterval-th XORed message by compressing it at both.
    const int lazy_level_;
    int xor_level_;
    ZSTD_CCtx* cctx_;
    ByteVector body_;      // the compressed payload, before it is known how long it is: never zero-filled
    ByteVector previous_;  // the last message's payload, the next one's prefix
    uint32_t previous_crc_ = 0;  // its CRC-32: coded messages start with it (kMsgBound)
    ByteVector xored_;
    std::vector<uint8_t> alternative_, probe_;  // kept across messages: no allocation per message
    uint64_t xored_messages_ = 0, coded_messages_ = 0, compressions_ = 0;
    // A program whose frames XOR far better than the prefix codes them (CPU-animated vertices)
    // does so frame after frame: while the last message coded both ways came out at least a
    // quarter smaller XORed, the prefix coding is skipped (half the writer's time there) and
    // tried again on every kXorProbeInterval-th message, or when the XOR residual is half as
    // large again as the last one or over an eighth of the frame (a frame unlike the last, where
    // the prefix coding may win by far). Measurements in docs/performance.md.
    bool xor_mode_ = false;
    size_t last_xor_bytes_ = 0;
};

}  // namespace glcast
