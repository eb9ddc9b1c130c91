//! The kernels' samplers (`sampler` in `[render]`): independent numbers from PCG streams, or
//! Owen-scrambled Sobol points (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT
//! 9(4)), and the CPU mirror of the Sobol sampler in `shaders/shared/sobol.wgsl`, bit for bit,
//! for the tests.
//!
//! The Sobol sampler is padded, as pbrt-v4's `PaddedSobolSampler`: each draw of a kernel,
//! one number or one pair (a light's choice, a point on it, a BSDF's direction, its lobe,
//! Russian roulette), is a *pattern* of its own, which takes Sobol's first one or two
//! dimensions (a (0,2)-sequence) at the sample's index shuffled by the pattern's own nested
//! scramble, with values Owen-scrambled by the pattern's own seeds. The shuffle is nested
//! from the index's top bit down, so any aligned block of 2^k samples, the first 2^k
//! included, maps onto an aligned block of 2^k Sobol points: every pattern's points of a
//! pixel are a (0,k,2)-net after 2^k samples. A pixel's sample index is its pass index
//! (times the samples per pass, plus the sample's number), each pixel has its own seed, and
//! SPPM's photons are numbered across passes, so batches and resumed runs draw the same
//! points. After [`SOBOL_PATTERNS`] draws a sample goes on with its PCG stream.

/// Where the kernels' random numbers come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampler {
    /// Independent uniform numbers from counter-based PCG streams (`"independent"`).
    Independent,
    /// Owen-scrambled Sobol points, padded per draw, falling back to the PCG stream after
    /// [`SOBOL_PATTERNS`] draws of a sample (`"sobol"`).
    Sobol,
}

impl Sampler {
    /// The sampler a scene gets when it names none: Sobol, which at equal time (30 s, the
    /// canonical scenes, docs/journal/session-12.md "Sobol sampler (issue 26)") cut pt-nee's relMSE on cornell-box by
    /// 42% and SPPM's by 13%, and tied within noise on cornell-glossy and cornell-spheres,
    /// whose error is mostly fireflies, at about 5-10% more time per pass.
    pub const DEFAULT: Sampler = Sampler::Sobol;

    /// The kernels' `SAMPLER_SOBOL` override constant: the Sobol code is compiled in only
    /// for the Sobol sampler.
    pub fn constants(self) -> [(&'static str, f64); 1] {
        [("SAMPLER_SOBOL", (self == Sampler::Sobol) as u32 as f64)]
    }
}

/// Draws per sample taken from Sobol points (`SOBOL_PATTERNS` in WGSL).
pub const SOBOL_PATTERNS: u32 = 32;

/// PCG hash (Jarzynski & Olano 2020), as `pcg_hash` in `shaders/shared/rng.wgsl`.
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// Nested uniform scramble of `v` read as a binary fraction (bit 31 is 1/2): each bit flipped
/// by a hash of the bits above it (Laine and Karras's hash on the reversed bits, Vegdahl's
/// constants).
pub fn owen_scramble(v: u32, seed: u32) -> u32 {
    let mut x = v.reverse_bits();
    x ^= x.wrapping_mul(0x3d20_adea);
    x = x.wrapping_add(seed);
    x = x.wrapping_mul((seed >> 16) | 1);
    x ^= x.wrapping_mul(0x0552_6c56);
    x ^= x.wrapping_mul(0x53a2_2864);
    x.reverse_bits()
}

/// The index shuffle of a pattern with seed `s`: two nested scrambles, as one leaves the
/// patterns of samples 16 apart slightly correlated.
pub fn sobol_shuffle(index: u32, s: u32) -> u32 {
    owen_scramble(owen_scramble(index, s), sobol_mix(s ^ 0x68bc_21eb))
}

/// Sobol's second dimension at index `i` as a 32-bit fraction (its first is
/// `i.reverse_bits()`): Pascal's triangle mod 2 as a superset sum over bit positions, as
/// `sobol_dim1` in WGSL ([`sobol_dim1_by_directions`] is the definition).
pub fn sobol_dim1(i: u32) -> u32 {
    let mut y = i;
    y ^= (y >> 1) & 0x5555_5555;
    y ^= (y >> 2) & 0x3333_3333;
    y ^= (y >> 4) & 0x0f0f_0f0f;
    y ^= (y >> 8) & 0x00ff_00ff;
    y ^= (y >> 16) & 0x0000_ffff;
    y.reverse_bits()
}

/// Sobol's second dimension from its direction numbers v_0 = 1/2, v_j = v_(j-1) xor
/// v_(j-1) / 2 (primitive polynomial x + 1).
pub fn sobol_dim1_by_directions(i: u32) -> u32 {
    let (mut x, mut v, mut bits) = (0u32, 0x8000_0000u32, i);
    while bits != 0 {
        if bits & 1 != 0 {
            x ^= v;
        }
        bits >>= 1;
        v ^= v >> 1;
    }
    x
}

/// A cheap integer mix for the seeds derived from a pattern's (`sobol_mix` in WGSL).
pub fn sobol_mix(s: u32) -> u32 {
    (s ^ (s >> 16)).wrapping_mul(0x7feb_352d)
}

/// The seed of pattern `dim` of the sequence with seed `seed`.
pub fn pattern_seed(seed: u32, dim: u32) -> u32 {
    pcg_hash(seed.wrapping_add(dim.wrapping_mul(0x9e37_79b9)))
}

/// The seed of sample sequence `key` (a pixel, or a run of photon passes) of `stream`.
pub fn sobol_seed(seed: u32, stream: u32, key: u32) -> u32 {
    pcg_hash(pcg_hash(seed ^ 0x5bd1_e995) ^ pcg_hash(stream ^ pcg_hash(key)))
}

/// A scrambling of Sobol points: the index shuffle and the value scramble, each
/// `(value, seed) -> value`. [`OWEN`] is the kernels'; tests swap in broken ones.
#[derive(Clone, Copy)]
pub struct Scramble {
    /// Applied to the sample index.
    pub shuffle: fn(u32, u32) -> u32,
    /// Applied to each coordinate.
    pub values: fn(u32, u32) -> u32,
}

/// The kernels' scrambling: nested uniform (Owen), twice for the index.
pub const OWEN: Scramble = Scramble { shuffle: sobol_shuffle, values: owen_scramble };

/// Pattern `dim`'s 2D point of sample `index` as 32-bit fractions, scrambled by `s`.
pub fn sobol_2d_bits(index: u32, seed: u32, dim: u32, s: Scramble) -> [u32; 2] {
    let p = pattern_seed(seed, dim);
    let i = (s.shuffle)(index, p);
    [(s.values)(i.reverse_bits(), sobol_mix(p.wrapping_add(1))), (s.values)(sobol_dim1(i), sobol_mix(p.wrapping_add(2)))]
}

/// A 32-bit fraction as the kernels' float in [0, 1): its 24 high bits.
pub fn to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Pattern `dim`'s 1D point of sample `index` (`sobol_1d` in WGSL).
pub fn sobol_1d(index: u32, seed: u32, dim: u32) -> f32 {
    to_unit(sobol_2d_bits(index, seed, dim, OWEN)[0])
}

/// Pattern `dim`'s 2D point of sample `index` (`sobol_2d` in WGSL).
pub fn sobol_2d(index: u32, seed: u32, dim: u32) -> [f32; 2] {
    let [x, y] = sobol_2d_bits(index, seed, dim, OWEN);
    [to_unit(x), to_unit(y)]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sobol's first points in its first two dimensions, from the definition.
    #[test]
    fn sobol_starts_as_published() {
        let first: Vec<[f64; 2]> =
            (0..8).map(|i: u32| [i.reverse_bits() as f64 / 4294967296.0, sobol_dim1(i) as f64 / 4294967296.0]).collect();
        let expected =
            [[0.0, 0.0], [0.5, 0.5], [0.25, 0.75], [0.75, 0.25], [0.125, 0.625], [0.625, 0.125], [0.375, 0.375], [0.875, 0.875]];
        assert_eq!(first, expected);
    }

    /// The superset sum is the direction numbers' product.
    #[test]
    fn sobol_dim1_matches_its_directions() {
        let mut x = 0x1234_5678u32;
        for i in (0..4096).chain([u32::MAX, 0x8000_0000, 0xdead_beef]) {
            assert_eq!(sobol_dim1(i), sobol_dim1_by_directions(i), "{i:#x}");
            x = pcg_hash(x);
            assert_eq!(sobol_dim1(x), sobol_dim1_by_directions(x), "{x:#x}");
        }
    }

    /// The scramble is a bijection that keeps the top bits' intervals together.
    #[test]
    fn owen_scramble_is_nested() {
        for seed in [0, 1, 0xdead_beef] {
            for v in [0u32, 1, 0x8000_0000, 0x1234_5678, u32::MAX] {
                let a = owen_scramble(v, seed);
                // Changing only bits below bit k changes only bits below bit k.
                for k in [4, 16, 31] {
                    let w = v ^ (1 << (k - 1));
                    assert_eq!(owen_scramble(w, seed) >> k, a >> k, "seed {seed} v {v:#x} k {k}");
                }
            }
        }
    }
}
