// The injected passes read and write depth one way: OpenGL's default clip space (z from -1 at
// the near plane to +1 at a finite far plane, GL_NEGATIVE_ONE_TO_ONE), depth range [0, 1], the
// background at depth 1, the origin lower left. Programs written since 2010 often draw another
// way: glClipControl(GL_ZERO_TO_ONE), reversed depth (near at 1, cleared to 0, GL_GREATER),
// infinite far planes, depth ranges of their own, an upper-left origin. For those the passes get
// a standard projection with the program's x, y and w rows (`pass_projection`: the same picture,
// standard depth) and the window's depth converted to it; their redraws of the program's draws
// are corrected from the program's projection to it. Pure arithmetic: unit-tested without a
// driver (tests/unit/depth_convention_test.cpp); the conversion itself runs in
// slave/effects/depth_convention.frag, which follows to_pass_depth() here.
#pragma once

#include <glm/glm.hpp>

namespace glcast::slave {

// What the program's state says of its depth at the end of the frame.
struct ProgramDepthState {
    bool zero_to_one = false;   // glClipControl's depth mode GL_ZERO_TO_ONE
    bool upper_left = false;    // glClipControl's origin GL_UPPER_LEFT
    double range_near = 0, range_far = 1;  // glDepthRange
    double clear_depth = 1;     // glClearDepth: the background's window depth
    // Not GL state: the scene drawn offscreen is shown upside down (SceneFacts::shown_mirrored),
    // which the window's picture has as an upper-left origin would give it.
    bool shown_mirrored = false;
    bool shown_mirrored_columns = false;  // ... mirrored left to right (SceneFacts::shown_mirrored_columns)
    bool flipped() const { return upper_left != shown_mirrored; }  // the window's rows run top down
    bool flipped_columns() const { return shown_mirrored_columns; }  // ... its columns right to left
};

struct DepthConvention {
    bool standard = true;  // the program's is the passes' own: nothing to convert, nothing changes
    glm::dmat4 pass_projection{1.0};  // the projection the passes see (the program's when standard)
    // The program's projection as its window shows it, in the passes' lower-left origin (y
    // flipped for an upper-left one, x for a scene shown mirrored left to right): the depth
    // conversion maps from its clip space.
    glm::dmat4 program_projection{1.0};
    // pass_projection * inverse(the program's projection): what a redraw of the program's
    // draws (run in the passes' clip convention) premultiplies to land as the passes see them.
    glm::dmat4 pass_from_program{1.0};
    double near = 0, far = 0;  // pass_projection's planes, eye distances (far finite)
    bool reversed = false;     // the program's depth falls with distance
    ProgramDepthState program;
};

// The far plane a program with an infinite one gets for the passes, in near-plane distances.
constexpr double kInfiniteFarInNears = 1e5;

// The convention of the main view's projection `projection` under `state`. A projection the
// passes cannot read depth through (no eye depth in its w row, or a depth that does not change
// with distance) is left standard: the passes then treat it as they always did.
DepthConvention depth_convention(const glm::dmat4& projection, const ProgramDepthState& state);

// The window depth the passes see for the program's window depth `depth` at tile clip (x, y),
// where `pass_clip_from_program_clip` maps the program's tile clip space to the passes'
// (T pass_projection inverse(T program_projection), T the tile's stretch or turn). The background (the
// program's clear depth) is 1. Mirrors depth_convention.frag.
double to_pass_depth(const DepthConvention& c, const glm::dmat4& pass_clip_from_program_clip, double x, double y,
                     double depth);

}  // namespace glcast::slave
