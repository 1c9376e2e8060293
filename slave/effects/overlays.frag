// The program's overlays over the decorated scene (slave/effects_runner.cpp, put_overlays_back):
// where the program's final picture differs from its scene before the first overlay, the
// final picture (its HUD and text, untouched); so too where the depth the passes saw is in
// front of `view_model_far` (a first-person weapon drawn with glDepthRange(0, 0.3)), and outside
// `scene_rect` (a scene another context drew, shown in part of the window) or, on a rotated tile
// that shows such a scene turned over all of itself, outside `scene_mask` (the program's
// interface around it: slave/shown_scene.h), and where the scene's
// own framebuffer object changed after its first overlay (`target_overlays`: a HUD drawn into the
// scene before it is shown; target_before/_final are that target's colour at its size, of which
// `target_rect` is the part this tile shows, in the scene's texels), and where an overlay engine's
// colour, composited over the scene before it was shown, covers it (`engine_overlay`: Blender's
// wire frames, grid, gizmo and viewport text, drawn into a target over the scene's depth, the
// scene's texels; alpha above 0 where drawn); elsewhere what the passes made of the scene.
uniform sampler2D final_image;
uniform sampler2D scene_image;
uniform sampler2D scene_depth;
uniform bool overlays;
uniform float view_model_far;  // 0: no view model this frame
uniform vec4 scene_rect;       // x0, y0, x1, y1 in this tile's pixels
uniform bool masked;
uniform sampler2D scene_mask;  // 1 where the tile shows the scene
uniform bool target_overlays;
uniform sampler2D target_before;
uniform sampler2D target_final;
uniform vec4 target_rect;      // x0, y0, x1, y1 in the target copies' texels (the scene's)
uniform bool engine_overlays;
uniform sampler2D engine_overlay;
uniform vec2 tile_size;
out vec4 color;

bool target_overlay() {
    if (!target_overlays) return false;
    vec2 at = mix(target_rect.xy, target_rect.zw, gl_FragCoord.xy / tile_size);
    ivec2 t = clamp(ivec2(floor(at)), ivec2(0), textureSize(target_final, 0) - 1);
    return texelFetch(target_final, t, 0).rgb != texelFetch(target_before, t, 0).rgb;
}

bool engine_overlay_here() {
    if (!engine_overlays) return false;
    ivec2 t = ivec2(floor(mix(target_rect.xy, target_rect.zw, gl_FragCoord.xy / tile_size)));
    if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, textureSize(engine_overlay, 0)))) return false;
    return texelFetch(engine_overlay, t, 0).a > 0.0;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 final_rgb = texelFetch(final_image, p, 0).rgb;
    bool overlay = overlays && final_rgb != texelFetch(scene_image, p, 0).rgb;
    bool view_model = view_model_far > 0.0 && texelFetch(scene_depth, p, 0).r < view_model_far;
    bool outside = masked ? texelFetch(scene_mask, p, 0).r < 0.5
                          : any(lessThan(gl_FragCoord.xy, scene_rect.xy)) || any(greaterThanEqual(gl_FragCoord.xy, scene_rect.zw));
    if (!overlay && !view_model && !outside && !target_overlay() && !engine_overlay_here()) discard;
    color = vec4(final_rgb, 1.0);
}
