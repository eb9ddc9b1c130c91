// The camera-path vertex loop, one for every kernel that traces paths from the camera: the
// path tracers (path_trace.wgsl: pt, pt-nee) and SPPM's camera pass (camera_pass.wgsl). From a
// camera ray through surfaces and, in participating media (shared/medium.wgsl), scattering
// events, it gathers the emission it hits, weighted by MIS against next-event estimation
// (shared/direct.wgsl), and with NEE the direct light at each vertex that can sample lights.
// What the kernels do differently they ask for by flags (CAMERA_PATH_*): a path tracer goes on
// to max_depth scattering events under Russian roulette; SPPM's camera pass ends at the first
// diffuse vertex or isotropic medium scattering event, its visible point (Hachisuka & Jensen
// 2009, sec. 4; Knaus & Zwicker 2011, sec. 5). One call site per kernel: the traversal is
// inlined once, and the flags, constants, fold away what a kernel does not ask for.

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import camera
#import lights
#import direct
#import medium
#import grid
#import vcm
#import bidir

// Russian roulette after three scattering events (pt).
const CAMERA_PATH_ROULETTE: u32 = 1u;
// The light sample's numbers drawn at diffuse vertices without NEE too, so that naive path
// tracing and NEE consume the same numbers and share streams (pt).
const CAMERA_PATH_SHARED_STREAMS: u32 = 2u;
// End at the first diffuse vertex (a BSDF sample of a diffuse lobe, next.diffuse) or isotropic
// medium scattering event, the visible point; with NEE one segment further, which only gathers
// the emission the BSDF or phase sample hits, the other half of MIS there (SPPM).
const CAMERA_PATH_VISIBLE_POINT: u32 = 4u;

// The camera subpath of the bidirectional methods (bpt): emission hit and next-event
// estimation weighted by the balance heuristic over the whole family (shared/bidir.wgsl), and
// at each vertex where a BSDF can be evaluated a connection to every vertex of the pass's
// light subpath the kernel chose (connect_light_subpath: bidir_connect.wgsl, which only the
// bidirectional kernel imports). Ask with nee, without media.
const CAMERA_PATH_BIDIR: u32 = 16u;

// Null boundaries a camera path crosses at most (see trace_camera_path).
const MAX_PATH_NULL_CROSSINGS: u32 = 64u;

const CAMERA_PATH_PT: u32 = CAMERA_PATH_ROULETTE | CAMERA_PATH_SHARED_STREAMS;
const CAMERA_PATH_SPPM: u32 = CAMERA_PATH_VISIBLE_POINT;

// What one camera path found: the light l it gathered along the way, and with
// CAMERA_PATH_VISIBLE_POINT the visible point vp where it ended (when `found`; the radius is
// the caller's to set).
struct CameraPath {
    l: vec3f,
    vp: VisiblePoint,
    found: bool,
}

// Russian roulette, keeping the largest channel's weight, judged without the refractions'
// 1 / eta^2 (pbrt-v4's PathIntegrator, sec. 13.4: rrBeta = beta etaScale): a path inside a
// diamond carries 1 / 2.42^2 of its weight until it leaves, and would otherwise end at 83% a
// bounce. False when the path ends.
fn roulette(beta: ptr<function, vec3f>, eta_scale: f32, rng: ptr<function, Rng>) -> bool {
    let q = max(0.05, 1.0 - max_component(*beta) * eta_scale);
    if rng_next(rng) < q {
        return false;
    }
    *beta /= 1.0 - q;
    return true;
}

// Trace a camera path from `ray` (camera_ray's). flags: CAMERA_PATH_*, a constant, so that
// what a kernel does not ask for compiles away. nee: sample direct light at diffuse, glossy,
// rough dielectric and plastic vertices and at medium scattering events, and weight emission
// hit after a BSDF or phase sample by MIS (path_trace.wgsl's PATH_NEE in the path tracers, frame.direct in SPPM).
fn trace_camera_path(ray: Ray, flags: u32, nee: bool, rng: ptr<function, Rng>) -> CameraPath {
    let use_roulette = (flags & CAMERA_PATH_ROULETTE) != 0u;
    let shared_streams = (flags & CAMERA_PATH_SHARED_STREAMS) != 0u;
    let visible_point = (flags & CAMERA_PATH_VISIBLE_POINT) != 0u;
    let bidir = (flags & CAMERA_PATH_BIDIR) != 0u;
    var path = CameraPath(vec3f(0.0), VisiblePoint(vec3f(0.0), 0.0, vec3f(0.0), 0u), false);
    var o = ray.o;
    var d = ray.d;
    var beta = vec3f(1.0);
    // Density of the BSDF or phase sample that led here, for MIS at an emitter it hits; 0
    // after the camera, after mirror or smooth glass, which NEE does not sample, and without
    // NEE.
    var pdf_prev = 0.0;
    // The product of eta^2 over the path's refractions (refraction_eta2), for roulette.
    var eta_scale = 1.0;
    // The medium the path travels through (shared/medium.wgsl).
    var medium = CAMERA_MEDIUM;
    // Where the sample that pdf_prev is the density of left from: o, but past a null boundary
    // of a medium, which the sample crossed unbent (shadow_transmittance).
    var mis_o = o;
    // Whether the path has left its visible point (CAMERA_PATH_VISIBLE_POINT with NEE).
    var past_vp = false;
    // The bidirectional MIS quantities of the subpath so far (shared/vcm.wgsl).
    var cm = SubpathMis(0.0, 0.0, 0.0, vec2f(0.0));
    // The subpath's vertices that merged (vcm merges at the first MERGES_A_PATH: vcm.wgsl), and
    // whether its latest vertex did (emission found next leaves that merge out of its weight).
    var merged = 0u;
    var last_merged = false;
    if bidir {
        cm = bidir_camera_start(d);
    }
    // A path has at most max_depth scattering events, so max_depth + 1 segments. A null
    // boundary of a medium is no scattering event (Mitsuba 3's volpath, pbrt-v4's `interface`,
    // the photons of photon_pass.wgsl): a segment goes on through it, the last one too, as NEE's
    // shadow rays do (shadow_transmittance), and `depth` stays. At most MAX_PATH_NULL_CROSSINGS of
    // them (a ray held by rounding between two coincident boundaries would not end).
    var depth = 0u;
    var crossings = 0u;
    loop {
        // The last segment only gathers the emission it meets, as a path tracer's last
        // segment does: after the max_depth-th scattering event, or past the visible point.
        let last = depth >= frame.max_depth || past_vp;
        let hit = trace_closest(o, d, 3.4e38);
        // In a medium the segment may end at a scattering event short of the surface (or of
        // escaping: hit.t is then 3.4e38).
        if USES_MEDIA && medium != NO_MEDIUM {
            let c = medium_coefficients(medium);
            let flight = sample_flight(c, hit.t, rng_next2(rng));
            if !flight.scattered {
                beta *= flight.weight;
            } else {
                beta *= flight.weight * c.sigma_s;
                if last || all(beta == vec3f(0.0)) {
                    break;
                }
                let p = o + flight.t * d;
                if nee {
                    path.l += beta * medium_direct_light(p, d, medium, c.g, vec3f(rng_next(rng), rng_next2(rng)));
                }
                // The phase function sampled exactly: the weight is 1.
                let wi = sample_phase(d, c.g, rng_next2(rng));
                if visible_point && c.g == 0.0 {
                    // The in-scattered radiance, sigma_s (in beta) times the phase function
                    // 1 / 4 pi times the fluence the volume photons estimate (update_stats.wgsl).
                    path.vp = VisiblePoint(p, 0.0, beta * INV_4PI, volume_normal(depth));
                    path.found = true;
                    if !nee {
                        break;
                    }
                    past_vp = true;
                }
                pdf_prev = select(0.0, phase_hg(dot(d, wi), c.g), nee);
                o = p;
                mis_o = p;
                d = wi;
                if use_roulette && depth >= 3u && !roulette(&beta, eta_scale, rng) {
                    break;
                }
                depth += 1u;
                continue;
            }
        }
        if hit.prim_ref == 0xffffffffu {
            // The ray escapes: the environment, weighted as emission is.
            if USES_ENVIRONMENT {
                if bidir {
                    let weight = bidir_escaped_weight(cm, o, d, depth == 0u, last_merged) * kept(STRATEGY_EMISSION);
                    path.l += beta * environment_eval(d).l * weight;
                } else {
                    path.l += beta * escaped_light(d, pdf_prev);
                }
            }
            break;
        }
        let s = surface_at(hit, o, d);
        if bidir {
            cm = mis_hit(cm, hit.t, dot(d, s.ns), true);
        }
        // Emission leaves the front of the geometric normal, or both sides (EMITS_BOTH).
        // Without NEE it counts whole (pdf_prev stays 0).
        let shape = shapes[s.shape];
        if shape.emits != 0u && (dot(d, s.ng) < 0.0 || shape.emits == EMITS_BOTH) {
            if bidir {
                path.l += beta * shape.emission * (bidir_emission_weight(cm, s.shape, abs(dot(d, s.ng)), depth == 0u, last_merged) * kept(STRATEGY_EMISSION));
            } else {
                path.l += beta * shape.emission * emission_weight(pdf_prev, mis_o, hit, s, d);
            }
        }
        if last {
            // Emission behind a null boundary of a medium, which NEE reached too: the segment
            // goes on through it.
            if USES_MEDIA && is_null(material_at(s)) && crossings < MAX_PATH_NULL_CROSSINGS {
                crossings += 1u;
                medium = medium_after(medium, s, d, d);
                o = offset_origin(s.p, s.ng, d);
                continue;
            }
            break;
        }
        let m = material_at(s);
        // A one-sided surface seen from behind is black: the path ends.
        if seen_from_behind(m, s, d) {
            break;
        }
        let wo = -d;
        let albedo = m.albedo;
        // NEE where the BSDF can sample lights (mirrors and smooth glass cannot), from one
        // call site: the shadow ray's traversal is inlined once.
        let nee_here = nee && bsdf_samples_lights(m);
        // Merging is a strategy here (vcm): one of the subpath's first vertices that merge.
        let merges = bidir && vcm_merges_at(m) && merged < MERGES_A_PATH;
        let merged_here = merged + select(0u, 1u, merges);
        if nee_here && bidir {
            bidir_work[WORK_CAMERA_VERTICES] += 1u;
            path.l += beta * bidir_direct_light(s, wo, m, albedo, cm, depth == 0u, vec3f(rng_next(rng), rng_next2(rng)))
                * kept(STRATEGY_NEE);
            if (frame.strategies & STRATEGY_CONNECT) != 0u && bidir_takes(frame.connect_share, 0u, depth) {
                path.l += beta * connect_light_subpath(s, m, albedo, wo, cm, depth + 1u, merges, merged_here) / frame.connect_share;
            }
            if merges && (frame.strategies & STRATEGY_MERGE) != 0u && bidir_takes(frame.merge_share, 1u, depth) {
                path.l += beta * merge_light_vertices(s, m, albedo, wo, cm, depth + 1u, merged_here) / frame.merge_share;
            }
        } else if nee_here {
            path.l += beta * direct_light(s, wo, m, albedo, medium, vec3f(rng_next(rng), rng_next2(rng)));
        } else if shared_streams && m.kind == MATERIAL_DIFFUSE {
            // The light sample's numbers, drawn and left (CAMERA_PATH_SHARED_STREAMS).
            _ = rng_next(rng);
            _ = rng_next2(rng);
        }
        let next = bsdf_sample(s, m, albedo, d, vec3f(rng_next2(rng), rng_next(rng)), true, nee_here);
        // A diffuse lobe (a diffuse surface's, a plastic's base's) leaves the visible point;
        // other lobes are passed through by sampling them, so that no BSDF is evaluated per
        // photon (as pbrt-v4's SPPM does for all but the last bounce). For a plastic the
        // expectation over its lobes is the whole BSDF's estimate.
        if visible_point && next.diffuse {
            let n = select(-s.ng, s.ng, dot(d, s.ng) < 0.0);
            // The photon pass adds flux * weight for photons near it.
            path.vp = VisiblePoint(s.p, 0.0, beta * next.vp_weight, encode_normal(n, depth));
            path.found = true;
            if !nee {
                break;
            }
            // Both MIS strategies are taken there: the light sample above, and the sampled
            // direction, whose emission the last segment weighs by emission_weight.
            past_vp = true;
        }
        if all(next.weight == vec3f(0.0)) {
            break;
        }
        beta *= next.weight;
        if bidir {
            // A delta lobe (mirror, smooth glass, a smooth plastic's coating) has no density.
            let specular = !nee_here || next.pdf <= 0.0;
            var pdf_rev = 0.0;
            if !specular && weighs_reverse(cm) {
                pdf_rev = bsdf_eval(s, m, albedo, next.wi, wo).pdf;
            }
            cm = mis_scatter(cm, next.pdf, pdf_rev, abs(dot(next.wi, s.ns)), specular, merges, depth == 0u, bidir_factors());
            // Past a delta lobe the path's vertex is specular: merging there is no strategy of
            // it, and a later vertex may merge in its place.
            last_merged = merges && !specular;
            merged += select(0u, 1u, last_merged);
        }
        if use_roulette {
            eta_scale *= refraction_eta2(m, s, d, next.wi);
        }
        medium = medium_after(medium, s, d, next.wi);
        d = next.wi;
        o = offset_origin(s.p, s.ng, d);
        // A null boundary of a medium is no scattering event: the depth, the MIS density and
        // its origin stay as they were.
        if USES_MEDIA && is_null(m) {
            crossings += 1u;
            if crossings > MAX_PATH_NULL_CROSSINGS {
                break;
            }
            continue;
        }
        pdf_prev = next.pdf;
        mis_o = o;
        if use_roulette && depth >= 3u && !roulette(&beta, eta_scale, rng) {
            break;
        }
        depth += 1u;
    }
    return path;
}
