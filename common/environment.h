// Every GLCAST_* variable that the glcast command, its slaves and its keepers read: read once,
// at the first use, and checked here, so that a bad value stops the command with the
// variable's name instead of turning silently into a default. The shim's own variables are read
// with the same parsers (interceptor/config.h); docs/environment.md lists them all.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace glcast {

// A GLCAST_* variable with a value it may not have; the message names it and what it may be.
struct EnvironmentError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The variable's text; empty when unset.
std::string env_text(const char* name);
// An integer in [min, max]; `fallback` when unset or empty. Throws EnvironmentError otherwise.
uint64_t env_uint(const char* name, uint64_t min, uint64_t max, uint64_t fallback);
// 0 or 1; `fallback` when unset or empty.
bool env_flag(const char* name, bool fallback);

struct Environment {
    std::string shim;                  // GLCAST_SHIM: libglcast.so to preload (default: beside glcast)
    std::string machine;               // GLCAST_MACHINE: this machine's name in display configs
    std::string keys;                  // GLCAST_KEYS: the folder of this machine's CURVE keys
    bool insecure = false;             // GLCAST_INSECURE=1: unauthenticated endpoints off loopback allowed
    uint64_t catch_up_bytes = uint64_t(2048) << 20;  // GLCAST_CATCH_UP_MB: one catching up's budget
    uint32_t egl_config_id = 0;        // GLCAST_EGL_CONFIG_ID: the EGL config for windows (0: chosen)
    std::string test_present_log;      // GLCAST_TEST_PRESENT_LOG: when each frame was shown (tests)
    std::string test_present_log_dir;  // GLCAST_TEST_PRESENT_LOG_DIR: glcast run's slaves' logs there
};

// Reads and checks every variable now; throws EnvironmentError on the first bad one.
Environment read_environment();
// This process's, read at the first call (which throws on a bad value, as does every later one).
const Environment& environment();

}  // namespace glcast
