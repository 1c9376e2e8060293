// Screen-space shadows, first step (docs/shadows.md, "Frames that cannot be re-rendered"): no
// shadow map, only the camera depth, the projection and the light. Each pixel's point of the
// scene marches towards the light; where the ray passes behind what the depth buffer shows
// there (by less than an object's assumed thickness), that surface blocks it. What the depth
// buffer cannot show (the backs of objects, what lies off the tile) casts nothing.
// Writes, per pixel (shadow_screen_filter.frag then softens it):
//   r: 1 lit, 0 blocked (a ramp of two pixels' depth at the blocker, against aliasing)
//   g: how much the surface faces the light (the darkening's weight)
//   b: blocked: the full penumbra width its first blocker casts here (parallel planes), eye
//      units (0: lit)
//   a: eye depth (0: background)
uniform mat4 u_eye_from_clip;   // work-area clip -> eye (E)
uniform mat4 u_clip_from_eye;   // its inverse
uniform vec4 u_light_eye;       // w = 0: unit direction towards the light; w = 1: its position
uniform int u_steps;
uniform float u_reach_px;       // the longest ray on the screen
uniform float u_max_reach;      // the longest ray, eye units
uniform float u_thickness;      // share of a sample's eye depth it hides behind it
out vec4 out_color;

vec3 eye_at(vec2 pixel, float depth) {
    vec4 e = u_eye_from_clip * vec4(pixel / u_work_size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    return e.xyz / e.w;
}

// The point's plane from the neighbours whose depth is closer (silhouettes do not tilt it);
// zero where a neighbour is background.
vec3 surface_normal(ivec2 p, float depth, vec3 at) {
    vec3 along[2];
    for (int axis = 0; axis < 2; ++axis) {
        ivec2 step = axis == 0 ? ivec2(1, 0) : ivec2(0, 1);
        float da = camera_depth(p + step), db = camera_depth(p - step);
        bool use_a = abs(da - depth) <= abs(db - depth);
        float dn = use_a ? da : db;
        if (dn >= 1.0) return vec3(0.0);
        ivec2 q = use_a ? p + step : p - step;
        along[axis] = (use_a ? 1.0 : -1.0) * (eye_at(vec2(q) + 0.5, dn) - at);
    }
    vec3 n = cross(along[0], along[1]);
    if (dot(n, n) <= 0.0) return vec3(0.0);
    n = normalize(n);
    return dot(n, -at) < 0.0 ? -n : n;  // the side the camera sees
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float depth = camera_depth(p);
    if (depth >= 1.0) {
        out_color = vec4(1.0, 1.0, 0.0, 0.0);
        return;
    }
    vec3 at = eye_at(vec2(p) + 0.5, depth);
    vec3 to_light = u_light_eye.w == 0.0 ? u_light_eye.xyz : normalize(u_light_eye.xyz - at);
    float light_distance = u_light_eye.w == 0.0 ? 1e30 : length(u_light_eye.xyz - at);
    vec3 normal = surface_normal(p, depth, at);
    float facing = dot(normal, normal) > 0.0 ? smoothstep(0.0, 0.2, dot(normal, to_light)) : 1.0;
    if (facing <= 0.0) {
        out_color = vec4(1.0, 0.0, 0.0, -at.z);
        return;
    }
    float eye_depth = -at.z;
    float pixel = eye_depth / u_focal_px;  // eye units across one pixel here
    float reach = min(u_max_reach, 0.95 * light_distance);
    // A ray towards the camera stops short of the eye plane, where projection folds over.
    if (to_light.z > 0.0) reach = min(reach, 0.9 * eye_depth / to_light.z);
    vec3 origin = at + normal * (1.5 * pixel);
    // The ray in clip space is a + t b (the projection is linear in homogeneous coordinates).
    // Its length on the screen, |t K| / (a.w (a.w + t b.w)) pixels, grows with t but not in
    // proportion; solved for the t that spans u_reach_px (none when it never does).
    vec4 a = u_clip_from_eye * vec4(origin, 1.0), b = u_clip_from_eye * vec4(to_light, 0.0);
    float k = length((b.xy * a.w - a.xy * b.w) * 0.5 * u_work_size);
    float denominator = k - u_reach_px * a.w * b.w;
    if (denominator > 0.0) reach = min(reach, u_reach_px * a.w * a.w / denominator);
    // Rows z and w of E: a depth sample's eye depth from its clip position, two dot products.
    vec4 z_row = vec4(u_eye_from_clip[0].z, u_eye_from_clip[1].z, u_eye_from_clip[2].z, u_eye_from_clip[3].z);
    vec4 w_row = vec4(u_eye_from_clip[0].w, u_eye_from_clip[1].w, u_eye_from_clip[2].w, u_eye_from_clip[3].w);

    // Steps denser near the receiver (contacts are sharp there); the start jittered by the
    // canvas pixel's noise, the same on every tile of a wall.
    float jitter = pixel_rotation(p) / 6.2831853;
    float visibility = 1.0, blocker = 0.0;
    for (int i = 0; i < u_steps; ++i) {
        float t = (float(i) + jitter) / float(u_steps);
        float travelled = reach * t * t;
        vec4 c = a + travelled * b;
        vec2 ndc = c.xy / c.w;
        if (any(greaterThanEqual(abs(ndc), vec2(1.0)))) break;  // off the tile: unknown
        float sd = camera_depth(ivec2((ndc * 0.5 + 0.5) * u_work_size));
        if (sd >= 1.0) continue;
        vec4 sc = vec4(ndc, sd * 2.0 - 1.0, 1.0);
        float surface = -dot(z_row, sc) / dot(w_row, sc);
        float behind = -(origin.z + to_light.z * travelled) - surface;  // > 0: hidden by the surface shown there
        if (behind > u_thickness * surface) continue;  // it passes behind an object: unknown, lit
        float v = clamp(0.5 - behind / (2.0 * pixel), 0.0, 1.0);
        if (v < visibility) {
            visibility = v;
            if (blocker == 0.0) {
                float spread = u_light_eye.w == 0.0 ? u_light_spread * travelled
                                                    : u_light_spread * travelled / max(light_distance - travelled, 1e-6);
                blocker = max(spread, 1e-6);
            }
        }
        if (visibility <= 0.0) break;
    }
    out_color = vec4(visibility, facing, blocker, eye_depth);
}
