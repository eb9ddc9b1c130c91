// Counter-based random numbers: every (seed, pass, stream, index) starts its own sequence, so
// a thread's samples do not depend on how the work was scheduled.

// PCG hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering").
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

struct Rng {
    state: u32,
}

fn rng_new(seed: u32, pass_index: u32, stream: u32, index: u32) -> Rng {
    let h = pcg_hash(seed ^ pcg_hash(pass_index ^ pcg_hash(stream ^ pcg_hash(index))));
    return Rng(h);
}

// Uniform in [0, 1).
fn rng_next(rng: ptr<function, Rng>) -> f32 {
    (*rng).state = (*rng).state * 747796405u + 2891336453u;
    let s = (*rng).state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    let r = (word >> 22u) ^ word;
    // 24 high bits, so the result stays below 1.
    return f32(r >> 8u) * (1.0 / 16777216.0);
}

fn rng_next2(rng: ptr<function, Rng>) -> vec2f {
    let x = rng_next(rng);
    let y = rng_next(rng);
    return vec2f(x, y);
}
