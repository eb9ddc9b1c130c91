// Counter-based random numbers: every (seed, pass, stream, index) starts its own sequence, so
// a thread's samples do not depend on how the work was scheduled. With the Sobol sampler
// (SAMPLER_SOBOL, shared/sobol.wgsl) a stream that rng_sobol gave a sample index draws its
// first SOBOL_PATTERNS numbers or pairs from that sample's Owen-scrambled Sobol points.

#import sobol

// PCG hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering").
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

struct Rng {
    state: u32,
    // Sobol: the sample's index in its sequence, the sequence's seed, and the next pattern
    // (SOBOL_OFF: PCG only).
    index: u32,
    seed: u32,
    dim: u32,
}

fn rng_new(seed: u32, pass_index: u32, stream: u32, index: u32) -> Rng {
    let h = pcg_hash(seed ^ pcg_hash(pass_index ^ pcg_hash(stream ^ pcg_hash(index))));
    return Rng(h, 0u, 0u, SOBOL_OFF);
}

// With the Sobol sampler, the draws of `rng` from here on are sample `index` of the sequence
// `seed` (a pixel's, or the photons'), from its first pattern; without, nothing changes.
fn rng_sobol(rng: ptr<function, Rng>, index: u32, seed: u32) {
    if SAMPLER_SOBOL {
        (*rng).index = index;
        (*rng).seed = seed;
        (*rng).dim = 0u;
    }
}

// Uniform in [0, 1).
fn rng_next(rng: ptr<function, Rng>) -> f32 {
    if SAMPLER_SOBOL && (*rng).dim < SOBOL_PATTERNS {
        (*rng).dim += 1u;
        return sobol_1d((*rng).index, (*rng).seed, (*rng).dim - 1u);
    }
    (*rng).state = (*rng).state * 747796405u + 2891336453u;
    let s = (*rng).state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    let r = (word >> 22u) ^ word;
    // 24 high bits, so the result stays below 1.
    return f32(r >> 8u) * (1.0 / 16777216.0);
}

// A pair: with the Sobol sampler, one 2D pattern, stratified as a (0,2)-sequence.
fn rng_next2(rng: ptr<function, Rng>) -> vec2f {
    if SAMPLER_SOBOL && (*rng).dim < SOBOL_PATTERNS {
        (*rng).dim += 1u;
        return sobol_2d((*rng).index, (*rng).seed, (*rng).dim - 1u);
    }
    let x = rng_next(rng);
    let y = rng_next(rng);
    return vec2f(x, y);
}
