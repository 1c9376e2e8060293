// Quads over the blocks of the work area that need a step's fragment shader (one instance per
// block of u_block_size pixels): a block is drawn when u_cull has an edge (r < 0.5) in it or in
// the u_cull_reach blocks around it, else its quad collapses outside the clip volume. A
// software rasterizer runs every branch of a fragment shader for every pixel it covers, so the
// searches and filters of erosion and shading run only near edges this way. Needs
// shadow_common.glsl before it (u_work_size).
uniform sampler2D u_cull;   // a min-max mipmap (flag in r)
uniform int u_cull_level;   // its level with one texel per block
uniform int u_cull_reach;
uniform int u_block_size;
uniform int u_blocks_x;
uniform int u_cull_by_width;  // 1: only blocks within the penumbra reach of the edges (u_cull.g
                              // widest penumbra, .b nearest eye depth, as shadow_minmax.frag keeps)

void main() {
    ivec2 block = ivec2(gl_InstanceID % u_blocks_x, gl_InstanceID / u_blocks_x);
    ivec2 last = max(ivec2(u_work_size) >> u_cull_level, ivec2(1)) - 1;
    bool needed = false;
    for (int y = -u_cull_reach; y <= u_cull_reach; ++y)
        for (int x = -u_cull_reach; x <= u_cull_reach; ++x) {
            vec4 t = texelFetch(u_cull, clamp(block + ivec2(x, y), ivec2(0), last), u_cull_level);
            if (t.r >= 0.5) continue;
            // The gap between the two blocks against the edges' reach (the erosion region's).
            vec2 gap = max(abs(vec2(x, y)) - 1.0, 0.0) * float(u_block_size);
            needed = needed || u_cull_by_width == 0 || length(gap) < t.g * u_focal_px / t.b + 2.0;
        }
    vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1);
    vec2 pixel = min((vec2(block) + corner) * float(u_block_size), u_work_size);
    gl_Position = needed ? vec4(pixel / u_work_size * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
}
