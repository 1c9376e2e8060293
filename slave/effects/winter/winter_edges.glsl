// Lower edges of the snow cover (docs/winter.md, "Lip and icicles"), shared by the snow's lip
// and the icicles' roots: a pixel with snow whose neighbour below is background, a surface
// turned away by more than the edge angle that cannot hold snow itself, for two pixels down (the
// vertical face under a roof's rim; not a kerb's face, nor a strip of another ground mesh where
// two cross, nor a crease between two slopes), or a surface much farther away (a ledge), but not a
// nearer one (an object in front: an occluding contour).
// Reads the guard-band buffers, so a tile sees the edges just beyond its border.
uniform float edge_cos;          // cos(cover.edge_angle)
uniform float lip_px;            // mean thickness of the snow's rounded lip, canvas pixels (0: none)
uniform int lip_seed_bits;

bool winter_lower_edge(sampler2D cover, sampler2D normals, ivec2 q) {
    if (q.y < 1) return false;
    vec4 here = texelFetch(cover, q, 0);
    if (here.a < 1.0 || here.r < 0.5) return false;
    ivec2 under = q - ivec2(0, 1);
    vec4 below = texelFetch(cover, under, 0);
    if (below.a < 0.0) return false;  // unknown (outside a tile reconstructed from depth)
    if (below.a == 0.0) return true;
    if (below.g < here.g * 0.97) return false;
    if (below.g > here.g * 1.1) return true;
    if (below.b >= 0.5 || dot(texelFetch(normals, q, 0).xyz, texelFetch(normals, under, 0).xyz) >= edge_cos)
        return false;
    if (q.y < 2) return true;
    vec4 next = texelFetch(cover, q - ivec2(0, 2), 0);
    return next.a == 0.0 || next.b < 0.5 || next.g > below.g * 1.1;
}

// Thickness of the lip hanging below the lower-edge pixel at canvas pixel `edge`: 0.5 to 1.5
// times lip_px, varying smoothly along the edge (seeded value noise of the canvas position).
float winter_lip_thickness(ivec2 edge) {
    if (lip_px <= 0.0) return 0.0;
    vec3 p = vec3(float(edge.x) / (4.0 * lip_px + 2.0), float(edge.y) * 0.618, 0.5);
    return lip_px * (0.5 + winter_value_noise(p, uint(lip_seed_bits) + 303u));
}
