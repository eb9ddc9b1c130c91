// What every BSDF family returns, and the one-sidedness they share. Directions: d is the
// direction of travel that arrived at the surface; wo = -d and wi point away from it.

#import types
#import scene

// Some non-dielectric material is one-sided (src/gpu/features.rs).
override USES_ONE_SIDED: bool = true;

// A sampled direction. A zero weight ends the path.
struct BsdfSample {
    wi: vec3f,
    // Throughput factor f |cos| / pdf (of the lobe chosen, over its probability).
    weight: vec3f,
    // Solid-angle density of wi, for MIS at the emission the next segment meets; 0 after a
    // delta lobe, and where the caller asked for none.
    pdf: f32,
    // Whether the lobe was diffuse (a Lambertian surface, a plastic's base): there SPPM's
    // camera path leaves its visible point, of weight vp_weight.
    diffuse: bool,
    // The diffuse lobe's f without the factor that depends on the photon's direction (which
    // the photon brings: bsdf_deposit).
    vp_weight: vec3f,
}

// A BSDF's value for a pair of directions and its sampler's density of wi.
struct BsdfEval {
    // f, without the cosine.
    f: vec3f,
    // Solid-angle density with which the sampler picks wi given wo.
    pdf: f32,
}

// A sample that ends the path, along d.
fn bsdf_absorbed(d: vec3f) -> BsdfSample {
    return BsdfSample(d, vec3f(0.0), 0.0, false, vec3f(0.0));
}

// Whether material m at s scatters nothing to or from direction w (pointing away from the
// surface): Mitsuba 3's BSDFs return zero for cos_theta <= 0 in the shading frame unless
// wrapped in `twosided`. Dielectrics are two-sided by nature and ignore the flag
// (MATERIAL_DIELECTRIC: bsdf/dielectric.wgsl, which bsdf.wgsl imports with every family).
fn one_sided_culls(m: Material, s: Surface, w: vec3f) -> bool {
    return USES_ONE_SIDED && m.one_sided != 0u && m.kind != MATERIAL_DIELECTRIC && dot(w, s.ns) <= 0.0;
}

// Whether a ray along d meets m at s from behind a one-sided surface (wo = -d below ns): the
// BSDF is zero there, so the camera path or photon ends, with no visible point, deposit or
// next-event estimate.
fn seen_from_behind(m: Material, s: Surface, d: vec3f) -> bool {
    return one_sided_culls(m, s, -d);
}

// A sample of direction wi and weight, its density not given: a delta lobe's, or a rough
// lobe's that bsdf_sample evaluates where MIS needs it.
fn bsdf_specular(wi: vec3f, weight: vec3f) -> BsdfSample {
    return BsdfSample(wi, weight, 0.0, false, vec3f(0.0));
}
