// The warp as a mesh (slave/projector_warp.h): one vertex per node, at its place on the output,
// carrying the source position it shows.
layout(location = 0) in vec2 node;    // the node's output position, 0..1, (0,0) top left
layout(location = 1) in vec2 source;  // where it samples the tile's image: u right, v down
out vec2 source_pos;
out vec2 out_pos;

void main() {
    source_pos = source;
    out_pos = node;
    gl_Position = vec4(node.x * 2.0 - 1.0, 1.0 - node.y * 2.0, 0.0, 1.0);
}
