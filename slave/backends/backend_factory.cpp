#include "slave/backends/backends_internal.h"

namespace glcast::slave {

std::unique_ptr<Backend> make_backend(const std::string& kind, std::string& error) {
    if (kind == "egl") return make_egl_backend(error);
    if (kind == "osmesa") return make_osmesa_backend(error);
    if (kind == "window") return make_window_backend(error);
    if (kind == "null") return make_null_backend(error);
    error = "unknown context backend \"" + kind + "\" (known: egl, osmesa, window, null)";
    return nullptr;
}

}  // namespace glcast::slave
