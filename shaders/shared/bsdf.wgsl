// The BSDF dispatcher: the one entry for each operation that camera paths (path_trace.wgsl,
// camera_pass.wgsl) and photons (photon_pass.wgsl) do at a surface, calling the material's
// family. One file a family in shared/bsdf/, each with its model and parameters at the top,
// its MATERIAL_* kind and its entry points <family>_sample (a direction, from the direction of
// travel) and <family>_eval (f and the sampler's density; the families whose lobes are all
// deltas have none): diffuse, conductor (smooth and rough), dielectric (smooth and rough),
// thin_dielectric (and null) and plastic (smooth and rough). Shared by them: lobe (the result
// types and one-sidedness), fresnel and microfacet. Only the families a scene has are
// compiled in: each file's USES_* overrides, set by the host (src/scene/material/).
//
// A new family takes its own file here, its import and a branch in each function below, and
// its host file in src/scene/material/ (docs/guide/how-it-works.md, "BSDF families").

#import types
#import scene
#import bsdf/lobe
#import bsdf/diffuse
#import bsdf/conductor
#import bsdf/dielectric
#import bsdf/thin_dielectric
#import bsdf/plastic

// Whether next-event estimation is done at a vertex of material m: every material whose
// BSDF can be evaluated, that is all but smooth conductors and smooth glass, thin or not (a
// smooth plastic's base is evaluated, its mirror not).
fn bsdf_samples_lights(m: Material) -> bool {
    return m.kind == MATERIAL_DIFFUSE || is_rough_conductor(m)
        || (USES_ROUGH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC && m.roughness > 0.0) || is_plastic(m);
}

// Whether material m at s scatters between w, a direction the path takes there, and w_new,
// one joined to it (a light sample, a connection, the camera): w_new on w's side of the
// geometric normal (a dielectric also transmits) and not behind a one-sided surface.
fn bsdf_joins(m: Material, s: Surface, w: vec3f, w_new: vec3f) -> bool {
    return (dot(w_new, s.ng) * dot(w, s.ng) > 0.0 || m.kind == MATERIAL_DIELECTRIC) && !one_sided_culls(m, s, w_new);
}

// f (radiance) and the sampler's density of wi given wo, at surface s of material m with
// `albedo` (its texture looked up), where bsdf_samples_lights(m).
fn bsdf_eval(s: Surface, m: Material, albedo: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    if is_rough_conductor(m) {
        return conductor_eval(m, albedo, s, wo, wi);
    }
    if USES_ROUGH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC {
        return dielectric_eval(m, albedo, s, wo, wi);
    }
    if is_plastic(m) {
        return plastic_eval(m, albedo, s, wo, wi);
    }
    return diffuse_eval(m, albedo, s, wo, wi);
}

// Sample the BSDF of material m with `albedo` at surface s from direction of travel d, u in
// [0, 1)^3: the next direction, its weight f |cos| / pdf (0 ends the path), its density
// where `mis` (the caller samples lights there; else 0), and whether the lobe was diffuse,
// where SPPM leaves a visible point of weight vp_weight. `radiance` is true for camera paths,
// false for photons, which carry flux.
fn bsdf_sample(s: Surface, m: Material, albedo: vec3f, d: vec3f, u: vec3f, radiance: bool, mis: bool) -> BsdfSample {
    // The families that give their own density.
    if m.kind == MATERIAL_DIFFUSE {
        var b = diffuse_sample(m, albedo, d, s, u, radiance);
        b.pdf = select(0.0, b.pdf, mis);
        return b;
    }
    if is_plastic(m) {
        var b = plastic_sample(m, albedo, d, s, u, radiance);
        b.pdf = select(0.0, b.pdf, mis);
        return b;
    }
    var next = bsdf_absorbed(d);
    if (USES_MIRROR || USES_GLOSSY) && m.kind == MATERIAL_CONDUCTOR {
        next = conductor_sample(m, albedo, d, s, u, radiance);
    }
    if (USES_SMOOTH_DIELECTRIC || USES_ROUGH_DIELECTRIC) && m.kind == MATERIAL_DIELECTRIC {
        next = dielectric_sample(m, albedo, d, s, u, radiance);
    }
    if USES_THIN_DIELECTRIC && m.kind == MATERIAL_THIN_DIELECTRIC {
        next = thin_dielectric_sample(m, albedo, d, s, u, radiance);
    }
    // The rough lobes' density, for MIS (the delta lobes have none).
    if mis && bsdf_samples_lights(m) {
        next.pdf = bsdf_eval(s, m, albedo, -d, next.wi).pdf;
    }
    return next;
}

// Whether photons deposit at material m: where it has a diffuse lobe.
fn bsdf_receives_photons(m: Material) -> bool {
    return m.kind == MATERIAL_DIFFUSE || is_plastic(m);
}

// What a photon of flux beta arriving along d at material m brings to the visible points
// around it: the part of the diffuse lobe's f that depends on its direction (1 for a
// Lambertian surface; a plastic's coating transmittance).
fn bsdf_deposit(m: Material, s: Surface, d: vec3f, beta: vec3f) -> vec3f {
    if is_plastic(m) {
        return beta * plastic_deposit(m, s, d);
    }
    return beta;
}
