// The program's GLSL as the slave's driver gets it, where a tile or a pass draws it elsewhere
// than the master did (slave/tile_adapter.h): pure text, testable without a driver.
#pragma once

#include <string>

namespace glcast::slave {

enum class ShaderPatch {
    Untouched,
    // A vertex shader's last step: gl_Position = glcast_clip * gl_Position (a rotated tile's turn,
    // a pass's redraw).
    Clip,
    // A fragment shader that reads gl_FragCoord reads the master window's coordinates instead:
    // glcast_FragCoord = gl_FragCoord with xy * (1 + glcast_fragcoord.xy) + glcast_fragcoord.zw.
    // The uniform's default (zero) leaves gl_FragCoord as it is.
    WindowFragCoord,
};

// `text` patched as `patch` says. False (text untouched): it has nothing to patch (no main, no
// gl_FragCoord), redeclares gl_FragCoord (a layout of its own for it), or holds a run of blanks
// or word characters longer than 4,096 (no shader's; the patterns' matching would recurse as deep).
bool patch_shader(std::string& text, ShaderPatch patch);

// The uniform glcast_fragcoord that makes a fragment at `actual` (x, y, width, height: the
// viewport the slave draws with) read the coordinates it had at `program` (the viewport the
// program set, the master window's). The identity is all zero.
void window_fragcoord(const double program[4], const double actual[4], float out[4]);

}  // namespace glcast::slave
