// Hard shadows of the work area (shadow_renderer.h), one texel per pixel:
//   r: 1 lit by the light's centre (or background), 0 shadowed
//   g: how much the surface faces the light (Receiver.facing; the darkening's weight)
//   b: shadowed: the full penumbra width its blocker casts here (parallel planes), eye units
//   a: eye depth (0: background)
// The second output starts the visibility (lit, facing): erosion and shading then only write
// it near edges.
out vec4 out_color;
layout(location = 1) out vec4 out_visibility;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float depth = camera_depth(p);
    if (depth >= 1.0) {
        out_color = vec4(1.0, 1.0, 0.0, 0.0);
        out_visibility = vec4(1.0, 1.0, 0.0, 0.0);
        return;
    }
    Receiver r = receiver_at(p, depth);
    float blocker = map_depth(r.uv);
    bool shadowed = blocker < r.depth - r.bias;
    out_color = vec4(shadowed ? 0.0 : 1.0, r.facing, shadowed ? penumbra_world(r.depth, blocker) : 0.0, r.eye_depth);
    out_visibility = vec4(out_color.rg, 0.0, 0.0);
}
