// The aimed disk of an environment's photons and light subpaths (shared/emitter/environment.wgsl)
// against the density the bidirectional methods weigh them by: for each point
// environment_origin draws, its weight (one over pi R^2 times the mixture's density there)
// times environment_disk_density at the photon's origin is 1 (tests/suite/environment.rs).

#import types
#import rng
#import sampling
#import scene
#import lights

struct EnvAimTestParams {
    count: u32,
    // The share aimed, the scene's radius R and the aimed sphere's radius.
    fraction: f32,
    big: f32,
    small: f32,
    // The aimed sphere's centre (the scene's is the origin), and the direction towards the
    // environment.
    centre: vec3f,
    w: vec3f,
}

@group(0) @binding(21) var<uniform> test_params: EnvAimTestParams;
// Per draw: weight times density, the weight, the density.
@group(0) @binding(22) var<storage, read_write> test_out: array<vec4f>;

@compute @workgroup_size(64)
fn env_aim_test(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = gid.x + gid.y * groups.x * 64u;
    let p = test_params;
    if i >= p.count {
        return;
    }
    var e: Emitter;
    e.kind = EMITTER_ENVIRONMENT;
    e.radius = p.big;
    e.area = PI * p.big * p.big;
    let aim = EnvironmentAim(p.fraction, p.small, p.centre, p.centre);
    let w = normalize(p.w);
    let b = basis(w);
    let u = vec2f(f32(pcg_hash(i) >> 8u), f32(pcg_hash(i ^ 0x9e3779b9u) >> 8u)) * (1.0 / 16777216.0);
    let o = environment_origin(e, b[0], b[1], u, aim);
    // The photon's origin as environment_emit places it.
    let x = e.position + 1.01 * e.radius * w + b[0] * o.q.x + b[1] * o.q.y;
    let density = environment_disk_density(e, w, x, aim);
    test_out[i] = vec4f(o.weight * density, o.weight, density, 0.0);
}
