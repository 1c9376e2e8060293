#include "slave/shader_patch.h"

#include <cctype>
#include <regex>

namespace glcast::slave {

namespace {

// A run of blanks or of word characters longer than any shader's (std::regex recurses once per
// character its \s+, \w+ or \d+ take: a stream's shader of megabytes of them would end the slave).
bool has_long_run(const std::string& text) {
    constexpr size_t kLongest = 4096;
    size_t run = 0;
    int kind = 0;  // 1: blank, 2: word character
    for (const char ch : text) {
        const auto u = static_cast<unsigned char>(ch);
        const int k = std::isspace(u) ? 1 : (std::isalnum(u) || ch == '_') ? 2 : 0;
        run = k && k == kind ? run + 1 : 1;
        kind = k;
        if (k && run > kLongest) return true;
    }
    return false;
}

bool with_clip_step(std::string& text) {
    static const std::regex main_function(R"(\bvoid\s+main\s*\()");
    if (!std::regex_search(text, main_function)) return false;
    text = std::regex_replace(text, main_function, "void glcast_program_main(", std::regex_constants::format_first_only);
    text += "\nuniform mat4 glcast_clip;\nvoid main() { glcast_program_main(); gl_Position = glcast_clip * gl_Position; }\n";
    return true;
}

// Where a declaration may go: after the #version line and every #extension directive (the
// driver refuses one after a declaration), outside any #if block around the last of them.
size_t declarations_start(const std::string& text) {
    size_t after = 0, pos = 0;
    int depth = 0, depth_after = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        size_t first = text.find_first_not_of(" \t\r", pos);
        if (first < end && text[first] == '#') {
            const size_t word = text.find_first_not_of(" \t", first + 1);
            auto is = [&](const char* d) { return word < end && text.compare(word, std::char_traits<char>::length(d), d) == 0; };
            if (is("if")) ++depth;  // #if, #ifdef, #ifndef
            else if (is("endif")) --depth;
            if (is("version") || is("extension")) after = end < text.size() ? end + 1 : end, depth_after = depth;
            else if (depth_after > 0 && depth < depth_after) after = end < text.size() ? end + 1 : end, depth_after = depth;
        }
        pos = end + 1;
    }
    return after;
}

bool with_window_fragcoord(std::string& text) {
    static const std::regex read(R"(\bgl_FragCoord\b)");
    static const std::regex redeclared(R"(\bin\s+(\w+\s+)?vec4\s+gl_FragCoord\b)");
    if (!std::regex_search(text, read) || std::regex_search(text, redeclared)) return false;
    const size_t at = declarations_start(text);
    static const std::regex es(R"(#\s*version\s+(100|\d+\s+es)\b)");
    const bool precision = std::regex_search(text.substr(0, at), es);
    std::string body = std::regex_replace(text.substr(at), read, "glcast_FragCoord");
    text = text.substr(0, at) + (precision ? "uniform highp vec4 glcast_fragcoord;\n" : "uniform vec4 glcast_fragcoord;\n") +
           "#define glcast_FragCoord vec4(gl_FragCoord.xy * (vec2(1.0) + glcast_fragcoord.xy) + glcast_fragcoord.zw, "
           "gl_FragCoord.zw)\n" +
           body;
    return true;
}

}  // namespace

bool patch_shader(std::string& text, ShaderPatch patch) {
    if (patch == ShaderPatch::Untouched || has_long_run(text)) return false;
    switch (patch) {
    case ShaderPatch::Clip: return with_clip_step(text);
    case ShaderPatch::WindowFragCoord: return with_window_fragcoord(text);
    case ShaderPatch::Untouched: return false;
    }
    return false;
}

void window_fragcoord(const double program[4], const double actual[4], float out[4]) {
    for (int axis = 0; axis < 2; ++axis) {
        const double scale = actual[axis + 2] > 0 && program[axis + 2] > 0 ? program[axis + 2] / actual[axis + 2] : 1.0;
        const double offset = actual[axis + 2] > 0 && program[axis + 2] > 0 ? program[axis] - actual[axis] * scale : 0.0;
        out[axis] = float(scale - 1.0);
        out[axis + 2] = float(offset);
    }
}

}  // namespace glcast::slave
