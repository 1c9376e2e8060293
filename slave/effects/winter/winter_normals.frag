#version 330 compatibility
// Eye-space normal and position of the nearest re-rendered surface at each pixel of the
// guard-band buffers. The normal is turned to the side the camera sees: a plane drawn once
// (a ground quad, a roof) is seen from either side, and snow lies on the visible one.
in vec3 v_normal;
in vec3 v_eye;
uniform bool use_vertex_normals;  // else the triangle's own plane

layout(location = 0) out vec4 out_normal;    // xyz: unit normal facing the camera; w: 1 (a surface)
layout(location = 1) out vec4 out_position;  // xyz: eye position; w: window depth of the fragment

void main() {
    vec3 facet = cross(dFdx(v_eye), dFdy(v_eye));
    facet = dot(facet, facet) > 0.0 ? normalize(facet) : vec3(0.0, 0.0, 1.0);
    if (dot(facet, v_eye) > 0.0) facet = -facet;
    vec3 n = facet;
    if (use_vertex_normals && dot(v_normal, v_normal) > 1e-12) {
        n = normalize(v_normal);
        if (dot(n, facet) < 0.0) n = -n;
    }
    out_normal = vec4(n, 1.0);
    out_position = vec4(v_eye, gl_FragCoord.z);
}
