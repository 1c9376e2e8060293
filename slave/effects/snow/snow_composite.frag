// The spectral-snow method's composite (docs/snow.md) I = I_snow a + (1 - a) I_bg (blending does the sum) while regions move
// differently: the texels (snow colour, a) at this canvas pixel are blended bilinearly between
// the regions' textures (docs/snow.md, "The pass"), so neighbouring regions with their own C and theta meet
// without an edge, and every tile of a wall reads the same canvas. (One region, or regions that
// all moved alike: snow_composite_single.*)
uniform sampler2DArray snow;  // regions^2 layers, M x M, wrapping (toroidal); RGBA8 from the worker
uniform int regions;
uniform vec2 canvas_offset;   // this tile's origin on the canvas
uniform vec2 canvas_size;
uniform float texels_per_pixel;  // 1 / (scale * M): texture repeats per canvas pixel
out vec4 out_color;

vec4 layer(ivec2 r, vec2 tc) { return texture(snow, vec3(tc, float(r.y * regions + r.x))); }

void main() {
    vec2 canvas = gl_FragCoord.xy + canvas_offset;
    vec2 tc = canvas * texels_per_pixel;
    vec2 g = clamp(canvas / canvas_size * float(regions) - 0.5, vec2(0.0), vec2(float(regions - 1)));
    ivec2 r0 = ivec2(floor(g));
    ivec2 r1 = min(r0 + 1, ivec2(regions - 1));
    vec2 f = g - vec2(r0);
    out_color = mix(mix(layer(r0, tc), layer(ivec2(r1.x, r0.y), tc), f.x),
                    mix(layer(ivec2(r0.x, r1.y), tc), layer(r1, tc), f.x), f.y);
}
