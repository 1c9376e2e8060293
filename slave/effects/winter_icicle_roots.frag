// The roots of the icicles: for each candidate icicle column of the guard-band buffers (x: cell -
// first_cell) and each row (y: buffer row), the icicle hanging from that pixel if it is a lower
// edge of snow and the seed puts one there. A lower edge: a pixel with snow whose neighbour
// below is background, a surface turned away by more than the edge angle (the vertical face
// under a roof's rim), or a surface much farther away (a ledge), but not a nearer one (that is
// an object in front).
uniform sampler2D cover;        // winter_cover.frag
uniform sampler2D normals;
uniform vec2 buffer_size;       // guard-band buffer, pixels
uniform vec2 canvas_origin;     // canvas pixel of buffer pixel (0, 0)
uniform int first_cell;
uniform float edge_cos;         // cos(icicles.edge_angle)

// x: root row (buffer); y: radius; z: length (0: no icicle); w: eye distance of the root.
out vec4 out_color;

bool is_lower_edge(ivec2 q) {
    if (q.y < 1) return false;
    vec4 here = texelFetch(cover, q, 0);
    if (here.a < 1.0 || here.r < 0.5) return false;
    ivec2 under = q - ivec2(0, 1);
    vec4 below = texelFetch(cover, under, 0);
    if (below.a < 0.0) return false;  // unknown (outside a tile reconstructed from depth)
    if (below.a == 0.0) return true;
    if (below.g < here.g * 0.97) return false;
    if (below.g > here.g * 1.1) return true;
    return dot(texelFetch(normals, q, 0).xyz, texelFetch(normals, under, 0).xyz) < edge_cos;
}

void main() {
    ivec2 f = ivec2(gl_FragCoord.xy);
    int column = icicle_column(first_cell + f.x);
    ivec2 q = ivec2(column - int(canvas_origin.x), f.y);
    out_color = vec4(0.0);
    if (q.x < 0 || q.x >= int(buffer_size.x) || !is_lower_edge(q)) return;
    vec3 icicle = icicle_at(ivec2(column, f.y + int(canvas_origin.y)));
    if (icicle.y > 0.0) out_color = vec4(float(f.y), icicle.x, icicle.y, texelFetch(cover, q, 0).g);
}
