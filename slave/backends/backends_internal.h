// Pieces the backends share with the factory; not part of the slave's interface.
#pragma once

#include <memory>
#include <string>

#include "slave/backend.h"

namespace glcast::slave {

std::unique_ptr<Backend> make_egl_backend(std::string& error);
std::unique_ptr<Backend> make_osmesa_backend(std::string& error);
std::unique_ptr<Backend> make_window_backend(std::string& error);
std::unique_ptr<Backend> make_null_backend(std::string& error);

// glfwInit and glfwTerminate are process-wide: every user of GLFW (the window backend, the stereo
// window) counts itself in; the last one out terminates it.
bool glfw_acquire(std::string& error);
void glfw_release();

// "3.3 core", "4.6 core forward-compatible debug", "compatibility (highest)": for messages.
inline std::string describe(const ContextRequest& r) {
    if (r.es) return "OpenGL ES " + std::to_string(r.major ? r.major : 1) + "." + std::to_string(r.minor);
    std::string s = r.major == 0 ? std::string("compatibility, highest version")
                                 : std::to_string(r.major) + "." + std::to_string(r.minor) +
                                       (r.core ? " core" : " compatibility");
    if (r.forward_compatible) s += " forward-compatible";
    if (r.debug) s += " debug";
    if (r.no_error) s += " no-error";
    return s;
}

}  // namespace glcast::slave
