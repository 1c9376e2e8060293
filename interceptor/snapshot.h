// Test mode (GLCAST_SNAPSHOT_DIR): the program's own frames, read from the back buffer just
// before each swap, so tests compare what the program drew with what a slave replays.
#pragma once

namespace glcast {
// Reads the current context's window back buffer (width x height) and writes
// DIR/frame-NNNNNN.png, NNNNNN counting this process's swaps from 0. Every piece of GL state
// it touches is restored: the program draws exactly what it would without it.
void snapshot_back_buffer(int width, int height);
}  // namespace glcast
