// A round flake (or a rain streak) with a soft rim: coverage falls off with the distance to the
// streak's core segment.
uniform float brightness;
uniform int test_scene_depth;   // 1: the window's depth is the program's own convention: test this
uniform sampler2D scene_depth;  // the passes' conversion of it (slave/scene/depth_convention.h)
in vec2 local;
flat in float half_length;
flat in float alpha;
out vec4 out_color;

void main() {
    if (test_scene_depth == 1 && gl_FragCoord.z >= texelFetch(scene_depth, ivec2(gl_FragCoord.xy), 0).r) discard;
    float d = length(vec2(local.x, max(abs(local.y) - half_length, 0.0)));
    float coverage = 1.0 - smoothstep(0.35, 1.0, d);
    if (coverage <= 0.0) discard;
    out_color = vec4(vec3(brightness), alpha * coverage);
}
