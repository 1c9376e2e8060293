// Particles of falling snow or rain (precipitation.cpp): instance i is one flake, drawn as a
// quad stretched along its motion over the exposure (motion blur). Every choice is a hash of
// the seed and the particle index, and its position a function of stream time: a rerun, and
// every tile of a wall, sees the same flakes.
uniform mat4 eye_from_world;
uniform mat4 clip_from_eye;   // the tile's: flakes cross tile borders continuously
uniform vec3 box_min;         // the volume around the camera, world coordinates
uniform vec3 origin;          // particle p sits at box_min + mod(p - origin, box_size)
uniform float box_size;
uniform float time;           // seconds (folded by an hour; sway only)
uniform float radius;         // mean flake radius, world units
uniform float sway;           // sideways amplitude, world units
uniform vec3 blur_eye;        // how far a flake moves (eye space) during the exposure
uniform vec2 viewport_size;
uniform uint seed;
uniform float opacity;

out vec2 local;               // x across the streak in radii, y along it
flat out float half_length;   // of the streak's core segment, in radii
flat out float alpha;

uint hash(uint x) {
    x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
    return x;
}
float random01(uint i, uint k) { return float(hash(hash(seed ^ 0x9e3779b9u) + i * 8u + k) >> 8) / 16777216.0; }

void main() {
    uint i = uint(gl_InstanceID);
    vec3 start = vec3(random01(i, 0u), random01(i, 1u), random01(i, 2u)) * box_size;
    vec3 inside = mod(start - origin, box_size);  // 0 .. box_size
    vec3 world = box_min + inside;
    float phase = random01(i, 3u) * 6.2831853, frequency = 0.3 + 0.7 * random01(i, 5u);
    world.x += sway * sin(6.2831853 * frequency * time + phase);
    world.z += sway * cos(6.2831853 * 0.7 * frequency * time + phase);
    // Fade in and out near the faces of the volume, where particles wrap around.
    vec3 edge = min(inside, box_size - inside) / box_size;
    float fade = smoothstep(0.0, 0.08, min(edge.x, min(edge.y, edge.z)));

    vec3 eye = (eye_from_world * vec4(world, 1.0)).xyz;
    float r = radius * (0.5 + random01(i, 4u));
    float a = opacity * fade;
    // Flakes smaller than a pixel would shimmer: keep 0.7 px and spread the same coverage.
    float pixels_per_unit = abs(clip_from_eye[0][0]) * viewport_size.x * 0.5 / max(-eye.z, 1e-6);
    float r_px = r * pixels_per_unit;
    if (r_px < 0.7) {
        a *= (r_px / 0.7) * (r_px / 0.7);
        r *= 0.7 / max(r_px, 1e-6);
    }
    vec3 ray = normalize(eye);
    float blur = length(blur_eye);
    vec3 along = blur > 1e-4 * r ? blur_eye / blur : vec3(0.0, 1.0, 0.0);
    vec3 across = cross(along, ray);
    if (length(across) < 1e-4) { along = vec3(0.0, 1.0, 0.0); across = cross(along, ray); blur = 0.0; }
    across = normalize(across);
    along = normalize(cross(ray, across));
    half_length = 0.5 * blur / r;
    // The coverage of one flake, spread over its streak.
    alpha = a * 3.14159 / (3.14159 + 4.0 * half_length);
    vec3 centre = eye - 0.5 * blur_eye;
    vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
    local = vec2(corner.x, corner.y * (half_length + 1.0));
    vec3 p = centre + across * (corner.x * r) + along * (corner.y * (half_length + 1.0) * r);
    gl_Position = clip_from_eye * vec4(p, 1.0);
}
