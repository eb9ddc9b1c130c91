// SPPM camera pass (Hachisuka & Jensen 2009, sec. 4): one path per visible-point slot, from a
// jittered point in its pixel through specular and glossy bounces to the first diffuse
// surface, where it leaves a visible point. Emission seen along the way is added to the slot's
// ld. With frame.direct == 1 the path also samples direct light at its glossy and rough
// dielectric vertices and at the visible point (direct_light, the code pt-nee runs), and
// weights emission it hits after such a bounce by MIS; pbrt-v4's SPPM samples direct light at
// camera vertices too. The photons then carry only light that has bounced at least once
// (photon_pass.wgsl), so no light is counted twice. With 0, photons carry all light and
// emission counts whole. In an isotropic participating medium (shared/medium.wgsl) the path
// may instead end at a scattering event, leaving a visible point in the medium that gathers
// the volume photons around it (Knaus & Zwicker 2011, sec. 5); in an anisotropic one it passes
// the event by sampling the phase function, as it passes glossy surfaces. The path is
// shared/camera_path.wgsl's, the path tracers' loop, asked to stop at the visible point
// (CAMERA_PATH_SPPM).
//
// With a global radius schedule under a wide pixel filter (frame.filter_reach > 0) each pass's
// estimate of a point is a camera sample splatted as the path tracers' are (the points cover
// splat_rows()): the first path leaves from a uniform place in the pixel, and its share of the
// direct light goes to `camera_samples`, which update_stats completes with the photons'
// density at its visible point; the other paths sample the filter as elsewhere, and their
// share is summed apart per pixel (`direct_sums`, averaged by passes). The splatted sample's
// expectation is the filtered indirect light and 1 / paths of the direct, the others' the rest
// of the direct light.

#import types
#import rng
#import sampling
#import camera
#import grid
#import camera_samples
#import bidir_connect_none
#import camera_path

@group(0) @binding(8) var<storage, read_write> visible_points: array<VisiblePoint>;
@group(0) @binding(10) var<storage, read_write> vp_stats: array<VpStats>;
// Under a splatting filter, per pixel of the band: the direct light of the paths after the
// first, summed over passes (rgb), and the passes (w).
@group(0) @binding(40) var<storage, read_write> direct_sums: array<vec4f>;
// Word 0: the largest radius of this pass's visible points, as f32 bits, for grid_setup.
// With an environment aimed at the visible points (frame.env_aim > 0), words 1 to 3 the
// largest x, y, z of the positions of those the camera sees directly (with no scattering
// event before) and words 4 to 6 the smallest, as order keys
// (shared/grid.wgsl: order_key, the smallest as the largest complement), for photon_pass.
@group(0) @binding(17) var<storage, read_write> grid_max_radius: array<atomic<u32>>;

const STREAM_CAMERA: u32 = 0u;

@compute @workgroup_size(64)
fn camera_pass(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    // This dispatch's part of the pass: points [work_first, work_end).
    let index = frame.work_first + gid.x + gid.y * groups.x * 64u;
    if index >= min(frame.work_end, frame.vp_count) {
        return;
    }
    // Keyed by the point's index in the whole image, so that a band draws the numbers the
    // whole image would. The points' rows: the band's, and a splatting filter's reach.
    let first_row = splat_rows().x;
    var rng = rng_new(frame.seed, frame.pass_index, STREAM_CAMERA, index + first_row * frame.width * frame.spp);
    let pixel = index / frame.spp;
    let px = pixel % frame.width;
    let row = first_row + pixel / frame.width;

    // The first path leaves the visible point. The light the paths gather is the mean over
    // frame.direct_samples paths through the pixel (1 where photons carry direct light): each
    // is an unbiased estimate of the pixel's emitted and direct light, and the extra paths
    // cost no visible point, grid entry or photon deposit.
    // One call site: the traversal inlined into this kernel once per call, not twice.
    var first: CameraPath;
    var ld = vec3f(0.0);
    let paths = max(frame.direct_samples, 1u);
    // With the Sobol sampler: path i of slot s of pixel p in pass n is sample
    // (n spp + s) paths + i of the pixel's sequence.
    let global = index + first_row * frame.width * frame.spp;
    let first_sample = (frame.pass_index * frame.spp + global % frame.spp) * paths;
    let pixel_seed = sobol_seed(frame.seed, STREAM_CAMERA, global / frame.spp);
    let splat = frame.filter_reach > 0u;
    var jitter = vec2f(0.0);
    for (var i = 0u; i < paths; i++) {
        rng_sobol(&rng, first_sample + i, pixel_seed);
        var at = rng_next2(&rng);
        if i == 0u {
            jitter = at;
        } else if splat {
            // Splatted, the first path's place in the pixel is uniform and the others sample
            // the filter (camera_ray_at samples it itself where nothing splats).
            at = 0.5 + sample_filter(at);
        }
        let ray = camera_ray_at(px, row, at, &rng);
        let path = trace_camera_path(ray, CAMERA_PATH_SPPM, frame.direct != 0u, &rng);
        ld += path.l;
        if i == 0u {
            first = path;
        }
    }
    var vp = first.vp;
    if first.found {
        // The point's own radius, or the pass's with a global schedule.
        vp.radius = select(vp_stats[index].radius, frame.global_radius, frame.global_radius > 0.0);
        // A point in a medium gathers over a wider sphere (shared/grid.wgsl).
        if in_volume(vp.normal) {
            vp.radius *= VOLUME_RADIUS_SCALE;
        }
        // Positive floats order like their bits.
        atomicMax(&grid_max_radius[0], bitcast<u32>(vp.radius));
        // Only points the camera sees directly: one seen in a mirror or glass may lie anywhere
        // (the far edge of a wide ground plane), and would stretch the bounds over the scene.
        if USES_ENVIRONMENT && frame.env_aim > 0.0 && vp_depth(vp.normal) == 0u {
            for (var k = 0u; k < 3u; k++) {
                let key = order_key(vp.p[k]);
                atomicMax(&grid_max_radius[1u + k], key);
                atomicMax(&grid_max_radius[4u + k], ~key);
            }
        }
    }
    visible_points[index] = vp;
    if splat {
        store_camera_sample(index, finite_sample(first.l / f32(paths)), jitter);
        // The band's own pixels sum the other paths' share.
        if row >= frame.row_offset && row < frame.row_offset + frame.height {
            let rest = finite_sample((ld - first.l) / f32(paths));
            direct_sums[px + (row - frame.row_offset) * frame.width] += vec4f(rest, 1.0);
        }
    } else {
        vp_stats[index].ld += ld / f32(paths);
    }
}
