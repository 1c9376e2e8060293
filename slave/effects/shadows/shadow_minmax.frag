// One level of the min-max mipmap of the edges: r = min (0 where any edge), g = max penumbra
// width, b = the nearest eye depth of its edges (the largest pixels per eye unit). A source of odd size gives its last column/row to the last texel, so every texel of
// level L covers pixels [t * 2^L, (t + 1) * 2^L), the last ones up to the border.
uniform sampler2D u_source;  // the level above (its base level is the source level)
out vec4 out_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(u_source, 0);
    ivec2 count = ivec2(2 * p.x + 3 == size.x ? 3 : 2, 2 * p.y + 3 == size.y ? 3 : 2);
    float lowest = 1.0, widest = 0.0, nearest = 65504.0;
    for (int j = 0; j < count.y; ++j)
        for (int i = 0; i < count.x; ++i) {
            vec4 t = texelFetch(u_source, min(2 * p + ivec2(i, j), size - 1), 0);
            lowest = min(lowest, t.r);
            widest = max(widest, t.g);
            if (t.r < 0.5) nearest = min(nearest, t.b);
        }
    out_color = vec4(lowest, widest, nearest, 0.0);
}
