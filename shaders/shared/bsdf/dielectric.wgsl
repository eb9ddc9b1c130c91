// Dielectric interfaces (MATERIAL_DIELECTRIC; Mitsuba 3's `dielectric` and
// `roughdielectric`, pbrt-v4's DielectricBxDF): glass, water.
//   Smooth (roughness 0): reflection or refraction about ns, chosen with the Fresnel
//   probability (pbrt-v4 sec. 9.5).
//   Rough: microfacets (shared/bsdf/microfacet.wgsl), Walter et al. 2007, eq. 20 and 21,
//   a visible normal sampled (Heitz 2018), then reflection or refraction through it.
// Radiance crossing the interface is scaled by 1 / eta^2; photons carry flux and are not
// (pbrt-v4 sec. 9.5.2): `radiance` tells which a path is. The side and the law both follow
// ns, as in pbrt-v4 (DielectricBxDF works in the shading frame, sec. 9.5) and Mitsuba 3: where
// ns and ng disagree about a direction's side (a ray grazing a smooth-shaded mesh) the path
// goes on, leaving on whichever side of ng its new direction points to.
// Parameters: `ior` of the inside relative to the outside; `roughness` (alpha, 0 smooth) and
// `distribution`; `specular` and `transmittance` (Mitsuba's specular_reflectance and
// specular_transmittance, 1 when physical) scale each lobe, which is still chosen with the
// Fresnel probability. Two-sided by nature.

#import types
#import sampling
#import scene
#import bsdf/lobe
#import bsdf/fresnel
#import bsdf/microfacet

const MATERIAL_DIELECTRIC: u32 = 2u;

// The scene has smooth dielectrics; rough ones (src/scene/material/dielectric.rs).
override USES_SMOOTH_DIELECTRIC: bool = true;
override USES_ROUGH_DIELECTRIC: bool = true;

// The smooth lobes: sample a smooth dielectric from direction of travel d at shading normal
// ns. Reflection or refraction is chosen with the Fresnel probability, so the weight is 1,
// times 1 / eta^2 for refracted radiance (pbrt-v4 sec. 9.5.2); photons carry flux and are
// not scaled. A smooth-shaded mesh refracts smoothly, not by its facets.
fn smooth_dielectric_sample(d: vec3f, ns: vec3f, ior: f32, u: f32, radiance: bool) -> BsdfSample {
    let entering = dot(d, ns) < 0.0;
    let n = select(-ns, ns, entering);
    let eta = select(1.0 / ior, ior, entering);
    let cos_i = -dot(d, n);
    if cos_i <= 0.0 {
        return bsdf_absorbed(d);
    }
    let f = fresnel_dielectric(cos_i, eta);
    if u < f {
        return bsdf_specular(reflect(d, n), vec3f(1.0));
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    let cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    let wt = normalize(d / eta + (cos_i / eta - cos_t) * n);
    let scale = select(1.0, 1.0 / (eta * eta), radiance);
    return bsdf_specular(wt, vec3f(scale));
}

// The rough lobes: sample a rough dielectric (Walter et al. 2007) from direction of travel d. A visible normal
// h is drawn, then reflection or refraction through h with the Fresnel probability, so the
// weight is G1(wi) (times visible_g1_ratio for Beckmann), times 1 / eta^2 for refracted
// radiance as in the smooth case.
fn rough_dielectric_sample(d: vec3f, ns: vec3f, ior: f32, alpha_in: f32, beckmann: bool, u: vec3f, radiance: bool) -> BsdfSample {
    let alpha = max(alpha_in, MIN_ALPHA);
    let entering = dot(d, ns) < 0.0;
    let n = select(-ns, ns, entering);
    let eta = select(1.0 / ior, ior, entering);
    let frame = basis(n);
    let wo = -d * frame;
    if wo.z <= 0.0 {
        return bsdf_absorbed(d);
    }
    let h = sample_visible_normal(wo, alpha, u.xy, beckmann);
    let ratio = visible_g1_ratio(wo.z, alpha, beckmann);
    let cos_o = dot(wo, h);
    let f = fresnel_dielectric(cos_o, eta);
    if u.z < f {
        let wi = reflect(-wo, h);
        if wi.z <= 0.0 {
            return bsdf_absorbed(d);
        }
        var g = microfacet_g1(wi.z, alpha, beckmann);
        if beckmann {
            g *= ratio;
        }
        return bsdf_specular(frame * wi, vec3f(g));
    }
    let sin2_t = (1.0 - cos_o * cos_o) / (eta * eta);
    let cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    let wt = normalize(-wo / eta + (cos_o / eta - cos_t) * h);
    if wt.z >= 0.0 {
        return bsdf_absorbed(d);
    }
    let scale = select(1.0, 1.0 / (eta * eta), radiance);
    var g = microfacet_g1(-wt.z, alpha, beckmann);
    if beckmann {
        g *= ratio;
    }
    return bsdf_specular(frame * wt, vec3f(g * scale));
}

// Sample dielectric m at s from direction of travel d, u in [0, 1)^3.
fn dielectric_sample(m: Material, albedo: vec3f, d: vec3f, s: Surface, u: vec3f, radiance: bool) -> BsdfSample {
    var next = bsdf_absorbed(d);
    if USES_ROUGH_DIELECTRIC && m.roughness > 0.0 {
        next = rough_dielectric_sample(d, s.ns, m.ior, m.roughness, is_beckmann(m), u, radiance);
    }
    if USES_SMOOTH_DIELECTRIC && m.roughness == 0.0 {
        next = smooth_dielectric_sample(d, s.ns, m.ior, u.z, radiance);
    }
    // Each lobe's factor (1 and 1 unless a scene asks otherwise), sampled as before.
    next.weight *= select(m.transmittance, m.specular, dot(next.wi, s.ns) * dot(d, s.ns) < 0.0);
    return next;
}

// Rough dielectric m's f (radiance) and dielectric_sample's density, with each lobe's factor
// as dielectric_sample applies it.
fn dielectric_eval(m: Material, albedo: vec3f, s: Surface, wo: vec3f, wi: vec3f) -> BsdfEval {
    var b = rough_dielectric_eval(m.ior, m.roughness, is_beckmann(m), wo, wi, s.ns, true);
    b.f *= select(m.transmittance, m.specular, dot(wi, s.ns) * dot(wo, s.ns) > 0.0);
    return b;
}

// eta^2 where a radiance sample through dielectric m at s, from direction of travel d to wi,
// refracted (its weight holds 1 / eta^2, eta the transmitted side's index over the incident
// side's), else 1: what pbrt-v4's path tracer multiplies into etaScale, so that Russian
// roulette judges the throughput without the factor a path leaving the glass undoes.
fn refraction_eta2(m: Material, s: Surface, d: vec3f, wi: vec3f) -> f32 {
    if m.kind != MATERIAL_DIELECTRIC || dot(wi, s.ns) * dot(d, s.ns) <= 0.0 {
        return 1.0;
    }
    let eta = select(1.0 / m.ior, m.ior, dot(d, s.ns) < 0.0);
    return eta * eta;
}

// The rough dielectric's f and rough_dielectric_sample's density, for wo and wi pointing away
// from the surface. As in the sampler, ns tells which side wo is on, the microfacets are about
// ns turned to that side, and eta is the index of the side wo is not on over the one it is.
// Reflection (wi.n > 0), h = normalize(wo + wi) (Walter et al. 2007, eq. 13):
//   f = F D G1(wo) G1(wi) / (4 cos_o cos_i)  (eq. 20),
//   pdf = F D_wo(h) / (4 wo.h)  (the Jacobian of eq. 14),
// with D_wo(h) = G1(wo) max(0, wo.h) D(h) / cos_o the visible-normal density (Heitz 2018; its
// G1 the exact one, visible_g1).
// Refraction (wi.n < 0), h = normalize(wo + eta wi) turned to n (eq. 16):
//   f = (1 - F) D G1(wo) G1(wi) |wo.h| |wi.h| / (cos_o |cos_i| (wo.h + eta wi.h)^2)  (eq. 21),
//   pdf = (1 - F) D_wo(h) eta^2 |wi.h| / (wo.h + eta wi.h)^2  (the Jacobian of eq. 17).
// f is that of radiance, wo towards the camera; photons carry flux and see eta^2 f (pbrt-v4
// sec. 9.5.2), the two 1 / eta^2 apart as in the sampler's weights.
fn rough_dielectric_eval(ior: f32, alpha_in: f32, beckmann: bool, wo: vec3f, wi: vec3f, ns: vec3f, radiance: bool) -> BsdfEval {
    let alpha = max(alpha_in, MIN_ALPHA);
    let entering = dot(wo, ns) > 0.0;
    let n = select(-ns, ns, entering);
    let eta = select(1.0 / ior, ior, entering);
    let cos_o = dot(wo, n);
    let cos_i = dot(wi, n);
    if cos_o <= 0.0 || cos_i == 0.0 {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let g1_o = microfacet_g1(cos_o, alpha, beckmann);
    let g1_i = microfacet_g1(abs(cos_i), alpha, beckmann);
    var visible_g1_o = g1_o;
    if beckmann {
        visible_g1_o = visible_g1(cos_o, alpha, beckmann);
    }
    if cos_i > 0.0 {
        let h = normalize(wo + wi);
        let wo_h = dot(wo, h);
        let fr = fresnel_dielectric(wo_h, eta);
        let d = microfacet_d(dot(h, n), alpha, beckmann);
        let f = fr * d * g1_o * g1_i / (4.0 * cos_o * cos_i);
        let d_wo = visible_g1_o * wo_h * d / cos_o;
        return BsdfEval(vec3f(f), fr * d_wo / (4.0 * wo_h));
    }
    let ht = normalize(wo + eta * wi);
    let h = select(ht, -ht, dot(ht, n) < 0.0);
    let wo_h = dot(wo, h);
    let wi_h = dot(wi, h);
    // Microfacets seen from behind by either direction refract neither into the other.
    if wo_h <= 0.0 || wi_h >= 0.0 || dot(h, n) <= 0.0 {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let ft = 1.0 - fresnel_dielectric(wo_h, eta);
    let d = microfacet_d(dot(h, n), alpha, beckmann);
    let denom = wo_h + eta * wi_h;
    let f = ft * d * g1_o * g1_i * wo_h * abs(wi_h) / (cos_o * abs(cos_i) * denom * denom);
    let d_wo = visible_g1_o * wo_h * d / cos_o;
    let pdf = ft * d_wo * eta * eta * abs(wi_h) / (denom * denom);
    return BsdfEval(vec3f(select(f * eta * eta, f, radiance)), pdf);
}
