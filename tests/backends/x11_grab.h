// What the window backend's current window shows, read back from the X server. Kept apart
// from the tests because the X11 headers define macros (None, Bool, Status) that clash with
// other code.
#pragma once

#include <string>

#include "common/image.h"

namespace glcast::test {

// The X window of the current GLFW context: its size and contents (RGBA, alpha 255, top row
// first), read on GLFW's own display connection so that it follows the swap's XPutImage.
bool grab_current_window(slave::Image& image, std::string& error);

}  // namespace glcast::test
