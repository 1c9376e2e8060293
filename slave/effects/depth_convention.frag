// The program's window depth in the passes' convention (slave/scene/depth_convention.h;
// to_pass_depth there is this, in double): its depth range and clip depth mode undone, its clip
// space mapped to the passes' standard projection, its background (the clear depth) at 1.
uniform sampler2D program_depth;         // the window's depth, this tile's size
uniform mat4 pass_clip_from_program_clip;
uniform vec2 tile_size;
uniform vec2 depth_range;                // the program's glDepthRange
uniform int zero_to_one;                 // its clip depth mode is GL_ZERO_TO_ONE
uniform float clear_depth;
in vec2 uv;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float d = texelFetch(program_depth, p, 0).r;
    if (abs(d - clear_depth) < 1e-6) {  // (a 24-bit depth buffer holds the clear value rounded)
        gl_FragDepth = 1.0;
        return;
    }
    float t = (d - depth_range.x) / (depth_range.y - depth_range.x);
    vec4 q = pass_clip_from_program_clip * vec4((vec2(p) + 0.5) / tile_size * 2.0 - 1.0,
                                                zero_to_one == 1 ? t : 2.0 * t - 1.0, 1.0);
    gl_FragDepth = q.w > 0.0 ? clamp(0.5 * q.z / q.w + 0.5, 0.0, 1.0) : 1.0;
}
