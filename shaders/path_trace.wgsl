// Path tracing, for comparison with SPPM: one sample per pixel per pass, added to `radiance`.
// Naive (frame.nee == 0): emission is found only by hitting it, so point and directional
// lights stay dark. With next-event estimation (frame.nee == 1): direct_light at diffuse,
// glossy and rough dielectric vertices, and emission hit by BSDF sampling weighted by
// emission_weight (shared/direct.wgsl, which SPPM's camera pass uses too). Scene, camera,
// lights and BSDF sampling are the ones SPPM's kernels use. In participating media
// (shared/medium.wgsl) each segment may end at a scattering event, where the phase function
// is sampled and, with NEE, a light through the medium's transmittance.

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import camera
#import lights
#import direct
#import medium

// Per pixel: the sum of the passes' samples (rgb) and the sample count (w).
@group(0) @binding(16) var<storage, read_write> radiance: array<vec4f>;

const STREAM_PATH: u32 = 2u;

// Russian roulette after three scattering events, keeping the largest channel's weight,
// judged without the refractions' 1 / eta^2 (pbrt-v4's PathIntegrator, sec. 13.4: rrBeta =
// beta etaScale): a path inside a diamond carries 1 / 2.42^2 of its weight until it leaves,
// and would otherwise end at 83% a bounce. False when the path ends.
fn roulette(beta: ptr<function, vec3f>, eta_scale: f32, rng: ptr<function, Rng>) -> bool {
    let q = max(0.05, 1.0 - max_component(*beta) * eta_scale);
    if rng_next(rng) < q {
        return false;
    }
    *beta /= 1.0 - q;
    return true;
}

@compute @workgroup_size(64)
fn path_trace(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    // This dispatch's part of the pass: pixels [work_first, work_end).
    let pixel = frame.work_first + gid.x + gid.y * groups.x * 64u;
    if pixel >= min(frame.work_end, frame.width * frame.height) {
        return;
    }
    // Keyed by the pixel's index in the whole image (this may be a band of it).
    var rng = rng_new(frame.seed, frame.pass_index, STREAM_PATH, pixel + frame.row_offset * frame.width);
    // With the Sobol sampler: the pixel's sample pass_index, one per pass.
    rng_sobol(&rng, frame.pass_index, sobol_seed(frame.seed, STREAM_PATH, pixel + frame.row_offset * frame.width));
    let ray = camera_ray(pixel % frame.width, pixel / frame.width, &rng);
    var o = ray.o;
    var d = ray.d;
    var beta = vec3f(1.0);
    var l = vec3f(0.0);
    // Density of the BSDF sample that led here, for MIS at an emitter it hits; 0 after the
    // camera, after mirror or smooth glass, which NEE does not sample, and always in naive
    // path tracing.
    var pdf_prev = 0.0;
    // The product of eta^2 over the path's refractions (refraction_eta2).
    var eta_scale = 1.0;
    // The medium the path travels through (shared/medium.wgsl).
    var medium = CAMERA_MEDIUM;
    // Where the BSDF sample that pdf_prev is the density of left from: o, but past a null
    // boundary of a medium, which the sample crossed unbent (shadow_transmittance).
    var mis_o = o;
    // A path has at most max_depth scattering events, so max_depth + 1 segments.
    for (var depth = 0u; depth <= frame.max_depth; depth++) {
        let hit = trace_closest(o, d, 3.4e38);
        // In a medium the segment may end at a scattering event short of the surface (or of
        // escaping: hit.t is then 3.4e38).
        if USES_MEDIA && medium != NO_MEDIUM {
            let c = medium_coefficients(medium);
            let flight = sample_flight(c, hit.t, rng_next2(&rng));
            if !flight.scattered {
                beta *= flight.weight;
            } else {
                beta *= flight.weight * c.sigma_s;
                if depth == frame.max_depth || all(beta == vec3f(0.0)) {
                    break;
                }
                let p = o + flight.t * d;
                if frame.nee != 0u {
                    l += beta * medium_direct_light(p, d, medium, c.g, vec3f(rng_next(&rng), rng_next2(&rng)));
                }
                // The phase function sampled exactly: the weight is 1.
                let wi = sample_phase(d, c.g, rng_next2(&rng));
                pdf_prev = select(0.0, phase_hg(dot(d, wi), c.g), frame.nee != 0u);
                o = p;
                mis_o = p;
                d = wi;
                if depth >= 3u && !roulette(&beta, eta_scale, &rng) {
                    break;
                }
                continue;
            }
        }
        if hit.prim_ref == 0xffffffffu {
            // The ray escapes: the environment, weighted as emission is.
            if USES_ENVIRONMENT {
                l += beta * escaped_light(d, pdf_prev);
            }
            break;
        }
        let s = surface_at(hit, o, d);
        let shape = shapes[s.shape];
        if shape.emits != 0u && dot(d, s.ng) < 0.0 {
            // Naive path tracing finds light only this way: whole (pdf_prev stays 0).
            l += beta * shape.emission * emission_weight(pdf_prev, mis_o, hit, s, d);
        }
        if depth == frame.max_depth {
            break;
        }
        let m = material_at(s);
        // A one-sided surface seen from behind is black: the path ends.
        if seen_from_behind(m, s, d) {
            break;
        }
        let wo = -d;
        let diffuse = m.kind == MATERIAL_DIFFUSE;
        let albedo = m.albedo;
        // Next-event estimation at diffuse, glossy and rough dielectric vertices (mirrors and
        // smooth glass cannot sample lights), from one call site: the shadow ray's traversal
        // is inlined once. At a diffuse vertex the numbers are drawn either way, so that the
        // two methods share streams.
        let nee = frame.nee != 0u && bsdf_samples_lights(m);
        var u_light = vec3f(0.0);
        if nee || diffuse {
            u_light = vec3f(rng_next(&rng), rng_next2(&rng));
        }
        if nee {
            l += beta * direct_light(s, wo, m, albedo, medium, u_light);
        }
        let next = bsdf_sample(s, m, albedo, d, vec3f(rng_next2(&rng), rng_next(&rng)), true, nee);
        if all(next.weight == vec3f(0.0)) {
            break;
        }
        beta *= next.weight;
        eta_scale *= refraction_eta2(m, s, d, next.wi);
        // A null boundary of a medium leaves the MIS density and origin as they were.
        let crossed_null = USES_MEDIA && is_null(m);
        if !crossed_null {
            pdf_prev = next.pdf;
        }
        medium = medium_after(medium, s, d, next.wi);
        d = next.wi;
        o = offset_origin(s.p, s.ng, d);
        if !crossed_null {
            mis_o = o;
        }
        if depth >= 3u && !roulette(&beta, eta_scale, &rng) {
            break;
        }
    }
    // A NaN or infinite sample counts as black rather than poisoning the pixel.
    let ok = all(l == l) && all(abs(l) < vec3f(3.0e38));
    radiance[pixel] += vec4f(select(vec3f(0.0), l, ok), 1.0);
}
