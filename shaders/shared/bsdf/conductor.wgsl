// Conductors (MATERIAL_CONDUCTOR; Mitsuba 3's `conductor` and `roughconductor`, pbrt-v4's
// ConductorBxDF): one family, smooth when its roughness is 0.
//   Smooth: a delta reflection about ns, weight albedo F(cos_o).
//   Rough: microfacets (shared/bsdf/microfacet.wgsl), f = albedo F(wo.h) D G / (4 cos_o cos_i)
//   (Walter et al. 2007, eq. 20), sampled by visible normals (Heitz 2018).
// Parameters: `albedo` (Mitsuba's specular_reflectance, linear RGB in [0, 1]) or a texture
// in its place; `roughness`, the distribution's alpha (0: smooth), and `distribution` (GGX or
// Beckmann); the complex index of refraction `eta` + i `k` of the Fresnel term F (flag
// `fresnel`; without it F = 1); `one_sided`. Reflection only: a direction that a shading
// normal sends through the surface ends the path.

#import types
#import sampling
#import scene
#import bsdf/lobe
#import bsdf/fresnel
#import bsdf/microfacet

const MATERIAL_CONDUCTOR: u32 = 1u;

// The scene has smooth conductors; rough ones (src/scene/material/conductor.rs).
override USES_MIRROR: bool = true;
override USES_GLOSSY: bool = true;
// Some conductor has a Fresnel term (a complex index of refraction).
override USES_CONDUCTOR_FRESNEL: bool = true;

// Whether m is a rough conductor (compiled out unless the scene has one).
fn is_rough_conductor(m: Material) -> bool {
    return USES_GLOSSY && m.kind == MATERIAL_CONDUCTOR && (!USES_MIRROR || m.roughness > 0.0);
}

// Whether conductor m has a Fresnel term: a complex index of refraction other than Mitsuba's
// `none` (compiled out unless some material has one). Without one its reflectance is albedo,
// and no Fresnel term is computed.
fn has_conductor_fresnel(m: Material) -> bool {
    return USES_CONDUCTOR_FRESNEL && m.fresnel != 0u;
}

// The smooth lobe: the mirror direction of d about ns turned towards it, weight albedo times
// Mitsuba 3's Fresnel term at the angle of incidence to ns.
fn smooth_conductor_sample(m: Material, d: vec3f, ns: vec3f) -> BsdfSample {
    let n = select(-ns, ns, dot(d, ns) < 0.0);
    var next = bsdf_specular(reflect(d, n), m.albedo);
    if has_conductor_fresnel(m) {
        next.weight *= fresnel_conductor(-dot(d, n), m.eta, m.k);
    }
    return next;
}

// The rough lobe (reflectance albedo times its Fresnel term, both sides alike) from direction
// of travel d at shading normal ns. With visible normals sampled, the weight f |cos| / pdf is
// albedo F(wo.h) G1(wi) (Heitz 2018, sec. 2, with G = G1(wo) G1(wi)), times visible_g1_ratio
// for Beckmann.
fn rough_conductor_sample(m: Material, d: vec3f, ns: vec3f, u: vec2f) -> BsdfSample {
    let alpha = max(m.roughness, MIN_ALPHA);
    let beckmann = is_beckmann(m);
    let n = select(-ns, ns, dot(d, ns) < 0.0);
    let frame = basis(n);
    let wo = -d * frame;
    if wo.z <= 0.0 {
        return bsdf_absorbed(d);
    }
    let h = sample_visible_normal(wo, alpha, u, beckmann);
    let wi = reflect(-wo, h);
    if wi.z <= 0.0 {
        return bsdf_absorbed(d);
    }
    var weight = m.albedo * microfacet_g1(wi.z, alpha, beckmann);
    if beckmann {
        weight *= visible_g1_ratio(wo.z, alpha, beckmann);
    }
    if has_conductor_fresnel(m) {
        weight *= fresnel_conductor(dot(wo, h), m.eta, m.k);
    }
    return bsdf_specular(frame * wi, weight);
}

// The rough lobe's f and rough_conductor_sample's density, for wo and wi pointing away from the
// surface, h = normalize(wo + wi): f = albedo F(wo.h) D G / (4 cos_o cos_i) (Walter et al. 2007,
// eq. 20) and pdf = G1(wo) D / (4 cos_o) (the visible-normal density over the reflection
// Jacobian, with the exact G1: visible_g1).
fn rough_conductor_eval(m: Material, wo: vec3f, wi: vec3f, ns: vec3f) -> BsdfEval {
    let alpha = max(m.roughness, MIN_ALPHA);
    let beckmann = is_beckmann(m);
    let n = select(-ns, ns, dot(wo, ns) > 0.0);
    let cos_o = dot(wo, n);
    let cos_i = dot(wi, n);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let h = normalize(wo + wi);
    let d = microfacet_d(dot(h, n), alpha, beckmann);
    let g1_o = microfacet_g1(cos_o, alpha, beckmann);
    var f = m.albedo * (d * g1_o * microfacet_g1(cos_i, alpha, beckmann) / (4.0 * cos_o * cos_i));
    if has_conductor_fresnel(m) {
        f *= fresnel_conductor(dot(wo, h), m.eta, m.k);
    }
    var pdf_g1 = g1_o;
    if beckmann {
        pdf_g1 = visible_g1(cos_o, alpha, beckmann);
    }
    return BsdfEval(f, pdf_g1 * d / (4.0 * cos_o));
}

// Sample conductor m at s from direction of travel d, u in [0, 1)^3 (u.xy used).
fn conductor_sample(m: Material, albedo: vec3f, d: vec3f, s: Surface, u: vec3f, radiance: bool) -> BsdfSample {
    var next = bsdf_absorbed(d);
    if USES_MIRROR && m.roughness == 0.0 {
        next = smooth_conductor_sample(m, d, s.ns);
    }
    if is_rough_conductor(m) {
        next = rough_conductor_sample(m, d, s.ns, u.xy);
    }
    // A shading normal can send a reflection below the surface; such paths end rather than
    // leak. A one-sided conductor reflects nothing behind ns (its samplers reflect about ns
    // turned towards wo, so only roundoff gets there).
    let reflected = dot(next.wi, s.ng) * dot(d, s.ng) < 0.0;
    if !reflected || one_sided_culls(m, s, next.wi) {
        next.weight = vec3f(0.0);
    }
    return next;
}

// Rough conductor m's f and conductor_sample's density of wi given wo (the smooth lobe, a
// delta, is never evaluated).
fn conductor_eval(m: Material, albedo: vec3f, s: Surface, wo: vec3f, wi: vec3f) -> BsdfEval {
    return rough_conductor_eval(m, wo, wi, s.ns);
}
