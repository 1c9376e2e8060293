// Uniform locations: the master's reply of glGetUniformLocation is mapped to the slave's own
// answer, per program, so glUniform* calls address the same variable on both.
#include <regex>
#include <string>

#include "common/gl_headers.h"
#include "slave/call_replay.h"
#include "slave/replay_limits.h"
#include "slave/slave_context.h"

namespace glcast::slave::replay_special {

void glGetUniformLocation(CallReplay& r, const Call& c) {
    const GLuint program = r.name<GLuint>(Ns::program, c, 0);
    const char* name = r.string(c, 1);
    const GLint slave = r.api().glGetUniformLocation(program, name);
    const auto master = int32_t(uint32_t(c.ret.bits));
    if (master >= 0 && slave >= 0) r.set_uniform_location(c.args[0].bits, master, slave);
}

// Rotated tiles with a program projection from the display config (docs/wall.md): vertex
// shaders get a last step, gl_Position = glcast_clip * gl_Position, the program's main renamed.
// glcast_clip is set before draws (TileAdapter::correct_shader_program).
void glShaderSource(CallReplay& r, const Call& c) {
    const GLuint shader = r.name<GLuint>(Ns::program, c, 0);
    const GLsizei count = r.value<GLsizei>(c, 1);
    // The driver reads count strings and, when there are lengths, count lengths.
    if (count < 0 || size_t(count) > c.args[2].strings.size())
        throw ReplayError("glShaderSource of " + std::to_string(count) + " strings, the stream has " +
                          std::to_string(c.args[2].strings.size()));
    r.need(c, 3, count);
    const char* const* strings = r.strings(c, 2);
    const auto* lengths = static_cast<const GLint*>(r.in(c, 3));
    auto source = [&r](GLuint s, GLsizei n, const char* const* text, const GLint* lengths) {
        r.api().glShaderSource(s, n, text, lengths);
    };
    if (!r.turns_vertex_shader(c.args[0].bits)) {
        source(shader, count, strings, lengths);
        return;
    }
    std::string text;
    for (GLsizei i = 0; i < count; ++i)
        if (strings[i]) text += lengths && lengths[i] >= 0 ? std::string(strings[i], size_t(lengths[i])) : std::string(strings[i]);
    static const std::regex main_function(R"(\bvoid\s+main\s*\()");
    if (!std::regex_search(text, main_function)) {
        source(shader, count, strings, lengths);
        return;
    }
    text = std::regex_replace(text, main_function, "void glcast_program_main(", std::regex_constants::format_first_only);
    text += "\nuniform mat4 glcast_clip;\nvoid main() { glcast_program_main(); gl_Position = glcast_clip * gl_Position; }\n";
    const char* patched = text.c_str();
    source(shader, 1, &patched, nullptr);
}

// Attribute locations index the context's vertex-array state, which every program shares, so
// they are not mapped: the slave's linker must assign what the master's did (the same driver
// does). The slave asks too, and a difference is an error the replay reports, not a silent
// misdraw.
void glGetAttribLocation(CallReplay& r, const Call& c) {
    const GLuint program = r.name<GLuint>(Ns::program, c, 0);
    const char* name = r.string(c, 1);
    const GLint slave = r.api().glGetAttribLocation(program, name);
    const auto master = int32_t(uint32_t(c.ret.bits));
    if (slave != master)
        throw ReplayError(std::string("attribute \"") + (name ? name : "") + "\" is at location " +
                          std::to_string(slave) + " on the slave, " + std::to_string(master) + " on the master");
}

}  // namespace glcast::slave::replay_special
