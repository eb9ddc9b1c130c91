// Bidirectional path tracing's camera pass (`--method bpt`; Veach 1997 ch. 10, in SmallVCM's
// recursive-MIS form, Georgiev 2012): after light_trace.wgsl has traced the pass's light
// subpaths, stored their vertices and splatted their joins to the camera, each pixel traces
// one camera subpath (shared/camera_path.wgsl under CAMERA_PATH_BIDIR) that at every vertex
// where a BSDF can be evaluated samples a light and connects to each stored vertex of light
// subpath (pixel mod n_light); emission it hits, next-event estimation, connections and light
// tracing are weighted by the balance heuristic so that together they make one estimate.
// Adds the camera subpath's light to `radiance` without counting a sample: splat_accumulate
// then adds the pass's splats and counts it; without light subpaths (vcm's light_paths = 0)
// there are no splats, and the sample is counted here. Under a wide pixel filter
// (frame.filter_reach > 0) the pass's samples of splat_rows() go to `camera_samples` instead,
// for filter_splat, and the splats to sums of their own.

#import types
#import rng
#import camera
#import camera_samples
#import bidir_connect
#import camera_path

// Per pixel: the sum of the passes' estimates (rgb) and their count (w).
@group(0) @binding(16) var<storage, read_write> radiance: array<vec4f>;

const STREAM_BIDIR_CAMERA: u32 = 4u;

@compute @workgroup_size(64)
fn bidir_camera(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    // A pixel of this renderer's rows, or of splat_rows() where a wide filter's samples are
    // splatted.
    let item = gid.x + gid.y * groups.x * 64u;
    let rows = splat_rows();
    if item >= frame.width * (rows.y - rows.x) {
        return;
    }
    // Keyed by the pixel's index in the whole image (this may be a band of it).
    let px = item % frame.width;
    let row = rows.x + item / frame.width;
    let index = px + row * frame.width;
    var rng = rng_new(frame.seed, frame.pass_index, STREAM_BIDIR_CAMERA, index);
    rng_sobol(&rng, frame.pass_index, sobol_seed(frame.seed, STREAM_BIDIR_CAMERA, index));
    bidir_light_path = index % max(frame.photon_count, 1u);
    bidir_block = index / 64u;
    let jitter = rng_next2(&rng);
    let ray = camera_ray_at(px, row, jitter, &rng);
    let l = finite_sample(trace_camera_path(ray, CAMERA_PATH_BIDIR | CAMERA_PATH_ROULETTE, true, &rng).l);
    if frame.filter_reach > 0u {
        store_camera_sample(item, l, jitter);
    } else {
        radiance[item] += vec4f(l, select(0.0, 1.0, frame.photon_count == 0u));
    }
    bidir_count_work();
}
