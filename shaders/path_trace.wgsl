// Path tracing, for comparison with SPPM: one sample per pixel per pass, added to `radiance`.
// Naive (PATH_NEE false): emission is found only by hitting it, so point and directional
// lights stay dark. With next-event estimation (PATH_NEE true): direct light at diffuse,
// glossy and rough dielectric vertices and at medium scattering events, and emission hit by
// BSDF sampling weighted by MIS. The path is shared/camera_path.wgsl's, SPPM's camera pass's
// loop, run to max_depth scattering events under Russian roulette (CAMERA_PATH_PT).

#import types
#import rng
#import camera
#import camera_samples
#import bidir_connect_none
#import camera_path

// Per pixel: the sum of the passes' samples (rgb) and the sample count (w).
@group(0) @binding(16) var<storage, read_write> radiance: array<vec4f>;

const STREAM_PATH: u32 = 2u;

// Next-event estimation (pt-nee; src/integrators/path.rs sets it): a constant, so that each
// method's kernel holds only its own path (pt-nee's pass 12% faster on cornell-box than under
// a frame field read at run time, the same on the bunny box: BENCHMARKS.md "VCM").
override PATH_NEE: bool = false;

@compute @workgroup_size(64)
fn path_trace(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    // This dispatch's part of the pass: pixels [work_first, work_end) of this renderer's rows,
    // or of splat_rows() where a wide filter's samples are splatted.
    let item = frame.work_first + gid.x + gid.y * groups.x * 64u;
    let rows = splat_rows();
    if item >= min(frame.work_end, frame.width * (rows.y - rows.x)) {
        return;
    }
    // Keyed by the pixel's index in the whole image (this may be a band of it).
    let px = item % frame.width;
    let row = rows.x + item / frame.width;
    let index = px + row * frame.width;
    var rng = rng_new(frame.seed, frame.pass_index, STREAM_PATH, index);
    // With the Sobol sampler: the pixel's sample pass_index, one per pass.
    rng_sobol(&rng, frame.pass_index, sobol_seed(frame.seed, STREAM_PATH, index));
    let jitter = rng_next2(&rng);
    let ray = camera_ray_at(px, row, jitter, &rng);
    let l = finite_sample(trace_camera_path(ray, CAMERA_PATH_PT, PATH_NEE, &rng).l);
    if frame.filter_reach > 0u {
        store_camera_sample(item, l, jitter);
    } else {
        radiance[item] += vec4f(l, 1.0);
    }
}
