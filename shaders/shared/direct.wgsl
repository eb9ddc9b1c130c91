// Direct light by next-event estimation with multiple importance sampling: the one code path
// the path tracer (pt-nee) and SPPM's camera pass share. At a diffuse, glossy or rough
// dielectric vertex a light is sampled by power and joined by a shadow ray; area lights are
// weighted against BSDF sampling by the power heuristic (Veach 1997, sec. 9.2.4), delta
// lights taken whole, and emission that BSDF sampling hits is weighted by emission_weight.

#import types
#import sampling
#import scene
#import bsdf
#import coating
#import lights

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

// Whether next-event estimation is done at a vertex of material m: every material whose
// BSDF can be evaluated, that is all but the mirror and smooth glass, thin or not (a smooth
// plastic's base is evaluated, its mirror not).
fn samples_lights(m: Material) -> bool {
    return m.kind == MATERIAL_DIFFUSE || (USES_GLOSSY && m.kind == MATERIAL_GLOSSY)
        || (USES_ROUGH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC && m.roughness > 0.0) || is_plastic(m);
}

// BSDF value (radiance) and sampling density at a vertex where samples_lights(m): diffuse
// (albedo / pi, cosine density about ns), the glossy conductor or the rough dielectric.
fn vertex_bsdf(s: Surface, m: Material, albedo: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    if USES_GLOSSY && m.kind == MATERIAL_GLOSSY {
        return glossy_eval(m, wo, wi, s.ns);
    }
    if USES_ROUGH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC {
        var b = rough_dielectric_eval(m.ior, m.roughness, is_beckmann(m), wo, wi, s.ng, s.ns, true);
        // The lobe's factor, as sample_nondiffuse applies it.
        b.f *= select(m.transmittance, m.specular, dot(wi, s.ng) * dot(wo, s.ng) > 0.0);
        return b;
    }
    if is_plastic(m) {
        return plastic_eval(m, albedo, wo, wi, s.ns);
    }
    return BsdfEval(albedo * INV_PI, abs(dot(wi, s.ns)) * INV_PI);
}

// One scattering event of a camera path (the path tracer's or SPPM's) at surface s of
// material m, met along d: the next direction, its weight f |cos| / pdf (0 ends the path),
// the density for MIS at the emission it meets (0 where no light is sampled, nee false, and
// after a delta lobe), and whether the lobe was diffuse (a diffuse surface or a plastic's
// base), where SPPM leaves a visible point of weight vp_weight (f without the photon's part).
struct VertexSample {
    wi: vec3f,
    weight: vec3f,
    pdf: f32,
    diffuse: bool,
    vp_weight: vec3f,
}

// Sample the BSDF at a camera-path vertex: cosine-weighted for diffuse (f cos / pdf = albedo),
// one lobe of a plastic (shared/coating.wgsl), or sample_nondiffuse. u from the path's stream.
fn sample_vertex(s: Surface, m: Material, albedo: vec3f, d: vec3f, nee: bool, u: vec3f) -> VertexSample {
    if m.kind == MATERIAL_DIFFUSE {
        let n_in = select(-s.ns, s.ns, dot(d, s.ng) < 0.0);
        let wi = sample_cosine_hemisphere(n_in, u.xy);
        // A shading normal can send wi through the surface, or behind a one-sided ns.
        let ok = dot(wi, s.ng) * dot(d, s.ng) < 0.0 && !one_sided_culls(m, s, wi);
        let pdf = select(0.0, abs(dot(wi, s.ns)) * INV_PI, nee);
        return VertexSample(wi, select(vec3f(0.0), albedo, ok), pdf, true, albedo * INV_PI);
    }
    if is_plastic(m) {
        let c = sample_plastic(m, albedo, d, s, u);
        return VertexSample(c.wi, c.weight, select(0.0, c.pdf, nee), c.base, c.vp_weight);
    }
    let next = sample_nondiffuse(m, d, s, u, true);
    var pdf = 0.0;
    if nee {
        pdf = vertex_bsdf(s, m, albedo, -d, next.wi).pdf;
    }
    return VertexSample(next.wi, next.weight, pdf, false, vec3f(0.0));
}

// Next-event estimate at surface s seen from wo, for a material where samples_lights(m) with
// `albedo` (its texture looked up): one light chosen by power and a point on it, u from the
// path's stream.
// Returns f |cos| Li / pdf times the MIS weight, without the path throughput.
fn direct_light(s: Surface, wo: vec3f, m: Material, albedo: vec3f, u: vec3f) -> vec3f {
    let ls = sample_light(s.p, u);
    // Only the side the path arrived on receives light, but for a dielectric, which also
    // transmits it; a one-sided material only from in front of ns.
    let same_side = dot(ls.wi, s.ng) * dot(wo, s.ng) > 0.0;
    if all(ls.li == vec3f(0.0)) || (!same_side && m.kind != MATERIAL_DIELECTRIC) || one_sided_culls(m, s, ls.wi) {
        return vec3f(0.0);
    }
    let b = vertex_bsdf(s, m, albedo, wo, ls.wi);
    if all(b.f == vec3f(0.0)) || !unoccluded(offset_origin(s.p, s.ng, ls.wi), ls.p_light) {
        return vec3f(0.0);
    }
    let weight = select(power_heuristic(ls.pdf, b.pdf), 1.0, ls.pdf == 0.0);
    return b.f * abs(dot(ls.wi, s.ns)) * ls.li * weight;
}

// MIS weight of emission that a ray from o along d hits (hit, at surface s), after a BSDF
// sample of solid-angle density pdf_prev. pdf_prev is 0 where next-event estimation could
// not have found the light (the camera, specular scattering): the emission then counts whole.
fn emission_weight(pdf_prev: f32, o: vec3f, hit: Hit, s: Surface, d: vec3f) -> f32 {
    if pdf_prev <= 0.0 {
        return 1.0;
    }
    return power_heuristic(pdf_prev, light_pdf(o, hit.prim_ref, s.shape, hit.t, -dot(d, s.ng)));
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
