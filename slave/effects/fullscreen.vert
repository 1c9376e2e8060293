// One triangle covering the viewport, without attributes (gl_util.h: draw_fullscreen).
out vec2 uv;  // 0..1 over the viewport

void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
