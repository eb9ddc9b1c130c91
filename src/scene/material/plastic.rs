//! Plastics (`plastic`; Mitsuba's `plastic` and `roughplastic`): a dielectric coating, smooth
//! or of microfacets, over a Lambertian base, with the light trapped between them summed
//! ([`crate::scene::coating`] computes what the kernels look up). Parameters: `albedo`
//! (diffuse_reflectance) or a texture in its place; `specular` (specular_reflectance); `ior`
//! of the coating; `roughness` (alpha, 0 smooth) and `distribution`; `nonlinear`;
//! `one_sided`. Kernel: `shaders/shared/bsdf/plastic.wgsl`.

use super::{microfacet, put_float, put_str, put_vec3, Features, GpuMaterial, Microfacet, Named, Table, Value, Vec3};
use crate::layout::{MATERIAL_PLASTIC, MICROFACET_BECKMANN, NO_TEXTURE};
use crate::scene::coating::{fresnel_diffuse_reflectance, rough_coating, RoughCoating};
use crate::scene::Texture;

/// The plastic's parameters, as [`super::MaterialKind::Plastic`] holds them.
pub(super) struct Plastic {
    pub albedo: Vec3,
    pub texture: Option<u32>,
    pub specular: Vec3,
    pub ior: f32,
    pub roughness: f32,
    pub distribution: Microfacet,
    pub nonlinear: bool,
}

/// On the GPU (Mitsuba 3's `parameters_changed`): the probability weight of its coating's
/// lobe, mean(specular) / (mean(albedo) + mean(specular)); Fdr, the coating's diffuse
/// reflectance from inside, by the fit for a smooth coating and by quadrature for a rough one,
/// whose transmittance table goes at the end of `attributes`.
pub(super) fn gpu(p: &Plastic, textures: &[Texture], attributes: &mut Vec<[f32; 4]>) -> GpuMaterial {
    let mut g = GpuMaterial {
        kind: MATERIAL_PLASTIC,
        albedo: p.albedo.into(),
        specular: p.specular.into(),
        ior: p.ior,
        roughness: p.roughness,
        distribution: microfacet(p.distribution),
        nonlinear: p.nonlinear as u32,
        texture: NO_TEXTURE,
        ..GpuMaterial::default()
    };
    // Mitsuba's weight takes a texture's mean over its texels.
    let base = match p.texture {
        Some(t) => textures[t as usize].texels.iter().sum::<Vec3>() / textures[t as usize].texels.len().max(1) as f32,
        None => p.albedo,
    };
    let (d_mean, s_mean) = (base.element_sum() / 3.0, p.specular.element_sum() / 3.0);
    g.coat_weight = s_mean / (d_mean + s_mean);
    if p.roughness == 0.0 {
        g.coat_fdr = fresnel_diffuse_reflectance(1.0 / p.ior);
        return g;
    }
    let coat = rough_coating_cached(p.ior, p.roughness, p.distribution);
    g.coat_fdr = coat.internal_reflectance;
    g.coat_table = attributes.len() as u32;
    attributes.extend(coat.transmittance.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]));
    g
}

/// [`rough_coating`], computed once per process for each coating (a quadrature of a million
/// points for the internal reflectance).
fn rough_coating_cached(ior: f32, alpha: f32, distribution: Microfacet) -> RoughCoating {
    use std::sync::Mutex;
    type Key = (u32, u32, bool);
    static CACHE: Mutex<Vec<(Key, RoughCoating)>> = Mutex::new(Vec::new());
    let key = (ior.to_bits(), alpha.to_bits(), distribution == Microfacet::Beckmann);
    if let Some((_, c)) = CACHE.lock().unwrap().iter().find(|(k, _)| *k == key) {
        return c.clone();
    }
    let c = rough_coating(ior, alpha, distribution);
    CACHE.lock().unwrap().push((key, c.clone()));
    c
}

pub(super) fn turn_on(m: &GpuMaterial, f: &mut Features) {
    let rough = m.kind == MATERIAL_PLASTIC && m.roughness > 0.0;
    f.plastic |= m.kind == MATERIAL_PLASTIC && m.roughness == 0.0;
    f.rough_plastic |= rough;
    f.beckmann |= rough && m.distribution == MICROFACET_BECKMANN;
}

pub(super) fn describe(roughness: f32) -> &'static str {
    if roughness > 0.0 {
        "rough plastic"
    } else {
        "plastic"
    }
}

pub(super) fn toml_keys(t: &mut Table, p: &Plastic) {
    put_str(t, "type", "plastic");
    put_vec3(t, "specular", p.specular);
    put_float(t, "ior", p.ior);
    put_float(t, "roughness", p.roughness);
    put_str(t, "distribution", p.distribution.name());
    t.insert("nonlinear".into(), Value::Boolean(p.nonlinear));
}
