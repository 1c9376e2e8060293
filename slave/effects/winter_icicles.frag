// Icicles over the window (tile pixels): the nearest icicle of the candidate columns around the
// pixel (winter_icicle_roots.frag), a tapered cone hanging straight down the screen from its
// root, shaded as translucent ice: the scene behind it shifted sideways as through a cylinder
// lens, tinted and darkened in the middle, brightened at the rims, with a specular highlight
// of the scene's light. Hidden where the window holds a surface well in front of its root.
uniform sampler2D roots;         // cells x buffer rows
uniform sampler2D scene;         // the window after the snow cover, tile pixels
uniform sampler2D window_depth;
uniform mat4 eye_from_tile_clip;
uniform vec2 tile_size;
uniform int guard;
uniform vec2 canvas_offset;      // canvas pixel of tile pixel (0, 0)
uniform int first_cell;
uniform int cell_count;
uniform float taper;
uniform float refraction;        // in icicle radii
uniform vec4 light_eye;

out vec4 out_color;

vec3 eye_at(vec2 pixel, float depth) {
    vec4 eye = eye_from_tile_clip * vec4(pixel / tile_size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    return eye.xyz / eye.w;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int row = p.y + guard;
    float x = canvas_offset.x + gl_FragCoord.x;  // canvas x of the pixel centre
    float reach = icicle_radius.y * 1.5 + 1.0;
    int c0 = int(floor((x - reach) / icicle_spacing)), c1 = int(floor((x + reach) / icicle_spacing));
    float nearest = 1e30, coverage = 0.0, across = 0.0, radius = 0.0;
    for (int c = c0; c <= c1 && c <= c0 + 16; ++c) {
        int i = c - first_cell;
        if (i < 0 || i >= cell_count) continue;
        vec4 root = texelFetch(roots, ivec2(i, row), 0);
        if (root.z <= 0.0) continue;
        vec3 icicle = icicle_at(ivec2(icicle_column(c), int(root.x + canvas_offset.y) - guard));
        float t = (root.x - (float(row) + 0.5)) / root.z;
        if (t >= 1.0) continue;
        float r = root.y * pow(1.0 - t, taper);
        float centre = float(icicle_column(c)) + 0.5 + 0.35 * root.y * t * sin(icicle.z + 5.0 * t);
        float dx = x - centre;
        float cover = clamp(r - abs(dx) + 0.5, 0.0, 1.0);
        if (cover <= 0.0 || root.w >= nearest) continue;
        nearest = root.w;
        coverage = cover;
        across = clamp(dx / max(r, 0.5), -1.0, 1.0);
        radius = r;
    }
    if (coverage <= 0.0) discard;
    float depth = texelFetch(window_depth, p, 0).r;
    if (depth < 1.0 && -eye_at(gl_FragCoord.xy, depth).z < nearest * 0.95) discard;

    float facing = sqrt(1.0 - across * across);
    vec3 n = normalize(vec3(across, 0.2, facing));
    ivec2 behind = clamp(ivec2(gl_FragCoord.xy + vec2(-across * refraction * radius, 0.0)), ivec2(0),
                         ivec2(tile_size) - 1);
    vec3 background = texelFetch(scene, behind, 0).rgb;
    vec3 ice = background * vec3(0.72, 0.86, 0.98) * (0.55 + 0.45 * facing) + (1.0 - facing) * vec3(0.30, 0.34, 0.38);

    vec3 direction = normalize(eye_at(gl_FragCoord.xy, 0.5));
    vec3 position = direction * (nearest / max(-direction.z, 1e-3));
    vec3 l = normalize(light_eye.xyz - position * light_eye.w);
    vec3 h = normalize(l - direction);
    ice += vec3(1.0, 0.99, 0.97) * (0.9 * pow(max(dot(n, h), 0.0), 40.0));

    out_color = vec4(min(ice, vec3(1.0)), coverage * (0.82 + 0.15 * (1.0 - facing)));
}
