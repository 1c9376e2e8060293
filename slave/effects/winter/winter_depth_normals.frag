// Normals reconstructed from the window's depth buffer (cover.normals=depth, or a frame that
// cannot be re-rendered): the eye position of each tile pixel from its depth, the normal from
// the differences to its neighbours, taking on each axis the side whose depth is closer (so a
// pixel at a depth edge uses the surface it belongs to). The window holds only this tile, so
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

// The neighbour at `t + step` (or `t - step` when closer in depth or the only one inside).
vec3 tangent(ivec2 t, ivec2 step, vec3 here, float depth) {
    ivec2 a = t + step, b = t - step;
    bool a_in = all(greaterThanEqual(a, ivec2(0))) && all(lessThan(a, ivec2(tile_size)));
    bool b_in = all(greaterThanEqual(b, ivec2(0))) && all(lessThan(b, ivec2(tile_size)));
    float da = a_in ? texelFetch(window_depth, a, 0).r : 2.0;
    float db = b_in ? texelFetch(window_depth, b, 0).r : 2.0;
    if (da < 1.0 && (abs(da - depth) <= abs(db - depth) || db >= 1.0)) return eye_at(a, da) - here;
    if (db < 1.0) return here - eye_at(b, db);
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
