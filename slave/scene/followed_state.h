// The part of a context's GL state the scene classifier asks at draws, followed from the calls
// the program makes, so that a decision costs no driver query (a GPU driver with a command
// thread answers a query only once it has run every call before it). A value no call has set
// yet, or one a call may have changed in a way this does not follow (glPopAttrib, a display
// list run, a bound framebuffer deleted), is unknown: the driver is asked once, and the answer
// is kept until the next call that sets it.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>

#include "common/gl_headers.h"
#include "protocol/decoder.h"
#include "slave/name_map.h"

namespace glcast::slave {

struct FollowedState {
    std::optional<GLuint> draw_framebuffer, read_framebuffer;  // the slave's names
    std::optional<bool> depth_test, depth_mask, cull_face, blend;
    std::optional<GLenum> cull_face_mode, front_face, depth_func;
    std::optional<std::pair<double, double>> depth_range;
    // Alpha test (compatibility profile): a value no call set counts as GL's initial one.
    bool alpha_test = false;
    GLenum alpha_func = GL_ALWAYS;
    double alpha_ref = 0;
    bool compiling_list = false;  // between glNewList(GL_COMPILE) and glEndList: nothing runs

    // Follows one call the slave's driver carried out in the context whose names are `names`.
    void follow(const Call& c, ContextNames& names);
    void forget();  // every value unknown
};

}  // namespace glcast::slave
