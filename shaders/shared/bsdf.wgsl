// Scattering at specular surfaces, shared by camera paths and photon paths.

// The non-diffuse materials the scene has (src/gpu/features.rs); see scene.wgsl.
override USES_MIRROR: bool = true;
override USES_GLOSSY: bool = true;
override USES_SMOOTH_DIELECTRIC: bool = true;
override USES_ROUGH_DIELECTRIC: bool = true;
// Some non-dielectric material is one-sided.
override USES_ONE_SIDED: bool = true;

// Whether material m at s scatters nothing to or from direction w (pointing away from the
// surface): Mitsuba 3's BSDFs return zero for cos_theta <= 0 in the shading frame unless
// wrapped in `twosided`. Dielectrics are two-sided by nature and ignore the flag.
fn one_sided_culls(m: Material, s: Surface, w: vec3f) -> bool {
    return USES_ONE_SIDED && m.one_sided != 0u && m.kind != MATERIAL_DIELECTRIC && dot(w, s.ns) <= 0.0;
}

// Whether a ray along d meets m at s from behind a one-sided surface (wo = -d below ns): the
// BSDF is zero there, so the camera path or photon ends, with no visible point, deposit or
// next-event estimate.
fn seen_from_behind(m: Material, s: Surface, d: vec3f) -> bool {
    return one_sided_culls(m, s, -d);
}

// Fresnel reflectance of a dielectric for unpolarized light (pbrt-v4 eq. 9.6); eta is the
// ratio of the transmitted side's index to the incident side's.
fn fresnel_dielectric(cos_i_in: f32, eta: f32) -> f32 {
    let cos_i = clamp(cos_i_in, 0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (r_parl * r_parl + r_perp * r_perp);
}

struct SpecularSample {
    wi: vec3f,
    // Throughput factor f * |cos| / pdf.
    weight: vec3f,
}

// Sample a smooth dielectric from direction of travel d at normal ng. Reflection or
// refraction is chosen with the Fresnel probability, so the weight is 1, times 1 / eta^2 for
// refracted radiance (pbrt-v4 sec. 9.5.2); photons carry flux and are not scaled.
fn sample_dielectric(d: vec3f, ng: vec3f, ior: f32, u: f32, radiance: bool) -> SpecularSample {
    let entering = dot(d, ng) < 0.0;
    let n = select(-ng, ng, entering);
    let eta = select(1.0 / ior, ior, entering);
    let cos_i = -dot(d, n);
    let f = fresnel_dielectric(cos_i, eta);
    if u < f {
        return SpecularSample(reflect(d, n), vec3f(1.0));
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    let cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    let wt = normalize(d / eta + (cos_i / eta - cos_t) * n);
    let scale = select(1.0, 1.0 / (eta * eta), radiance);
    return SpecularSample(wt, vec3f(scale));
}

// GGX (Trowbridge-Reitz) microfacet distribution with Smith masking, isotropic alpha
// (Walter et al. 2007, eq. 33 and 34). Directions are in a frame whose z is the normal.

fn ggx_d(cos_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let k = cos_h * cos_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * k * k);
}

// Smith's masking G1 of a direction at |cos theta| = c (Walter et al. 2007, eq. 34).
fn ggx_g1(c: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

// A microfacet normal from the distribution of normals visible from wo (wo.z > 0), Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals", listing 1. Its density is
// G1(wo) max(0, wo.h) D(h) / wo.z.
fn sample_ggx_visible_normal(wo: vec3f, alpha: f32, u: vec2f) -> vec3f {
    let vh = normalize(vec3f(alpha * wo.x, alpha * wo.y, wo.z));
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = select(vec3f(1.0, 0.0, 0.0), vec3f(-vh.y, vh.x, 0.0) / sqrt(len2), len2 > 0.0);
    let t2 = cross(vh, t1);
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3f(alpha * nh.x, alpha * nh.y, max(1e-6, nh.z)));
}

// Smallest GGX alpha the samplers use: below it the distribution's peak overflows f32.
const MIN_ALPHA: f32 = 1e-4;

// Sample the glossy conductor (GGX, Fresnel 1, reflectance `albedo`, both sides alike) from
// direction of travel d at shading normal ns. With visible normals sampled, the weight
// f |cos| / pdf is albedo * G1(wi) (Heitz 2018, sec. 2, with G = G1(wo) G1(wi)).
fn sample_glossy(albedo: vec3f, alpha_in: f32, d: vec3f, ns: vec3f, u: vec2f) -> SpecularSample {
    let alpha = max(alpha_in, MIN_ALPHA);
    let n = select(-ns, ns, dot(d, ns) < 0.0);
    let frame = basis(n);
    let wo = -d * frame;
    if wo.z <= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
    let h = sample_ggx_visible_normal(wo, alpha, u);
    let wi = reflect(-wo, h);
    if wi.z <= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
    return SpecularSample(frame * wi, albedo * ggx_g1(wi.z, alpha));
}

// Sample a rough dielectric (Walter et al. 2007) from direction of travel d. A visible normal
// h is drawn, then reflection or refraction through h with the Fresnel probability, so the
// weight is G1(wi), times 1 / eta^2 for refracted radiance as in the smooth case.
fn sample_rough_dielectric(d: vec3f, ng: vec3f, ns: vec3f, ior: f32, alpha_in: f32, u: vec3f, radiance: bool) -> SpecularSample {
    let alpha = max(alpha_in, MIN_ALPHA);
    let entering = dot(d, ng) < 0.0;
    let n = select(-ns, ns, entering);
    let eta = select(1.0 / ior, ior, entering);
    let frame = basis(n);
    let wo = -d * frame;
    if wo.z <= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
    let h = sample_ggx_visible_normal(wo, alpha, u.xy);
    let cos_o = dot(wo, h);
    let f = fresnel_dielectric(cos_o, eta);
    if u.z < f {
        let wi = reflect(-wo, h);
        if wi.z <= 0.0 {
            return SpecularSample(d, vec3f(0.0));
        }
        return SpecularSample(frame * wi, vec3f(ggx_g1(wi.z, alpha)));
    }
    let sin2_t = (1.0 - cos_o * cos_o) / (eta * eta);
    let cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    let wt = normalize(-wo / eta + (cos_o / eta - cos_t) * h);
    if wt.z >= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
    let scale = select(1.0, 1.0 / (eta * eta), radiance);
    return SpecularSample(frame * wt, vec3f(ggx_g1(-wt.z, alpha) * scale));
}

// Scatter at a non-diffuse surface: mirror, glossy conductor, smooth or rough dielectric.
// A zero weight ends the path. `radiance` is true for camera paths, false for photons.
// Only the materials the scene has are compiled in (USES_*, set by the host).
fn sample_nondiffuse(m: Material, d: vec3f, s: Surface, u: vec3f, radiance: bool) -> SpecularSample {
    var next = SpecularSample(d, vec3f(0.0));
    if USES_MIRROR && m.kind == MATERIAL_MIRROR {
        let n = select(-s.ns, s.ns, dot(d, s.ns) < 0.0);
        next = SpecularSample(reflect(d, n), m.albedo);
    }
    if USES_GLOSSY && m.kind == MATERIAL_GLOSSY {
        next = sample_glossy(m.albedo, m.roughness, d, s.ns, u.xy);
    }
    if USES_ROUGH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC && m.roughness > 0.0 {
        next = sample_rough_dielectric(d, s.ng, s.ns, m.ior, m.roughness, u, radiance);
    }
    if USES_SMOOTH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC && m.roughness == 0.0 {
        next = sample_dielectric(d, s.ng, m.ior, u.z, radiance);
    }
    // A shading normal can send a reflection below the surface or a refraction back out of
    // it; such paths end rather than leak.
    let reflected = dot(next.wi, s.ng) * dot(d, s.ng) < 0.0;
    let wants_reflection = m.kind != MATERIAL_DIELECTRIC;
    // A one-sided conductor reflects nothing behind ns (its samplers reflect about ns turned
    // towards wo, so only roundoff gets there).
    if wants_reflection && (!reflected || one_sided_culls(m, s, next.wi)) {
        next.weight = vec3f(0.0);
    }
    return next;
}

struct BsdfEval {
    // f, without the cosine.
    f: vec3f,
    // Solid-angle density with which the sampler picks wi given wo.
    pdf: f32,
}

// The glossy conductor's f and sample_glossy's density, for wo and wi pointing away from the
// surface: f = albedo D G / (4 cos_o cos_i) (Walter et al. 2007, eq. 20 with F = 1) and
// pdf = G1(wo) D / (4 cos_o) (the visible-normal density over the reflection Jacobian).
fn glossy_eval(albedo: vec3f, alpha_in: f32, wo: vec3f, wi: vec3f, ns: vec3f) -> BsdfEval {
    let alpha = max(alpha_in, MIN_ALPHA);
    let n = select(-ns, ns, dot(wo, ns) > 0.0);
    let cos_o = dot(wo, n);
    let cos_i = dot(wi, n);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let h = normalize(wo + wi);
    let d = ggx_d(dot(h, n), alpha);
    let g1_o = ggx_g1(cos_o, alpha);
    let f = albedo * (d * g1_o * ggx_g1(cos_i, alpha) / (4.0 * cos_o * cos_i));
    return BsdfEval(f, g1_o * d / (4.0 * cos_o));
}

// The rough dielectric's f and sample_rough_dielectric's density, for wo and wi pointing away
// from the surface. As in the sampler, ng tells which side wo is on, the microfacets are about
// ns turned to that side, and eta is the index of the side wo is not on over the one it is.
// Reflection (wi.n > 0), h = normalize(wo + wi) (Walter et al. 2007, eq. 13):
//   f = F D G1(wo) G1(wi) / (4 cos_o cos_i)  (eq. 20),
//   pdf = F D_wo(h) / (4 wo.h)  (the Jacobian of eq. 14),
// with D_wo(h) = G1(wo) max(0, wo.h) D(h) / cos_o the visible-normal density (Heitz 2018).
// Refraction (wi.n < 0), h = normalize(wo + eta wi) turned to n (eq. 16):
//   f = (1 - F) D G1(wo) G1(wi) |wo.h| |wi.h| / (cos_o |cos_i| (wo.h + eta wi.h)^2)  (eq. 21),
//   pdf = (1 - F) D_wo(h) eta^2 |wi.h| / (wo.h + eta wi.h)^2  (the Jacobian of eq. 17).
// f is that of radiance, wo towards the camera; photons carry flux and see eta^2 f (pbrt-v4
// sec. 9.5.2), the two 1 / eta^2 apart as in the sampler's weights.
fn rough_dielectric_eval(ior: f32, alpha_in: f32, wo: vec3f, wi: vec3f, ng: vec3f, ns: vec3f, radiance: bool) -> BsdfEval {
    let alpha = max(alpha_in, MIN_ALPHA);
    let entering = dot(wo, ng) > 0.0;
    let n = select(-ns, ns, entering);
    let eta = select(1.0 / ior, ior, entering);
    let cos_o = dot(wo, n);
    let cos_i = dot(wi, n);
    if cos_o <= 0.0 || cos_i == 0.0 {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let g1_o = ggx_g1(cos_o, alpha);
    let g1_i = ggx_g1(abs(cos_i), alpha);
    if cos_i > 0.0 {
        let h = normalize(wo + wi);
        let wo_h = dot(wo, h);
        let fr = fresnel_dielectric(wo_h, eta);
        let d = ggx_d(dot(h, n), alpha);
        let f = fr * d * g1_o * g1_i / (4.0 * cos_o * cos_i);
        let d_wo = g1_o * wo_h * d / cos_o;
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
    let d = ggx_d(dot(h, n), alpha);
    let denom = wo_h + eta * wi_h;
    let f = ft * d * g1_o * g1_i * wo_h * abs(wi_h) / (cos_o * abs(cos_i) * denom * denom);
    let d_wo = g1_o * wo_h * d / cos_o;
    let pdf = ft * d_wo * eta * eta * abs(wi_h) / (denom * denom);
    return BsdfEval(vec3f(select(f * eta * eta, f, radiance)), pdf);
}
