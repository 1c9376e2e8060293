// Darkens the tile: with blending dst * src, color *= 1 - strength * facing * (1 - visibility).
// facing (the steps' Receiver.facing) fades the darkening out on surfaces turned away from the
// light: the program's own lighting leaves those unlit already, and a plane grazed by the light
// would show the shadow map's acne. Pixels left at factor 1 are discarded, so they stay
// bit-identical whatever the blending arithmetic.
uniform sampler2D u_visibility;  // r: visibility, g: facing
uniform vec2 u_tile_offset;      // work texel of tile pixel (0, 0)
uniform float u_strength;
out vec4 out_color;

void main() {
    vec2 v = texelFetch(u_visibility, ivec2(gl_FragCoord.xy) + ivec2(u_tile_offset), 0).rg;
    float factor = 1.0 - u_strength * clamp(v.g, 0.0, 1.0) * (1.0 - clamp(v.r, 0.0, 1.0));
    if (factor >= 1.0) discard;
    out_color = vec4(factor, factor, factor, 1.0);
}
