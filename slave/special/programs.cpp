// Uniform locations: the master's reply of glGetUniformLocation is mapped to the slave's own
// answer, per program, so glUniform* calls address the same variable on both.
#include <string>

#include "common/gl_headers.h"
#include "slave/call_replay.h"
#include "slave/replay_limits.h"
#include "slave/shader_patch.h"
#include "slave/slave_context.h"

namespace glcast::slave::replay_special {

void glGetUniformLocation(CallReplay& r, const Call& c) {
    const GLuint program = r.name<GLuint>(Ns::program, c, 0);
    const char* name = r.string(c, 1);
    const GLint slave = r.api().glGetUniformLocation(program, name);
    const auto master = int32_t(uint32_t(c.ret.bits));
    if (master >= 0 && slave >= 0) r.set_uniform_location(c.args[0].bits, master, slave);
}

// Shaders a tile or a pass draws elsewhere than the master did (slave/shader_patch.h): vertex
// shaders get a last step, gl_Position = glcast_clip * gl_Position (set before draws by
// TileAdapter::correct_shader_program); fragment shaders that read gl_FragCoord read the master
// window's coordinates (TileAdapter::correct_fragcoord).
void glShaderSource(CallReplay& r, const Call& c) {
    const GLuint shader = r.name<GLuint>(Ns::program, c, 0);
    const GLsizei count = r.value<GLsizei>(c, 1);
    // The driver reads count strings and, when there are lengths, count lengths.
    if (count < 0 || size_t(count) > c.args[2].strings.size())
        throw ReplayError("glShaderSource of " + std::to_string(count) + " strings, the stream has " +
                          std::to_string(c.args[2].strings.size()));
    r.need(c, 3, count);
    const char* const* strings = r.strings(c, 2, 3);
    const auto* lengths = static_cast<const GLint*>(r.in(c, 3));
    const ShaderPatch patch = r.shader_patch(c.args[0].bits);
    std::string text;
    if (patch != ShaderPatch::Untouched)
        for (GLsizei i = 0; i < count; ++i)
            if (strings[i]) text += lengths && lengths[i] >= 0 ? std::string(strings[i], size_t(lengths[i])) : std::string(strings[i]);
    if (patch == ShaderPatch::Untouched || !patch_shader(text, patch)) {
        r.api().glShaderSource(shader, count, strings, lengths);
        return;
    }
    const char* patched = text.c_str();
    r.api().glShaderSource(shader, 1, &patched, nullptr);
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
