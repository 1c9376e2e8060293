// glLockArraysEXT promises that the locked elements stay unchanged until unlock, and lets the
// driver read all of them: the shim ships the locked range with every draw in between.
#include "glcast_encode.h"
#include "glcast_special.h"
#include "interceptor/client_arrays.h"
#include "interceptor/shim.h"

namespace glcast {

void special::glLockArraysEXT(glLockArraysEXT_fn real, CallScope& scope, GLint first, GLsizei count) {
    real(first, count);
    lock_client_arrays(first, count);
    if (scope.recording())
        scope.record([&](Encoder& e, SizeQueries& sz) { encode_glLockArraysEXT(e, sz, first, count); });
}

void special::glUnlockArraysEXT(glUnlockArraysEXT_fn real, CallScope& scope) {
    real();
    unlock_client_arrays();
    if (scope.recording()) scope.record([&](Encoder& e, SizeQueries& sz) { encode_glUnlockArraysEXT(e, sz); });
}

}  // namespace glcast
