#include "common/environment.h"
#include "common/immortal.h"

#include <cerrno>
#include <cstdlib>
#include <mutex>
#include <optional>

namespace glcast {

std::string env_text(const char* name) {
    const char* text = std::getenv(name);
    return text ? text : "";
}

uint64_t env_uint(const char* name, uint64_t min, uint64_t max, uint64_t fallback) {
    const std::string text = env_text(name);
    if (text.empty()) return fallback;
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
    if (errno || *end || text[0] == '-' || text[0] == '+' || text[0] == ' ' || v < min || v > max)
        throw EnvironmentError(std::string(name) + "=" + text + " is not an integer from " + std::to_string(min) +
                               " to " + std::to_string(max));
    return v;
}

bool env_flag(const char* name, bool fallback) {
    const std::string text = env_text(name);
    if (text.empty()) return fallback;
    if (text == "0" || text == "1") return text == "1";
    throw EnvironmentError(std::string(name) + "=" + text + " is neither 0 nor 1");
}

Environment read_environment() {
    Environment e;
    e.shim = env_text("GLCAST_SHIM");
    e.machine = env_text("GLCAST_MACHINE");
    e.keys = env_text("GLCAST_KEYS");
    e.insecure = env_flag("GLCAST_INSECURE", false);
    e.catch_up_bytes = env_uint("GLCAST_CATCH_UP_MB", 1, uint64_t(1) << 20, 2048) << 20;
    e.egl_config_id = uint32_t(env_uint("GLCAST_EGL_CONFIG_ID", 0, INT32_MAX, 0));
    e.test_present_log = env_text("GLCAST_TEST_PRESENT_LOG");
    e.test_present_log_dir = env_text("GLCAST_TEST_PRESENT_LOG_DIR");
    return e;
}

const Environment& environment() {
    // Immortal: the shim reads it from calls a program makes after static destruction.
    static Immortal<std::optional<Environment>> read;
    static Immortal<std::string> error;
    static std::once_flag once;
    std::call_once(once, [] {
        try {
            *read = read_environment();
        } catch (const EnvironmentError& e) {
            *error = e.what();
        }
    });
    if (!*read) throw EnvironmentError(*error);
    return **read;
}

}  // namespace glcast
