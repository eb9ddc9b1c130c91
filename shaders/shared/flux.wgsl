// The photon pass's flux accumulator, added to with 64-bit atomics (a device with
// SHADER_INT64_ATOMIC_ALL_OPS; flux_u32.wgsl is the same sum from pairs of u32 atomics). A
// visible point's ACCUM_STRIDE words hold r, g, b in 32.32 fixed point, little-endian (low
// word first, as update_stats reads them), then the photon count. Integer sums do not depend
// on the order in which photons arrive: the same seed gives the same image on either path.

#import types

@group(0) @binding(14) var<storage, read_write> flux_accum: array<atomic<u64>>;

// c >= 0 in 32.32 fixed point (fixed_point_words), as one 64-bit word.
fn fixed_point(c: f32) -> u64 {
    let w = fixed_point_words(c);
    return (u64(w.y) << 32u) | u64(w.x);
}

// Add a photon's flux beta and one to the count of visible point v.
fn accumulate_flux(v: u32, beta: vec3f) {
    let base = v * (accum_stride() / 2u);
    atomicAdd(&flux_accum[base], fixed_point(beta.x));
    atomicAdd(&flux_accum[base + 1u], fixed_point(beta.y));
    atomicAdd(&flux_accum[base + 2u], fixed_point(beta.z));
    // Words 6 and 7: the count, and a word no count reaches (fewer than 2^32 photons a pass).
    atomicAdd(&flux_accum[base + 3u], 1lu);
}

// Add a photon's offset moments (offset_moments) to visible point v's words 8 to 11, two to a
// 64-bit word: each low half sums to less than 2^32 (fewer than 2^21 photons a point and pass),
// so no carry reaches the high half, and the words hold what flux_u32.wgsl's hold.
fn accumulate_moments(v: u32, q: vec4u) {
    let base = v * (accum_stride() / 2u) + 4u;
    atomicAdd(&flux_accum[base], (u64(q.y) << 32u) | u64(q.x));
    atomicAdd(&flux_accum[base + 1u], (u64(q.w) << 32u) | u64(q.z));
}
