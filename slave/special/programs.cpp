// Uniform locations: the master's reply of glGetUniformLocation is mapped to the slave's own
// answer, per program, so glUniform* calls address the same variable on both.
#include "master/gl_headers.h"
#include "slave/replayer.h"

namespace glcast::slave::replay_special {

void glGetUniformLocation(Replayer& r, const Call& c) {
    const GLuint program = r.name<GLuint>(Ns::program, c, 0);
    const char* name = r.string(c, 1);
    const GLint slave = r.gl<decltype(&::glGetUniformLocation)>(OP_glGetUniformLocation)(program, name);
    const auto master = int32_t(uint32_t(c.ret.bits));
    if (master >= 0 && slave >= 0) r.set_uniform_location(c.args[0].bits, master, slave);
}

// Attribute locations index the context's vertex-array state, which every program shares, so
// they are not mapped: the slave's linker must assign what the master's did (the same driver
// does). The slave asks too, and a difference is an error the replay reports, not a silent
// misdraw.
void glGetAttribLocation(Replayer& r, const Call& c) {
    const GLuint program = r.name<GLuint>(Ns::program, c, 0);
    const char* name = r.string(c, 1);
    const GLint slave = r.gl<decltype(&::glGetAttribLocation)>(OP_glGetAttribLocation)(program, name);
    const auto master = int32_t(uint32_t(c.ret.bits));
    if (slave != master)
        throw ReplayError(std::string("attribute \"") + (name ? name : "") + "\" is at location " +
                          std::to_string(slave) + " on the slave, " + std::to_string(master) + " on the master");
}

}  // namespace glcast::slave::replay_special
