// Scattering at specular surfaces, shared by camera paths and photon paths.

// The non-diffuse materials the scene has (src/gpu/features.rs); see scene.wgsl.
override USES_MIRROR: bool = true;
override USES_GLOSSY: bool = true;
override USES_SMOOTH_DIELECTRIC: bool = true;
override USES_ROUGH_DIELECTRIC: bool = true;
// Some non-dielectric material is one-sided.
override USES_ONE_SIDED: bool = true;
// Some mirror or glossy conductor has a Fresnel term (a complex index of refraction).
override USES_CONDUCTOR_FRESNEL: bool = true;
// Some glossy conductor, rough dielectric or rough plastic has Beckmann microfacets.
override USES_BECKMANN: bool = true;
// Some material is a thin dielectric.
override USES_THIN_DIELECTRIC: bool = true;

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

// Fresnel reflectance of a conductor of complex index of refraction eta + i k for unpolarized
// light, per channel: pbrt-v4's FrComplex (eq. 9.6 with a complex eta) in real arithmetic. With
// t = eta^2 - k^2 - sin^2, a^2 + b^2 = sqrt(t^2 + 4 eta^2 k^2) and a^2 = (a^2 + b^2 + t) / 2,
//   R_s = (a^2 + b^2 + cos^2 - 2 a cos) / (a^2 + b^2 + cos^2 + 2 a cos),
//   R_p = R_s ((a^2 + b^2) cos^2 + sin^4 - 2 a cos sin^2) / ((a^2 + b^2) cos^2 + sin^4 + 2 a cos sin^2)
// (Born and Wolf, "Principles of Optics", sec. 14.2), and F = (R_s + R_p) / 2. eta 0, k 1 gives
// exactly 1.
fn fresnel_conductor(cos_i_in: f32, eta: vec3f, k: vec3f) -> vec3f {
    let cos_i = clamp(cos_i_in, 0.0, 1.0);
    let cos2 = cos_i * cos_i;
    let sin2 = 1.0 - cos2;
    let t = eta * eta - k * k - vec3f(sin2);
    let a2_b2 = sqrt(max(vec3f(0.0), t * t + 4.0 * eta * eta * k * k));
    let a = sqrt(max(vec3f(0.0), 0.5 * (a2_b2 + t)));
    let s_sum = a2_b2 + vec3f(cos2);
    let s_diff = 2.0 * cos_i * a;
    let r_s = (s_sum - s_diff) / max(s_sum + s_diff, vec3f(1e-30));
    let p_sum = a2_b2 * cos2 + vec3f(sin2 * sin2);
    let p_diff = s_diff * sin2;
    let r_p = r_s * (p_sum - p_diff) / max(p_sum + p_diff, vec3f(1e-30));
    return 0.5 * (r_s + r_p);
}

// Whether conductor m (a mirror or glossy conductor) has a Fresnel term: a complex index of
// refraction other than Mitsuba's `none` (compiled out unless some material has one). Without
// one its reflectance is albedo, and no Fresnel term is computed.
fn has_conductor_fresnel(m: Material) -> bool {
    return USES_CONDUCTOR_FRESNEL && m.fresnel != 0u;
}

struct SpecularSample {
    wi: vec3f,
    // Throughput factor f * |cos| / pdf.
    weight: vec3f,
}

// Sample a smooth dielectric from direction of travel d at geometric normal ng and shading
// normal ns. Reflection or refraction is chosen with the Fresnel probability, so the weight
// is 1, times 1 / eta^2 for refracted radiance (pbrt-v4 sec. 9.5.2); photons carry flux and
// are not scaled. The side comes from ng, the law from ns, as in the rough case: Mitsuba 3's
// dielectric works in the shading frame, so a smooth-shaded mesh refracts smoothly, not by
// its facets. A direction at or below ns's horizon ends the path.
fn sample_dielectric(d: vec3f, ng: vec3f, ns: vec3f, ior: f32, u: f32, radiance: bool) -> SpecularSample {
    let entering = dot(d, ng) < 0.0;
    let n = select(-ns, ns, entering);
    let eta = select(1.0 / ior, ior, entering);
    let cos_i = -dot(d, n);
    if cos_i <= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
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

// Microfacet distributions with Smith's separable masking G = G1(wo) G1(wi), isotropic alpha,
// as Mitsuba 3's MicrofacetDistribution: GGX (Trowbridge-Reitz) and Beckmann (Walter et al.
// 2007, eq. 33, 34 and 25, 27). Directions are in a frame whose z is the normal. `beckmann`
// picks the distribution; it is false in kernels of scenes without Beckmann microfacets, so
// only GGX is compiled there.

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

// Beckmann's D = exp(-tan^2 / alpha^2) / (pi alpha^2 cos^4) (Walter et al. 2007, eq. 25); 0 at
// grazing microfacets.
fn beckmann_d(cos_h: f32, alpha: f32) -> f32 {
    let c2 = max(cos_h * cos_h, 1e-12);
    let a2 = alpha * alpha;
    return exp(-(1.0 - c2) / (c2 * a2)) / (PI * a2 * c2 * c2);
}

// Beckmann's masking G1 at |cos theta| = c in Walter et al.'s rational approximation (2007,
// eq. 27, within 0.35% of the exact one), with a = 1 / (alpha tan theta):
// (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1. Mitsuba 3 uses it for
// its BSDFs' values, and so do we, to render what it renders.
fn beckmann_g1(c: f32, alpha: f32) -> f32 {
    let sin_t = sqrt(max(0.0, 1.0 - c * c));
    if c >= 1.6 * alpha * sin_t {
        return 1.0;
    }
    let a = c / (alpha * sin_t);
    return (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
}

// The error function, by Abramowitz and Stegun's 7.1.26 (absolute error below 1.5e-7).
fn erf(x: f32) -> f32 {
    let z = abs(x);
    let t = 1.0 / (1.0 + 0.3275911 * z);
    let poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    return sign(x) * (1.0 - poly * exp(-z * z));
}

// The inverse error function on (-1, 1), by Giles' single-precision polynomials ("Approximating
// the erfinv function", GPU Computing Gems Jade Edition, 2011).
fn erfinv(x: f32) -> f32 {
    var w = -log((1.0 - x) * (1.0 + x));
    var p: f32;
    if w < 5.0 {
        w -= 2.5;
        p = 2.81022636e-08;
        p = 3.43273939e-07 + p * w;
        p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w;
        p = 0.246640727 + p * w;
        p = 1.50140941 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -0.000200214257;
        p = 0.000100950558 + p * w;
        p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w;
        p = 0.00573950773 + p * w;
        p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w;
        p = 1.00167406 + p * w;
        p = 2.83297682 + p * w;
    }
    return p * x;
}

const INV_SQRT_PI: f32 = 0.564189583547756;

// Beckmann's exact Smith masking, 1 / (1 + Lambda) with Lambda(a) = (erf(a) - 1) / 2 +
// exp(-a^2) / (2 a sqrt(pi)), a = 1 / (alpha tan theta) (Walter et al. 2007, eq. 27; Heitz
// 2014, "Understanding the Masking-Shadowing Function", eq. 74 ff.). It normalizes the density
// of visible normals that sample_beckmann_visible_normal draws from.
fn beckmann_g1_exact(c: f32, alpha: f32) -> f32 {
    let sin_t = sqrt(max(0.0, 1.0 - c * c));
    // Lambda(4) is about 2e-9.
    if c >= 4.0 * alpha * sin_t {
        return 1.0;
    }
    if c <= 0.0 {
        return 0.0;
    }
    let a = c / (alpha * sin_t);
    let lambda = 0.5 * (erf(a) - 1.0) + 0.5 * INV_SQRT_PI * exp(-a * a) / a;
    return 1.0 / (1.0 + lambda);
}

fn microfacet_d(cos_h: f32, alpha: f32, beckmann: bool) -> f32 {
    if beckmann {
        return beckmann_d(cos_h, alpha);
    }
    return ggx_d(cos_h, alpha);
}

// G1 in the BSDF's value.
fn microfacet_g1(c: f32, alpha: f32, beckmann: bool) -> f32 {
    if beckmann {
        return beckmann_g1(c, alpha);
    }
    return ggx_g1(c, alpha);
}

// G1(wo) of the density of normals visible from wo: the exact one, the normalization of what
// the sampler draws.
fn visible_g1(c: f32, alpha: f32, beckmann: bool) -> f32 {
    if beckmann {
        return beckmann_g1_exact(c, alpha);
    }
    return ggx_g1(c, alpha);
}

// G1 of the BSDF's value over visible_g1, at wo: the factor by which a sample's weight f |cos|
// / pdf differs from G1(wi) (times Fresnel and albedo). 1 for GGX, whose G1 is exact; within
// 0.35% of 1 for Beckmann.
fn visible_g1_ratio(c: f32, alpha: f32, beckmann: bool) -> f32 {
    if beckmann {
        return beckmann_g1(c, alpha) / beckmann_g1_exact(c, alpha);
    }
    return 1.0;
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

// A microfacet normal from the Beckmann distribution of normals visible from wo (wo.z > 0),
// with density G1(wo) max(0, wo.h) D(h) / wo.z, G1 the exact one (beckmann_g1_exact). As Heitz
// and d'Eon 2014 ("Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible
// Normals", sec. 4): stretch wo to alpha 1, draw the slopes (x, y) of a normal visible from it
// with wo turned to azimuth 0, turn them back and unstretch; the normal is (-x, -y, 1).
//
// At alpha 1 and incidence theta, the slope y is a normal variate of variance 1/2 (density
// exp(-y^2) / sqrt(pi)), and x has density proportional to (1 - x tan theta) exp(-x^2) for
// x < cot theta. x is drawn as in Jakob's "An Improved Visible Normal Sampling Routine for the
// Beckmann Distribution" (2014), in the variable e = erf(x): its CDF is proportional to
//   C(e) = 1 + e + tan theta exp(-x^2) / sqrt(pi),  dC/de = 1 - x tan theta,
// on [-1, erf(cot theta)], and C(e) = u C(erf(cot theta)) is solved by Newton's method from
// the exact solution at theta = 90 degrees (x = -sqrt(-ln u)), rescaled to the interval.
fn sample_beckmann_visible_normal(wo: vec3f, alpha: f32, u_in: vec2f) -> vec3f {
    let ws = normalize(vec3f(alpha * wo.x, alpha * wo.y, wo.z));
    let sin_s = sqrt(ws.x * ws.x + ws.y * ws.y);
    let cos_phi = select(1.0, ws.x / sin_s, sin_s > 0.0);
    let sin_phi = select(0.0, ws.y / sin_s, sin_s > 0.0);
    let u = clamp(u_in, vec2f(1e-6), vec2f(1.0 - 1e-6));
    let tan_t = max(sin_s / ws.z, 1e-6);
    let cot_t = 1.0 / tan_t;
    let e_max = erf(cot_t);
    let goal = u.x * (1.0 + e_max + INV_SQRT_PI * tan_t * exp(-cot_t * cot_t));
    // e stays inside (-1, 1), where erfinv is finite.
    let e_hi = min(e_max, 0.99999994);
    var e = clamp(e_max - (1.0 + e_max) * erf(sqrt(-log(u.x))), -0.99999994, e_hi);
    for (var i = 0; i < 3; i++) {
        let x = erfinv(e);
        let c = 1.0 + e + INV_SQRT_PI * tan_t * exp(-x * x) - goal;
        e = clamp(e - c / (1.0 - x * tan_t), -0.99999994, e_hi);
    }
    let slope = vec2f(erfinv(e), erfinv(2.0 * u.y - 1.0));
    let x = alpha * (cos_phi * slope.x - sin_phi * slope.y);
    let y = alpha * (sin_phi * slope.x + cos_phi * slope.y);
    return normalize(vec3f(-x, -y, 1.0));
}

fn sample_visible_normal(wo: vec3f, alpha: f32, u: vec2f, beckmann: bool) -> vec3f {
    if beckmann {
        return sample_beckmann_visible_normal(wo, alpha, u);
    }
    return sample_ggx_visible_normal(wo, alpha, u);
}

// Smallest alpha the samplers use: below it GGX's peak overflows f32.
const MIN_ALPHA: f32 = 1e-4;

// Whether material m (a glossy conductor or rough dielectric) has Beckmann microfacets.
fn is_beckmann(m: Material) -> bool {
    return USES_BECKMANN && m.distribution == MICROFACET_BECKMANN;
}

// Sample glossy conductor m (reflectance albedo times its Fresnel term, both sides alike) from
// direction of travel d at shading normal ns. With visible normals sampled, the weight
// f |cos| / pdf is albedo F(wo.h) G1(wi) (Heitz 2018, sec. 2, with G = G1(wo) G1(wi)), times
// visible_g1_ratio for Beckmann.
fn sample_glossy(m: Material, d: vec3f, ns: vec3f, u: vec2f) -> SpecularSample {
    let alpha = max(m.roughness, MIN_ALPHA);
    let beckmann = is_beckmann(m);
    let n = select(-ns, ns, dot(d, ns) < 0.0);
    let frame = basis(n);
    let wo = -d * frame;
    if wo.z <= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
    let h = sample_visible_normal(wo, alpha, u, beckmann);
    let wi = reflect(-wo, h);
    if wi.z <= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
    var weight = m.albedo * microfacet_g1(wi.z, alpha, beckmann);
    if beckmann {
        weight *= visible_g1_ratio(wo.z, alpha, beckmann);
    }
    if has_conductor_fresnel(m) {
        weight *= fresnel_conductor(dot(wo, h), m.eta, m.k);
    }
    return SpecularSample(frame * wi, weight);
}

// Sample a rough dielectric (Walter et al. 2007) from direction of travel d. A visible normal
// h is drawn, then reflection or refraction through h with the Fresnel probability, so the
// weight is G1(wi) (times visible_g1_ratio for Beckmann), times 1 / eta^2 for refracted
// radiance as in the smooth case.
fn sample_rough_dielectric(d: vec3f, ng: vec3f, ns: vec3f, ior: f32, alpha_in: f32, beckmann: bool, u: vec3f, radiance: bool) -> SpecularSample {
    let alpha = max(alpha_in, MIN_ALPHA);
    let entering = dot(d, ng) < 0.0;
    let n = select(-ns, ns, entering);
    let eta = select(1.0 / ior, ior, entering);
    let frame = basis(n);
    let wo = -d * frame;
    if wo.z <= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
    let h = sample_visible_normal(wo, alpha, u.xy, beckmann);
    let ratio = visible_g1_ratio(wo.z, alpha, beckmann);
    let cos_o = dot(wo, h);
    let f = fresnel_dielectric(cos_o, eta);
    if u.z < f {
        let wi = reflect(-wo, h);
        if wi.z <= 0.0 {
            return SpecularSample(d, vec3f(0.0));
        }
        var g = microfacet_g1(wi.z, alpha, beckmann);
        if beckmann {
            g *= ratio;
        }
        return SpecularSample(frame * wi, vec3f(g));
    }
    let sin2_t = (1.0 - cos_o * cos_o) / (eta * eta);
    let cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    let wt = normalize(-wo / eta + (cos_o / eta - cos_t) * h);
    if wt.z >= 0.0 {
        return SpecularSample(d, vec3f(0.0));
    }
    let scale = select(1.0, 1.0 / (eta * eta), radiance);
    var g = microfacet_g1(-wt.z, alpha, beckmann);
    if beckmann {
        g *= ratio;
    }
    return SpecularSample(frame * wt, vec3f(g * scale));
}

// Sample thin dielectric m (Mitsuba 3's thindielectric) from direction of travel d at s:
// reflect about ns with the slab's summed reflectance R' = R + T^2 R / (1 - R^2) = 2R / (1 + R),
// R = F(|cos|) at its index (thindielectric.cpp), else pass straight through, unbent. The
// branch is chosen with its probability, so the weights are the tints; flux and radiance alike,
// since nothing refracts. A reflection about ns that crosses ng ends the path.
fn sample_thin_dielectric(m: Material, d: vec3f, s: Surface, u: f32) -> SpecularSample {
    // Index 1 (Mitsuba's null BSDF) reflects nothing; exactly, not by Fresnel's roundoff.
    let r = select(fresnel_dielectric(abs(dot(d, s.ns)), m.ior), 0.0, m.ior == 1.0);
    if u < 2.0 * r / (1.0 + r) {
        let n = select(-s.ns, s.ns, dot(d, s.ns) < 0.0);
        let wi = reflect(d, n);
        let weight = select(vec3f(0.0), m.specular, dot(wi, s.ng) * dot(d, s.ng) < 0.0);
        return SpecularSample(wi, weight);
    }
    return SpecularSample(d, m.transmittance);
}

// eta^2 where a radiance sample through dielectric m at s, from direction of travel d to wi,
// refracted (its weight holds 1 / eta^2, eta the transmitted side's index over the incident
// side's), else 1: what pbrt-v4's path tracer multiplies into etaScale, so that Russian
// roulette judges the throughput without the factor a path leaving the glass undoes.
fn refraction_eta2(m: Material, s: Surface, d: vec3f, wi: vec3f) -> f32 {
    if m.kind != MATERIAL_DIELECTRIC || dot(wi, s.ng) * dot(d, s.ng) <= 0.0 {
        return 1.0;
    }
    let eta = select(1.0 / m.ior, m.ior, dot(d, s.ng) < 0.0);
    return eta * eta;
}

// Scatter at a non-diffuse surface: mirror, glossy conductor, smooth or rough dielectric,
// thin dielectric.
// A zero weight ends the path. `radiance` is true for camera paths, false for photons.
// Only the materials the scene has are compiled in (USES_*, set by the host).
fn sample_nondiffuse(m: Material, d: vec3f, s: Surface, u: vec3f, radiance: bool) -> SpecularSample {
    var next = SpecularSample(d, vec3f(0.0));
    if USES_MIRROR && m.kind == MATERIAL_MIRROR {
        let n = select(-s.ns, s.ns, dot(d, s.ns) < 0.0);
        next = SpecularSample(reflect(d, n), m.albedo);
        // Mitsuba 3's smooth conductor: F at the angle of incidence to ns.
        if has_conductor_fresnel(m) {
            next.weight *= fresnel_conductor(-dot(d, n), m.eta, m.k);
        }
    }
    if USES_GLOSSY && m.kind == MATERIAL_GLOSSY {
        next = sample_glossy(m, d, s.ns, u.xy);
    }
    if USES_ROUGH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC && m.roughness > 0.0 {
        next = sample_rough_dielectric(d, s.ng, s.ns, m.ior, m.roughness, is_beckmann(m), u, radiance);
    }
    if USES_SMOOTH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC && m.roughness == 0.0 {
        next = sample_dielectric(d, s.ng, s.ns, m.ior, u.z, radiance);
    }
    // Mitsuba's specular_reflectance and specular_transmittance scale each lobe of a
    // dielectric (1 and 1 unless a scene asks otherwise), sampled as before.
    if m.kind == MATERIAL_DIELECTRIC {
        next.weight *= select(m.transmittance, m.specular, dot(next.wi, s.ng) * dot(d, s.ng) < 0.0);
    }
    if USES_THIN_DIELECTRIC && m.kind == MATERIAL_THIN_DIELECTRIC {
        next = sample_thin_dielectric(m, d, s, u.z);
    }
    // A shading normal can send a reflection below the surface or a refraction back out of
    // it; such paths end rather than leak.
    let reflected = dot(next.wi, s.ng) * dot(d, s.ng) < 0.0;
    let wants_reflection = m.kind != MATERIAL_DIELECTRIC && (!USES_THIN_DIELECTRIC || m.kind != MATERIAL_THIN_DIELECTRIC);
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

// Glossy conductor m's f and sample_glossy's density, for wo and wi pointing away from the
// surface, h = normalize(wo + wi): f = albedo F(wo.h) D G / (4 cos_o cos_i) (Walter et al.
// 2007, eq. 20) and pdf = G1(wo) D / (4 cos_o) (the visible-normal density over the reflection
// Jacobian, with the exact G1: visible_g1).
fn glossy_eval(m: Material, wo: vec3f, wi: vec3f, ns: vec3f) -> BsdfEval {
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

// The rough dielectric's f and sample_rough_dielectric's density, for wo and wi pointing away
// from the surface. As in the sampler, ng tells which side wo is on, the microfacets are about
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
fn rough_dielectric_eval(ior: f32, alpha_in: f32, beckmann: bool, wo: vec3f, wi: vec3f, ng: vec3f, ns: vec3f, radiance: bool) -> BsdfEval {
    let alpha = max(alpha_in, MIN_ALPHA);
    let entering = dot(wo, ng) > 0.0;
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
