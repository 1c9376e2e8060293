// glXGetProcAddress(ARB) and eglGetProcAddress hand out our wrapper for every function the
// driver has, so programs that fetch their GL entry points are captured like linked ones.
// The lookups themselves are not part of the stream: a slave resolves its own functions.
#include <cstring>

#include "glcast_commands.h"
#include "glcast_special.h"
#include "interceptor/dl_hooks.h"
#include "interceptor/shim.h"
#include "protocol/command_info.h"

namespace glcast {

template <class Ret>
static Ret ours_if_real(const char* name, Ret real_result) {
    if (!real_result || !name) return real_result;
    const int op = opcode_by_name(name);
    return op >= 0 ? reinterpret_cast<Ret>(kEntryPoints[op]) : real_result;
}

__GLXextFuncPtr special::glXGetProcAddress(glXGetProcAddress_fn real, CallScope&, const GLubyte* procName) {
    return ours_if_real(reinterpret_cast<const char*>(procName), real(procName));
}

__GLXextFuncPtr special::glXGetProcAddressARB(glXGetProcAddressARB_fn real, CallScope&, const GLubyte* procName) {
    return ours_if_real(reinterpret_cast<const char*>(procName), real(procName));
}

__eglMustCastToProperFunctionPointerType special::eglGetProcAddress(eglGetProcAddress_fn real, CallScope&,
                                                                    const char* procname) {
    note_egl_in_use();
    return ours_if_real(procname, real(procname));
}

}  // namespace glcast
