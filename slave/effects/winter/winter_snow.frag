// Snow shading over the window (tile pixels), blended by the cover amount: a bright, slightly
// blue-white diffuse surface lit by the scene's light (wrap lighting for the light that snow
// scatters under its surface), a blue sky fill, a fine bump of world-space noise and sparse
// glints, as the snow shader of docs/winter.md (lighting plus anti-aliased noise for the
// specular and the bump). Below the lower edges of the cover the snow hangs over in a rounded
// lip of seeded thickness (winter_edges.glsl).
uniform sampler2D cover;         // winter_cover.frag, guard-band pixels
uniform sampler2D normals;
uniform sampler2D positions;
uniform int guard;
uniform vec2 canvas_offset;      // canvas pixel of tile pixel (0, 0)
uniform mat4 world_from_eye;
uniform vec3 up_eye;
uniform vec4 light_eye;          // eye space; w = 0: directional
uniform float noise_scale;       // world size of the snow patches: the bump is 1/40 of it
uniform float brightness;
uniform int seed_bits;      // the seed's unsigned bits (glUniform1i)
uniform int lip_rows;            // rows searched above a pixel for the lip's edge

out vec4 out_color;

void main() {
    uint seed = uint(seed_bits);
    ivec2 q = ivec2(gl_FragCoord.xy) + guard;
    float amount = texelFetch(cover, q, 0).r;
    ivec2 surface = q;  // the pixel whose surface holds the snow seen here
    float down_lip = -1.0;  // 0 at a lower edge to 1 at the lip's bottom; -1: not on a lip
    if (amount < 0.5 && lip_px > 0.0) {
        // The lip: snow rounded over a lower edge a few pixels above, hanging down its face.
        for (int k = 1; k <= lip_rows; ++k) {
            ivec2 e = q + ivec2(0, k);
            if (winter_lower_edge(cover, normals, e)) {
                float thickness = winter_lip_thickness(ivec2(canvas_offset) + e - guard);
                float reach = clamp(thickness - float(k) + 1.0, 0.0, 1.0);  // antialiased bottom
                if (reach > 0.0) {
                    down_lip = (float(k) - 0.5) / thickness;
                    surface = e;
                    amount = max(amount, reach * texelFetch(cover, e, 0).r);
                }
                break;
            }
            if (texelFetch(cover, e, 0).r >= 0.5) break;  // snow above that is no edge
        }
    }
    if (amount <= 1.0 / 512.0) discard;
    vec3 n = texelFetch(normals, surface, 0).xyz;
    vec3 p = texelFetch(positions, surface, 0).xyz;
    if (down_lip >= 0.0) {
        // Rounded from the top's normal towards the face below (or the camera, over the sky).
        vec4 face = texelFetch(normals, surface - ivec2(0, 1), 0);
        vec3 front = face.w > 0.0 ? face.xyz : normalize(-p);
        n = normalize(mix(n, front, smoothstep(0.0, 1.0, clamp(down_lip, 0.0, 1.0))));
    }
    vec3 world = (world_from_eye * vec4(p, 1.0)).xyz;

    // Bump: the gradient of fine noise tilts the normal a little.
    vec3 gradient = winter_value_noise_gradient(world / (noise_scale / 40.0), seed + 101u).yzw;
    // The gradient is a world-space vector; v * M is transpose(M) * v, the inverse rotation.
    vec3 bumped = normalize(n - 0.12 * (gradient * mat3(world_from_eye)));

    vec3 l = normalize(light_eye.xyz - p * light_eye.w);
    vec3 v = normalize(-p);
    float wrap = clamp((dot(bumped, l) + 0.3) / 1.3, 0.0, 1.0);
    float sky = 0.5 + 0.5 * dot(bumped, up_eye);
    vec3 color = vec3(0.93, 0.95, 1.0) * (0.62 * wrap * vec3(1.0, 0.98, 0.95) + 0.42 * sky * vec3(0.80, 0.88, 1.0));

    // Glints: a few pixels hold an ice crystal that mirrors the light. Chosen by canvas pixel,
    // not by world position: a crystal is far smaller than a pixel, and a world lattice that
    // fine would pick different crystals for the same pixel on two tiles (their re-renders
    // interpolate positions a rounding step apart).
    float crystal = winter_random(ivec3(ivec2(canvas_offset + gl_FragCoord.xy), 7), seed + 202u);
    float mirror = pow(max(dot(reflect(-l, n), v), 0.0), 6.0);
    color += step(0.985, crystal) * mirror * 0.9;

    out_color = vec4(min(color * brightness, vec3(1.0)), amount);
}
