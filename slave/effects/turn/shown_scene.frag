// A scene the program shows in part of its window, over a rotated tile (slave/shown_scene.h): the
// scene's target, drawn with the tile's frustum, covers the tile wherever the tile does not see
// the program's screen, and where the program showed it on that screen; elsewhere the program's
// interface stays as it drew it there.
in vec2 uv;  // 0..1 across the tile's frustum
out vec4 colour;

uniform sampler2D scene;
uniform sampler2D footprint;  // over the program's window: depth 0 where it showed its scene
// The tile's clip (x, y, w) to the program's window on its screen (x, y, 1), scaled by the
// tile's 1 / w: the inverse of what the tile's correction does to the interface's draws.
uniform mat3 tile_to_screen;

void main() {
    vec3 h = tile_to_screen * vec3(uv * 2.0 - 1.0, 1.0);
    if (h.z > 0.0) {  // the screen lies in front of the tile's camera here
        vec2 w = h.xy / h.z;
        if (all(lessThanEqual(abs(w), vec2(1.0))) && texture(footprint, w * 0.5 + 0.5).r > 0.5) discard;
    }
#ifdef MASK
    colour = vec4(1.0);  // where the tile shows the scene (the passes' overlays keep the rest)
#else
    colour = texture(scene, uv);
#endif
}
