// Edges of the hard shadows (the erosion method's edge detection, docs/shadows.md), drawn over the blocks that hold
// candidates (shadow_candidates.frag): a 3x3 Laplacian (five taps) of the lit channel, kept
// only where the shadow map has a silhouette at the pixel's light position (the same
// Laplacian over shadow tests there), so edges that come from occlusion in the camera's view
// are dropped (Arvo et al.). Output, the min-max mipmap's level 0:
//   r: 0 on an edge, 1 elsewhere (min-reduced)
//   g: the edge's full penumbra width, eye units (max-reduced): the largest of its shadowed
//      taps (a lit edge pixel has no blocker of its own)
//   b: eye depth of the edge pixel
// OCCLUSION_EDGES (erosion/PCF): a pixel just beyond an object's outline in the camera's view
// may lie in the penumbra of a shadow edge that the object hides; when a few blocker taps
// around it (over the largest possible penumbra) are mixed, it becomes an edge with the
// penumbra width of their mean blocker, so the eroded region covers that penumbra too.
uniform int u_silhouette_check;
out vec4 out_color;

// The receiver's shadow-map neighbourhood, one screen pixel's footprint apart, has both lit
// and shadowed tests.
bool silhouette(ivec2 p, float depth) {
    Receiver r = receiver_at(p, depth);
    vec2 texel_world = 1.0 / (uv_scale(r.depth) * u_map_size);
    float footprint = (r.eye_depth / u_focal_px) / max(texel_world.x, texel_world.y);
    vec2 step = vec2(max(1.0, 1.5 * footprint) / u_map_size);
    float laplacian = 4.0 * lit_at(r, vec2(0.0)) - lit_at(r, vec2(step.x, 0.0)) - lit_at(r, vec2(-step.x, 0.0)) -
                      lit_at(r, vec2(0.0, step.y)) - lit_at(r, vec2(0.0, -step.y));
    return laplacian != 0.0;
}

#ifdef OCCLUSION_EDGES
const int kOutlineTaps = 8;

// The width of the penumbra the pixel may be in, or -1 when its taps agree.
float hidden_penumbra(ivec2 p) {
    Receiver r = receiver_at(p, camera_depth(p));
    vec2 radius = max_half_width_uv(r);
    float rotation = pixel_rotation(p), sum = 0.0, found = 0.0;
    for (int i = 0; i < kOutlineTaps; ++i) {
        vec2 o = disk_point(i, kOutlineTaps, rotation) * radius;
        float b = map_depth(r.uv + o);
        if (b < r.depth + dot(r.slope, o) - r.bias) {
            sum += b;
            found += 1.0;
        }
    }
    return found > 0.0 && found < float(kOutlineTaps) ? penumbra_world(r.depth, sum / found) : -1.0;
}
#endif

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = hard(p), w = hard(p - ivec2(1, 0)), e = hard(p + ivec2(1, 0)), s = hard(p - ivec2(0, 1)),
         n = hard(p + ivec2(0, 1));
    bool candidate = c.a > 0.0 && 4.0 * c.r - w.r - e.r - s.r - n.r != 0.0;
#ifdef OCCLUSION_EDGES
    bool outline = c.a > 0.0 && beyond_outline(c, w, e, s, n);
#else
    bool outline = false;
#endif
    if (!candidate && !outline) discard;  // the cleared (1, 0, 0, 0)
    if (candidate && (u_silhouette_check == 0 || silhouette(p, camera_depth(p)))) {
        out_color = vec4(0.0, max(c.b, max(max(w.b, e.b), max(s.b, n.b))), c.a, 0.0);
        return;
    }
#ifdef OCCLUSION_EDGES
    float width = outline ? hidden_penumbra(p) : -1.0;
    if (width >= 0.0) {
        out_color = vec4(0.0, width, c.a, 1.0);
        return;
    }
#endif
    discard;
}
