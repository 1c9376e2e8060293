// Context backends of a slave: where its GL contexts and their window framebuffers come from.
//
// The program's window framebuffer (name 0) is the backend's default framebuffer, of the
// master's drawable size and in the format of an X11 TrueColor window (8-bit B, G, R, no
// alpha; 24-bit depth, 8-bit stencil): an EGL pbuffer, an OSMesa BGRA buffer, or a GLFW
// window. Not an FBO: Mesa rasterizes window-system framebuffers with another orientation and,
// for BGRA formats, other fast paths, so only a real window-format buffer replays pixel-exactly.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace glcast::slave {

// The context the master's program asked for (from its glXCreateContextAttribsARB /
// eglCreateContext attributes); major 0 means "whatever compatibility context is best".
struct ContextRequest {
    int major = 0, minor = 0;
    bool es = false;                 // OpenGL ES (major 0: ES 1); core means nothing then
    bool core = false;               // core profile (else compatibility)
    bool forward_compatible = false;
    bool debug = false;
    bool no_error = false;           // KHR_no_error: the driver may skip its error checks
    // Samples of the program's framebuffer (glcast.context_format; 0: single-sampled). A
    // backend that cannot match it says so once and renders single-sampled.
    int samples = 0;
    // Bits of the program's window framebuffer (glcast.context_bits; else a slave's own: 0, 24, 8).
    int alpha = 0, depth = 24, stencil = 8;
};

// A backend is called from one thread at a time (the slave replays on one thread) and does no
// locking of its own; a context released on one thread may be made current on another.
class Backend {
public:
    virtual ~Backend() = default;
    virtual const char* name() const = 0;

    // Creates the context for stream context `id`, sharing objects with the context of
    // `share_id` (0: none). False with `error` set when the request cannot be met.
    virtual bool create_context(uint32_t id, uint32_t share_id, const ContextRequest& request,
                                std::string& error) = 0;
    // Makes context `id` current on the calling thread with a default framebuffer of
    // width x height (created, or replaced when the size changed; 0 x 0: none yet), or
    // releases the current context when id is 0.
    virtual bool make_current(uint32_t id, int width, int height, std::string& error) = 0;
    virtual void destroy_context(uint32_t id) = 0;

    // A GL entry point of this backend's driver (resolved for the current API), or nullptr.
    virtual void* proc_address(const char* name) = 0;

    // Shows the finished frame of the current context (a swap). Headless backends do nothing.
    virtual void present() = 0;

    // Where on the screen the window backend puts its windows (a tile's place on the canvas, so
    // that the tiles of a wall on one screen form its image). Others ignore it.
    virtual void set_position(int x, int y) { (void)x, (void)y; }
};

// kind: "egl" (EGL surfaceless: headless, also the path for GPUs), "osmesa" (software),
// "window" (GLFW window; needs a display), "null" (no driver: distribution benchmarks).
// nullptr with `error` set when unavailable.
std::unique_ptr<Backend> make_backend(const std::string& kind, std::string& error);

}  // namespace glcast::slave
