// How the generated recording functions (glcast_recording_gl.cpp) write one argument down:
// its bits as a Call would hold them, and its text. Internal to the recording GL.
#pragma once

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <string>
#include <type_traits>

#include "common/gl_headers.h"
#include "protocol/command_info.h"
#include "slave/backends/recording/recording_gl.h"

namespace glcast::slave::recording {

enum class Show { Plain, Enum, Text };

// The gl.xml group of parameter `index` of the call's command (names an enum by its group's
// name: GL_TRIANGLES rather than GL_LINE_BIT for 4), or -1.
inline int group_of(const RecordedCall& c, size_t index) {
    const CommandInfo* info = command_info(c.opcode);
    return info && info->params && index < info->param_count ? info->params[index].group : -1;
}

template <class T>
void arg(RecordedCall& c, T v, Show show = Show::Plain) {
    uint64_t bits = 0;
    char text[64];
    if constexpr (std::is_pointer_v<T>) {
        bits = uint64_t(uintptr_t(v));
        if (!v) std::snprintf(text, sizeof text, "NULL");
        else if (show == Show::Text) {  // const GLchar *: a string the caller passes
            if (!c.args.empty()) c.text += ", ";
            c.args.push_back(bits);
            c.text += '"';
            c.text += reinterpret_cast<const char*>(v);
            c.text += '"';
            return;
        } else std::snprintf(text, sizeof text, "0x%" PRIxPTR, uintptr_t(v));
    } else if constexpr (std::is_floating_point_v<T>) {
        std::memcpy(&bits, &v, sizeof v);
        std::snprintf(text, sizeof text, "%g", double(v));
    } else if constexpr (std::is_signed_v<T>) {
        bits = uint64_t(int64_t(v));
        std::snprintf(text, sizeof text, "%" PRId64, int64_t(v));
    } else {
        bits = uint64_t(v);
        const int group = show == Show::Enum ? group_of(c, c.args.size()) : -1;
        const char* name = show != Show::Enum ? nullptr : group >= 0 ? enum_name(uint32_t(v), group) : enum_name(uint32_t(v));
        if (name) std::snprintf(text, sizeof text, "%s", name);
        else std::snprintf(text, sizeof text, show == Show::Enum ? "0x%" PRIx64 : "%" PRIu64, uint64_t(v));
    }
    if (!c.args.empty()) c.text += ", ";
    c.args.push_back(bits);
    c.text += text;
}

template <class T>
T reply(const RecordedCall& c) {
    if constexpr (std::is_void_v<T>) {
        return;
    } else if constexpr (std::is_pointer_v<T>) {
        return reinterpret_cast<T>(uintptr_t(c.reply));
    } else if constexpr (std::is_floating_point_v<T>) {
        T v;
        std::memcpy(&v, &c.reply, sizeof v);
        return v;
    } else {
        return static_cast<T>(c.reply);
    }
}

// A generator's output: n new names (glGenTextures(n, textures)).
template <class T>
void generate(RecordingGl& gl, T* names, int64_t n) {
    if (!names || n <= 0) return;
    const uint32_t first = gl.new_names(uint32_t(n));
    for (int64_t i = 0; i < n; ++i) names[i] = T(first + uint32_t(i));
}

}  // namespace glcast::slave::recording
