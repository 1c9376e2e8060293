// The GL functions the injected passes call: the slave's one typed table (glcast_gl_api.h,
// generated), resolved from the slave's backend (the slave links no GL library). A pass calls
// `gl.glEnable(...)`; compatibility-only functions are asked for with `gl.has(OP_...)` first.
#pragma once

#include <string>

#include "glcast_gl_api.h"

namespace glcast::slave::effects {

using glcast::GlApi;

// The GL 3.3 core functions every pass may use: "" when the driver has them all, else a
// message naming the first it lacks.
std::string missing_pass_function(const GlApi& gl);

}  // namespace glcast::slave::effects
