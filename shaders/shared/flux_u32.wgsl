// flux.wgsl for a device without 64-bit atomics: each 32.32 fixed-point sum from two u32
// atomics, the carry out of the low word detected from the value it held. The totals are
// those of flux.wgsl bit for bit, whatever the order.

#import types

@group(0) @binding(14) var<storage, read_write> flux_accum: array<atomic<u32>>;

// Add c >= 0 to the fixed-point counter at words (lo, lo + 1).
fn accumulate_fixed(lo: u32, c: f32) {
    let w = fixed_point_words(c);
    let old = atomicAdd(&flux_accum[lo], w.x);
    let carry = select(0u, 1u, old > 0xffffffffu - w.x);
    let hi_add = w.y + carry;
    if hi_add != 0u {
        atomicAdd(&flux_accum[lo + 1u], hi_add);
    }
}

// Add a photon's flux beta and one to the count of visible point v.
fn accumulate_flux(v: u32, beta: vec3f) {
    let base = v * accum_stride();
    accumulate_fixed(base, beta.x);
    accumulate_fixed(base + 2u, beta.y);
    accumulate_fixed(base + 4u, beta.z);
    atomicAdd(&flux_accum[base + 6u], 1u);
}

// Add a photon's offset moments (offset_moments) to visible point v's words 8 to 11.
fn accumulate_moments(v: u32, q: vec4u) {
    let base = v * accum_stride() + 8u;
    for (var c = 0u; c < 4u; c++) {
        atomicAdd(&flux_accum[base + c], q[c]);
    }
}
