// One of the master's contexts as the slave keeps it: the name maps, its window framebuffer's
// size against the master's, and the state the replay follows for the calls that need it.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "slave/name_map.h"

namespace glcast::slave {

// The elements [first, end) a per-instance client array (divisor > 0) of the last
// glcast.client_arrays tuple holds.
struct ClientInstanceRange {
    uint32_t divisor = 1;
    int64_t first = 0, end = 0;
};

// One of the master's contexts on the slave: its names and what its window framebuffer is.
struct SlaveContext {
    uint32_t id = 0;
    uint64_t handle = 0;            // the master's driver handle
    ContextNames names;
    int width = 0, height = 0;      // its window framebuffer (the backend's default framebuffer)
    int master_width = 0, master_height = 0;  // the master's drawable
    bool double_buffered = true;
    bool made_current = false;
    int es_version = 0;             // OpenGL ES version times 10 (its GL_VERSION), 0 for desktop GL
    uint64_t drawable = 0;
    bool drawing_to_window = true;  // the draw framebuffer is the window (tracked by TileAdapter)
    uint64_t current_program = 0;   // master name, for glUniform* locations
    uint64_t program_deleted_in_use = 0;  // master name deleted while current: unmapped when unused
    uint32_t list_base = 0;         // glListBase, applied to glCallLists on the slave side
    // The window's draw and read buffers as the master named them (GL_BACK, ...; 0: never set):
    // the slave's driver holds its own window's (slave/special/framebuffers.cpp).
    uint32_t window_draw_buffer = 0, window_read_buffer = 0;
    std::map<uint32_t, std::vector<uint8_t>> client_arrays;  // by cache handle
    uint64_t client_array_bytes = 0;  // in client_arrays
    // The vertices [client_first, client_end) that every client array of the last
    // glcast.client_arrays tuple holds: the draw that follows it may read only those.
    bool client_range_pending = false;
    // The last glcast.client_arrays tuple was refused: the arrays may point at copies that are
    // gone, so the draw after it is refused too.
    bool client_arrays_refused = false;
    int64_t client_first = 0, client_end = 0;
    std::vector<ClientInstanceRange> client_instances;  // its per-instance arrays
    std::vector<uint8_t> select_buffer, feedback_buffer;
};

}  // namespace glcast::slave
