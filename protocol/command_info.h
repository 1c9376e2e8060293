// Descriptions of every opcode's wire layout. The tables are generated (glcast_commands.cpp);
// these types are shared by the encoder, the decoder and the dump.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>

#include "glcast_commands.h"

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

// What a command means beyond its wire layout, from codegen/annotations/semantics.yaml
// (docs/codegen.md). A twin (a gl.xml alias, or an unaliased extension command with the same
// meaning) carries the same properties as its core command.
// (No enumerator is called None: Xlib defines it as a macro.)
enum class MatrixOp : uint8_t { Nothing, Mode, Push, Pop, Load, Multiply };
enum class RedrawKind : uint8_t { Ignored, State, Draw, Begin, End, NewList, EndList, Pixels, ProgramState, Copy, Clear };
enum class WindowMapping : uint8_t {
    Nothing, Viewport, Scissor, ViewportIndexed, ScissorIndexed, ViewportArray, ScissorArray,
    LineWidth, PointSize, PixelZoom, Blit, DrawFramebuffer,
};
enum class ObjectAccess : uint8_t { Nothing, Bound, Named };
enum class ContextOp : uint8_t { Nothing, Create, MakeCurrent, Swap, Destroy };
enum class ListOp : uint8_t { Nothing, New, Call, CallMany };
enum SemanticFlags : uint8_t {
    kSemDeletes = 1,        // releases the names it is given
    kSemLinksProgram = 2,   // links a program: its uniforms start over
    kSemFrameOnly = 4,      // changes only the pixels of the framebuffer drawn to
    kSemWindowQuery = 8,    // glGet*v of a pname that may describe the window system
    kSemEgl = 16,           // an EGL call (attribute lists use EGL's keys)
};

struct CommandSemantics {
    uint32_t twin;              // opcode of the core command it means the same as; its own if none
    MatrixOp matrix;            // on the stack glMatrixMode selects
    RedrawKind redraw;          // what the frame recorder keeps of it
    WindowMapping window;       // window coordinates or pixel sizes a tile maps
    int8_t window_params[10];   // ... taken from these parameters, in the mapping's order
    StateGroup state;           // the context state it sets
    int8_t state_key[2];        // parameters saying which entry of the group (-1: none)
    ObjectAccess writes;        // object contents it writes ...
    Ns writes_ns;               // ... of this namespace ...
    int8_t writes_param;        // ... found by this parameter (a binding target, or a name)
    int8_t program_use;         // the parameter naming the program it makes current, or -1
    int8_t shader_type;         // the parameter giving the type of the shader it returns, or -1
    ContextOp context;          // a window-system call the slave follows ...
    int8_t context_param;       // ... with this parameter (attributes, drawable, context), or -1
    ListOp list;                // records or runs display lists
    int8_t subject_params[2];   // what it acts on: the matrix stack (MatrixOp::Mode), the list and
                                // glNewList's mode (ListOp), the program linked (kSemLinksProgram); -1: none
    uint8_t flags;              // SemanticFlags
    uint8_t redraw_first_count; // > 0: kept for redraw only when the first parameter is one of
    const uint32_t* redraw_first_values;
    int8_t primitive_param;     // a draw's primitive mode (gl.xml group PrimitiveType), or -1
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
    CommandSemantics sem;
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
// A pname of the glGet*v calls marked kSemWindowQuery that describes the window system
// (double buffering, the window's draw and read buffers): semantics.yaml window_system_pnames.
bool is_window_system_pname(uint32_t pname);

}  // namespace glcast
