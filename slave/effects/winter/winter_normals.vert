#version 330 compatibility
// The frame's geometry re-rendered by FrameView::redraw (winter_surface_buffers.cpp): the
// program's vertices and normals through its own matrices; GL_PROJECTION holds the guard-band
// correction times the program's projection, so gl_ModelViewProjectionMatrix includes it.
out vec3 v_normal;  // eye space, not normalized
out vec3 v_eye;     // eye-space position

void main() {
    vec4 eye = gl_ModelViewMatrix * gl_Vertex;
    v_eye = eye.xyz / eye.w;
    v_normal = gl_NormalMatrix * gl_Normal;
    gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex;
}
