//! Conductors: the smooth `mirror` (Mitsuba's `conductor`) and the microfacet `glossy`
//! (`roughconductor`), f = albedo F(wo.h) D G / (4 cos_o cos_i) (Walter et al. 2007, eq. 20).
//! Parameters: `albedo` (specular_reflectance) or a texture in its place; glossy's
//! `roughness` (alpha) and `distribution`; the complex index of refraction `eta` + i `k` of
//! the Fresnel term (without it, F = 1); `one_sided`. Kernel:
//! `shaders/shared/bsdf/conductor.wgsl`.

use super::{microfacet, put_float, put_str, put_vec3, ComplexIor, Features, GpuMaterial, Microfacet, Named, Table, Vec3};
use crate::layout::{MATERIAL_GLOSSY, MATERIAL_MIRROR, MICROFACET_BECKMANN, NO_TEXTURE};

pub(super) fn gpu_mirror(albedo: Vec3, fresnel: Option<ComplexIor>) -> GpuMaterial {
    let mut g = GpuMaterial { kind: MATERIAL_MIRROR, albedo: albedo.into(), texture: NO_TEXTURE, ..GpuMaterial::default() };
    set_fresnel(&mut g, fresnel);
    g
}

pub(super) fn gpu_glossy(albedo: Vec3, roughness: f32, distribution: Microfacet, fresnel: Option<ComplexIor>) -> GpuMaterial {
    let mut g = GpuMaterial {
        kind: MATERIAL_GLOSSY,
        albedo: albedo.into(),
        roughness,
        distribution: microfacet(distribution),
        texture: NO_TEXTURE,
        ..GpuMaterial::default()
    };
    set_fresnel(&mut g, fresnel);
    g
}

/// The Fresnel term on the GPU: none (Fresnel 1, nothing computed) for no complex IOR or for
/// eta 0, k 1 exactly, Mitsuba's `none`, whose Fresnel term is 1.
fn set_fresnel(g: &mut GpuMaterial, fresnel: Option<ComplexIor>) {
    if let Some(ComplexIor { eta, k }) = fresnel {
        if eta != Vec3::ZERO || k != Vec3::ONE {
            g.fresnel = 1;
            g.eta = eta.into();
            g.k = k.into();
        }
    }
}

pub(super) fn turn_on(m: &GpuMaterial, f: &mut Features) {
    f.mirror |= m.kind == MATERIAL_MIRROR;
    f.glossy |= m.kind == MATERIAL_GLOSSY;
    f.conductor_fresnel |= m.fresnel != 0;
    f.beckmann |= m.kind == MATERIAL_GLOSSY && m.distribution == MICROFACET_BECKMANN;
}

pub(super) fn describe(rough: bool, texture: Option<u32>) -> &'static str {
    match (rough, texture.is_some()) {
        (false, false) => "mirror",
        (false, true) => "textured mirror",
        (true, false) => "glossy conductor",
        (true, true) => "textured glossy conductor",
    }
}

/// `roughness` and `distribution` are written for a glossy conductor (`rough`) only.
pub(super) fn toml_keys(t: &mut Table, rough: Option<(f32, Microfacet)>, fresnel: Option<ComplexIor>) {
    put_str(t, "type", if rough.is_some() { "glossy" } else { "mirror" });
    if let Some((roughness, distribution)) = rough {
        put_float(t, "roughness", roughness);
        put_str(t, "distribution", distribution.name());
    }
    if let Some(ComplexIor { eta, k }) = fresnel {
        put_vec3(t, "eta", eta);
        put_vec3(t, "k", k);
    }
}
