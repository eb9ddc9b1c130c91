// SPPM camera pass (Hachisuka & Jensen 2009, sec. 4): one path per visible-point slot, from a
// jittered point in its pixel through specular bounces to the first non-specular surface,
// where it leaves a visible point. Emission seen along the way is added to the slot's ld.

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import camera

@group(0) @binding(8) var<storage, read_write> visible_points: array<VisiblePoint>;
@group(0) @binding(9) var<storage, read_write> vp_points: array<vec4f>;
@group(0) @binding(10) var<storage, read_write> vp_stats: array<VpStats>;
// The largest radius of this pass's visible points, as f32 bits, for grid_setup.
@group(0) @binding(17) var<storage, read_write> grid_max_radius: array<atomic<u32>>;

const STREAM_CAMERA: u32 = 0u;

@compute @workgroup_size(64)
fn camera_pass(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= frame.vp_count {
        return;
    }
    // Keyed by the point's index in the whole image, so that a band draws the numbers the
    // whole image would.
    var rng = rng_new(frame.seed, frame.pass_index, STREAM_CAMERA, index + frame.row_offset * frame.width * frame.spp);
    let pixel = index / frame.spp;
    let px = pixel % frame.width;
    let py = pixel / frame.width;

    let ray = camera_ray(px, py, &rng);
    var o = ray.o;
    var d = ray.d;

    var beta = vec3f(1.0);
    var ld = vec3f(0.0);
    var vp = VisiblePoint(vec3f(0.0), 0u, vec3f(0.0), 0u);
    var vp_position = vec4f(0.0);
    for (var depth = 0u; depth < frame.max_depth; depth++) {
        let hit = trace_closest(o, d, 3.4e38);
        if hit.prim_ref == 0xffffffffu {
            break;
        }
        let s = surface_at(hit, o, d);
        // Emission is one-sided: only the front of the geometric normal emits.
        let shape = shapes[s.shape];
        if shape.emits != 0u && dot(d, s.ng) < 0.0 {
            ld += beta * shape.emission;
        }
        let m = materials[s.material];
        if m.kind == MATERIAL_DIFFUSE {
            // The visible point: the photon pass adds flux * weight for photons near it.
            let n = select(-s.ng, s.ng, dot(d, s.ng) < 0.0);
            vp = VisiblePoint(n, 0u, beta * diffuse_albedo(m, s.uv) * INV_PI, 0u);
            vp_position = vec4f(s.p, vp_stats[index].radius);
            // Positive floats order like their bits.
            atomicMax(&grid_max_radius[0], bitcast<u32>(vp_position.w));
            break;
        }
        // Specular and glossy surfaces are passed through by sampling them, so visible points
        // lie on diffuse surfaces only (as pbrt-v4's SPPM does for all but the last bounce):
        // the estimate at a glossy surface is then the unbiased average over its lobe of
        // the density estimates further on, and no BSDF has to be evaluated per photon.
        let next = sample_nondiffuse(m, d, s, vec3f(rng_next2(&rng), rng_next(&rng)), true);
        if all(next.weight == vec3f(0.0)) {
            break;
        }
        beta *= next.weight;
        o = offset_origin(s.p, s.ng, next.wi);
        d = next.wi;
    }
    visible_points[index] = vp;
    vp_points[index] = vp_position;
    vp_stats[index].ld += ld;
}
