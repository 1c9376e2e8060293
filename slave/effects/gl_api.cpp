#include "slave/effects/gl_api.h"

namespace glcast::slave::effects {

bool GlApi::load(const std::function<void*(const char*)>& resolve, std::string& error) {
#define GLCAST_EFFECTS_LOAD_CORE(name)                                                          \
    name = reinterpret_cast<decltype(name)>(resolve(#name));                                    \
    if (!name) {                                                                                \
        error = "the slave's driver has no " #name ", which the injected passes need (GL 3.3)"; \
        return false;                                                                           \
    }
#define GLCAST_EFFECTS_LOAD_COMPAT(name) name = reinterpret_cast<decltype(name)>(resolve(#name));
    GLCAST_EFFECTS_GL_CORE(GLCAST_EFFECTS_LOAD_CORE)
    GLCAST_EFFECTS_GL_COMPAT(GLCAST_EFFECTS_LOAD_COMPAT)
#undef GLCAST_EFFECTS_LOAD_CORE
#undef GLCAST_EFFECTS_LOAD_COMPAT
    return true;
}

}  // namespace glcast::slave::effects
