// Light reaching the camera from light subpaths, splatted into the pixels it lands on: per
// pixel r, g, b in 32.32 fixed point, each from two u32 atomics with the carry out of the low
// word detected from the value it held (as flux_u32.wgsl sums flux). Integer sums do not
// depend on the order in which splats arrive: the same seed gives the same image.

#import types

@group(0) @binding(28) var<storage, read_write> splat: array<atomic<u32>>;

// Words per pixel: (lo, hi) for r, g and b.
const SPLAT_STRIDE: u32 = 6u;

// Add c >= 0 to the fixed-point counter at words (lo, lo + 1).
fn splat_fixed(lo: u32, c: f32) {
    let w = fixed_point_words(c);
    if w.x == 0u && w.y == 0u {
        return;
    }
    let old = atomicAdd(&splat[lo], w.x);
    let carry = select(0u, 1u, old > 0xffffffffu - w.x);
    let hi_add = w.y + carry;
    if hi_add != 0u {
        atomicAdd(&splat[lo + 1u], hi_add);
    }
}

// Add radiance c to pixel `pixel` of this renderer's rows.
fn splat_add(pixel: u32, c: vec3f) {
    let base = pixel * SPLAT_STRIDE;
    splat_fixed(base, c.x);
    splat_fixed(base + 2u, c.y);
    splat_fixed(base + 4u, c.z);
}
