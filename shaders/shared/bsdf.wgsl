// The BSDF dispatcher: the one entry for each operation that camera paths (path_trace.wgsl,
// camera_pass.wgsl) and photons (photon_pass.wgsl) do at a surface, calling the material's
// family. One file a family in shared/bsdf/, each with its model and parameters at the top:
// diffuse, conductor (mirror and glossy), dielectric (smooth and rough), thin_dielectric (and
// null) and plastic (smooth and rough); shared by them: lobe (the result types and
// one-sidedness), fresnel and microfacet. Only the families a scene has are compiled in:
// each file's USES_* overrides, set by the host (src/gpu/features.rs).
//
// A new family takes its own file here, a MATERIAL_* kind (src/gpu/types.rs and
// shared/types.wgsl), a branch in each function below, and its host file in
// src/scene/material/.

#import types
#import scene
#import bsdf/lobe
#import bsdf/diffuse
#import bsdf/conductor
#import bsdf/dielectric
#import bsdf/thin_dielectric
#import bsdf/plastic

// Whether next-event estimation is done at a vertex of material m: every material whose
// BSDF can be evaluated, that is all but the mirror and smooth glass, thin or not (a smooth
// plastic's base is evaluated, its mirror not).
fn bsdf_samples_lights(m: Material) -> bool {
    return m.kind == MATERIAL_DIFFUSE || (USES_GLOSSY && m.kind == MATERIAL_GLOSSY)
        || (USES_ROUGH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC && m.roughness > 0.0) || is_plastic(m);
}

// f (radiance) and the sampler's density of wi given wo, at surface s of material m with
// `albedo` (its texture looked up), where bsdf_samples_lights(m).
fn bsdf_eval(s: Surface, m: Material, albedo: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    if USES_GLOSSY && m.kind == MATERIAL_GLOSSY {
        return glossy_eval(m, wo, wi, s.ns);
    }
    if USES_ROUGH_DIELECTRIC && m.kind == MATERIAL_DIELECTRIC {
        return dielectric_eval(m, s, wo, wi);
    }
    if is_plastic(m) {
        return plastic_eval(m, albedo, wo, wi, s.ns);
    }
    return diffuse_eval(albedo, s, wi);
}

// Sample the BSDF of material m with `albedo` at surface s from direction of travel d, u in
// [0, 1)^3: the next direction, its weight f |cos| / pdf (0 ends the path), its density
// where `mis` (the caller samples lights there; else 0), and whether the lobe was diffuse,
// where SPPM leaves a visible point of weight vp_weight. `radiance` is true for camera paths,
// false for photons, which carry flux.
fn bsdf_sample(s: Surface, m: Material, albedo: vec3f, d: vec3f, u: vec3f, radiance: bool, mis: bool) -> BsdfSample {
    if m.kind == MATERIAL_DIFFUSE {
        var b = diffuse_sample(m, albedo, d, s, u.xy);
        b.pdf = select(0.0, b.pdf, mis);
        return b;
    }
    if is_plastic(m) {
        var b = sample_plastic(m, albedo, d, s, u);
        b.pdf = select(0.0, b.pdf, mis);
        return b;
    }
    var next = bsdf_absorbed(d);
    if (USES_MIRROR || USES_GLOSSY) && (m.kind == MATERIAL_MIRROR || m.kind == MATERIAL_GLOSSY) {
        next = conductor_sample(m, d, s, u.xy);
    }
    if (USES_SMOOTH_DIELECTRIC || USES_ROUGH_DIELECTRIC) && m.kind == MATERIAL_DIELECTRIC {
        next = dielectric_sample(m, d, s, u, radiance);
    }
    if USES_THIN_DIELECTRIC && m.kind == MATERIAL_THIN_DIELECTRIC {
        next = sample_thin_dielectric(m, d, s, u.z);
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
