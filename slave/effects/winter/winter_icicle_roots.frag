// The roots of the icicles: for each candidate icicle column of the guard-band buffers (x: cell -
// first_cell) and each row (y: buffer row), the icicle hanging from that pixel if it is a lower
// edge of snow (winter_edges.glsl) and the seed puts one there.
uniform sampler2D cover;        // winter_cover.frag
uniform sampler2D normals;
uniform vec2 buffer_size;       // guard-band buffer, pixels
uniform vec2 canvas_origin;     // canvas pixel of buffer pixel (0, 0)
uniform int first_cell;

// x: root row (buffer); y: radius; z: length (0: no icicle); w: eye distance of the root.
out vec4 out_color;

void main() {
    ivec2 f = ivec2(gl_FragCoord.xy);
    int column = icicle_column(first_cell + f.x);
    ivec2 q = ivec2(column - int(canvas_origin.x), f.y);
    out_color = vec4(0.0);
    if (q.x < 0 || q.x >= int(buffer_size.x) || !winter_lower_edge(cover, normals, q)) return;
    float distance = texelFetch(cover, q, 0).g;
    vec3 icicle = icicle_at(column, distance);
    if (icicle.y > 0.0) out_color = vec4(float(f.y), icicle.x, icicle.y, distance);
}
