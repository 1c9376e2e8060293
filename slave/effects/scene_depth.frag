// A scene drawn offscreen, its depth brought to this tile (slave/scene/window_copies.cpp,
// scene_depth_copy): the tile's rectangle of the program's window, stretched over the tile, in
// the scene target's pixels (which a scene shown in part of the window covers only part of).
// Window-space depth is linear across a planar surface: between four texels of one plane it is
// interpolated, so depth reconstructed from it keeps surfaces flat where a nearest stretch would
// make steps; across an edge (the diagonals disagree) the nearest texel, so that no surface is
// invented between a box and what lies behind it.
uniform sampler2D scene_depth;  // the program's window, its own size
uniform vec4 source_rect;       // x0, y0, x1, y1 in its pixels
in vec2 uv;

void main() {
    vec2 q = mix(source_rect.xy, source_rect.zw, uv);
    ivec2 size = textureSize(scene_depth, 0);
    // (a scene placed in part of the window: around it, the far plane)
    if (any(lessThan(q, vec2(0.0))) || any(greaterThan(q, vec2(size)))) {
        gl_FragDepth = 1.0;
        return;
    }
    vec2 p = q - 0.5;  // texel centres at integers
    ivec2 i = ivec2(floor(p));
    vec2 f = p - vec2(i);
    ivec2 lo = clamp(i, ivec2(0), size - 1), hi = clamp(i + 1, ivec2(0), size - 1);
    float a = texelFetch(scene_depth, lo, 0).r, b = texelFetch(scene_depth, ivec2(hi.x, lo.y), 0).r;
    float c = texelFetch(scene_depth, ivec2(lo.x, hi.y), 0).r, d = texelFetch(scene_depth, hi, 0).r;
    if (abs((a + d) - (b + c)) > 1e-5) {
        gl_FragDepth = f.y < 0.5 ? (f.x < 0.5 ? a : b) : (f.x < 0.5 ? c : d);
        return;
    }
    gl_FragDepth = mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}
