// The frame's record: the calls that re-render its geometry without side effects on objects
// (draws, immediate-mode blocks, display-list calls, matrix, vertex-array and shader-program
// state), kept as raw tuples and decoded again when a pass redraws the scene. Only the tuples
// and what a redraw needs to replay them; what the draws *are* (main view, overlays) is the
// scene classifier's (scene_classifier.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/gl_headers.h"

namespace glcast::slave {

struct RecordEntry {
    size_t begin = 0, size = 0;  // the tuple's bytes in FrameRecord::bytes
    bool draw = false;           // a draw or part of a glBegin/glEnd block
    bool opens = false;          // the draw call or the glBegin itself (its projection is corrected)
    bool main = false;           // ... of the main view
    bool program_state = false;  // shader-program state: replayed only in frames with shader draws
    bool offscreen = false;      // a draw into the framebuffer object that holds the scene
    // Face culling as the draw had it (GL_CULL_FACE, glCullFace, glFrontFace): a redraw culls
    // what the program culled, whatever the frame's last draws left set (a game that culls its
    // level's back faces and then draws its menu without culling would otherwise hide its
    // floor behind the backs of its rails).
    bool cull = false;
    uint16_t cull_face = 0, front_face = 0;
    // The alpha test as the draw had it: a redraw of shader programs tests what the program's
    // fragment shaders write as the program did (leaves cut out of alpha-tested quads).
    bool alpha_test = false;
    uint16_t alpha_func = GL_ALWAYS;
    float alpha_ref = 0;
};

// More than this a frame: the frame cannot be re-rendered (the record says so once and stops).
constexpr size_t kMaxRecordBytes = size_t(256) << 20;

struct FrameRecord {
    std::vector<uint8_t> bytes;
    std::vector<RecordEntry> entries;
    bool in_begin_end = false, begin_is_main = false;
    bool compiling_list = false;  // between glNewList and glEndList: nothing is drawn
    bool overflow = false;        // more than kMaxRecordBytes
    // The program current when the frame began (GL's name and the stream's): a redraw starts
    // from it, as the frame's first draws did.
    bool started = false;
    GLint start_program = 0;
    uint64_t start_program_stream = 0;

    // Keeps the tuple; false (and overflow set) when the frame has no room for it.
    bool append(const uint8_t* tuple, size_t size, const RecordEntry& entry);
    // The next frame's record: every field as a new one has it, the buffers' memory kept.
    void clear();
};

}  // namespace glcast::slave
