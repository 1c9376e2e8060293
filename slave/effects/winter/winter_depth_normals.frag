// Normals reconstructed from the window's depth buffer (cover.normals=depth, or a frame that
// cannot be re-rendered): the eye position of each tile pixel from its depth, the normal from
// the differences to its neighbours, taking on each axis the side whose depth continues its own
// (so a pixel at a depth edge uses the surface it belongs to). The window holds only this tile, so
// guard-band pixels are marked unknown (w = -1): the icicle pass starts no icicle there.
// Before a re-render (winter_surface_buffers.cpp) it also writes the window's depth, a little
// behind, so that the re-rendered surfaces replace these normals where they are the visible ones.
uniform sampler2D window_depth;  // tile pixels
uniform bool write_depth;
uniform int guard;
uniform vec2 tile_size;       // pixels (integers)
uniform mat4 eye_from_tile_clip;

layout(location = 0) out vec4 out_normal;
layout(location = 1) out vec4 out_position;

vec3 eye_at(ivec2 t, float depth) {
    vec4 clip = vec4((vec2(t) + 0.5) / tile_size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    vec4 eye = eye_from_tile_clip * clip;
    return eye.xyz / eye.w;
}

bool inside(ivec2 t) { return all(greaterThanEqual(t, ivec2(0))) && all(lessThan(t, ivec2(tile_size))); }
float depth_at(ivec2 t) { return inside(t) ? texelFetch(window_depth, t, 0).r : 2.0; }

// How far the depth of the neighbour `t + step` and the one beyond it, continued as a straight line,
// misses `depth`: on a plane the window's depth is affine in screen space, so the side on this
// pixel's own surface continues to it exactly. Without the one beyond: their difference.
float continuation_miss(ivec2 t, ivec2 step, float depth, float near) {
    float beyond = depth_at(t + 2 * step);
    return beyond < 1.0 ? abs(2.0 * near - beyond - depth) : abs(near - depth);
}

// The tangent towards the neighbour at `t + step`, or from the one at `t - step`: the side that
// continues this pixel's surface (where two meshes cross, as a track over its terrain, a strip a
// pixel tall lies between neighbours of the other mesh, at depths as close as its own: the
// nearer depth is no guide there).
vec3 tangent(ivec2 t, ivec2 step, vec3 here, float depth) {
    float da = depth_at(t + step), db = depth_at(t - step);
    if (da < 1.0 && (db >= 1.0 || continuation_miss(t, step, depth, da) <= continuation_miss(t, -step, depth, db)))
        return eye_at(t + step, da) - here;
    if (db < 1.0) return here - eye_at(t - step, db);
    return vec3(0.0);
}

void main() {
    ivec2 t = ivec2(gl_FragCoord.xy) - guard;
    gl_FragDepth = 1.0;
    if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, ivec2(tile_size)))) {
        out_normal = vec4(0.0, 0.0, 0.0, -1.0);
        out_position = vec4(0.0);
        return;
    }
    float depth = texelFetch(window_depth, t, 0).r;
    if (write_depth && depth < 1.0) gl_FragDepth = min(1.0, depth + 1e-5);
    if (depth >= 1.0) {
        out_normal = vec4(0.0);
        out_position = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    vec3 here = eye_at(t, depth);
    vec3 n = cross(tangent(t, ivec2(1, 0), here, depth), tangent(t, ivec2(0, 1), here, depth));
    n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
    if (dot(n, here) > 0.0) n = -n;
    out_normal = vec4(n, 1.0);
    out_position = vec4(here, depth);
}
