// Where icicles hang and how big they are (docs/winter.md, "Icicles"), shared by the root pass
// and the icicle quads. The icicle generator (docs/winter.md) scatters icicles along an edge with a seeded
// count and gives each a seeded radius; here the candidate places are columns of the canvas,
// one per cell of `icicle_spacing` canvas pixels at a seeded offset, and an icicle hangs in a
// column from every lower edge of snow it crosses, kept or dropped and sized by a hash of the
// column and of the root's distance band (9% wide): an edge that moves up or down the screen
// keeps its icicles, and edges at other distances in the same column get their own. Nothing
// depends on the tile or on the frame (but for growth), so an icicle stays put while the camera
// does and continues across a tile border.
uniform float icicle_spacing;     // canvas pixels between candidate columns
uniform int icicle_seed_bits;     // the seed's unsigned bits
uniform float icicle_density;     // fraction of roots that hold an icicle
uniform vec2 icicle_radius;       // smallest, largest root radius, canvas pixels
uniform float icicle_length_max;  // length of an icicle of the largest radius, canvas pixels
uniform float icicle_growth_frames;  // 0: fully grown
uniform float icicle_frame;       // the master's frame number

// Canvas x of the candidate column of cell `cell`: inside the cell, away from its borders.
int icicle_column(int cell) {
    float jitter = 0.2 + 0.6 * winter_random(ivec3(cell, 0, 0), uint(icicle_seed_bits));
    return int(floor((float(cell) + jitter) * icicle_spacing));
}

// The icicle hanging in canvas column `column` from a lower edge at eye distance `distance`: x
// its root radius, y its length (0: no icicle), z the phase of its slight bend. Height
// proportional to radius^(4/3) (Short et al.: the shape of icicles), also while it grows.
vec3 icicle_at(int column, float distance) {
    uint seed = uint(icicle_seed_bits);
    ivec2 root = ivec2(column, int(floor(8.0 * log2(max(distance, 1e-20)))));
    if (winter_random(ivec3(root, 1), seed) >= icicle_density) return vec3(0.0);
    float radius = mix(icicle_radius.x, icicle_radius.y, winter_random(ivec3(root, 2), seed));
    float len = icicle_length_max * pow(radius / icicle_radius.y, 4.0 / 3.0);
    if (icicle_growth_frames > 0.0) {
        float start = floor(winter_random(ivec3(root, 3), seed) * icicle_growth_frames);
        float grown = clamp((icicle_frame - start) / icicle_growth_frames, 0.0, 1.0);
        len *= grown;
        radius *= pow(grown, 0.75);
    }
    return vec3(radius, len, 6.2831853 * winter_random(ivec3(root, 4), seed));
}
