// The spectral layer when every region has moved alike (one texture): texture coordinates are
// interpolated from the vertices, which lets llvmpipe take its fast path for a plain textured,
// blended draw (a coordinate computed per fragment from gl_FragCoord does not).
uniform vec2 tile_size;          // pixels
uniform vec2 canvas_offset;      // this tile's origin on the canvas
uniform float texels_per_pixel;  // texture repeats per canvas pixel
out vec2 tc;

void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    tc = (p * tile_size + canvas_offset) * texels_per_pixel;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
