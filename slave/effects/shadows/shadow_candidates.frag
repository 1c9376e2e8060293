// Where edge detection has to look (r = 0): the 3x3 Laplacian (five taps) of the hard shadows'
// lit channel is not zero, or (OCCLUSION_EDGES) the pixel lies just beyond an object's outline.
// Cheap on every pixel; its min mipmap tells shadow_blocks.vert which blocks hold candidates.
out vec4 out_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = hard(p), w = hard(p - ivec2(1, 0)), e = hard(p + ivec2(1, 0)), s = hard(p - ivec2(0, 1)),
         n = hard(p + ivec2(0, 1));
    bool candidate = c.a > 0.0 && 4.0 * c.r - w.r - e.r - s.r - n.r != 0.0;
#ifdef OCCLUSION_EDGES
    candidate = candidate || (c.a > 0.0 && beyond_outline(c, w, e, s, n));
#endif
    out_color = vec4(candidate ? 0.0 : 1.0, 0.0, 0.0, 0.0);
}
