// SPPM photon gather, after the photon pass: each visible point adds the photon hits stored
// within its radius (photon_pass.wgsl) to its accumulator. It walks the lists of the buckets
// of the cells its disc overlaps (at most two per axis, each bucket once), so every hit within
// the radius is met exactly once; the tests are those of a direct deposit (accepts in
// shared/gather.wgsl). The sums are kept in registers in the 32.32 fixed point of
// shared/flux.wgsl and added once, without atomics: only this thread
// writes its point's words in this dispatch (the direct deposits of resumed photon threads,
// with atomics, are dispatches of their own). Integer sums do not
// depend on the order of the terms, so the accumulator holds the bits a direct deposit of
// every hit would leave. With ADAPTIVE_RADIUS the hits' offsets from the point are summed too
// (offset_moments in shared/types.wgsl), for the adaptive radius rule's test.

#import types
#import sampling
#import grid
#import gather

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(8) var<storage, read> visible_points: array<VisiblePoint>;
@group(0) @binding(11) var<uniform> grid: GridParams;
@group(0) @binding(14) var<storage, read_write> flux_accum: array<u32>;
// PhotonHit as three vec4u (see photon_pass.wgsl).
@group(0) @binding(23) var<storage, read> photon_hits: array<vec4u>;
@group(0) @binding(24) var<storage, read> photon_hit_lists: array<u32>;

// The 64-bit sum a + w of two fixed-point numbers as (low, high) words.
fn add_fixed(a: vec2u, w: vec2u) -> vec2u {
    let lo = a.x + w.x;
    return vec2u(lo, a.y + w.y + select(0u, 1u, lo < w.x));
}

@compute @workgroup_size(64)
fn photon_gather(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= frame.vp_count {
        return;
    }
    let q = visible_points[index];
    let b = point_buckets(grid, q.p, q.radius);
    let g = gatherer(q);
    var flux = array<vec2u, 3>(vec2u(0u), vec2u(0u), vec2u(0u));
    var count = 0u;
    var moments = vec4u(0u);
    for (var k = 0u; k < 8u; k++) {
        if !visits(b, k) {
            continue;
        }
        var next = photon_hit_lists[2u + b.h[k]];
        while next != 0u {
            let i = 3u * (next - 1u);
            let head = photon_hits[i];
            next = head.w;
            // The radius first, before the hit's other loads: most hits fail it (accepts
            // tests it again, which the compiler folds).
            if !within_radius(g.p, g.radius, bitcast<vec3f>(head.xyz)) {
                continue;
            }
            let arrival = photon_hits[i + 1u];
            // The flux, and the normal of the surface the photon hit.
            let carried = photon_hits[i + 2u];
            if !accepts(g, bitcast<vec3f>(head.xyz), bitcast<vec3f>(arrival.xyz), arrival.w, carried.w, frame.max_depth) {
                continue;
            }
            if ADAPTIVE_RADIUS {
                moments += offset_moments((bitcast<vec3f>(head.xyz) - q.p) / q.radius);
            }
            let beta = bitcast<vec3f>(carried.xyz);
            flux[0] = add_fixed(flux[0], fixed_point_words(beta.x));
            flux[1] = add_fixed(flux[1], fixed_point_words(beta.y));
            flux[2] = add_fixed(flux[2], fixed_point_words(beta.z));
            count += 1u;
        }
    }
    if count == 0u {
        return;
    }
    // Words 2c, 2c + 1: channel c, low word first; word 6: the count (flux.wgsl).
    let base = index * accum_stride();
    for (var c = 0u; c < 3u; c++) {
        let sum = add_fixed(vec2u(flux_accum[base + 2u * c], flux_accum[base + 2u * c + 1u]), flux[c]);
        flux_accum[base + 2u * c] = sum.x;
        flux_accum[base + 2u * c + 1u] = sum.y;
    }
    flux_accum[base + 6u] += count;
    if ADAPTIVE_RADIUS {
        // Words 8 to 11: the offsets' moments (update_stats.wgsl).
        for (var c = 0u; c < 4u; c++) {
            flux_accum[base + 8u + c] += moments[c];
        }
    }
}
