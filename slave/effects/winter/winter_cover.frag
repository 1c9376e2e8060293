// Snow cover, the snow accumulator of docs/winter.md in screen space: how much snow each pixel of the
// guard-band buffers holds. A surface holds snow where its normal lies within the spread angle
// of "up" (the direction opposite to the snowfall), in patches of seeded noise in world space
// (stable while the camera moves, the same on every tile) whose covered fraction is the density,
// times the mask image over the canvas.
uniform sampler2D normals;       // winter_normals.frag / winter_depth_normals.frag
uniform sampler2D positions;
uniform sampler2D window_depth;  // tile pixels: the window's own depth, to drop hidden surfaces
uniform bool check_visibility;   // the buffers were re-rendered: compare with the window's depth
uniform int guard;
uniform vec2 tile_size;       // pixels (integers)
uniform mat4 eye_from_tile_clip;
uniform mat4 world_from_eye;     // identity when "up" is given in eye space
uniform vec3 up_eye;
uniform float spread_deg, softness_deg;
uniform bool random_spread;
uniform vec3 random_shape;       // offset, stepper, exponent
uniform float random_scale;
uniform float density;           // already scaled by the build-up over frames
uniform float edge, noise_scale;
uniform int seed_bits;      // the seed's unsigned bits (glUniform1i)
uniform bool has_mask;
uniform sampler2D mask;          // canvas-stretched, row 0 at the bottom
uniform vec2 canvas_origin;      // canvas pixel of guard-buffer pixel (0, 0)
uniform vec2 canvas_size;

// r: snow amount 0..1; g: the eye's distance (its range, not -z: a turned tile of a CAVE or a
// cylinder sees points beside and behind the program's camera, whose -z is 0 or negative); b: how
// far the surface faces up to hold snow, before the noise and the mask (the lower edges of
// winter_edges.glsl tell the ground from a wall by it); a: 1 surface, 0 background, -1 unknown.
out vec4 out_color;

vec3 eye_at(ivec2 t, float depth) {
    vec4 clip = vec4((vec2(t) + 0.5) / tile_size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    vec4 eye = eye_from_tile_clip * clip;
    return eye.xyz / eye.w;
}
float eye_range_at(ivec2 t, float depth) { return length(eye_at(t, depth)); }

void main() {
    uint seed = uint(seed_bits);
    ivec2 q = ivec2(gl_FragCoord.xy);
    vec4 normal = texelFetch(normals, q, 0);
    if (normal.w <= 0.0) {
        out_color = vec4(0.0, 0.0, 0.0, normal.w);
        return;
    }
    vec4 position = texelFetch(positions, q, 0);
    float distance = length(position.xyz);
    ivec2 t = q - guard;
    if (check_visibility && all(greaterThanEqual(t, ivec2(0))) && all(lessThan(t, ivec2(tile_size)))) {
        // Something the re-render does not draw (another view, a HUD) is in front: no snow.
        float window = texelFetch(window_depth, t, 0).r;
        // (compared as distances from the eye: a turned tile of a CAVE or a cylinder sees points
        // beside and behind the program's camera, whose -z is 0 or negative)
        float seen = window < 1.0 ? eye_range_at(t, window) : 1e30;
        if (seen < length(position.xyz) * (1.0 - 2e-3) - 1e-4) {
            out_color = vec4(0.0, seen, 0.0, 1.0);
            return;
        }
    }
    vec3 world = (world_from_eye * vec4(position.xyz, 1.0)).xyz;

    float angle = degrees(acos(clamp(dot(normal.xyz, up_eye), -1.0, 1.0)));
    float spread = spread_deg;
    if (random_spread) {
        float r = winter_value_noise(world / random_scale, seed ^ 0x9e3779b9u);
        spread = clamp(spread * pow(max((r + random_shape.x) * random_shape.y, 0.0), random_shape.z), 0.0, 180.0);
    }
    float slope = 1.0 - smoothstep(spread - softness_deg, spread + softness_deg, angle);
    float allowed = 1.0;
    if (has_mask) {
        vec4 m = textureLod(mask, (canvas_origin + vec2(q) + 0.5) / canvas_size, 0.0);
        allowed = dot(m.rgb, vec3(0.2126, 0.7152, 0.0722)) * m.a;
    }
    if (slope * allowed <= 0.0) {  // walls, undersides, masked out: no need for the noise
        out_color = vec4(0.0, distance, slope, 1.0);
        return;
    }
    // Covered where the uniformized noise is below the density; the band of width 2 edge is
    // moved so that density 0 covers nothing and density 1 everything.
    float level = density * (1.0 + 2.0 * edge) - edge;
    float patches = smoothstep(-edge, edge, level - winter_uniform_fbm(world / noise_scale, seed));
    out_color = vec4(slope * allowed * patches, distance, slope, 1.0);
}
