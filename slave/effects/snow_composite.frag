// The seed's composite I = I_snow a + (1 - a) I_bg (blending does the sum): a is the spectral
// opacity at this canvas pixel, blended bilinearly between the regions' textures (seed sec. 7),
// so neighbouring regions with their own C and theta meet without an edge, and every tile of a
// wall reads the same canvas.
uniform sampler2DArray opacity_layers;  // regions^2 layers, M x M, wrapping (toroidal); already
                                        // raised to snow.sharpness by the synthesis worker
uniform int regions;
uniform int uniform_motion;   // every region has moved alike so far: their textures are identical
uniform vec2 canvas_offset;   // this tile's origin on the canvas
uniform vec2 canvas_size;
uniform float texels_per_pixel;  // 1 / (scale * M): texture repeats per canvas pixel
uniform float strength;
uniform float brightness;
out vec4 out_color;

float layer(ivec2 r, vec2 tc) { return texture(opacity_layers, vec3(tc, float(r.y * regions + r.x))).r; }

void main() {
    vec2 canvas = gl_FragCoord.xy + canvas_offset;
    vec2 tc = canvas * texels_per_pixel;
    if (uniform_motion != 0) {
        out_color = vec4(vec3(brightness), layer(ivec2(0), tc) * strength);
        return;
    }
    vec2 g = clamp(canvas / canvas_size * float(regions) - 0.5, vec2(0.0), vec2(float(regions - 1)));
    ivec2 r0 = ivec2(floor(g));
    ivec2 r1 = min(r0 + 1, ivec2(regions - 1));
    vec2 f = g - vec2(r0);
    float a = mix(mix(layer(r0, tc), layer(ivec2(r1.x, r0.y), tc), f.x),
                  mix(layer(ivec2(r0.x, r1.y), tc), layer(r1, tc), f.x), f.y);
    out_color = vec4(vec3(brightness), a * strength);
}
