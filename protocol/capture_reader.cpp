#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include <zstd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "common/xor_bytes.h"
#include "glcast_commands.h"
#include "protocol/decoder.h"

namespace glcast {
namespace {

class FileSource : public Source {
public:
    explicit FileSource(const std::string& path) : path_(path) {
        fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd_ < 0) throw std::runtime_error(path + ": " + std::strerror(errno));
        struct stat st {};
        if (fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
            ::close(fd_);
            throw std::runtime_error(path + ": not a regular file");
        }
        size_ = uint64_t(st.st_size);
    }
    ~FileSource() override { ::close(fd_); }
    uint64_t size() const override { return size_; }
    void read(uint64_t offset, void* dst, size_t n) override {
        auto p = static_cast<uint8_t*>(dst);
        while (n) {
            const ssize_t got = ::pread(fd_, p, n, off_t(offset));
            if (got < 0 && errno == EINTR) continue;
            if (got <= 0) throw DecodeError(offset, path_ + ": read failed");
            p += got;
            offset += uint64_t(got);
            n -= size_t(got);
        }
    }

private:
    std::string path_;
    int fd_ = -1;
    uint64_t size_ = 0;
};

class MemorySource : public Source {
public:
    MemorySource(const uint8_t* data, size_t size) : data_(data), size_(size) {}
    uint64_t size() const override { return size_; }
    void read(uint64_t offset, void* dst, size_t n) override {
        if (n) std::memcpy(dst, data_ + offset, n);
    }

private:
    const uint8_t* data_;
    size_t size_;
};

std::string hex(uint64_t v) {
    char b[24];
    std::snprintf(b, sizeof b, "0x%016llx", (unsigned long long)v);
    return b;
}

}  // namespace

std::unique_ptr<Source> open_file_source(const std::string& path) { return std::make_unique<FileSource>(path); }
std::unique_ptr<Source> memory_source(const uint8_t* data, size_t size) {
    return std::make_unique<MemorySource>(data, size);
}

CaptureReader::CaptureReader(std::unique_ptr<Source> source) : source_(std::move(source)) {
    if (source_->size() < sizeof(FileHeader)) {
        char magic[8] = {};
        source_->read(0, magic, std::min<uint64_t>(sizeof magic, source_->size()));
        if (std::memcmp(magic, kFileMagic, std::min<uint64_t>(8, source_->size())) != 0 || source_->size() == 0)
            throw DecodeError(0, "not a glcast capture (bad magic)");
        throw DecodeError(source_->size(), "truncated file header (" + std::to_string(source_->size()) + " of " +
                                               std::to_string(sizeof(FileHeader)) + " bytes)");
    }
    source_->read(0, &header_, sizeof header_);
    if (std::memcmp(header_.magic, kFileMagic, sizeof kFileMagic) != 0)
        throw DecodeError(0, "not a glcast capture (bad magic)");
    if (header_.version < kOldestReadableFormatVersion || header_.version > kFormatVersion)
        throw DecodeError(8, "format version " + std::to_string(header_.version) + ", this glcast reads versions " +
                                 std::to_string(kOldestReadableFormatVersion) + " to " + std::to_string(kFormatVersion) +
                                 (header_.version > kFormatVersion ? " (written by a newer glcast)" : ""));
    if (header_.header_bytes < sizeof(FileHeader) || header_.header_bytes > 4096 ||
        header_.header_bytes > source_->size())
        throw DecodeError(12, "implausible header length " + std::to_string(header_.header_bytes));
    if (header_.opcode_table_hash != kOpcodeTableHash || header_.opcode_count != kOpcodeCount)
        throw DecodeError(16, "opcode table mismatch: file " + hex(header_.opcode_table_hash) + " with " +
                                  std::to_string(header_.opcode_count) + " opcodes, this glcast " +
                                  hex(kOpcodeTableHash) + " with " + std::to_string(kOpcodeCount) +
                                  " (captured with a different registry or annotation set)");
    offset_ = header_.header_bytes;
}

MessageChain::MessageChain() = default;
MessageChain::~MessageChain() { ZSTD_freeDCtx(static_cast<ZSTD_DCtx*>(dctx_)); }

void MessageChain::remember(uint64_t sequence, const std::vector<uint8_t>& payload) {
    payload_.assign(payload.begin(), payload.end());
    payload_crc_ = uint32_t(crc32(0, payload_.data(), uInt(payload_.size())));
    sequence_ = sequence;
    valid_ = true;
}

void MessageChain::unpack_delta(const MessageHeader& h, const uint8_t* stored, uint64_t offset, std::vector<uint8_t>& out) {
    const uint64_t payload_at = offset + sizeof(MessageHeader);
    if (h.sequence == 0 || !holds(h.sequence - 1))
        throw DecodeError(payload_at, "message " + std::to_string(h.sequence) + " is coded against message " +
                                          std::to_string(h.sequence - 1) + ", which this reader does not have" +
                                          (valid_ ? " (it holds message " + std::to_string(sequence_) + ")" : ""));
    uint32_t stored_bytes = h.stored_bytes;
    if (h.flags & kMsgBound) {
        if (stored_bytes < 4) throw DecodeError(payload_at, "a bound message shorter than its predecessor's checksum");
        const uint32_t named = uint32_t(stored[0]) | uint32_t(stored[1]) << 8 | uint32_t(stored[2]) << 16 |
                               uint32_t(stored[3]) << 24;
        if (named != payload_crc_)
            throw DecodeError(payload_at, "message " + std::to_string(h.sequence) + " is coded against another message " +
                                              std::to_string(h.sequence - 1) + " than the one this reader holds (its " +
                                              "checksum differs): messages of two streams mixed");
        stored += 4;
        stored_bytes -= 4;
    }
    const bool xor_coded = h.flags & kMsgXor;
    if (xor_coded && payload_.size() != h.raw_bytes)
        throw DecodeError(offset + 20, "message " + std::to_string(h.sequence) + " is XORed with message " +
                                           std::to_string(h.sequence - 1) + " of " + std::to_string(payload_.size()) +
                                           " bytes, but has " + std::to_string(h.raw_bytes));
    if (!dctx_) dctx_ = ZSTD_createDCtx();
    auto* dctx = static_cast<ZSTD_DCtx*>(dctx_);
    // The window a frame may ask for is bounded by zstd's default limit (2^27): no frame makes
    // the reader allocate more than its raw_bytes, which the header checks bound.
    ZSTD_DCtx_reset(dctx, ZSTD_reset_session_and_parameters);
    if (!xor_coded) ZSTD_DCtx_refPrefix(dctx, payload_.data(), payload_.size());
    out.resize(h.raw_bytes);
    const size_t n = ZSTD_decompressDCtx(dctx, out.data(), out.size(), stored, stored_bytes);
    if (ZSTD_isError(n) || n != h.raw_bytes)
        throw DecodeError(payload_at, std::string("bad zstd payload (coded against the previous message): ") +
                                          (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "length differs from header"));
    if (xor_coded)
        xor_bytes(out.data(), out.data(), payload_.data(), out.size());
}

// The checks every message gets, wherever it came from.
static void check_and_unpack(const MessageHeader& h, const uint8_t* stored_data, uint64_t offset, Message& m,
                             MessageChain* chain, bool delta_allowed = true) {
    const uint64_t payload_at = offset + sizeof(MessageHeader);
    if (h.magic != kMessageMagic) throw DecodeError(offset, "bad message magic (corrupted stream)");
    const uint32_t known = kMsgCompressed | kMsgFrameEnd | kMsgStreamEnd |
                           (delta_allowed ? uint32_t(kMsgDelta | kMsgXor | kMsgBound) : 0u);
    if (h.flags & ~known) throw DecodeError(offset + 4, "unknown message flags " + std::to_string(h.flags));
    if ((h.flags & kMsgDelta) && (h.flags & kMsgXor))
        throw DecodeError(offset + 4, "a message coded against the previous one both as prefix and XOR (flags " +
                                          std::to_string(h.flags) + ")");
    if ((h.flags & kMsgBound) && !(h.flags & (kMsgDelta | kMsgXor)))
        throw DecodeError(offset + 4, "a key message bound to a predecessor (flags " + std::to_string(h.flags) + ")");
    if ((h.flags & (kMsgDelta | kMsgXor)) && !(h.flags & kMsgCompressed))
        throw DecodeError(offset + 4, "a message coded against the previous one must be compressed (flags " +
                                          std::to_string(h.flags) + ")");
    if (h.raw_bytes > kMaxMessageBytes || h.stored_bytes > kMaxMessageBytes)
        throw DecodeError(offset + 20, "absurd message length (" + std::to_string(h.stored_bytes) + " stored, " +
                                           std::to_string(h.raw_bytes) + " raw; limit " +
                                           std::to_string(kMaxMessageBytes) + ")");
    if (!(h.flags & kMsgCompressed) && h.stored_bytes != h.raw_bytes)
        throw DecodeError(offset + 20, "uncompressed message with different stored and raw lengths");
#ifndef GLCAST_FUZZING  // the fuzzer could not get past a checksum to the decoder behind it
    if (uint32_t(crc32(0, stored_data, uInt(h.stored_bytes))) != h.crc32)
        throw DecodeError(payload_at, "message checksum mismatch (corrupted stream)");
#endif
    m.header = h;
    m.offset = offset;
    if (h.flags & (kMsgDelta | kMsgXor)) {
        if (!chain)
            throw DecodeError(payload_at, "message " + std::to_string(h.sequence) +
                                              " is coded against the previous one, and this reader keeps none");
        chain->unpack_delta(h, stored_data, offset, m.payload);
    } else if (h.flags & kMsgCompressed) {
        m.payload.resize(h.raw_bytes);
        const size_t n = ZSTD_decompress(m.payload.data(), m.payload.size(), stored_data, h.stored_bytes);
        if (ZSTD_isError(n) || n != h.raw_bytes)
            throw DecodeError(payload_at, std::string("bad zstd payload: ") +
                                              (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "length differs from header"));
    } else {
        m.payload.assign(stored_data, stored_data + h.stored_bytes);
    }
    if (chain) chain->remember(h.sequence, m.payload);
}

void decode_message(const uint8_t* data, size_t size, uint64_t offset, Message& m, MessageChain* chain) {
    if (size < sizeof(MessageHeader))
        throw DecodeError(offset, "truncated message header (" + std::to_string(size) + " bytes)");
    MessageHeader h;
    std::memcpy(&h, data, sizeof h);
    if (h.magic == kMessageMagic && h.stored_bytes != size - sizeof h)
        throw DecodeError(offset + 20, "message announces " + std::to_string(h.stored_bytes) + " bytes, carries " +
                                           std::to_string(size - sizeof h));
    check_and_unpack(h, data + sizeof h, offset, m, chain);
}

bool CaptureReader::next(Message& m) {
    const uint64_t size = source_->size();
    if (ended_) {
        if (offset_ != size) throw DecodeError(offset_, std::to_string(size - offset_) + " bytes after the end record");
        return false;
    }
    if (offset_ == size) {
        if (header_.features & kFileHasEndRecord)
            throw DecodeError(offset_, "the capture was cut after message " +
                                           (expected_sequence_ ? std::to_string(expected_sequence_ - 1) : "(none)") +
                                           ", frame " + std::to_string(expected_frame_) +
                                           ": it has no end record (the program or its capture ended before it was "
                                           "complete, or the disk was full); everything before is intact");
        return false;
    }
    if (size - offset_ < sizeof(MessageHeader))
        throw DecodeError(offset_, "truncated message header (" + std::to_string(size - offset_) + " bytes left)");
    MessageHeader h;
    source_->read(offset_, &h, sizeof h);
    if (h.magic != kMessageMagic) throw DecodeError(offset_, "bad message magic (corrupted stream)");
    if (h.sequence != expected_sequence_)
        throw DecodeError(offset_ + 8, "message sequence " + std::to_string(h.sequence) + ", expected " +
                                           std::to_string(expected_sequence_));
    if (h.frame != expected_frame_)
        throw DecodeError(offset_ + 16, "message of frame " + std::to_string(h.frame) + ", expected frame " +
                                            std::to_string(expected_frame_));
    if (h.raw_bytes > kMaxMessageBytes || h.stored_bytes > kMaxMessageBytes)
        throw DecodeError(offset_ + 20, "absurd message length (" + std::to_string(h.stored_bytes) + " stored, " +
                                            std::to_string(h.raw_bytes) + " raw; limit " +
                                            std::to_string(kMaxMessageBytes) + ")");
    const uint64_t payload_at = offset_ + sizeof(MessageHeader);
    if (h.stored_bytes > size - payload_at)
        throw DecodeError(payload_at, "truncated message: " + std::to_string(h.stored_bytes) + " bytes announced, " +
                                          std::to_string(size - payload_at) + " left");
    std::vector<uint8_t> stored(h.stored_bytes);
    source_->read(payload_at, stored.data(), stored.size());
    if ((h.flags & kMsgStreamEnd) && h.stored_bytes == 0) {  // the end record
        offset_ = payload_at;
        ended_ = true;
        return next(m);
    }
    check_and_unpack(h, stored.data(), offset_, m, &chain_, header_.version >= 2);
    offset_ = payload_at + h.stored_bytes;
    expected_sequence_++;
    if (h.flags & kMsgFrameEnd) expected_frame_++;
    return true;
}

CaptureEnd capture_end(const std::string& path) {
    CaptureEnd end;
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) {
        end.why = "cannot open " + path + ": " + std::strerror(errno);
        return end;
    }
    FileHeader fh{};
    if (std::fread(&fh, sizeof fh, 1, f) != 1 || std::memcmp(fh.magic, kFileMagic, sizeof kFileMagic) != 0 ||
        fh.header_bytes < sizeof fh || fh.header_bytes > 4096) {
        std::fclose(f);
        end.why = "no whole file header";
        return end;
    }
    uint64_t offset = fh.header_bytes;
    for (;;) {
        MessageHeader h{};
        if (std::fseek(f, long(offset), SEEK_SET) != 0 || std::fread(&h, sizeof h, 1, f) != 1) break;
        if (h.magic != kMessageMagic || h.stored_bytes > kMaxMessageBytes) break;
        const uint64_t next = offset + sizeof h + h.stored_bytes;
        if (std::fseek(f, 0, SEEK_END) != 0 || uint64_t(std::ftell(f)) < next) break;
        if ((h.flags & kMsgStreamEnd) && h.stored_bytes == 0) {
            end.complete = uint64_t(std::ftell(f)) == next;
            if (!end.complete) end.why = "bytes after its end record";
            std::fclose(f);
            return end;
        }
        end.messages++;
        if (h.flags & kMsgFrameEnd) end.frames++;
        offset = next;
    }
    std::fclose(f);
    end.complete = !(fh.features & kFileHasEndRecord);  // a writer before end records: cannot tell
    if (!end.complete)
        end.why = "cut after " + std::to_string(end.messages) + " whole messages (" + std::to_string(end.frames) +
                  " frames): no end record";
    return end;
}

}  // namespace glcast
