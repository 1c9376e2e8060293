// Program binaries (commands.yaml answered_by_shim): a binary is one driver's own format, which
// a slave with another driver or version cannot load. The shim reports no binary format, so
// programs that ask compile from source; a program that loads a cached binary without asking
// gets a load that fails, as GL lets any load fail (the driver is handed the format with no
// bytes, and sets GL_LINK_STATUS to false), and the slave replays the same failing load. Such
// programs check the link status and compile from source (Qt does), and the sources travel.
#include "glcast_encode.h"
#include "glcast_special.h"
#include "interceptor/shim.h"

namespace glcast {

void special::glProgramBinary(glProgramBinary_fn real, CallScope& scope, GLuint program, GLenum binaryFormat,
                     const void* binary, GLsizei length) {
    (void)length;
    real(program, binaryFormat, binary, 0);
    if (scope.recording())
        scope.record([&](Encoder& e, SizeQueries& sz) { encode_glProgramBinary(e, sz, program, binaryFormat, binary, 0); });
}

}  // namespace glcast
