// Mitsuba 3's plastic and roughplastic (MATERIAL_PLASTIC): a dielectric coating, smooth or of
// microfacets (roughness > 0), over a Lambertian base, with the light trapped between them
// summed. Two lobes (Mitsuba 3.9.1's src/bsdfs/plastic.cpp and roughplastic.cpp, read for the
// mathematics; src/scene/coating.rs computes what they precompute):
//   coating: the interface's reflection times specular_reflectance, a mirror when smooth,
//            else F D G1(wo) G1(wi) / (4 cos_o cos_i) (Walter et al. 2007, eq. 20);
//   base:    f_base = albedo / (1 - [albedo] Fdr) / (pi eta^2) t(cos_o) t(cos_i),
// t the coating's transmittance: 1 - F for a smooth coating, a rough one's tabulated T. Fdr is
// the coating's diffuse reflectance from inside; `nonlinear` puts the albedo in the trapped
// light's series, darkening and saturating the base. Both are symmetric in wo and wi, so
// photons scatter as camera paths do. pbrt-v4's coateddiffuse (src/scene/coating.rs) adds an
// absorbing layer under the coating, a(c) = exp(-thickness / cos_t) a crossing, and a walk
// that ends after n scatterings at the base:
//   f_base = albedo (1 - x^n) / (1 - x) / (pi eta^2) t(cos_o) a(cos_o) t(cos_i) a(cos_i),
// x = albedo Fdr' (Fdr attenuated by the layer, on the host).
//
// A lobe is sampled with Mitsuba's probability, q = (1 - t_o) w / ((1 - t_o) w + t_o (1 - w)),
// w = specular_sampling_weight, and weighted by its own f |cos| / (lobe probability * lobe
// density): the expectation over the choice is the whole BSDF's integral. SPPM relies on the
// split: its camera path passes the coating's lobe through and leaves a visible point for the
// base's (camera_pass.wgsl). For MIS the density of a direction is the mixture of both.
//
// Parameters: `albedo` (diffuse_reflectance, linear RGB in [0, 1]) or a texture in its place;
// `specular` (specular_reflectance); `ior` of the coating; `roughness` (alpha, 0 smooth) and
// `distribution`; `nonlinear`; `coat_thickness` and `coat_scatterings` (0 for Mitsuba's);
// precomputed on the host: `coat_weight` (w), `coat_fdr` (Fdr, or Fdr') and a rough coating's
// table `coat_table` of T; `one_sided`.

#import types
#import sampling
#import scene
#import bsdf/lobe
#import bsdf/fresnel
#import bsdf/microfacet

const MATERIAL_PLASTIC: u32 = 4u;

// Some plastic has a smooth coating; some has a rough one (src/scene/material/plastic.rs).
override USES_PLASTIC: bool = true;
override USES_ROUGH_PLASTIC: bool = true;

// Whether m is a plastic (compiled out unless the scene has one).
fn is_plastic(m: Material) -> bool {
    return (USES_PLASTIC || USES_ROUGH_PLASTIC) && m.kind == MATERIAL_PLASTIC;
}

// Whether plastic m's coating is rough.
fn rough_coat(m: Material) -> bool {
    return USES_ROUGH_PLASTIC && (!USES_PLASTIC || m.roughness > 0.0);
}

// t(c): what the coating lets through at cos c to its normal. Smooth: 1 - F (plastic.cpp).
// Rough: the table T at cos = k / 63, interpolated linearly as roughplastic.cpp's
// lerp_gather does.
fn coat_transmittance(m: Material, c: f32) -> f32 {
    if rough_coat(m) {
        let x = clamp(c, 0.0, 1.0) * f32(COAT_TABLE_SIZE - 1u);
        let i = min(u32(x), COAT_TABLE_SIZE - 2u);
        let v0 = attributes[m.coat_table + i / 4u][i % 4u];
        let v1 = attributes[m.coat_table + (i + 1u) / 4u][(i + 1u) % 4u];
        return mix(v0, v1, x - f32(i));
    }
    return 1.0 - fresnel_dielectric(c, m.ior);
}

// a(c): what crosses the layer under the coating once, having met the coating at cos c
// outside: exp(-thickness / cos_t), cos_t the refracted cosine (pbrt-v4's Tr); 1 without a layer.
fn coat_layer(m: Material, c: f32) -> f32 {
    if m.coat_thickness <= 0.0 {
        return 1.0;
    }
    let cos_t = sqrt(max(1.0 - (1.0 - c * c) / (m.ior * m.ior), 0.0));
    return exp(-m.coat_thickness / max(cos_t, 1e-6));
}

// t(c) a(c): what reaches the base through the coating and the layer under it, at cos c outside.
fn coat_through(m: Material, c: f32) -> f32 {
    return coat_transmittance(m, c) * coat_layer(m, c);
}

// f_base / (t(cos_o) a(cos_o) t(cos_i) a(cos_i)): albedo / (1 - [albedo] Fdr) / (pi eta^2),
// the series cut at n terms, (1 - x^n), where coat_scatterings sets n.
fn plastic_base(m: Material, albedo: vec3f) -> vec3f {
    let trapped = select(vec3f(m.coat_fdr), albedo * m.coat_fdr, m.nonlinear != 0u);
    var base = albedo;
    if m.coat_scatterings > 0u {
        base *= vec3f(1.0) - pow(trapped, vec3f(f32(m.coat_scatterings)));
    }
    return base / (vec3f(1.0) - trapped) * (INV_PI / (m.ior * m.ior));
}

// Probability of sampling the coating's lobe, seen from wo with t_o = t(cos_o): Mitsuba's
// prob_specular.
fn coat_probability(m: Material, t_o: f32) -> f32 {
    let s = (1.0 - t_o) * m.coat_weight;
    let sum = s + t_o * (1.0 - m.coat_weight);
    return select(0.0, s / sum, sum > 0.0);
}

// Both lobes of plastic m for wo and wi pointing away from the surface, n = ns turned to wo:
// each lobe's f, and its density times its probability (their sum is the sampler's density).
// A smooth coating's mirror is a delta: 0 here.
struct PlasticLobes {
    coat: BsdfEval,
    base: BsdfEval,
}

fn plastic_lobes(m: Material, albedo: vec3f, wo: vec3f, wi: vec3f, n: vec3f) -> PlasticLobes {
    var out = PlasticLobes(BsdfEval(vec3f(0.0), 0.0), BsdfEval(vec3f(0.0), 0.0));
    let cos_o = dot(wo, n);
    let cos_i = dot(wi, n);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return out;
    }
    let t_o = coat_transmittance(m, cos_o);
    let q = coat_probability(m, t_o);
    out.base = BsdfEval(plastic_base(m, albedo) * (t_o * coat_layer(m, cos_o) * coat_through(m, cos_i)), (1.0 - q) * cos_i * INV_PI);
    if rough_coat(m) {
        // Walter et al. 2007, eq. 20, and the visible-normal density over the reflection's
        // Jacobian, G1(wo) D / (4 cos_o), its G1 the exact one (as rough_conductor_eval).
        let alpha = max(m.roughness, MIN_ALPHA);
        let beckmann = is_beckmann(m);
        let h = normalize(wo + wi);
        let d = microfacet_d(dot(h, n), alpha, beckmann);
        let g1_o = microfacet_g1(cos_o, alpha, beckmann);
        let g = g1_o * microfacet_g1(cos_i, alpha, beckmann);
        let f = fresnel_dielectric(dot(wo, h), m.ior) * d * g / (4.0 * cos_o * cos_i);
        var pdf_g1 = g1_o;
        if beckmann {
            pdf_g1 = visible_g1(cos_o, alpha, beckmann);
        }
        out.coat = BsdfEval(m.specular * f, q * pdf_g1 * d / (4.0 * cos_o));
    }
    return out;
}

// Plastic m's f (both lobes) and the sampler's density of wi, for next-event estimation.
fn plastic_eval(m: Material, albedo: vec3f, s: Surface, wo: vec3f, wi: vec3f) -> BsdfEval {
    let n = select(-s.ns, s.ns, dot(wo, s.ns) > 0.0);
    let l = plastic_lobes(m, albedo, wo, wi, n);
    return BsdfEval(l.coat.f + l.base.f, l.coat.pdf + l.base.pdf);
}

// Sample plastic m at s from direction of travel d (camera paths and photons alike): a lobe
// with probability q (the coating) or 1 - q (the base), then its direction. Coating: the mirror
// direction, weight specular F(cos_o) / q (plastic.cpp); rough, a visible normal h, weight
// specular F(wo.h) G1(wi) / q (times visible_g1_ratio for Beckmann, as rough_conductor_sample). Base: a
// cosine-distributed direction, weight pi f_base / (1 - q); there SPPM's visible point weighs
// f_base / (t a)(cos_i) over the base's probability, albedo / (1 - [albedo] Fdr) / (pi eta^2)
// (t a)(cos_o) / (1 - q): a photon arriving at cos_i brings (t a)(cos_i) (plastic_deposit), so that
// the point gathers f_base times the flux. The density is the mixture's (0 after a smooth
// coating's mirror).
fn plastic_sample(m: Material, albedo: vec3f, d: vec3f, s: Surface, u: vec3f, radiance: bool) -> BsdfSample {
    let wo = -d;
    let n = select(-s.ns, s.ns, dot(wo, s.ns) > 0.0);
    let cos_o = dot(wo, n);
    let t_o = coat_transmittance(m, cos_o);
    let q = coat_probability(m, t_o);
    let base = plastic_base(m, albedo);
    var out = BsdfSample(d, vec3f(0.0), 0.0, u.z >= q, base * (t_o * coat_layer(m, cos_o) / max(1.0 - q, 1e-30)));
    if cos_o <= 0.0 {
        return out;
    }
    if out.diffuse {
        out.wi = sample_cosine_hemisphere(n, u.xy);
        let cos_i = dot(out.wi, n);
        out.weight = PI * out.vp_weight * coat_through(m, cos_i);
        out.pdf = (1.0 - q) * max(cos_i, 0.0) * INV_PI;
    } else if rough_coat(m) {
        let alpha = max(m.roughness, MIN_ALPHA);
        let beckmann = is_beckmann(m);
        let frame = basis(n);
        let wo_l = wo * frame;
        let h = sample_visible_normal(wo_l, alpha, u.xy, beckmann);
        let wi_l = reflect(-wo_l, h);
        if wi_l.z > 0.0 {
            var g = microfacet_g1(wi_l.z, alpha, beckmann);
            if beckmann {
                g *= visible_g1_ratio(wo_l.z, alpha, beckmann);
            }
            out.wi = frame * wi_l;
            out.weight = m.specular * (fresnel_dielectric(dot(wo_l, h), m.ior) * g / q);
        }
    } else {
        out.wi = reflect(d, n);
        out.weight = m.specular * (fresnel_dielectric(cos_o, m.ior) / q);
    }
    if rough_coat(m) {
        let l = plastic_lobes(m, albedo, wo, out.wi, n);
        out.pdf = l.coat.pdf + l.base.pdf;
    }
    // A shading normal can send the direction through the surface, or behind a one-sided
    // one's ns: the path ends there.
    if dot(out.wi, s.ng) * dot(wo, s.ng) <= 0.0 || one_sided_culls(m, s, out.wi) {
        out.weight = vec3f(0.0);
    }
    return out;
}

// What a photon arriving along d at plastic m brings to the visible points around it:
// (t a)(cos_i) of its flux, the part of f_base that depends on its direction (see
// plastic_sample).
fn plastic_deposit(m: Material, s: Surface, d: vec3f) -> f32 {
    return coat_through(m, abs(dot(d, s.ns)));
}
