// Seeded hashes and value noise of the winter passes (docs/winter.md), prepended to their
// shaders by winter_gl.cpp. Everything here is a pure function of integer lattice points (canvas
// pixels, world cells) and a seed, so a rerun, or the neighbouring tile, computes the same value.

// lowbias32 (C. Wellons): a full-avalanche 32-bit integer hash.
uint winter_hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// A lattice point: its coordinates spread by large odd multipliers, then one avalanche (four
// nested avalanches cost four times as much in the noise's 32 lookups per octave stack, for no
// difference in the patches' statistics, docs/winter.md).
uint winter_hash(ivec3 v, uint seed) {
    uvec3 u = uvec3(v);  // two's complement bits: negative cells hash like any other
    return winter_hash((u.x * 0x8da6b343u) ^ (u.y * 0xd8163841u) ^ (u.z * 0xcb1ab31fu) ^ (seed * 0x9e3779b9u));
}

// Uniform in [0, 1) from the top 24 bits.
float winter_unit(uint h) { return float(h >> 8) * (1.0 / 16777216.0); }

float winter_random(ivec3 cell, uint seed) { return winter_unit(winter_hash(cell, seed)); }

// Value noise in [0, 1): random values on the integer lattice, quintic interpolation between.
float winter_value_noise(vec3 p, uint seed) {
    vec3 cell = floor(p);
    ivec3 i = ivec3(cell);
    vec3 f = p - cell;
    vec3 u = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    float c000 = winter_random(i, seed), c100 = winter_random(i + ivec3(1, 0, 0), seed);
    float c010 = winter_random(i + ivec3(0, 1, 0), seed), c110 = winter_random(i + ivec3(1, 1, 0), seed);
    float c001 = winter_random(i + ivec3(0, 0, 1), seed), c101 = winter_random(i + ivec3(1, 0, 1), seed);
    float c011 = winter_random(i + ivec3(0, 1, 1), seed), c111 = winter_random(i + ivec3(1, 1, 1), seed);
    return mix(mix(mix(c000, c100, u.x), mix(c010, c110, u.x), u.y),
               mix(mix(c001, c101, u.x), mix(c011, c111, u.x), u.y), u.z);
}

// Value noise and its gradient (x: value, yzw: d value / d p), from the same eight lattice
// values: the snow's bump needs the slope, and four noise lookups would cost four times as much.
vec4 winter_value_noise_gradient(vec3 p, uint seed) {
    vec3 cell = floor(p);
    ivec3 i = ivec3(cell);
    vec3 f = p - cell;
    vec3 u = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    vec3 du = 30.0 * f * f * (f - 1.0) * (f - 1.0);
    float c000 = winter_random(i, seed), c100 = winter_random(i + ivec3(1, 0, 0), seed);
    float c010 = winter_random(i + ivec3(0, 1, 0), seed), c110 = winter_random(i + ivec3(1, 1, 0), seed);
    float c001 = winter_random(i + ivec3(0, 0, 1), seed), c101 = winter_random(i + ivec3(1, 0, 1), seed);
    float c011 = winter_random(i + ivec3(0, 1, 1), seed), c111 = winter_random(i + ivec3(1, 1, 1), seed);
    float k1 = c100 - c000, k2 = c010 - c000, k3 = c001 - c000;
    float k4 = c000 - c100 - c010 + c110, k5 = c000 - c010 - c001 + c011, k6 = c000 - c100 - c001 + c101;
    float k7 = -c000 + c100 + c010 - c110 + c001 - c101 - c011 + c111;
    float value = c000 + k1 * u.x + k2 * u.y + k3 * u.z + k4 * u.x * u.y + k5 * u.y * u.z + k6 * u.z * u.x +
                  k7 * u.x * u.y * u.z;
    vec3 gradient = du * vec3(k1 + k4 * u.y + k6 * u.z + k7 * u.y * u.z, k2 + k5 * u.z + k4 * u.x + k7 * u.z * u.x,
                              k3 + k6 * u.x + k5 * u.y + k7 * u.x * u.y);
    return vec4(value, gradient);
}

// Four octaves of value noise, mean 0.5. The sum of octaves is close to normally distributed
// with standard deviation WINTER_FBM_SIGMA (measured: docs/winter.md); winter_uniform_fbm maps
// it through that normal's CDF, so that P(winter_uniform_fbm < d) is close to d and a snow
// density d covers about the fraction d of a surface.
const float WINTER_FBM_SIGMA = 0.121;

float winter_fbm(vec3 p, uint seed) {
    float sum = 0.0, amplitude = 0.5;
    for (int octave = 0; octave < 4; ++octave) {
        sum += amplitude * winter_value_noise(p + vec3(17.13, 31.71, 5.37) * float(octave), seed + uint(octave));
        p *= 2.0;
        amplitude *= 0.5;
    }
    return sum / 0.9375;
}

float winter_uniform_fbm(vec3 p, uint seed) {
    float x = (winter_fbm(p, seed) - 0.5) / WINTER_FBM_SIGMA;
    // Normal CDF, tanh approximation (error below 2e-4).
    return 0.5 * (1.0 + tanh(0.7978845608 * (x + 0.044715 * x * x * x)));
}
