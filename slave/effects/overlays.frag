// The program's overlays over the decorated scene (slave/effects_runner.cpp, put_overlays_back):
// where the program's final picture differs from its scene before the first overlay, the
// final picture (its HUD and text, untouched); so too where the depth the passes saw is in
// front of `view_model_far` (a first-person weapon drawn with glDepthRange(0, 0.3)), and outside
// `scene_rect` (a scene another context drew, shown in part of the window); elsewhere what the
// passes made of the scene.
uniform sampler2D final_image;
uniform sampler2D scene_image;
uniform sampler2D scene_depth;
uniform bool overlays;
uniform float view_model_far;  // 0: no view model this frame
uniform vec4 scene_rect;       // x0, y0, x1, y1 in this tile's pixels
out vec4 color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 final_rgb = texelFetch(final_image, p, 0).rgb;
    bool overlay = overlays && final_rgb != texelFetch(scene_image, p, 0).rgb;
    bool view_model = view_model_far > 0.0 && texelFetch(scene_depth, p, 0).r < view_model_far;
    bool outside = any(lessThan(gl_FragCoord.xy, scene_rect.xy)) || any(greaterThanEqual(gl_FragCoord.xy, scene_rect.zw));
    if (!overlay && !view_model && !outside) discard;
    color = vec4(final_rgb, 1.0);
}
