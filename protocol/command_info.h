// Descriptions of every opcode's wire layout. The tables are generated (glcast_commands.cpp);
// these types are shared by the encoder, the decoder and the dump.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>

namespace glcast {

// How one parameter or return value is encoded; see docs/stream-format.md.
enum class ArgKind : uint8_t {
    Value,          // fixed-size scalar of `wire`
    In,             // pointer record: data the call read
    Out,            // marker in the request, data in the reply
    String,         // pointer record of text
    OutString,      // marker in the request, text in the reply
    StringArray,    // u32 count, then that many pointer records
    Address,        // u64 pointer value, never dereferenced by a slave
    Deferred,       // pointer record: buffer offset or client address; data shipped at the draw
    AttribList,     // pointer record of a 0-terminated key/value list
    VisualAttribs,  // pointer record of glXChooseVisual's list
    VisualInfo,     // pointer record of an encoded XVisualInfo
    IndexArrays,    // u32 count, then that many pointer records (data or buffer offsets)
};

enum class Wire : uint8_t { U8, I8, U16, I16, U32, I32, U64, I64, F32, F64 };

inline constexpr size_t wire_bytes(Wire w) {
    switch (w) {
    case Wire::U8: case Wire::I8: return 1;
    case Wire::U16: case Wire::I16: return 2;
    case Wire::U32: case Wire::I32: case Wire::F32: return 4;
    default: return 8;
    }
}

// How the dump shows a value (named to stay clear of Xlib's Display and Bool macros).
enum class ShowAs : uint8_t { Plain, Enum, Bitfield, Boolean, Text, Handle };

// Tags of a pointer record.
enum class PtrTag : uint8_t {
    Null = 0,        // the application passed NULL
    Data = 1,        // u32 element count, then the elements
    Offset = 2,      // u64 offset into a bound buffer object
    ClientAddress = 3,  // u64 client address; the data travels with the draw that reads it
    Reply = 4,       // an output: the data is in the reply part of the tuple
};

struct ParamInfo {
    const char* name;
    ArgKind kind;
    Wire wire;
    ShowAs show;
    int16_t group;  // gl.xml enum group of the value, -1 if none: names enums and bits
};

enum CommandFlags : uint8_t {
    kSerializable = 1,  // every parameter has an encoding; otherwise forwarded and counted
    kReplyOnly = 2,     // answers the application only; a slave need not execute it
    kDraw = 4,          // reads client arrays at draw time
    kHandwritten = 8,   // semantics in interceptor/special/
};

struct CommandInfo {
    const char* name;
    const ParamInfo* params;
    uint16_t param_count;
    bool has_ret;
    ParamInfo ret;
    uint8_t flags;
    const char* origin;  // GL_VERSION_x_y or the extension that introduced it
    const char* reason;  // why it is not serializable, or ""
};

// A value as its wire type: handles and other pointers by address, numbers by conversion.
template <class W, class T>
inline W to_wire(T v) {
    if constexpr (std::is_pointer_v<T>)
        return static_cast<W>(reinterpret_cast<uintptr_t>(v));
    else
        return static_cast<W>(v);
}

const CommandInfo* command_info(uint32_t opcode);  // nullptr for an unknown opcode
const char* enum_name(uint32_t value);             // nullptr when the registry has none
const char* enum_name(uint32_t value, int group);  // prefers the name of `group`, then any name
std::string bitfield_names(uint32_t value, int group);  // "GL_A_BIT | GL_B_BIT | 0x100"
uint32_t opcode_count();
uint64_t opcode_table_hash();
int opcode_by_name(const char* name);  // -1 if unknown

}  // namespace glcast
