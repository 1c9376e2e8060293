// The program's overlays over the decorated scene (slave/frame_recorder.cpp, put_overlays_back):
// where the program's final picture differs from its scene before the first overlay, the
// final picture (its HUD and text, untouched); elsewhere what the passes made of the scene.
uniform sampler2D final_image;
uniform sampler2D scene_image;
out vec4 color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 final_rgb = texelFetch(final_image, p, 0).rgb;
    if (final_rgb == texelFetch(scene_image, p, 0).rgb) discard;
    color = vec4(final_rgb, 1.0);
}
