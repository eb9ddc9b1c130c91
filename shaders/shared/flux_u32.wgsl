// flux.wgsl for a device without 64-bit atomics: each 32.32 fixed-point sum from two u32
// atomics, the carry out of the low word detected from the value it held. The totals are
// those of flux.wgsl bit for bit, whatever the order.

@group(0) @binding(14) var<storage, read_write> flux_accum: array<atomic<u32>>;

// Add c >= 0 to the fixed-point counter at words (lo, lo + 1).
fn accumulate_fixed(lo: u32, c: f32) {
    let hi_part = floor(c);
    let lo_part = min((c - hi_part) * 4294967296.0, 4294967040.0);
    let lo_add = u32(lo_part);
    let old = atomicAdd(&flux_accum[lo], lo_add);
    let carry = select(0u, 1u, old > 0xffffffffu - lo_add);
    let hi_add = u32(hi_part) + carry;
    if hi_add != 0u {
        atomicAdd(&flux_accum[lo + 1u], hi_add);
    }
}

// Add a photon's flux beta and one to the count of visible point v.
fn accumulate_flux(v: u32, beta: vec3f) {
    let base = v * ACCUM_STRIDE;
    accumulate_fixed(base, beta.x);
    accumulate_fixed(base + 2u, beta.y);
    accumulate_fixed(base + 4u, beta.z);
    atomicAdd(&flux_accum[base + 6u], 1u);
}
