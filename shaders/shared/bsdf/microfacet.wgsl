// Microfacet distributions, shared by the rough BSDF families (conductor, dielectric,
// plastic): their normal densities D, Smith masking G1, and sampling of visible normals.

#import types

// Some glossy conductor, rough dielectric or rough plastic has Beckmann microfacets
// (src/gpu/features.rs); without, only GGX is compiled.
override USES_BECKMANN: bool = true;

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

// Whether material m (a glossy conductor, rough dielectric or rough plastic) has Beckmann
// microfacets.
fn is_beckmann(m: Material) -> bool {
    return USES_BECKMANN && m.distribution == MICROFACET_BECKMANN;
}
