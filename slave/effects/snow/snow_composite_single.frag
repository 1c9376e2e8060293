// I = I_snow a + (1 - a) I_bg with one texture of (snow colour, a) texels from the synthesis
// worker: a plain fetch, which llvmpipe draws on its fast path.
uniform sampler2D snow;
in vec2 tc;
out vec4 out_color;

void main() { out_color = texture(snow, tc); }
