// The glcast stream format (docs/stream-format.md). All integers little-endian.
//
//   capture file = FileHeader, then messages until end of file
//   message      = MessageHeader, payload (zstd-compressed when kMsgCompressed)
//   payload      = tuples
//   tuple        = u32 opcode, u32 context id, u32 body length, body
//
// The wire carries the same messages without the file header (design.md 1).
#pragma once

#include <cstdint>

namespace glcast {

inline constexpr char kFileMagic[8] = {'G', 'L', 'C', 'A', 'S', 'T', '\r', '\n'};

// Rows: what changed in each version.
//   1  first format: request/reply tuples, synthetic opcodes 0xFFFF0000.., zstd messages
inline constexpr uint32_t kFormatVersion = 1;

struct FileHeader {
    char magic[8];
    uint32_t version;
    uint32_t header_bytes;     // sizeof(FileHeader): lets a newer reader skip added fields
    uint64_t opcode_table_hash;
    uint32_t opcode_count;
    uint32_t reserved;
    char registry[32];         // registry revision, NUL-padded
};
static_assert(sizeof(FileHeader) == 64);

inline constexpr uint32_t kMessageMagic = 0x4d434c47;  // "GLCM"
enum MessageFlags : uint32_t {
    kMsgCompressed = 1,  // payload is one zstd frame
    kMsgFrameEnd = 2,    // the last tuple of the payload ends a frame (a swap)
    kMsgStreamEnd = 4,   // the program has ended: nothing follows (live streams)
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

// Synthetic opcodes: tuples glcast adds to the application's calls (apitrace's FLAG_FAKE).
enum SyntheticOpcode : uint32_t {
    kSynthBase = 0xFFFF0000u,
    // Client arrays a draw reads, just before that draw's tuple (design.md 4).
    //   u32 array count, then per array: u8 slot kind, u32 slot index, i32 size, u32 type,
    //   i32 stride (effective), u8 normalized, u8 integer, u32 handle, u32 first byte,
    //   u8 cached (1: the slave's copy of `handle` is current; no data), else u32 bytes + data
    kSynthClientArrays = kSynthBase + 1,
    // Data written through a mapped buffer range, before the unmap/flush/draw that publishes it.
    //   u32 buffer name, u64 offset, u32 bytes, data
    kSynthBufferWrite = kSynthBase + 2,
    // A call that was forwarded but not serialized: u32 opcode, then the reason text.
    kSynthUnserialized = kSynthBase + 3,
    // Size of the drawable a context renders to, at make-current and when it changes.
    //   u64 drawable, i32 width, i32 height
    kSynthDrawableSize = kSynthBase + 4,
    // A context came into being (after its creation call's tuple): u32 context id,
    //   u64 the driver's context handle, u32 share context id (0: none), u8 api (0 GLX, 1 EGL)
    kSynthContext = kSynthBase + 5,
};
inline constexpr uint32_t kSynthCount = 6;  // kSynthBase + 0 .. kSynthBase + 5

enum class ClientSlot : uint8_t {
    Vertex, Normal, Color, SecondaryColor, FogCoord, Index, EdgeFlag, TexCoord, Attrib
};

}  // namespace glcast
