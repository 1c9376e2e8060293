// Visibility of each work pixel (r), with the receiver's facing (g) for the darkening.
//   EROSION_PCF: in the eroded penumbra regions PCF over the region's penumbra half-width at
//     this receiver (the erosion method's first solution); elsewhere the hard shadow.
//   PCSS: Fernando's percentage-closer soft shadows: the mean depth of the blockers found by
//     u_blocker_samples taps over the largest possible penumbra, the parallel-planes width
//     from it, PCF over half of it.
uniform sampler2D u_erosion;
uniform int u_pcf_samples;
uniform int u_blocker_samples;
out vec4 out_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float depth = camera_depth(p);
    out_color = vec4(1.0, 1.0, 0.0, 0.0);
    if (depth >= 1.0) return;
#ifdef EROSION_PCF
    vec2 region = texelFetch(u_erosion, p, 0).rg;
    if (region.g < 0.5) {
        out_color.rg = texelFetch(u_hard, p, 0).rg;
        return;
    }
    Receiver r = receiver_at(p, depth);
    out_color.g = r.facing;
    vec2 radius = min(0.5 * region.r * uv_scale(r.depth), max_half_width_uv(r));
    out_color.r = pcf_narrowed(r, radius, u_pcf_samples, pixel_rotation(p));
#else
    Receiver r = receiver_at(p, depth);
    out_color.g = r.facing;
    float rotation = pixel_rotation(p);
    vec2 search = max_half_width_uv(r);
    float blockers = 0.0, sum = 0.0;
    for (int i = 0; i < u_blocker_samples; ++i) {
        vec2 o = disk_point(i, u_blocker_samples, rotation) * search;
        float b = map_depth(r.uv + o);
        if (b < r.depth + dot(r.slope, o) - r.bias) {
            sum += b;
            blockers += 1.0;
        }
    }
    if (blockers == 0.0) return;
    out_color.r = pcf(r, half_width_uv(r, sum / blockers), u_pcf_samples, rotation);
#endif
}
