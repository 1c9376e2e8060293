// One quad per texel of the roots buffer (winter_icicle_roots.frag), instanced: the bounding
// box of the icicle hanging from that root, in tile pixels; texels without an icicle give an
// empty quad. Only the icicles' own pixels reach the fragment shader.
uniform sampler2D roots;
uniform int cell_count;
uniform int first_cell;
uniform int guard;
uniform vec2 tile_size;
uniform vec2 canvas_offset;      // canvas pixel of tile pixel (0, 0)

flat out vec4 v_root;            // x: tile y of the root pixel's lower side; y: radius; z: length; w: distance
flat out float v_axis;           // tile x of the icicle's axis
flat out float v_phase;          // of its slight bend

void main() {
    ivec2 texel = ivec2(gl_InstanceID % cell_count, gl_InstanceID / cell_count);
    vec4 root = texelFetch(roots, texel, 0);
    v_root = vec4(root.x - float(guard), root.yzw);
    int column = icicle_column(first_cell + texel.x);
    v_axis = float(column) - canvas_offset.x + 0.5;
    v_phase = 0.0;
    if (root.z <= 0.0) {
        gl_Position = vec4(-2.0, -2.0, 0.0, 1.0);  // all four corners alike: nothing drawn
        return;
    }
    ivec2 root_canvas = ivec2(column, int(root.x + canvas_offset.y) - guard);
    v_phase = icicle_at(column, root.w).z;
    v_root.x -= winter_lip_thickness(root_canvas);  // it hangs from below the snow's lip
    float half_width = 1.35 * root.y + 1.5;  // radius, bend, antialiasing
    vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
    vec2 pixel = vec2(v_axis + (2.0 * corner.x - 1.0) * half_width, v_root.x - (1.0 - corner.y) * (root.z + 1.0));
    gl_Position = vec4(pixel / tile_size * 2.0 - 1.0, 0.0, 1.0);
}
