// Screen-space shadows, second step: the marched hard shadows (shadow_screen_space.frag, in
// u_hard) softened as PCSS softens a shadow map's, but over the screen: the blockers found
// within the largest penumbra around the pixel give their mean penumbra width (the march's
// parallel-planes estimate), and the visibility is the mean of the hard shadows over a disk of
// that width. Sharp at contact, soft further away.
// Only samples on surfaces at about the pixel's own depth count: a shadow does not bleed from
// the ground onto an object standing in front of it.
uniform int u_search_samples;  // blocker search
uniform int u_samples;         // the softening disk
out vec4 out_color;

bool same_surface(vec4 s, float eye_depth) {
    return s.a > 0.0 && abs(s.a - eye_depth) < 0.05 * eye_depth;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = hard(p);
    if (c.a <= 0.0 || c.g <= 0.0) {
        out_color = vec4(c.r, c.g, 0.0, 0.0);
        return;
    }
    float rotation = pixel_rotation(p);
    float pixel = c.a / u_focal_px;  // eye units across one pixel at this depth
    float search = u_max_radius_px;
    float blockers = 0.0, width_sum = 0.0;
    for (int i = 0; i < u_search_samples; ++i) {
        vec4 s = hard(p + ivec2(round(disk_point(i, u_search_samples, rotation) * search)));
        if (s.b > 0.0 && same_surface(s, c.a)) {
            width_sum += s.b;
            blockers += 1.0;
        }
    }
    if (blockers == 0.0) {
        out_color = vec4(c.r, c.g, 0.0, 0.0);
        return;
    }
    float radius = clamp(0.5 * width_sum / blockers / pixel, 0.5, search);
    float lit = 0.0, weight = 0.0;
    for (int i = 0; i < u_samples; ++i) {
        vec4 s = hard(p + ivec2(round(disk_point(i, u_samples, rotation + 1.0) * radius)));
        if (!same_surface(s, c.a)) continue;
        lit += s.r;
        weight += 1.0;
    }
    out_color = vec4(weight > 0.0 ? lit / weight : c.r, c.g, 0.0, 0.0);
}
