// The direction samplers against the densities the integrators weight them by, for the
// chi-square tests (tests/chi_square.rs, after pbrt-v4's bsdfs_test.cpp). One pass draws
// directions with a sampler; the other integrates its density over bins of directions.

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import lights
#import medium

const SAMPLER_COSINE: u32 = 0u;
const SAMPLER_GLOSSY: u32 = 1u;
const SAMPLER_ROUGH_DIELECTRIC: u32 = 2u;
const SAMPLER_LIGHT: u32 = 3u;
// plastic_sample against plastic_eval's mixture density; a smooth coating's mirror samples go
// to the unusable samples, whose share must be its probability.
const SAMPLER_PLASTIC: u32 = 4u;
// thin_dielectric_sample: each sample's direction and weight, the densities left at 0.
const SAMPLER_THIN_DIELECTRIC: u32 = 5u;
// smooth_dielectric_sample, the same way.
const SAMPLER_SMOOTH_DIELECTRIC: u32 = 6u;
// sample_phase (shared/medium.wgsl) against phase_hg, g in `alpha`, travelling along -wo.
const SAMPLER_PHASE: u32 = 7u;
// sample_flight: each sample's distance, whether it interacted and its weight, for a medium of
// sigma_a `ns`, sigma_s `ng` and a segment of length `alpha` (the densities are the host's).
const SAMPLER_FLIGHT: u32 = 8u;

// Draw `count` samples.
const PASS_SAMPLE: u32 = 0u;
// Integrate the density over `count` bins.
const PASS_INTEGRATE: u32 = 1u;

// Gauss-Legendre rule on [0, 1]: (node, weight, -, -); `points` of them are used.
const MAX_POINTS: u32 = 16u;

struct SamplerTestParams {
    sampler: u32,
    pass_kind: u32,
    count: u32,
    seed: u32,
    // BSDFs: wo (pointing away from the surface), roughness, shading normal, index of
    // refraction, geometric normal, albedo of the glossy conductor.
    wo: vec3f,
    alpha: f32,
    ns: vec3f,
    ior: f32,
    ng: vec3f,
    albedo: f32,
    // Lights: the receiving point. BSDFs: 1 for radiance (camera paths), 0 for photons.
    p: vec3f,
    radiance: u32,
    // Bin (i, j) holds the directions at polar angle theta in [i, i + 1) pi / theta_res and
    // azimuth phi in [j, j + 1) 2 pi / phi_res about the frame (x, y, z).
    x: vec3f,
    theta_res: u32,
    y: vec3f,
    phi_res: u32,
    z: vec3f,
    points: u32,
    // Polar angles, ascending, where the density may jump or rise without bound (-1 for
    // none): the bins are integrated on either side of them.
    breaks: vec4f,
    // Midpoint-rule points per dimension for bins where the density is 0 in part.
    fine: u32,
    // MICROFACET_GGX or MICROFACET_BECKMANN.
    distribution: u32,
    // Glossy conductor: 1 for a Fresnel term of the complex index of refraction eta + i k.
    fresnel: u32,
    _pad0: u32,
    eta: vec3f,
    // The plastic: Material's coat_thickness and coat_scatterings.
    coat_thickness: f32,
    k: vec3f,
    coat_scatterings: u32,
    // The plastic: Material's coat_weight, coat_fdr, coat_table (its table appended to the
    // scene's attributes by the test) and nonlinear; albedo is its base's.
    coat_weight: f32,
    coat_fdr: f32,
    coat_table: u32,
    nonlinear: u32,
    gauss: array<vec4f, MAX_POINTS>,
}

@group(0) @binding(21) var<uniform> test_params: SamplerTestParams;
// Sample i: (wi, weight) at 2i and (f, pdf, |cos(wi, ns)|, -) at 2i + 1 for a BSDF; for a
// light (wi, the cosine at the light point if usable else 0) and (pdf, traced pdf, li pdf,
// traced Le), red channels.
// Bin i: (integral of the density, -, -, -) at i.
@group(0) @binding(22) var<storage, read_write> test_out: array<vec4f>;

// Density and red emission of the emitter that the ray from p along w meets first, if it
// meets its front (either side of one emitting from both): light_pdf at the hit, as the
// integrators weigh emission they hit; the environment's where the ray escapes.
fn traced_light(p: vec3f, w: vec3f) -> vec2f {
    let hit = trace_closest(p, w, 3.4e38);
    if hit.prim_ref == 0xffffffffu {
        if USES_ENVIRONMENT && frame.emitter_count > 0u && environment().kind == EMITTER_ENVIRONMENT {
            let env = environment_eval(w);
            return vec2f(env.pdf, env.l.x);
        }
        return vec2f(0.0);
    }
    let s = surface_at(hit, p, w);
    // As the camera path takes emission: from the front, or from both sides (EMITS_BOTH).
    let cos_l = abs(dot(w, s.ng));
    let emits = shapes[s.shape].emits;
    if emits == 0u || (dot(w, s.ng) >= 0.0 && emits != EMITS_BOTH) {
        return vec2f(0.0);
    }
    return vec2f(light_pdf(p, hit.prim_ref, s.shape, hit.t, cos_l), shapes[s.shape].emission.x);
}

// The rough conductor under test.
fn test_glossy() -> Material {
    let q = test_params;
    var m: Material;
    m.albedo = vec3f(q.albedo);
    m.kind = MATERIAL_CONDUCTOR;
    m.roughness = q.alpha;
    m.texture = NO_TEXTURE;
    m.distribution = q.distribution;
    m.eta = q.eta;
    m.fresnel = q.fresnel;
    m.k = q.k;
    return m;
}

// The plastic under test (roughness alpha, 0 for a smooth coating), or the thin dielectric
// (specular_reflectance 0.9, specular_transmittance 0.7): two-sided, white specular.
fn test_coated(kind: u32) -> Material {
    let q = test_params;
    var m: Material;
    m.albedo = vec3f(q.albedo);
    m.kind = kind;
    m.ior = q.ior;
    m.roughness = q.alpha;
    m.texture = NO_TEXTURE;
    m.distribution = q.distribution;
    m.specular = vec3f(select(1.0, 0.9, kind == MATERIAL_THIN_DIELECTRIC));
    m.transmittance = vec3f(0.7);
    m.coat_weight = q.coat_weight;
    m.coat_fdr = q.coat_fdr;
    m.coat_table = q.coat_table;
    m.nonlinear = q.nonlinear;
    m.coat_thickness = q.coat_thickness;
    m.coat_scatterings = q.coat_scatterings;
    return m;
}

// A surface at the origin with the test's normals.
fn test_surface() -> Surface {
    var s: Surface;
    s.ng = test_params.ng;
    s.ns = test_params.ns;
    return s;
}

// Whether the rough dielectric under test has Beckmann microfacets.
fn test_beckmann() -> bool {
    return test_params.distribution == MICROFACET_BECKMANN;
}

// Solid-angle density of direction w under the chosen sampler.
fn test_density(w: vec3f) -> f32 {
    let q = test_params;
    switch q.sampler {
        case SAMPLER_COSINE: {
            return max(0.0, dot(w, q.ns)) * INV_PI;
        }
        case SAMPLER_GLOSSY: {
            return rough_conductor_eval(test_glossy(), q.wo, w, q.ns).pdf;
        }
        case SAMPLER_ROUGH_DIELECTRIC: {
            return rough_dielectric_eval(q.ior, q.alpha, test_beckmann(), q.wo, w, q.ns, q.radiance != 0u).pdf;
        }
        case SAMPLER_PLASTIC: {
            return plastic_eval(test_coated(MATERIAL_PLASTIC), vec3f(q.albedo), test_surface(), q.wo, w).pdf;
        }
        case SAMPLER_PHASE: {
            return phase_hg(dot(-q.wo, w), q.alpha);
        }
        case SAMPLER_THIN_DIELECTRIC, SAMPLER_SMOOTH_DIELECTRIC: {
            return 0.0;
        }
        default: {
            return traced_light(q.p, w).x;
        }
    }
}

fn draw_sample(i: u32) {
    let q = test_params;
    var rng = rng_new(q.seed, 0u, q.sampler, i);
    let u = vec3f(rng_next(&rng), rng_next2(&rng));
    if q.sampler == SAMPLER_LIGHT {
        let ls = sample_light(q.p, u);
        let usable = any(ls.li != vec3f(0.0));
        // The cosine at the light point sample_light chose (the test's lights are area lights),
        // 1 for the environment (at infinity).
        let cos_l = select(max(ls.cos_l, 1e-30), 1.0, ls.dist >= 3.4e38);
        test_out[2u * i] = vec4f(ls.wi, select(0.0, cos_l, usable));
        let traced = traced_light(q.p, ls.wi);
        test_out[2u * i + 1u] = vec4f(ls.pdf, traced.x, ls.li.x * ls.pdf, traced.y);
        return;
    }
    if q.sampler == SAMPLER_FLIGHT {
        let f = sample_flight(MediumCoefficients(q.ns, 0.0, q.ng), q.alpha, u.xy);
        test_out[2u * i] = vec4f(f.t, select(0.0, 1.0, f.scattered), f.weight.x, f.weight.y);
        test_out[2u * i + 1u] = vec4f(f.weight.z, 0.0, 0.0, 0.0);
        return;
    }
    var s = bsdf_absorbed(-q.wo);
    var b = BsdfEval(vec3f(0.0), 0.0);
    switch q.sampler {
        case SAMPLER_COSINE: {
            s = bsdf_specular(sample_cosine_hemisphere(q.ns, u.xy), vec3f(1.0));
            b = BsdfEval(vec3f(INV_PI), test_density(s.wi));
        }
        case SAMPLER_GLOSSY: {
            s = rough_conductor_sample(test_glossy(), -q.wo, q.ns, u.xy);
            b = rough_conductor_eval(test_glossy(), q.wo, s.wi, q.ns);
        }
        case SAMPLER_PLASTIC: {
            // The sampled lobe's f and probability times density against the weight; the
            // mirror of a smooth coating (a delta) among the unusable samples.
            let m = test_coated(MATERIAL_PLASTIC);
            let c = plastic_sample(m, m.albedo, -q.wo, test_surface(), u, true);
            let n = select(-q.ns, q.ns, dot(q.wo, q.ns) > 0.0);
            let l = plastic_lobes(m, m.albedo, q.wo, c.wi, n);
            let delta = !c.diffuse && q.alpha == 0.0;
            s = bsdf_specular(c.wi, select(c.weight, vec3f(0.0), delta));
            b = l.coat;
            if c.diffuse {
                b = l.base;
            }
        }
        case SAMPLER_THIN_DIELECTRIC: {
            let m = test_coated(MATERIAL_THIN_DIELECTRIC);
            s = thin_dielectric_sample(m, m.albedo, -q.wo, test_surface(), vec3f(0.0, 0.0, u.x), true);
        }
        case SAMPLER_PHASE: {
            // Its weight is p / pdf, no cosine: f = p / |cos| puts it in the host's f |cos| / pdf.
            s = bsdf_specular(sample_phase(-q.wo, q.alpha, u.xy), vec3f(1.0));
            let p = phase_hg(dot(-q.wo, s.wi), q.alpha);
            b = BsdfEval(vec3f(p / max(abs(dot(s.wi, q.ns)), 1e-30)), test_density(s.wi));
        }
        case SAMPLER_SMOOTH_DIELECTRIC: {
            s = smooth_dielectric_sample(-q.wo, q.ns, q.ior, u.x, q.radiance != 0u);
        }
        default: {
            let radiance = q.radiance != 0u;
            s = rough_dielectric_sample(-q.wo, q.ns, q.ior, q.alpha, test_beckmann(), u, radiance);
            b = rough_dielectric_eval(q.ior, q.alpha, test_beckmann(), q.wo, s.wi, q.ns, radiance);
        }
    }
    test_out[2u * i] = vec4f(s.wi, s.weight.x);
    test_out[2u * i + 1u] = vec4f(b.f.x, b.pdf, abs(dot(s.wi, q.ns)), 0.0);
}

// Node and weight k of a rule on [0, 1]: Gauss-Legendre with `points` nodes, or the midpoint
// rule with `fine`.
fn rule(fine: bool, k: u32) -> vec2f {
    if fine {
        let n = f32(test_params.fine);
        return vec2f((f32(k) + 0.5) / n, 1.0 / n);
    }
    return test_params.gauss[k].xy;
}

struct Band {
    integral: f32,
    // Whether the density was 0 at some point, and positive at some point.
    zero: bool,
    positive: bool,
}

// Integral of the density over polar angles [theta0, theta1] of the bins in column j: a
// product rule in (s, phi), where theta = theta0 + (theta1 - theta0) (1 - cos(pi s)) / 2
// crowds the points towards theta0 and theta1. The substitution turns an inverse square root
// there (the limb of a sphere light) into a smooth integrand.
fn integrate_band(theta0: f32, theta1: f32, j: u32, fine: bool) -> Band {
    let q = test_params;
    let n = select(q.points, q.fine, fine);
    let d_theta = theta1 - theta0;
    let d_phi = 2.0 * PI / f32(q.phi_res);
    let phi0 = d_phi * f32(j);
    var band = Band(0.0, false, false);
    for (var a = 0u; a < n; a++) {
        let ra = rule(fine, a);
        let theta = theta0 + 0.5 * d_theta * (1.0 - cos(PI * ra.x));
        // d theta / ds, times sin(theta) for the solid angle, times the weights.
        let row_weight = 0.5 * PI * d_theta * sin(PI * ra.x) * sin(theta) * d_phi * ra.y;
        var row = 0.0;
        for (var c = 0u; c < n; c++) {
            let rc = rule(fine, c);
            let phi = phi0 + d_phi * rc.x;
            let w = sin(theta) * (cos(phi) * q.x + sin(phi) * q.y) + cos(theta) * q.z;
            let density = test_density(w);
            band.zero = band.zero || density == 0.0;
            band.positive = band.positive || density > 0.0;
            row += rc.y * density;
        }
        band.integral += row_weight * row;
    }
    return band;
}

// Integral of the density over bin i, split at the breaks inside it.
fn integrate_split(i: u32, fine: bool) -> Band {
    let q = test_params;
    let d_theta = PI / f32(q.theta_res);
    let theta1 = d_theta * f32(i / q.phi_res + 1u);
    let j = i % q.phi_res;
    var lo = theta1 - d_theta;
    var bin = Band(0.0, false, false);
    for (var k = 0u; k < 5u; k++) {
        let hi = select(theta1, q.breaks[min(k, 3u)], k < 4u);
        if hi > lo && hi <= theta1 {
            let band = integrate_band(lo, hi, j, fine);
            bin = Band(bin.integral + band.integral, bin.zero || band.zero, bin.positive || band.positive);
            lo = hi;
        }
    }
    return bin;
}

// Integral of the density over bin i. Gauss-Legendre suits smooth densities; where an edge
// beyond which the density is 0 crosses the bin (of a light, or of the directions a BSDF
// reaches) it would err by a good part of the bin, and many midpoints are used instead. With
// the substitution of integrate_band, their error is about (pi / 2 fine)^2 / 6 of the bin.
// One call of integrate_split in a loop rather than two calls: the driver inlines every call,
// so each would be a copy of the density code (every sampler's, and a traversal); with one
// copy lavapipe compiles the kernel in much less time.
fn integrate_bin(i: u32) -> f32 {
    var fine = false;
    var bin: Band;
    loop {
        bin = integrate_split(i, fine);
        if fine || !(bin.zero && bin.positive) {
            break;
        }
        fine = true;
    }
    return bin.integral;
}

@compute @workgroup_size(64)
fn sampler_test(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= test_params.count {
        return;
    }
    if test_params.pass_kind == PASS_SAMPLE {
        draw_sample(index);
    } else {
        test_out[index] = vec4f(integrate_bin(index), 0.0, 0.0, 0.0);
    }
}
