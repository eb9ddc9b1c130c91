// The end of a light-tracing pass: each pixel's splats (splat.wgsl, 32.32 fixed point) become
// one more sample of its estimate in the per-pixel sums the path tracers keep (rgb, and the
// sample count in w), or under a wide filter (frame.filter_reach > 0, where the camera's
// samples are summed by their weights) in sums of their own, and the splats are cleared for
// the next pass.

#import types
#import splat

@group(0) @binding(0) var<uniform> frame: Frame;

// Per pixel: the sum of the passes' estimates (rgb) and their count (w).
@group(0) @binding(16) var<storage, read_write> radiance: array<vec4f>;
// Under a wide filter: the splats' sums apart from the camera's (rgb) and their count (w).
@group(0) @binding(38) var<storage, read_write> light_sums: array<vec4f>;

@compute @workgroup_size(64)
fn splat_accumulate(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let pixel = gid.x + gid.y * groups.x * 64u;
    if pixel >= frame.width * frame.height {
        return;
    }
    let base = pixel * SPLAT_STRIDE;
    var c = vec3f(0.0);
    for (var k = 0u; k < 3u; k++) {
        let lo = atomicExchange(&splat[base + 2u * k], 0u);
        let hi = atomicExchange(&splat[base + 2u * k + 1u], 0u);
        c[k] = f32(hi) + f32(lo) * (1.0 / 4294967296.0);
    }
    if frame.filter_reach > 0u {
        light_sums[pixel] += vec4f(c, 1.0);
    } else {
        radiance[pixel] += vec4f(c, 1.0);
    }
}
