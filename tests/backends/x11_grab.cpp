#include "tests/backends/x11_grab.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>

// From <GLFW/glfw3native.h>, which cannot be included without the Xrandr development headers.
extern "C" Display* glfwGetX11Display(void);
extern "C" ::Window glfwGetX11Window(GLFWwindow* window);

namespace glcast::test {

namespace {
int shift_of(unsigned long mask) {
    int s = 0;
    while (mask && !(mask & 1)) {
        mask >>= 1;
        ++s;
    }
    return s;
}
}  // namespace

bool grab_current_window(slave::Image& image, std::string& error) {
    GLFWwindow* current = glfwGetCurrentContext();
    Display* display = glfwGetX11Display();
    if (!current || !display) {
        error = "no current GLFW window";
        return false;
    }
    const ::Window window = glfwGetX11Window(current);
    XWindowAttributes attributes;
    if (!XGetWindowAttributes(display, window, &attributes)) {
        error = "XGetWindowAttributes failed";
        return false;
    }
    XImage* x = XGetImage(display, window, 0, 0, attributes.width, attributes.height, AllPlanes, ZPixmap);
    if (!x) {
        error = "XGetImage failed (window not viewable?)";
        return false;
    }
    image.width = attributes.width;
    image.height = attributes.height;
    image.rgba.resize(size_t(image.width) * image.height * 4);
    const int rs = shift_of(x->red_mask), gs = shift_of(x->green_mask), bs = shift_of(x->blue_mask);
    for (int y = 0; y < image.height; ++y)
        for (int xx = 0; xx < image.width; ++xx) {
            const unsigned long p = XGetPixel(x, xx, y);
            uint8_t* o = &image.rgba[(size_t(y) * image.width + xx) * 4];
            o[0] = uint8_t((p & x->red_mask) >> rs);
            o[1] = uint8_t((p & x->green_mask) >> gs);
            o[2] = uint8_t((p & x->blue_mask) >> bs);
            o[3] = 255;
        }
    XDestroyImage(x);
    return true;
}

}  // namespace glcast::test
