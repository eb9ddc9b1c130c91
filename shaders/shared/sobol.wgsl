// Owen-scrambled Sobol points (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT
// 9(4)), padded as pbrt-v4's PaddedSobolSampler is: every draw of a kernel (a 1D or a 2D
// pattern: a light's choice, a point on it, a BSDF's direction, its lobe, Russian roulette)
// takes Sobol's first one or two dimensions, a (0,2)-sequence, at the sample's index shuffled
// by the pattern's own nested scramble, with the values Owen-scrambled by the pattern's own
// seeds. The index shuffle is nested from the top bit down, so the first 2^k samples of a
// pixel are an aligned block of 2^k Sobol points: a (0,k,2)-net in every pattern, whatever k.
// Different patterns shuffle differently, which decorrelates them; the seeds come from a
// per-pixel (or per-photon-stream) hash. The CPU mirror is src/sampler.rs.

// The kernels' sampler: false draws every number from the PCG stream (the independent
// sampler), true the first SOBOL_PATTERNS draws of a sample from Sobol (rng_sobol).
override SAMPLER_SOBOL: bool = false;

// Draws (1D or 2D) per sample taken from Sobol; later ones come from the PCG stream. A path
// tracer's camera takes 2, each bounce 5 (light choice, point on the light, direction, lobe,
// roulette): 32 cover six bounces, past which paths carry little of the image.
const SOBOL_PATTERNS: u32 = 32u;
// Rng.dim of a stream that draws from PCG only.
const SOBOL_OFF: u32 = 0xffffffffu;

// Nested uniform scramble of v read as a binary fraction (bit 31 is 1/2): each bit is
// flipped by a hash of the bits above it, so intervals [j 2^-k, (j + 1) 2^-k) map onto such
// intervals. The hash is Laine and Karras's construction on the reversed bits, with Vegdahl's
// constants ("Building a Better LK Hash", 2021), as pbrt-v4's FastOwenScrambler.
fn owen_scramble(v: u32, seed: u32) -> u32 {
    var x = reverseBits(v);
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return reverseBits(x);
}

// The index shuffle of a pattern with seed s: two nested scrambles, as one leaves the
// patterns of samples 16 apart slightly correlated (tests/sobol.rs).
fn sobol_shuffle(index: u32, s: u32) -> u32 {
    return owen_scramble(owen_scramble(index, s), sobol_mix(s ^ 0x68bc21ebu));
}

// Sobol's second dimension at index i (its first is reverseBits(i)): direction numbers
// v_0 = 1/2, v_j = v_(j-1) xor v_(j-1) / 2 (primitive polynomial x + 1), whose matrix is
// Pascal's triangle mod 2: bit k of the fraction (from its top) is the parity of the index
// bits j whose positions contain k's as bit sets (Lucas), a superset sum over the five bits
// of a position, in five shifts.
fn sobol_dim1(i: u32) -> u32 {
    var y = i;
    y ^= (y >> 1u) & 0x55555555u;
    y ^= (y >> 2u) & 0x33333333u;
    y ^= (y >> 4u) & 0x0f0f0f0fu;
    y ^= (y >> 8u) & 0x00ff00ffu;
    y ^= (y >> 16u) & 0x0000ffffu;
    return reverseBits(y);
}

// A cheap integer mix for the seeds derived from a pattern's (the first half of Wellons's
// lowbias32).
fn sobol_mix(s: u32) -> u32 {
    return (s ^ (s >> 16u)) * 0x7feb352du;
}

// The seed of pattern `dim` of a sample sequence with seed `seed`.
fn sobol_pattern_seed(seed: u32, dim: u32) -> u32 {
    return pcg_hash(seed + dim * 0x9e3779b9u);
}

// 24 high bits, as rng_next's, so the result stays below 1.
fn sobol_float(x: u32) -> f32 {
    return f32(x >> 8u) * (1.0 / 16777216.0);
}

// Pattern `dim`'s 1D point of sample `index`.
fn sobol_1d(index: u32, seed: u32, dim: u32) -> f32 {
    let s = sobol_pattern_seed(seed, dim);
    let i = sobol_shuffle(index, s);
    return sobol_float(owen_scramble(reverseBits(i), sobol_mix(s + 1u)));
}

// Pattern `dim`'s 2D point of sample `index`.
fn sobol_2d(index: u32, seed: u32, dim: u32) -> vec2f {
    let s = sobol_pattern_seed(seed, dim);
    let i = sobol_shuffle(index, s);
    let x = owen_scramble(reverseBits(i), sobol_mix(s + 1u));
    let y = owen_scramble(sobol_dim1(i), sobol_mix(s + 2u));
    return vec2f(sobol_float(x), sobol_float(y));
}

// The seed of the sample sequence `key` (a pixel, or a run of photon passes) of `stream`.
fn sobol_seed(seed: u32, stream: u32, key: u32) -> u32 {
    return pcg_hash(pcg_hash(seed ^ 0x5bd1e995u) ^ pcg_hash(stream ^ pcg_hash(key)));
}
