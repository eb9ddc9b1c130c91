// Direct light by next-event estimation with multiple importance sampling: the one code path
// the path tracer (pt-nee) and SPPM's camera pass share. At a diffuse, glossy or rough
// dielectric vertex a light is sampled by power and joined by a shadow ray; area lights are
// weighted against BSDF sampling by the power heuristic (Veach 1997, sec. 9.2.4), delta
// lights taken whole, and emission that BSDF sampling hits is weighted by emission_weight.

#import types
#import sampling
#import scene
#import bsdf
#import lights
#import medium

// Power heuristic with beta = 2 (Veach 1997, eq. 9.13).
fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    return a / (a + pdf_b * pdf_b);
}

// Whether nothing blocks the segment from p0 to p1, both already offset off their surfaces
// (pbrt-v4 sec. 6.8.6, SpawnRayTo: the ray is aimed from the offset origin at the offset end,
// so a grazing segment cannot clip the light's own surface before its end).
fn unoccluded(p0: vec3f, p1: vec3f) -> bool {
    let to = p1 - p0;
    let dist = length(to);
    if !(dist > 0.0) {
        return true;
    }
    return !occluded(p0, to / dist, dist * (1.0 - 1e-4));
}

// Next-event estimate at surface s seen from wo, for a material where bsdf_samples_lights(m) with
// `albedo` (its texture looked up): one light chosen by power and a point on it, u from the
// path's stream.
// medium: the one the path arrived through. Returns f |cos| Li / pdf times the MIS weight,
// without the path throughput.
fn direct_light(s: Surface, wo: vec3f, m: Material, albedo: vec3f, medium: u32, u: vec3f) -> vec3f {
    let ls = sample_light(s.p, u);
    // Only the side the path arrived on receives light, but for a dielectric, which also
    // transmits it; a one-sided material only from in front of ns.
    if all(ls.li == vec3f(0.0)) || !bsdf_joins(m, s, wo, ls.wi) {
        return vec3f(0.0);
    }
    let b = bsdf_eval(s, m, albedo, wo, ls.wi);
    if all(b.f == vec3f(0.0)) {
        return vec3f(0.0);
    }
    // With media, through the medium on the light's side (medium_after) and null boundaries.
    var tr = vec3f(1.0);
    if USES_MEDIA {
        tr = shadow_transmittance(offset_origin(s.p, s.ng, ls.wi), ls.p_light, medium_after(medium, s, -wo, ls.wi));
        if all(tr == vec3f(0.0)) {
            return vec3f(0.0);
        }
    } else if !unoccluded(offset_origin(s.p, s.ng, ls.wi), ls.p_light) {
        return vec3f(0.0);
    }
    let weight = select(power_heuristic(ls.pdf, b.pdf), 1.0, ls.pdf == 0.0);
    return b.f * abs(dot(ls.wi, s.ns)) * ls.li * weight * tr;
}

// MIS weight of emission that a ray from o along d hits (hit, at surface s), after a BSDF
// sample of solid-angle density pdf_prev. pdf_prev is 0 where next-event estimation could
// not have found the light (the camera, specular scattering): the emission then counts whole.
fn emission_weight(pdf_prev: f32, o: vec3f, hit: Hit, s: Surface, d: vec3f) -> f32 {
    if pdf_prev <= 0.0 {
        return 1.0;
    }
    // With media, o is the last vertex that was not a null surface: the light is as far as
    // that, whatever null boundaries the path crossed.
    let t = select(hit.t, length(s.p - o), USES_MEDIA);
    return power_heuristic(pdf_prev, light_pdf(o, hit.prim_ref, s.shape, t, abs(dot(d, s.ng))));
}

// Radiance of the environment that a ray escaping the scene along d brings, weighted as
// emission_weight weighs emission it hits: the light pdf is environment_eval's. Call only
// where USES_ENVIRONMENT.
fn escaped_light(d: vec3f, pdf_prev: f32) -> vec3f {
    let env = environment_eval(d);
    if pdf_prev <= 0.0 {
        return env.l;
    }
    return env.l * power_heuristic(pdf_prev, env.pdf);
}

// Next-event estimate at point p in medium `medium`, scattering light that travels on along
// d by the phase function of mean cosine g (shared/medium.wgsl): one light chosen by power and
// a point on it, weighted against phase sampling by the power heuristic, through the
// transmittance of the shadow ray. Returns p Tr Li / pdf times the MIS weight, without the
// path throughput (which holds sigma_s).
fn medium_direct_light(p: vec3f, d: vec3f, medium: u32, g: f32, u: vec3f) -> vec3f {
    let ls = sample_light(p, u);
    if all(ls.li == vec3f(0.0)) {
        return vec3f(0.0);
    }
    let tr = shadow_transmittance(p, ls.p_light, medium);
    let phase = phase_hg(dot(d, ls.wi), g);
    let weight = select(power_heuristic(ls.pdf, phase), 1.0, ls.pdf == 0.0);
    return phase * ls.li * tr * weight;
}

// Null boundaries a shadow ray crosses at most.
const MAX_NULL_CROSSINGS: u32 = 8u;

// The transmittance of the segment from p0 to p1 (both off their surfaces) for a shadow ray
// leaving p0 in `medium`: 0 where a surface blocks it, but for Mitsuba's null boundaries of
// media (is_null), which it crosses as a path would, changing medium (medium_after), up to
// MAX_NULL_CROSSINGS of them; times each medium's exp(-sigma_t length). Camera paths keep their
// MIS density and origin across null surfaces (path_trace.wgsl, camera_pass.wgsl), so that
// emission they hit behind one is weighted against this estimate. Call only where USES_MEDIA.
fn shadow_transmittance(p0: vec3f, p1: vec3f, medium: u32) -> vec3f {
    var o = p0;
    var m = medium;
    var tr = vec3f(1.0);
    for (var i = 0u; i <= MAX_NULL_CROSSINGS; i++) {
        let to = p1 - o;
        let dist = length(to);
        if !(dist > 0.0) {
            return tr;
        }
        let d = to / dist;
        let hit = trace_closest(o, d, dist * (1.0 - 1e-4));
        if hit.prim_ref == 0xffffffffu {
            return tr * medium_transmittance(m, dist);
        }
        let s = surface_at(hit, o, d);
        if !is_null(material_at(s)) {
            return vec3f(0.0);
        }
        tr *= medium_transmittance(m, hit.t);
        m = medium_after(m, s, d, d);
        o = offset_origin(s.p, s.ng, d);
    }
    return vec3f(0.0);
}
