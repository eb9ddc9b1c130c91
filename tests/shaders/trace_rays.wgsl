// Closest hits (or occlusion) for a batch of rays: the BVH traversal alone, for the test that checks it
// against the CPU oracle and for the rays/s benchmark.

#import types
#import scene

// Ray i: origin rays[2i].xyz, direction rays[2i + 1].xyz, t_max rays[2i].w.
@group(0) @binding(8) var<storage, read> rays: array<vec4f>;
// Hit i: (t, prim_ref as bits, b1, b2); prim_ref 0xffffffff on a miss. With ANY_HIT, the
// shadow-ray query instead: (0, 0 if anything lies along the ray else 0xffffffff, 0, 0).
@group(0) @binding(9) var<storage, read_write> hits: array<vec4f>;

override ANY_HIT: bool = false;

@compute @workgroup_size(64)
fn trace_rays(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= arrayLength(&hits) {
        return;
    }
    let o = rays[2u * index];
    let d = rays[2u * index + 1u].xyz;
    if ANY_HIT {
        let blocked = occluded(o.xyz, d, o.w);
        hits[index] = vec4f(0.0, bitcast<f32>(select(0xffffffffu, 0u, blocked)), 0.0, 0.0);
        return;
    }
    let hit = trace_closest(o.xyz, d, o.w);
    hits[index] = vec4f(hit.t, bitcast<f32>(hit.prim_ref), hit.b.x, hit.b.y);
}
