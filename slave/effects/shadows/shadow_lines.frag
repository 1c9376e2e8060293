// The erosion method's distance correction (docs/shadows.md) for erosion/direct: a least-squares line through the edge
// pixels of the 5x5 neighbourhood of each edge pixel (the principal axis of their positions).
// Both sides of a hard-shadow boundary are edge pixels, so the line runs along the boundary
// itself. Output rg: the vector from the pixel's centre to the line (pixels).
uniform sampler2D u_edges;
out vec4 out_color;

bool is_edge(ivec2 p) {
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, ivec2(u_work_size)))) return false;
    return texelFetch(u_edges, p, 0).r < 0.5;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    out_color = vec4(0.0);
    if (!is_edge(p)) return;
    vec2 sum = vec2(0.0);
    vec3 moments = vec3(0.0);  // xx, xy, yy
    float n = 0.0;
    for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i) {
            if (!is_edge(p + ivec2(i, j))) continue;
            vec2 o = vec2(i, j);
            sum += o;
            moments += vec3(o.x * o.x, o.x * o.y, o.y * o.y);
            n += 1.0;
        }
    if (n < 3.0) return;
    vec2 mean = sum / n;
    vec3 cov = moments / n - vec3(mean.x * mean.x, mean.x * mean.y, mean.y * mean.y);
    // No preferred direction (a blob): leave the pixel uncorrected.
    if (abs(2.0 * cov.y) + abs(cov.x - cov.z) < 1e-4) return;
    float angle = 0.5 * atan(2.0 * cov.y, cov.x - cov.z);
    vec2 normal = vec2(-sin(angle), cos(angle));
    out_color = vec4(normal * dot(mean, normal), 0.0, 0.0);
}
