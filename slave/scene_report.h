// What the passes took a frame for, written beside its picture (`glcast replay --scene-report
// DIR`): the measurements of real programs (scripts/compatibility.py) need the scene's depth and
// the pixels the program keeps as the slave saw them, not guessed again from the picture.
//
// Per decorated frame N, in DIR:
//   frame-N-scene.json   {"frame", "width", "height", "view_known", "eye_from_tile_clip" (16
//                        numbers, column-major), "modelview" (16), "kept_pixels"}
//   frame-N-depth.f32    width x height little-endian floats, rows bottom to top (GL's order):
//                        the depth the passes read, in their convention (0 near, 1 far); only
//                        when view_known
//   frame-N-kept.png     white where the program's own pixels are put back over the passes
//                        (overlays, a view model, outside a borrowed scene), black elsewhere;
//                        in a frame decorated under its overlays (docs/effects.md, "Overlays"),
//                        where the program drew its overlays over the decorated scene
//   frame-N-under-plain.png, frame-N-under-decorated.png
//                        only for a frame decorated under its overlays: the window when its
//                        overlays started, before the passes and after them. A translucent
//                        overlay lets the passes' change through, at most what it is here
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/gl_headers.h"
#include "slave/effects/frame_view.h"

namespace glcast {
class GlApi;
}

namespace glcast::slave {

// Writes the three files; false with `error` set (naming the file) on a write failure.
// `kept_fb` is an RGBA framebuffer of the tile's size whose alpha is nonzero where the program's
// pixels are kept (0: none kept). The window must be current; GL state is restored.
bool write_scene_report(const GlApi& gl, const std::string& dir, const effects::FrameView& view, GLuint kept_fb,
                        std::string& error);
// Writes frame-N-under-`what`.png: the window's `buffer` (GL_BACK or GL_FRONT) as it is now.
bool write_scene_under_overlays(const GlApi& gl, const std::string& dir, const effects::FrameView& view, GLenum buffer,
                                const char* what, std::string& error);

}  // namespace glcast::slave
