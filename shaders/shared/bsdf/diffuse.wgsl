// Lambertian reflection (MATERIAL_DIFFUSE; Mitsuba 3's `diffuse`, pbrt-v4's DiffuseBxDF).
//   f = albedo / pi, on the side the light arrived on; sampled by cosine, pdf = |cos_i| / pi,
//   so a sample's weight f |cos| / pdf is the albedo.
// Parameters: `albedo` (linear RGB in [0, 1]), or a texture in its place (looked up by
// material_at); `one_sided`: black seen from behind its shading normal.
// SPPM leaves its visible points on this lobe: vp_weight = f, and photons bring their whole
// flux (the factor bsdf_deposit leaves at 1).

#import types
#import sampling
#import scene
#import bsdf/lobe

const MATERIAL_DIFFUSE: u32 = 0u;

// Sample diffuse m of reflectance albedo at s from direction of travel d, u in [0, 1)^3 (u.xy
// used).
fn diffuse_sample(m: Material, albedo: vec3f, d: vec3f, s: Surface, u: vec3f, radiance: bool) -> BsdfSample {
    let n_in = select(-s.ns, s.ns, dot(d, s.ng) < 0.0);
    let wi = sample_cosine_hemisphere(n_in, u.xy);
    // A shading normal can send wi through the surface, or behind a one-sided ns.
    let ok = dot(wi, s.ng) * dot(d, s.ng) < 0.0 && !one_sided_culls(m, s, wi);
    return BsdfSample(wi, select(vec3f(0.0), albedo, ok), abs(dot(wi, s.ns)) * INV_PI, true, albedo * INV_PI);
}

// f and diffuse_sample's density of wi.
fn diffuse_eval(m: Material, albedo: vec3f, s: Surface, wo: vec3f, wi: vec3f) -> BsdfEval {
    return BsdfEval(albedo * INV_PI, abs(dot(wi, s.ns)) * INV_PI);
}
