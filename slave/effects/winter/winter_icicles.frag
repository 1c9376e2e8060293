// An icicle over the window: a tapered cone hanging straight down the screen from its root,
// shaded as translucent ice: the scene behind it shifted sideways as through a cylinder lens,
// tinted and darkened in the middle, brightened at the rims, with a specular highlight of the
// scene's light. Hidden where the window holds a surface well in front of its root.
flat in vec4 v_root;
flat in float v_axis;
flat in float v_phase;
uniform sampler2D scene;         // the window after the snow cover, tile pixels
uniform sampler2D window_depth;
uniform mat4 eye_from_tile_clip;
uniform vec2 tile_size;
uniform float taper;
uniform float refraction;        // in icicle radii
uniform vec4 light_eye;

out vec4 out_color;

vec3 eye_at(vec2 pixel, float depth) {
    vec4 eye = eye_from_tile_clip * vec4(pixel / tile_size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    return eye.xyz / eye.w;
}

void main() {
    float t = (v_root.x - gl_FragCoord.y) / v_root.z;  // 0 at the root, 1 at the tip
    if (t <= 0.0 || t >= 1.0) discard;
    float radius = v_root.y * pow(1.0 - t, taper);
    float dx = gl_FragCoord.x - (v_axis + 0.35 * v_root.y * t * sin(v_phase + 5.0 * t));
    float coverage = clamp(radius - abs(dx) + 0.5, 0.0, 1.0);
    if (coverage <= 0.0) discard;
    ivec2 p = ivec2(gl_FragCoord.xy);
    float depth = texelFetch(window_depth, p, 0).r;
    // The icicle hangs at its root's distance (from the eye, as the cover keeps it); a surface well
    // in front of it hides it.
    if (depth < 1.0 && length(eye_at(gl_FragCoord.xy, depth)) < v_root.w * 0.95) discard;

    float across = clamp(dx / max(radius, 0.5), -1.0, 1.0);
    float facing = sqrt(1.0 - across * across);
    // Its normal in the tile's screen axes, brought into the program's eye space, where the light
    // is: the tile may be turned from the program's camera (a cylinder's or a CAVE's side). Points
    // of one depth on the screen lie in a plane square to the tile's view.
    vec3 at = eye_at(gl_FragCoord.xy, 0.5);
    vec3 right = normalize(eye_at(gl_FragCoord.xy + vec2(1.0, 0.0), 0.5) - at);
    vec3 up = normalize(eye_at(gl_FragCoord.xy + vec2(0.0, 1.0), 0.5) - at);
    vec3 n = normalize(across * right + 0.2 * up + facing * cross(right, up));
    ivec2 behind = clamp(ivec2(gl_FragCoord.xy + vec2(-across * refraction * radius, 0.0)), ivec2(0),
                         ivec2(tile_size) - 1);
    vec3 background = texelFetch(scene, behind, 0).rgb;
    vec3 ice = background * vec3(0.72, 0.86, 0.98) * (0.55 + 0.45 * facing) + (1.0 - facing) * vec3(0.30, 0.34, 0.38);

    vec3 direction = normalize(eye_at(gl_FragCoord.xy, 0.5));
    vec3 position = direction * v_root.w;
    vec3 l = normalize(light_eye.xyz - position * light_eye.w);
    vec3 h = normalize(l - direction);
    ice += vec3(1.0, 0.99, 0.97) * (0.9 * pow(max(dot(n, h), 0.0), 40.0));

    out_color = vec4(min(ice, vec3(1.0)), coverage * (0.82 + 0.15 * (1.0 - facing)));
}
