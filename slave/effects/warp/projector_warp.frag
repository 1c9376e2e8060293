// A projector's output (slave/projector_warp.h): the frame sampled where the warp says, times
// the blend, lifted by the black level.
in vec2 source_pos;  // u right, v down, (0,0) the top left of the tile's image
in vec2 out_pos;     // 0..1 over the output, (0,0) its top left, as the maps have it
out vec4 colour;

uniform sampler2D source;  // the frame as the window held it (GL's rows: bottom to top)
uniform sampler2D alpha;   // RGB, rows top to bottom, stretched over the output (HAS_ALPHA)
uniform sampler2D beta;    // (HAS_BETA)

void main() {
    // Outside the tile's image: no light.
    vec2 inside = step(vec2(0.0), source_pos) * step(source_pos, vec2(1.0));
    vec3 c = texture(source, vec2(source_pos.x, 1.0 - source_pos.y)).rgb * (inside.x * inside.y);
#ifdef HAS_ALPHA
    c *= texture(alpha, out_pos).rgb;
#endif
#ifdef HAS_BETA
    vec3 b = texture(beta, out_pos).rgb;
    c = b + c * (1.0 - b);  // black lifted to the level, white kept
#endif
    colour = vec4(c, 1.0);
}
