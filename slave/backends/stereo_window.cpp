#include "slave/backends/stereo_window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <condition_variable>
#include <mutex>
#include <thread>

#include "common/gl_headers.h"
#include "slave/backends/backends_internal.h"

namespace glcast::slave {

namespace {

std::string glfw_problem() {
    const char* description = nullptr;
    const int code = glfwGetError(&description);
    return description ? description : "GLFW error " + std::to_string(code);
}

}  // namespace

// The window's context lives on a thread of its own: the eyes' EGL contexts are current on the
// replay thread, and GLX and EGL contexts taking turns on one thread make Mesa's GLX fail
// (BadAccess in X_GLXMakeCurrent). GLFW creates the window and polls its events on the main thread.
struct StereoWindow::Impl {
    GLFWwindow* window = nullptr;
    bool quad_buffer = false, counted = false;
    std::thread thread;
    std::mutex mutex;
    std::condition_variable wake;
    const Image *tile = nullptr, *left = nullptr, *right = nullptr;  // the frame to show, while showing
    bool stopping = false;
    // Resolved through GLFW with the window's context current: the process also has EGL contexts.
    // (GL 1.0's entry points have no PFN types in glext.h)
    void(APIENTRY* draw_buffer)(GLenum) = nullptr;
    void(APIENTRY* window_pos)(GLint, GLint) = nullptr;
    void(APIENTRY* pixel_zoom)(GLfloat, GLfloat) = nullptr;
    void(APIENTRY* draw_pixels)(GLsizei, GLsizei, GLenum, GLenum, const void*) = nullptr;
    void(APIENTRY* pixel_store)(GLenum, GLint) = nullptr;

    void draw(GLenum buffer, const Image& image) {
        draw_buffer(buffer);
        // Rows top to bottom: drawn downwards from the top-left corner.
        window_pos(0, image.height);
        pixel_zoom(1, -1);
        draw_pixels(image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    }

    void serve() {
        glfwMakeContextCurrent(window);
        std::unique_lock lock(mutex);
        for (;;) {
            wake.wait(lock, [this] { return stopping || tile; });
            if (stopping) break;
            if (quad_buffer) {
                draw(GL_BACK_LEFT, *left);
                draw(GL_BACK_RIGHT, *right);
            } else {
                draw(GL_BACK, *tile);
            }
            glfwSwapBuffers(window);
            tile = left = right = nullptr;
            wake.notify_all();
        }
        glfwMakeContextCurrent(nullptr);
    }
};

std::unique_ptr<StereoWindow> StereoWindow::open(int width, int height, bool quad_buffer, std::string& error) {
    std::unique_ptr<StereoWindow> w(new StereoWindow);
    w->impl_ = std::make_unique<Impl>();
    Impl& s = *w->impl_;
    if (!glfw_acquire(error)) return nullptr;
    s.counted = true;
    s.quad_buffer = quad_buffer;
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_NATIVE_CONTEXT_API);
    glfwWindowHint(GLFW_STEREO, quad_buffer ? GLFW_TRUE : GLFW_FALSE);
    s.window = glfwCreateWindow(width, height, "glcast stereo", nullptr, nullptr);
    if (!s.window) {
        error = quad_buffer ? "quad-buffer stereo: this display offers no stereo visual (GLFW_STEREO: " + glfw_problem() +
                                  "); Mesa's drivers and Xvfb have none. Use side-by-side, top-bottom or anaglyph, or "
                                  "one tile per eye (\"eye\")"
                            : "stereo window: " + glfw_problem();
        return nullptr;
    }
    glfwMakeContextCurrent(s.window);
    s.draw_buffer = reinterpret_cast<decltype(s.draw_buffer)>(glfwGetProcAddress("glDrawBuffer"));
    s.window_pos = reinterpret_cast<decltype(s.window_pos)>(glfwGetProcAddress("glWindowPos2i"));
    s.pixel_zoom = reinterpret_cast<decltype(s.pixel_zoom)>(glfwGetProcAddress("glPixelZoom"));
    s.draw_pixels = reinterpret_cast<decltype(s.draw_pixels)>(glfwGetProcAddress("glDrawPixels"));
    s.pixel_store = reinterpret_cast<decltype(s.pixel_store)>(glfwGetProcAddress("glPixelStorei"));
    if (!s.draw_buffer || !s.window_pos || !s.pixel_zoom || !s.draw_pixels || !s.pixel_store) {
        error = "stereo window: its context lacks glWindowPos2i or glDrawPixels";
        return nullptr;
    }
    s.pixel_store(GL_UNPACK_ALIGNMENT, 1);
    glfwMakeContextCurrent(nullptr);
    s.thread = std::thread([&s] { s.serve(); });
    return w;
}

StereoWindow::~StereoWindow() {
    if (!impl_) return;
    if (impl_->thread.joinable()) {
        {
            std::lock_guard lock(impl_->mutex);
            impl_->stopping = true;
        }
        impl_->wake.notify_all();
        impl_->thread.join();
    }
    if (impl_->window) glfwDestroyWindow(impl_->window);
    if (impl_->counted) glfw_release();
}

void StereoWindow::show(const Image& tile, const Image& left, const Image& right) {
    Impl& s = *impl_;
    {
        std::unique_lock lock(s.mutex);
        s.tile = &tile, s.left = &left, s.right = &right;
        s.wake.notify_all();
        s.wake.wait(lock, [&s] { return !s.tile; });  // shown: the images may go
    }
    glfwPollEvents();
}

}  // namespace glcast::slave
