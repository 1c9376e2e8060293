// The reference: one point of the area light per draw (its own shadow map and light
// uniforms), added with weight 1/N into the visibility (and its facing) by additive blending.
uniform float u_weight;
out vec4 out_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float depth = camera_depth(p);
    float lit = 1.0, facing = 1.0;
    if (depth < 1.0) {
        Receiver r = receiver_at(p, depth);
        lit = lit_at(r, vec2(0.0));
        facing = r.facing;
    }
    out_color = vec4(lit, facing, 0.0, 0.0) * u_weight;
}
