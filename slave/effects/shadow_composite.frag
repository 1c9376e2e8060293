// Darkens the tile: with blending dst * src, color *= 1 - strength * (1 - visibility). Fully lit
// pixels are discarded, so they stay bit-identical whatever the blending arithmetic.
uniform sampler2D u_visibility;
uniform vec2 u_tile_offset;  // work texel of tile pixel (0, 0)
uniform float u_strength;
out vec4 out_color;

void main() {
    float v = texelFetch(u_visibility, ivec2(gl_FragCoord.xy) + ivec2(u_tile_offset), 0).r;
    float factor = 1.0 - u_strength * (1.0 - clamp(v, 0.0, 1.0));
    if (factor >= 1.0) discard;
    out_color = vec4(factor, factor, factor, 1.0);
}
