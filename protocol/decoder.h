// Reading the stream back: capture files and messages (CaptureReader), and tuples
// (decode_tuple). The decoder distrusts its input: every length is checked
// against what is left, every opcode against the table, and a violation throws DecodeError
// naming the byte offset. Nothing is allocated from an unchecked length.
#pragma once

#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "protocol/command_info.h"
#include "protocol/format.h"

namespace glcast {

class DecodeError : public std::runtime_error {
public:
    DecodeError(uint64_t offset, const std::string& what);
    uint64_t offset() const { return offset_; }

private:
    uint64_t offset_;
};

// Bounds-checked little-endian reads over one buffer; `base` is the buffer's position in
// the file, for error messages.
class ByteReader {
public:
    ByteReader(const uint8_t* data, size_t size, uint64_t base) : data_(data), size_(size), base_(base) {}
    template <class T>
    T get() {
        T v;
        need(sizeof v, "value");
        std::memcpy(&v, data_ + pos_, sizeof v);
        pos_ += sizeof v;
        return v;
    }
    const uint8_t* bytes(size_t n, const char* what) {
        need(n, what);
        const uint8_t* p = data_ + pos_;
        pos_ += n;
        return p;
    }
    size_t remaining() const { return size_ - pos_; }
    uint64_t offset() const { return base_ + pos_; }
    void need(size_t n, const char* what) const;

private:
    const uint8_t* data_;
    size_t size_;
    size_t pos_ = 0;
    uint64_t base_;
};

struct PtrRecord {
    PtrTag tag = PtrTag::Null;
    uint32_t count = 0;            // elements, for Data
    const uint8_t* data = nullptr; // count * wire_bytes(elem) bytes
    uint64_t value = 0;            // Offset / ClientAddress
};

struct Arg {
    uint64_t bits = 0;             // Value / Address: raw little-endian bits
    PtrRecord ptr;                 // pointer kinds
    std::vector<PtrRecord> strings;// StringArray, IndexArrays
    PtrRecord reply;               // Out / OutString: data from the reply part (tag Data)
};

struct Call {
    uint32_t opcode = 0;
    uint32_t context = 0;
    uint64_t offset = 0;           // file offset of the tuple header (or payload offset)
    const CommandInfo* info = nullptr;  // nullptr for synthetic opcodes
    std::vector<Arg> args;
    Arg ret;
    const uint8_t* body = nullptr; // raw body (synthetic tuples are parsed by their users)
    uint32_t body_bytes = 0;
};

// What one tuple may make the decoder allocate beyond its own bytes: each pointer record of a
// string or index-array list takes one byte on the wire and a PtrRecord (24 bytes) decoded.
struct DecodeLimits {
    uint32_t list_entries = 1u << 20;
};

// Decodes one tuple at the reader's position.
void decode_tuple(ByteReader& r, Call& call, const DecodeLimits& limits = DecodeLimits{});

struct Message {
    MessageHeader header{};
    uint64_t offset = 0;           // file offset of the message header
    std::vector<uint8_t> payload;  // decompressed
};

// Byte source of a capture: a file, or memory (tests and the fuzzer).
class Source {
public:
    virtual ~Source() = default;
    virtual uint64_t size() const = 0;
    virtual void read(uint64_t offset, void* dst, size_t n) = 0;  // within size()
};
std::unique_ptr<Source> open_file_source(const std::string& path);  // throws std::runtime_error
std::unique_ptr<Source> memory_source(const uint8_t* data, size_t size);

// Where messages come from: a capture file, or a slave's subscription to a live master.
class MessageSource {
public:
    virtual ~MessageSource() = default;
    virtual bool next(Message& m) = 0;  // false at the end of the stream; throws DecodeError
};

// What a reader of inter-frame coded messages (kMsgDelta) keeps: the last payload it unpacked and
// its sequence number, the prefix of the next message. One per stream read in order.
class MessageChain {
public:
    MessageChain();
    ~MessageChain();
    MessageChain(const MessageChain&) = delete;
    MessageChain& operator=(const MessageChain&) = delete;
    // Unpacks a kMsgDelta message (stored -> out, raw_bytes long); throws DecodeError when the
    // chain does not end at message sequence - 1 (the reader started after it) or zstd refuses.
    void unpack_delta(const MessageHeader& h, const uint8_t* stored, uint64_t offset, std::vector<uint8_t>& out);
    void remember(uint64_t sequence, const std::vector<uint8_t>& payload);
    void forget() { valid_ = false; }
    bool holds(uint64_t sequence) const { return valid_ && sequence_ == sequence; }

private:
    bool valid_ = false;
    uint64_t sequence_ = 0;
    std::vector<uint8_t> payload_;
    uint32_t payload_crc_ = 0;  // what a bound message (kMsgBound) says its predecessor's is
    void* dctx_ = nullptr;  // ZSTD_DCtx
};

// Checks and unpacks one framed message held in memory (header and stored payload, exactly
// `size` bytes); `offset` is where it starts, for errors. `chain`: the stream's previous message,
// needed for kMsgDelta messages, and advanced to this one. Throws DecodeError.
void decode_message(const uint8_t* data, size_t size, uint64_t offset, Message& m, MessageChain* chain = nullptr);

// How a capture file ends, from its message headers alone (nothing is decompressed): whether it
// has its end record (or was written before end records, which cannot tell), and how many whole
// messages and frames it holds before the end or the cut.
struct CaptureEnd {
    bool complete = false;
    uint64_t messages = 0, frames = 0;
    std::string why;  // when not complete: where and how it was cut
};
CaptureEnd capture_end(const std::string& path);

class CaptureReader : public MessageSource {
public:
    explicit CaptureReader(std::unique_ptr<Source> source);  // reads and checks the header
    const FileHeader& header() const { return header_; }
    bool next(Message& m) override;  // false at a clean end of file; throws DecodeError

private:
    std::unique_ptr<Source> source_;
    FileHeader header_{};
    uint64_t offset_ = 0;
    uint64_t expected_sequence_ = 0;
    uint64_t expected_frame_ = 0;
    bool ended_ = false;  // the end record was read
    MessageChain chain_;
};

}  // namespace glcast
