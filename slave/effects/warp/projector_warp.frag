// A projector's output (slave/projector_warp.h): the frame sampled where the warp says, times
// the blend, lifted by the black level.
in vec2 uv;  // 0..1 over the output, (0,0) its bottom left
out vec4 colour;

uniform sampler2D source;  // the frame as the window held it (GL's rows: bottom to top)
uniform sampler2D warp;    // RG: source position per node (u right, v down), rows top to bottom
uniform sampler2D alpha;   // RGB, rows top to bottom, stretched over the output
uniform sampler2D beta;
uniform vec2 warp_nodes;   // the warp grid's width and height in nodes
uniform bool has_warp, has_alpha, has_beta;

void main() {
    vec2 out_pos = vec2(uv.x, 1.0 - uv.y);  // (0,0) top left, as the maps have it
    vec3 c;
    if (has_warp) {
        // Node i sits at i / (n - 1) across the output, and at the centre of texel i: the linear
        // filter then interpolates bilinearly between nodes (a NaN node gives NaN around it).
        vec2 s = texture(warp, (out_pos * (warp_nodes - 1.0) + 0.5) / warp_nodes).rg;
        if (isnan(s.x) || isnan(s.y) || s.x < 0.0 || s.y < 0.0 || s.x > 1.0 || s.y > 1.0) {
            colour = vec4(0.0, 0.0, 0.0, 1.0);
            return;
        }
        c = texture(source, vec2(s.x, 1.0 - s.y)).rgb;
    } else {
        c = texture(source, uv).rgb;
    }
    if (has_alpha) c *= texture(alpha, out_pos).rgb;
    if (has_beta) {
        vec3 b = texture(beta, out_pos).rgb;
        c = b + c * (1.0 - b);  // black lifted to the level, white kept
    }
    colour = vec4(c, 1.0);
}
