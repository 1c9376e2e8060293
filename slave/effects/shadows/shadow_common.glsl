// Shared by the soft-shadow shaders (shadow_renderer.cpp prepends it): the camera depth of the
// work area (tile + guard band), the shadow map and the light's frame, receivers in light
// space, hard tests, blocker search and PCF. Light depth = distance along the light's axis.

uniform sampler2D u_depth;        // camera depth of the work area, 0..1
uniform sampler2D u_shadow_map;   // light depth, 0..1
uniform vec2 u_work_size;
uniform vec2 u_canvas_origin;     // canvas pixel of work pixel (0, 0)
uniform float u_focal_px;         // pixels per eye-space unit at eye depth 1
uniform float u_max_radius_px;    // penumbra half-widths are bounded by this many pixels

uniform mat4 u_light_view_from_clip;  // L E: work-area clip -> light view (homogeneous, w of eye space)
uniform mat4 u_light_clip_from_clip;  // P_light L E
uniform vec4 u_eye_z_row;             // row z of E: the eye-space z of a work-area clip point (homogeneous)
uniform vec3 u_camera_in_light_view;
uniform int u_light_ortho;        // 1: orthographic map (directional light)
uniform float u_light_near, u_light_far;
uniform vec2 u_uv_per_unit;       // map uv per eye unit across the axis (at light depth 1 if perspective)
uniform float u_map_size;
uniform float u_light_spread;     // positional: disk diameter; directional: 2 tan(angle / 2)
uniform float u_bias_texels;

uniform sampler2D u_hard;         // the hard-shadow buffer (shadow_hard.frag)

const float kNoBlocker = 1e30;

vec4 hard(ivec2 p) {
    return texelFetch(u_hard, clamp(p, ivec2(0), ivec2(u_work_size) - 1), 0);
}

// Hard-shadow texel c lies just beyond an object's outline in the camera's view: a 4-neighbour
// is clearly nearer (background, eye depth 0, never hides anything).
bool beyond_outline(vec4 c, vec4 w, vec4 e, vec4 s, vec4 n) {
    float nearer = 0.97 * c.a;
    return (w.a > 0.0 && w.a < nearer) || (e.a > 0.0 && e.a < nearer) || (s.a > 0.0 && s.a < nearer) ||
           (n.a > 0.0 && n.a < nearer);
}

float camera_depth(ivec2 p) {
    return texelFetch(u_depth, clamp(p, ivec2(0), ivec2(u_work_size) - 1), 0).r;
}

// A pixel's point of the scene: shadow-map uv, light depth, light-view position (a rigid
// motion of eye space: distances and angles are the eye's) and eye depth.
struct ScenePoint {
    vec2 uv;
    float depth;
    vec3 light_view;
    float eye_depth;
};

ScenePoint scene_point(ivec2 p, float depth) {
    vec4 clip = vec4((vec2(p) + 0.5) / u_work_size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    vec4 v = u_light_view_from_clip * clip, k = u_light_clip_from_clip * clip;
    ScenePoint q;
    q.light_view = v.xyz / v.w;
    q.depth = -q.light_view.z;
    q.uv = k.xy / k.w * 0.5 + 0.5;
    q.eye_depth = -dot(u_eye_z_row, clip) / v.w;
    return q;
}

float light_depth_from_map(float d) {
    if (u_light_ortho == 1) return u_light_near + d * (u_light_far - u_light_near);
    float ndc = d * 2.0 - 1.0;
    return 2.0 * u_light_near * u_light_far / (u_light_far + u_light_near - ndc * (u_light_far - u_light_near));
}

// The blocker's light depth at `uv`; nothing blocks outside the map.
float map_depth(vec2 uv) {
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return kNoBlocker;
    return light_depth_from_map(texelFetch(u_shadow_map, ivec2(uv * u_map_size), 0).r);
}

// Map uv per eye unit across the light axis at light depth `depth`.
vec2 uv_scale(float depth) {
    return u_light_ortho == 1 ? u_uv_per_unit : u_uv_per_unit / max(depth, 1e-6);
}

// The parallel-planes estimate: full penumbra width on the receiver, eye units.
float penumbra_world(float receiver, float blocker) {
    float gap = max(receiver - blocker, 0.0);
    return u_light_ortho == 1 ? u_light_spread * gap : u_light_spread * gap / max(blocker, 1e-6);
}

struct Receiver {
    vec2 uv;          // shadow-map position
    float depth;      // light depth
    vec2 slope;       // d depth / d uv of the receiver's plane (Isidoro's receiver-plane bias)
    float eye_depth;  // distance along the camera's axis
    float bias;       // light depth a blocker must be nearer by
    float facing;     // 0 where the plane turns from the light, 1 from N.L = 0.2 on
};

// The receiver at work pixel p (camera depth `depth`, not background). Its plane comes from
// the neighbours on the side whose depth is closer, so silhouettes do not tilt it.
Receiver receiver_at(ivec2 p, float depth) {
    ScenePoint c = scene_point(p, depth);
    vec3 d[2], along[2];
    bool plane = true;
    for (int axis = 0; axis < 2; ++axis) {
        ivec2 step = axis == 0 ? ivec2(1, 0) : ivec2(0, 1);
        float da = camera_depth(p + step), db = camera_depth(p - step);
        bool use_a = abs(da - depth) <= abs(db - depth);
        float dn = use_a ? da : db;
        if (dn >= 1.0) {
            d[axis] = vec3(0.0);
            along[axis] = vec3(0.0);
            plane = false;
            continue;
        }
        ScenePoint n = scene_point(use_a ? p + step : p - step, dn);
        float sign = use_a ? 1.0 : -1.0;
        d[axis] = sign * (vec3(n.uv, n.depth) - vec3(c.uv, c.depth));
        along[axis] = sign * (n.light_view - c.light_view);
    }
    Receiver r;
    r.uv = c.uv;
    r.depth = c.depth;
    r.eye_depth = c.eye_depth;
    mat2 j = mat2(d[0].xy, d[1].xy);  // columns: d uv / d pixel x, d uv / d pixel y
    float det = determinant(j);
    r.slope = abs(det) > 1e-14 ? vec2(d[0].z, d[1].z) * inverse(j) : vec2(0.0);
    // Beyond ~80 degrees of incidence the plane's slope is noise; cap it.
    vec2 texel_world = 1.0 / (uv_scale(r.depth) * u_map_size);
    float cap = 6.0 * max(texel_world.x, texel_world.y) * u_map_size;
    float s = length(r.slope);
    if (s > cap) r.slope *= cap / s;
    r.bias = u_bias_texels * max(texel_world.x, texel_world.y) + (abs(r.slope.x) + abs(r.slope.y)) / u_map_size;
    r.facing = 1.0;
    vec3 normal = cross(along[0], along[1]);
    if (plane && dot(normal, normal) > 0.0) {
        normal = normalize(normal);
        if (dot(normal, u_camera_in_light_view - c.light_view) < 0.0) normal = -normal;  // the side we see
        vec3 to_light = u_light_ortho == 1 ? vec3(0.0, 0.0, 1.0) : normalize(-c.light_view);
        r.facing = smoothstep(0.0, 0.2, dot(normal, to_light));
    }
    return r;
}

// 1 if the receiver, moved by `offset` (uv) along its plane, is lit by the light's centre.
float lit_at(Receiver r, vec2 offset) {
    return map_depth(r.uv + offset) < r.depth + dot(r.slope, offset) - r.bias ? 0.0 : 1.0;
}

// Interleaved gradient noise of the canvas pixel: the same on every tile of a wall.
float pixel_rotation(ivec2 p) {
    vec2 q = vec2(p) + u_canvas_origin;
    return 6.2831853 * fract(52.9829189 * fract(dot(q, vec2(0.06711056, 0.00583715))));
}

// Point i of n on the unit disk (Vogel spiral: equal areas), turned by `rotation`.
vec2 disk_point(int i, int n, float rotation) {
    float r = sqrt((float(i) + 0.5) / float(n));
    float a = float(i) * 2.39996323 + rotation;
    return r * vec2(cos(a), sin(a));
}

// Percentage-closer filtering over a disk of `radius` (uv).
float pcf(Receiver r, vec2 radius, int samples, float rotation) {
    float lit = 0.0;
    for (int i = 0; i < samples; ++i) lit += lit_at(r, disk_point(i, samples, rotation) * radius);
    return lit / float(samples);
}

// The largest penumbra half-width (uv) a receiver can have: the light's cone reaching the
// map's near plane, bounded by u_max_radius_px pixels on the screen.
vec2 max_half_width_uv(Receiver r) {
    float blocker = u_light_ortho == 1 ? u_light_near : max(u_light_near, 1e-6);
    float world = 0.5 * penumbra_world(r.depth, blocker);
    float bound = u_max_radius_px * r.eye_depth / u_focal_px;
    return min(world, bound) * uv_scale(r.depth);
}

// The penumbra half-width (uv) for a blocker at light depth `blocker`, bounded likewise.
vec2 half_width_uv(Receiver r, float blocker) {
    float world = 0.5 * penumbra_world(r.depth, blocker);
    float bound = u_max_radius_px * r.eye_depth / u_focal_px;
    return min(world, bound) * uv_scale(r.depth);
}

// PCF over the eroded kernel `radius`, then narrowed to the penumbra its own blockers imply:
// the samples that hit blockers give their mean depth (a blocker search for free), the
// parallel-planes half-width of that depth gives a sub-disk, and the visibility is the share
// of lit samples inside it (the hard test when none falls inside). A kernel sized by a wide
// penumbra nearby then does not blur the sharp shadow of a blocker close to the receiver.
float pcf_narrowed(Receiver r, vec2 radius, int samples, float rotation) {
    float blocker_sum = 0.0, blockers = 0.0;
    uint lit_bits[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);  // samples <= 256
    for (int i = 0; i < samples; ++i) {
        vec2 o = disk_point(i, samples, rotation) * radius;
        float b = map_depth(r.uv + o);
        if (b < r.depth + dot(r.slope, o) - r.bias) {
            blocker_sum += b;
            blockers += 1.0;
        } else {
            lit_bits[i >> 5] |= 1u << uint(i & 31);
        }
    }
    if (blockers == 0.0) return 1.0;
    if (blockers == float(samples)) return 0.0;
    vec2 narrow = half_width_uv(r, blocker_sum / blockers);
    float share = min(narrow.x / max(radius.x, 1e-12), 1.0);
    // Vogel point i lies at sqrt((i + 0.5) / n) of the radius: the first k are inside.
    int inside = int(floor(share * share * float(samples) - 0.5)) + 1;
    if (inside <= 0) return lit_at(r, vec2(0.0));
    float lit = 0.0;
    for (int i = 0; i < inside; ++i) lit += float((lit_bits[i >> 5] >> uint(i & 31)) & 1u);
    return lit / float(inside);
}
