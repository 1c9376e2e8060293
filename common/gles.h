// What an OpenGL ES context lacks that desktop GL has, for the queries glcast makes of its own
// (the shim's size queries, the slave's, the state guards around glcast's passes and
// read-backs): asking an ES context what its version lacks raises GL_INVALID_ENUM, which the
// program's next glGetError would see. Where a value is lacking, GL's default holds there (0: no
// row length, no skipping, no swapping), as the context behaves.
//
// `es`: the ES version times 10 (30: ES 3.0), 0 for desktop GL.
#pragma once

#include <cstdint>

namespace glcast {

int gles_version(const char* gl_version);      // of glGetString(GL_VERSION)
bool gles_lacks(uint32_t pname, int es);       // as glGetIntegerv's pname
bool gles_lacks_tex_level_query(int es);       // glGetTexLevelParameter is ES 3.1's
bool gles_lacks_buffer_read(int es);           // glGetBufferSubData is desktop GL's

}  // namespace glcast
