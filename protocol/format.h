// The glcast stream format (docs/stream-format.md). All integers little-endian.
//
//   capture file = FileHeader, then messages until end of file
//   message      = MessageHeader, payload (zstd-compressed when kMsgCompressed; against the
//                  previous message's payload as a zstd prefix when also kMsgDelta)
//   payload      = tuples
//   tuple        = u32 opcode, u32 context id, u32 body length, body
//                  (opcodes from kSynthBase on are glcast's own: codegen/annotations/synthetic.yaml)
//
// The wire carries the same messages without the file header (docs/stream-format.md).
#pragma once

#include <cstdint>

#include "glcast_synthetic.h"

namespace glcast {

inline constexpr char kFileMagic[8] = {'G', 'L', 'C', 'A', 'S', 'T', '\r', '\n'};

// Rows: what changed in each version.
//   1  first format: request/reply tuples, synthetic opcodes 0xFFFF0000.., zstd messages
//   2  inter-frame coding: a message may be compressed against the previous message's payload
//      (kMsgDelta: as a zstd prefix; kMsgXor: XORed with it, same length); key messages (without it) start a capture, a keeper's snapshot, and come
//      every kKeyIntervalMessages. Version 1 files are still read (they have no kMsgDelta).
inline constexpr uint32_t kFormatVersion = 2;
inline constexpr uint32_t kOldestReadableFormatVersion = 1;
// A key message at least this often, so that a reader can start near any message (a journal's
// SINCE, a slave joining from a keeper) by decoding from the key before it.
inline constexpr uint64_t kKeyIntervalMessages = 64;

struct FileHeader {
    char magic[8];
    uint32_t version;
    uint32_t header_bytes;     // sizeof(FileHeader): lets a newer reader skip added fields
    uint64_t opcode_table_hash;
    uint32_t opcode_count;
    uint32_t features;         // FileFeatures (0 in files of writers before them)
    char registry[32];         // registry revision, NUL-padded
};
static_assert(sizeof(FileHeader) == 64);

enum FileFeatures : uint32_t {
    // A complete capture ends with an end record: a message of flags kMsgStreamEnd and no payload.
    // A file that says so and has none was cut (the program or its capture ended first, a full
    // disk): its readers say where.
    kFileHasEndRecord = 1,
};

inline constexpr uint32_t kMessageMagic = 0x4d434c47;  // "GLCM"
enum MessageFlags : uint32_t {
    kMsgCompressed = 1,  // payload is one zstd frame
    kMsgFrameEnd = 2,    // the last tuple of the payload ends a frame (a swap)
    kMsgStreamEnd = 4,   // the program has ended: nothing follows (live streams; a capture's end record)
    kMsgDelta = 8,       // with kMsgCompressed: the zstd frame uses message sequence - 1's payload as its prefix
    kMsgXor = 16,        // with kMsgCompressed: the zstd frame holds the payload XOR message sequence - 1's (same length)
    // With kMsgDelta or kMsgXor: the stored payload starts with the CRC-32 of message sequence - 1's
    // payload (4 bytes, little endian), so that a message is never unpacked against another
    // stream's message of that number (a journal of another program, two streams mixed).
    kMsgBound = 32,
};
struct MessageHeader {
    uint32_t magic;
    uint32_t flags;
    uint64_t sequence;      // 0, 1, 2, ... per stream: a gap is loss
    uint32_t frame;         // frame number of the first tuple
    uint32_t stored_bytes;  // payload bytes following this header
    uint32_t raw_bytes;     // payload bytes after decompression
    uint32_t crc32;         // of the stored payload
};
static_assert(sizeof(MessageHeader) == 32);

inline constexpr uint32_t kMaxMessageBytes = 256u << 20;  // refuse larger length fields
inline constexpr uint32_t kTupleHeaderBytes = 12;

// Synthetic opcodes, their fields, writers and readers: codegen/annotations/synthetic.yaml,
// generated into glcast_synthetic.h (kSynthBase, kSynthClientArrays, ..., read_synthetic).

enum class ClientSlot : uint8_t {
    Vertex, Normal, Color, SecondaryColor, FogCoord, Index, EdgeFlag, TexCoord, Attrib
};

// glcast.context's api: the window system, and whether the context is OpenGL ES (a slave makes
// an ES context too: its version strings, extensions and shader rules are ES's).
enum class ContextApi : uint8_t { Glx, Egl, GlxEs, EglEs };
inline bool is_es(ContextApi api) { return api == ContextApi::GlxEs || api == ContextApi::EglEs; }

}  // namespace glcast
