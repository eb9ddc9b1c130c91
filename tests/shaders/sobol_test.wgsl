// The Sobol sampler's draws as the kernels make them, for tests/sobol.rs to compare bit for
// bit with its CPU mirror (src/sampler.rs): thread i is sample first + i of the sequence
// `seed`, whose stream rng_new(seed, 0, 0, i) draws `draws` times, a pair at even draws and
// one number at odd ones. Compiled with SAMPLER_SOBOL = true.

#import rng

struct SobolTestParams {
    seed: u32,
    first: u32,
    count: u32,
    draws: u32,
}

@group(0) @binding(40) var<uniform> sobol_params: SobolTestParams;
// Per thread and draw: (x, y), y = 0 for one number.
@group(0) @binding(41) var<storage, read_write> sobol_out: array<vec2f>;

@compute @workgroup_size(64)
fn sobol_test(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = gid.x + gid.y * groups.x * 64u;
    let q = sobol_params;
    if i >= q.count {
        return;
    }
    var rng = rng_new(q.seed, 0u, 0u, i);
    rng_sobol(&rng, q.first + i, q.seed);
    for (var d = 0u; d < q.draws; d++) {
        var v = vec2f(0.0);
        if d % 2u == 0u {
            v = rng_next2(&rng);
        } else {
            v.x = rng_next(&rng);
        }
        sobol_out[i * q.draws + d] = v;
    }
}
