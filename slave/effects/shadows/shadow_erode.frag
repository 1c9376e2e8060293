// Erosion of the hard-shadow edges through their min-max mipmap (docs/shadows.md). Per
// pixel: the level whose 2x2 block covers the largest search radius; no edge there: done.
// Else the widest penumbra there gives a smaller radius and a finer level, until the radius
// stops shrinking; an edge within the final radius puts the pixel in a penumbra region.
//   EROSION_DIRECT undefined (erosion/PCF): out rg = (the region's widest penumbra, eye units;
//     1 inside a region, 0 outside), for the PCF of shadow_shade.frag.
//   EROSION_DIRECT: out r = visibility from the distance to the nearest edge whose penumbra
//     reaches the pixel, with the method's s_outer = (w - d) / 2w, s_inner = 1 - s_outer
//     (w: the edge's penumbra half-width, d: distance to its least-squares line, both on the
//     receiver); out g = the hard texel's facing.
uniform sampler2D u_edges;   // min-max mipmap, levels 0..u_levels
uniform sampler2D u_lines;
uniform int u_levels;
uniform int u_line_fit;
uniform int u_disk_profile;
out vec4 out_color;

// A region reaches as far as the full penumbra width (twice the half-width): PCF decides the
// value inside, so a generous region costs time, never quality, and covers the stretch of
// penumbras on receivers inclined to the light.
const float kRegionScale = 1.0;
// The widest block window one search step reads (blocks per side).
const int kMaxBlocks = 4;

// What the hierarchical search found: the edges that can reach the pixel lie in blocks of
// `level` within `radius` pixels; the widest penumbra among them and the width of the
// nearest such block.
struct Search {
    bool found;
    float radius;
    float widest;
    float nearest_width;
};

// Descends the min-max mipmap from the block size that covers the largest search square:
// at each level, blocks without edges, or whose widest penumbra cannot reach the pixel from
// the block's nearest point, are dropped; the farthest reach of the rest bounds the next,
// finer, search. Stops at pixels or when a finer level would need more than kMaxBlocks^2
// reads.
Search search(ivec2 p, float px_per_unit) {
    Search s = Search(false, u_max_radius_px + 1.0, 0.0, 0.0);
    vec2 q = vec2(p) + 0.5;
    int previous = u_levels + 1;
    for (int step = 0; step < 16; ++step) {
        float radius = s.radius;
        int level = min(clamp(int(ceil(log2(max(radius / 1.5, 1.0)))), 0, u_levels), previous - 1);
        if (level < 0) break;
        int block = 1 << level;
        // Not textureSize(u_edges, level): llvmpipe answers it for one lane's level only.
        ivec2 size = max(ivec2(u_work_size) >> level, ivec2(1));
        int reach_px = int(ceil(radius));
        ivec2 lo = min(max(p - reach_px, ivec2(0)) >> level, size - 1);
        ivec2 hi = min(max(p + reach_px, ivec2(0)) >> level, size - 1);
        if (step > 0 && (hi.x - lo.x >= kMaxBlocks || hi.y - lo.y >= kMaxBlocks)) break;
        bool any = false;
        float next = 0.0, widest = 0.0, nearest = 1e9, nearest_width = 0.0;
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                vec4 t = texelFetch(u_edges, ivec2(x, y), level);
                if (t.r > 0.5) continue;
                // The block's pixels; the last block of a row or column takes the remainder.
                vec2 bmin = vec2(ivec2(x, y) * block);
                vec2 bmax = vec2(x == size.x - 1 ? int(u_work_size.x) : (x + 1) * block,
                                 y == size.y - 1 ? int(u_work_size.y) : (y + 1) * block);
                float d = length(max(max(bmin - q, q - bmax), vec2(0.0)));
                float reach = kRegionScale * t.g * px_per_unit + 1.0;
                if (d >= reach) continue;
                any = true;
                next = max(next, min(reach, length(max(abs(q - bmin), abs(q - bmax)))));
                widest = max(widest, t.g);
                if (d < nearest) {
                    nearest = d;
                    nearest_width = t.g;
                }
            }
        if (!any) return Search(false, 0.0, 0.0, 0.0);
        s = Search(true, min(next, radius), widest, nearest_width);
        previous = level;
        if (level == 0) break;
    }
    return s;
}

#ifdef EROSION_DIRECT
// Distances are taken on the receiver: a screen offset v (pixels) is the offset
// surface_x * v.x + surface_y * v.y of the receiver's plane at the pixel, so a penumbra on a
// surface seen at a grazing angle is not squeezed by the view (the seed measures in pixels).
vec3 surface_x, surface_y;
float best_distance = 1e9, best_reach = 0.0;  // eye units

void consider(ivec2 p, ivec2 e) {
    if (any(lessThan(e, ivec2(0))) || any(greaterThanEqual(e, ivec2(u_work_size)))) return;
    vec4 edge = texelFetch(u_edges, e, 0);
    if (edge.r > 0.5) return;
    float reach = 0.5 * edge.g;  // the edge's penumbra half-width
    vec2 v = vec2(e - p);
    if (u_line_fit == 1) v += texelFetch(u_lines, e, 0).rg;
    float d = length(surface_x * v.x + surface_y * v.y);
    if (d < reach && d < best_distance) {
        best_distance = d;
        best_reach = reach;
    }
}

// The receiver plane's offsets per pixel step (light-view space: a rigid motion of eye space),
// from the neighbour on the side whose depth is closer (as receiver_at does).
void receiver_plane(ivec2 p) {
    float depth = camera_depth(p);
    vec3 here = scene_point(p, depth).light_view;
    vec3 axis[2];
    for (int a = 0; a < 2; ++a) {
        ivec2 step = a == 0 ? ivec2(1, 0) : ivec2(0, 1);
        float da = camera_depth(p + step), db = camera_depth(p - step);
        bool use_a = abs(da - depth) <= abs(db - depth);
        axis[a] = use_a ? scene_point(p + step, da).light_view - here : here - scene_point(p - step, db).light_view;
    }
    surface_x = axis[0];
    surface_y = axis[1];
}

// The least a one-pixel screen step moves on the receiver (the plane's smaller singular value).
float smallest_step() {
    float a = dot(surface_x, surface_x), b = dot(surface_x, surface_y), c = dot(surface_y, surface_y);
    float mid = 0.5 * (a + c), spread = sqrt(0.25 * (a - c) * (a - c) + b * b);
    return sqrt(max(mid - spread, 0.0));
}
#endif

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 h = texelFetch(u_hard, p, 0);
    out_color = vec4(h.r, h.g, 0.0, 0.0);  // direct: visibility and facing, as the hard shadow
    if (h.a == 0.0) return;
    Search s = search(p, u_focal_px / h.a);
    if (!s.found) return;
#ifndef EROSION_DIRECT
    // The kernel's width: a shadowed pixel's own blocker gives it (measured against a wider
    // choice: lower error on every test scene); a lit one takes the nearest reaching block's.
    out_color = vec4(h.r < 0.5 ? h.b : s.nearest_width, 1.0, 0.0, 0.0);
#else
    // Rings of growing Chebyshev distance; none can hold a nearer edge once k - 1.5 pixels
    // (line corrections move an edge by at most ~1 pixel) are further than the best distance.
    receiver_plane(p);
    float step = smallest_step();
    int reach = int(ceil(s.radius));
    for (int k = 0; k <= reach; ++k) {
        if ((float(k) - 1.5) * step > best_distance) break;
        for (int i = -k; i <= k; ++i) {
            consider(p, p + ivec2(i, -k));
            if (k > 0) consider(p, p + ivec2(i, k));
        }
        for (int j = 1 - k; j <= k - 1; ++j) {
            consider(p, p + ivec2(-k, j));
            consider(p, p + ivec2(k, j));
        }
    }
    if (best_reach > 0.0) {
        // The share of the light hidden on the lit side: the method's ramp (w - d) / 2w, or the
        // area of a round light's disk beyond the line at distance d.
        float u = clamp(best_distance / best_reach, 0.0, 1.0);
        float outer = u_disk_profile == 1 ? (acos(u) - u * sqrt(1.0 - u * u)) / 3.14159265 : 0.5 * (1.0 - u);
        out_color.r = h.r > 0.5 ? 1.0 - outer : outer;
    }
#endif
}
