// Darkens the tile: with blending dst * src, color *= 1 - strength * facing * (1 - visibility).
// facing fades the darkening out on surfaces turned away from the light (N.L from the camera
// depth's plane, 0 at N.L <= 0, 1 from N.L = 0.2): the program's own lighting leaves those
// unlit already, and a plane grazed by the light would show the shadow map's acne. Pixels left
// at factor 1 are discarded, so they stay bit-identical whatever the blending arithmetic.
uniform sampler2D u_visibility;
uniform vec2 u_tile_offset;  // work texel of tile pixel (0, 0)
uniform float u_strength;
uniform vec4 u_light_eye;    // the light's GL_POSITION in eye space (w = 0: directional)
out vec4 out_color;

float facing(ivec2 p) {
    float depth = camera_depth(p);
    if (depth >= 1.0) return 1.0;
    vec3 eye = eye_position(p, depth);
    vec3 axis[2];
    for (int a = 0; a < 2; ++a) {
        ivec2 step = a == 0 ? ivec2(1, 0) : ivec2(0, 1);
        float da = camera_depth(p + step), db = camera_depth(p - step);
        bool use_a = abs(da - depth) <= abs(db - depth);
        axis[a] = use_a ? eye_position(p + step, da) - eye : eye - eye_position(p - step, db);
    }
    vec3 n = cross(axis[0], axis[1]);
    if (dot(n, n) == 0.0) return 1.0;
    n = normalize(n);
    if (dot(n, eye) > 0.0) n = -n;  // towards the camera: the side we see
    vec3 l = normalize(u_light_eye.w == 0.0 ? u_light_eye.xyz : u_light_eye.xyz / u_light_eye.w - eye);
    return smoothstep(0.0, 0.2, dot(n, l));
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy) + ivec2(u_tile_offset);
    float v = texelFetch(u_visibility, p, 0).r;
    if (v >= 1.0) discard;
    float factor = 1.0 - u_strength * facing(p) * (1.0 - clamp(v, 0.0, 1.0));
    if (factor >= 1.0) discard;
    out_color = vec4(factor, factor, factor, 1.0);
}
