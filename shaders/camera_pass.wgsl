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
// the event by sampling the phase function, as it passes glossy surfaces.

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import camera
#import lights
#import direct
#import grid
#import medium

@group(0) @binding(8) var<storage, read_write> visible_points: array<VisiblePoint>;
@group(0) @binding(10) var<storage, read_write> vp_stats: array<VpStats>;
// Word 0: the largest radius of this pass's visible points, as f32 bits, for grid_setup.
// With an environment aimed at the visible points (frame.env_aim > 0), words 1 to 3 the
// largest x, y, z of the positions of those the camera sees directly (with no scattering
// event before) and words 4 to 6 the smallest, as order keys
// (shared/grid.wgsl: order_key, the smallest as the largest complement), for photon_pass.
@group(0) @binding(17) var<storage, read_write> grid_max_radius: array<atomic<u32>>;

const STREAM_CAMERA: u32 = 0u;

// What one camera path found: the light it gathered along the way, and where it ended on a
// diffuse surface (`found`; the radius is set by the caller).
struct CameraPath {
    ld: vec3f,
    vp: VisiblePoint,
    found: bool,
}

// Trace a camera path through pixel (px, py) to its first diffuse surface.
fn trace_camera_path(px: u32, py: u32, rng: ptr<function, Rng>) -> CameraPath {
    let ray = camera_ray(px, py, rng);
    var o = ray.o;
    var d = ray.d;
    var beta = vec3f(1.0);
    var path = CameraPath(vec3f(0.0), VisiblePoint(vec3f(0.0), 0.0, vec3f(0.0), 0u), false);
    let sample_direct = frame.direct != 0u;
    // Density of the BSDF sample that led here, for MIS at an emitter; 0 after the camera,
    // mirrors and smooth glass, and when direct light is not sampled.
    var pdf_prev = 0.0;
    // Past the visible point the path goes one segment further, only to meet emission that a
    // BSDF sample hits (the other half of MIS there), traced by the same call as the rest: the
    // traversal is inlined into the kernel once.
    var to_emission = false;
    // The medium the path travels through.
    var medium = CAMERA_MEDIUM;
    // Where the BSDF sample that pdf_prev is the density of left from: o, but past a null
    // boundary of a medium, which the sample crossed unbent (shadow_transmittance).
    var mis_o = o;
    for (var depth = 0u; depth < frame.max_depth || to_emission; depth++) {
        let hit = trace_closest(o, d, 3.4e38);
        // In a medium the segment may end at a scattering event short of the surface.
        if USES_MEDIA && medium != NO_MEDIUM {
            let c = medium_coefficients(medium);
            let flight = sample_flight(c, hit.t, rng_next2(rng));
            if !flight.scattered {
                beta *= flight.weight;
            } else {
                beta *= flight.weight * c.sigma_s;
                // Past the visible point the path only looks for emission.
                if to_emission || all(beta == vec3f(0.0)) {
                    break;
                }
                let p = o + flight.t * d;
                if sample_direct {
                    path.ld += beta * medium_direct_light(p, d, medium, c.g, vec3f(rng_next(rng), rng_next2(rng)));
                }
                let wi = sample_phase(d, c.g, rng_next2(rng));
                if c.g == 0.0 {
                    // The in-scattered radiance, sigma_s (in beta) times the phase function
                    // 1 / 4 pi times the fluence the volume photons estimate (update_stats.wgsl).
                    path.vp = VisiblePoint(p, 0.0, beta * INV_4PI, volume_normal(depth));
                    path.found = true;
                    if !sample_direct {
                        break;
                    }
                    to_emission = true;
                }
                pdf_prev = select(0.0, phase_hg(dot(d, wi), c.g), sample_direct);
                o = p;
                mis_o = p;
                d = wi;
                if depth + 1u >= frame.max_depth {
                    to_emission = true;
                }
                continue;
            }
        }
        if hit.prim_ref == 0xffffffffu {
            // The ray escapes: the environment, weighted as emission is.
            if USES_ENVIRONMENT {
                path.ld += beta * escaped_light(d, pdf_prev);
            }
            break;
        }
        let s = surface_at(hit, o, d);
        // Emission is one-sided: only the front of the geometric normal emits.
        let shape = shapes[s.shape];
        if shape.emits != 0u && dot(d, s.ng) < 0.0 {
            path.ld += beta * shape.emission * emission_weight(pdf_prev, mis_o, hit, s, d);
        }
        if to_emission {
            // Emission behind a null boundary of a medium, which next-event estimation reached
            // too (shadow_transmittance): the segment goes on through it.
            if USES_MEDIA && is_null(material_at(s)) {
                medium = medium_after(medium, s, d, d);
                o = offset_origin(s.p, s.ng, d);
                continue;
            }
            break;
        }
        let m = material_at(s);
        // A one-sided surface seen from behind is black: the path ends, leaving no visible point.
        if seen_from_behind(m, s, d) {
            break;
        }
        let albedo = m.albedo;
        // Next-event estimation at diffuse, glossy, rough dielectric and plastic vertices
        // (mirrors and smooth glass cannot sample lights), from one call site: the shadow
        // ray's traversal is inlined once.
        let nee = sample_direct && bsdf_samples_lights(m);
        if nee {
            path.ld += beta * direct_light(s, -d, m, albedo, medium, vec3f(rng_next(rng), rng_next2(rng)));
        }
        // The BSDF sampled once (shared/bsdf.wgsl): a diffuse surface's or a plastic's base's
        // lobe leaves the visible point; any other is passed through. For a plastic the
        // expectation over its lobes is the whole BSDF's estimate.
        let next = bsdf_sample(s, m, albedo, d, vec3f(rng_next2(rng), rng_next(rng)), true, nee);
        if next.diffuse {
            // The visible point: the photon pass adds flux * weight for photons near it.
            let n = select(-s.ng, s.ng, dot(d, s.ng) < 0.0);
            path.vp = VisiblePoint(s.p, 0.0, beta * next.vp_weight, encode_normal(n, depth));
            path.found = true;
            if !sample_direct {
                break;
            }
            // The path ends here, so both MIS strategies are taken: the light sample above,
            // and the sampled direction, whose emission the next segment weighs by
            // emission_weight.
            to_emission = true;
        }
        // Specular and glossy surfaces are passed through by sampling them, so visible points
        // lie on diffuse surfaces only (as pbrt-v4's SPPM does for all but the last bounce):
        // the estimate at a glossy surface is then the unbiased average over its lobe of
        // the density estimates further on, and no BSDF has to be evaluated per photon.
        if all(next.weight == vec3f(0.0)) {
            break;
        }
        beta *= next.weight;
        // A null boundary of a medium leaves the MIS density and origin as they were.
        let crossed_null = USES_MEDIA && is_null(m);
        if !crossed_null {
            pdf_prev = next.pdf;
        }
        medium = medium_after(medium, s, d, next.wi);
        o = offset_origin(s.p, s.ng, next.wi);
        d = next.wi;
        if !crossed_null {
            mis_o = o;
        }
        // That was the last scattering event max_depth allows: the next segment only gathers
        // the emission it meets, weighed by MIS, as a path tracer's last segment does.
        if depth + 1u >= frame.max_depth {
            to_emission = true;
        }
    }
    return path;
}

@compute @workgroup_size(64)
fn camera_pass(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    // This dispatch's part of the pass: points [work_first, work_end).
    let index = frame.work_first + gid.x + gid.y * groups.x * 64u;
    if index >= min(frame.work_end, frame.vp_count) {
        return;
    }
    // Keyed by the point's index in the whole image, so that a band draws the numbers the
    // whole image would.
    var rng = rng_new(frame.seed, frame.pass_index, STREAM_CAMERA, index + frame.row_offset * frame.width * frame.spp);
    let pixel = index / frame.spp;
    let px = pixel % frame.width;
    let py = pixel / frame.width;

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
    let global = index + frame.row_offset * frame.width * frame.spp;
    let first_sample = (frame.pass_index * frame.spp + global % frame.spp) * paths;
    let pixel_seed = sobol_seed(frame.seed, STREAM_CAMERA, global / frame.spp);
    for (var i = 0u; i < paths; i++) {
        rng_sobol(&rng, first_sample + i, pixel_seed);
        let path = trace_camera_path(px, py, &rng);
        ld += path.ld;
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
    vp_stats[index].ld += ld / f32(paths);
}
