// Window backend: one GLFW window per context; the window's own default framebuffer is the
// program's window framebuffer (8-bit RGB, 24-bit depth, 8-bit stencil, double-buffered, like
// the program's GLX visual), and present() swaps it. Windows start hidden and a window is shown
// at its first present(), so a context that only shares objects (a loader thread's context)
// never shows an empty window.
//
// GLFW's rules apply: the backend must be created, and create_context/make_current/present
// called, on the process's main thread (window creation, resizing, showing and event polling
// are main-thread-only in GLFW). GLFW loads libGL itself; we link only libglfw.

#define GLFW_INCLUDE_NONE
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>
#include <GLFW/glfw3.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "slave/backends/backends_internal.h"
#include "slave/backends/context_backend.h"

namespace glcast::slave {
namespace {

// glfwInit/glfwTerminate are process-wide; count the backends that use them.
std::mutex g_glfw_mutex;
int g_glfw_users = 0;

std::string glfw_error() {
    const char* description = nullptr;
    const int code = glfwGetError(&description);
    if (code == GLFW_NO_ERROR) return "no GLFW error reported";
    return description ? description : "GLFW error " + std::to_string(code);
}

}  // namespace

bool glfw_acquire(std::string& error) {
    std::lock_guard<std::mutex> lock(g_glfw_mutex);
    if (!glfwInit()) {
        error = "window: glfwInit failed: " + glfw_error();
        return false;
    }
    ++g_glfw_users;
    return true;
}

void glfw_release() {
    std::lock_guard<std::mutex> lock(g_glfw_mutex);
    if (--g_glfw_users == 0) glfwTerminate();
}

namespace {

class WindowDriver : public DriverDefaults {
public:
    struct Context {
        GLFWwindow* window = nullptr;
        int width = 0, height = 0;  // the size last asked of the window
        bool shown = false;
    };
    static constexpr const char* name = "window";

    ~WindowDriver() {
        if (glfw_counted_) glfw_release();
    }

    bool init(std::string& error) {
        glfw_counted_ = glfw_acquire(error);
        return glfw_counted_;
    }

    bool create(const Context* share, const ContextRequest& request, Context& out, std::string& error) {
        glfwDefaultWindowHints();
        glfwWindowHint(GLFW_CLIENT_API, request.es ? GLFW_OPENGL_ES_API : GLFW_OPENGL_API);
        glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_NATIVE_CONTEXT_API);
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
        glfwWindowHint(GLFW_RED_BITS, 8);
        glfwWindowHint(GLFW_GREEN_BITS, 8);
        glfwWindowHint(GLFW_BLUE_BITS, 8);
        glfwWindowHint(GLFW_ALPHA_BITS, request.alpha);
        glfwWindowHint(GLFW_DEPTH_BITS, request.depth);
        glfwWindowHint(GLFW_STENCIL_BITS, request.stencil);
        glfwWindowHint(GLFW_SAMPLES, request.samples > 1 ? request.samples : 0);
        if (request.es) {  // GLFW's defaults hold for the rest
            glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, request.major ? request.major : 1);
            glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, request.minor);
        } else if (request.major > 0) {
            glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, request.major);
            glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, request.minor);
            const bool has_profile = request.major > 3 || (request.major == 3 && request.minor >= 2);
            glfwWindowHint(GLFW_OPENGL_PROFILE, !has_profile ? GLFW_OPENGL_ANY_PROFILE
                                                : request.core ? GLFW_OPENGL_CORE_PROFILE
                                                               : GLFW_OPENGL_COMPAT_PROFILE);
            glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT,
                           request.forward_compatible && request.major >= 3 ? GLFW_TRUE : GLFW_FALSE);
        }
        // major 0: GLFW's default 1.0 with any profile, which GLX answers with the highest
        // compatibility context.
        glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, request.debug ? GLFW_TRUE : GLFW_FALSE);
        glfwWindowHint(GLFW_CONTEXT_NO_ERROR, request.no_error ? GLFW_TRUE : GLFW_FALSE);

        glfwGetError(nullptr);
        const bool first = !share;
        out.window = glfwCreateWindow(first ? 640 : 1, first ? 480 : 1, "glcast slave", nullptr,
                                      share ? share->window : nullptr);
        if (!out.window)
            return fail(error, "glfwCreateWindow(" + describe(request) + ") failed: " + glfw_error());
        glfwSetWindowUserPointer(out.window, &out);
        return true;
    }

    bool resize(Context& c, int width, int height, std::string&) {
        glfwSetWindowSize(c.window, width, height);
        // The X server resizes asynchronously: wait (briefly) until the framebuffer has the size.
        for (int i = 0; i < 200; ++i) {
            int fw = 0, fh = 0;
            glfwGetFramebufferSize(c.window, &fw, &fh);
            if (fw == width && fh == height) break;
            glfwWaitEventsTimeout(0.005);
        }
        return true;
    }

    bool bind(uint32_t id, Context& c, bool, std::string& error) {
        glfwGetError(nullptr);
        glfwMakeContextCurrent(c.window);
        if (glfwGetCurrentContext() != c.window)
            return fail(error, "glfwMakeContextCurrent(context " + std::to_string(id) + ") failed: " + glfw_error());
        return true;
    }

    bool release(std::string&) {
        glfwMakeContextCurrent(nullptr);
        return true;
    }

    void destroy(Context& c) {
        if (glfwGetCurrentContext() == c.window) glfwMakeContextCurrent(nullptr);
        glfwDestroyWindow(c.window);
    }

    void* proc_address(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

    void set_position(int x, int y) {
        position_x_ = x;
        position_y_ = y;
        has_position_ = true;
    }

    void present() {
        GLFWwindow* window = glfwGetCurrentContext();
        if (!window) return;
        auto* c = static_cast<Context*>(glfwGetWindowUserPointer(window));
        if (!c) return;  // a window that is not ours
        if (!c->shown) {
            if (has_position_) glfwSetWindowPos(window, position_x_, position_y_);
            glfwShowWindow(window);
            c->shown = true;
        }
        glfwSwapBuffers(window);
        glfwPollEvents();
    }

private:
    static bool fail(std::string& error, const std::string& what) {
        error = "window: " + what;
        return false;
    }

    bool glfw_counted_ = false;
    bool has_position_ = false;
    int position_x_ = 0, position_y_ = 0;
};

}  // namespace

std::unique_ptr<Backend> make_window_backend(std::string& error) {
    return make_context_backend<WindowDriver>(error);
}

}  // namespace glcast::slave
