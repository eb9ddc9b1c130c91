//! Dielectric interfaces (`dielectric` in TOML; Mitsuba 3's `dielectric` and `roughdielectric`;
//! pbrt-v4's DielectricBxDF): glass, water. Reflection and refraction chosen with the Fresnel
//! probability, smooth (roughness 0) or of microfacets (Walter et al. 2007, eq. 20 and 21).
//! Two-sided by nature.
//!
//! Parameters: `ior` > 0, of the inside relative to the outside (Mitsuba: `int_ior` / `ext_ior`,
//! numbers or named media, by default bk7 over air; they must differ); `roughness` (alpha in
//! [0, 1], 0 smooth; Mitsuba's `alpha`, 0.1) and `distribution`; `reflectance` and
//! `transmittance` in [0, 1], each 1 unless given (Mitsuba's `specular_reflectance` and
//! `specular_transmittance`), scaling each lobe.
//! Kernel: `shaders/shared/bsdf/dielectric.wgsl`.

use super::{
    microfacet, put_float, put_str, put_vec3, read_distribution, read_tint, Features, GpuMaterial, MaterialKind, Microfacet,
    MitsubaBsdf, MitsubaPlugins, Named, Result, TomlType,
};
use crate::layout::{MICROFACET_BECKMANN, NO_TEXTURE};
use crate::scene::param::{self, Bound, Invalid, UNIT};
use crate::scene::toml_table::Table;
use crate::scene::Texture;
use glam::Vec3;

/// [`GpuMaterial::kind`] of a dielectric interface, smooth (roughness 0) or rough.
pub const MATERIAL_DIELECTRIC: u32 = 2;

pub(super) const TOML: TomlType =
    TomlType { name: "dielectric", keys: &["ior", "roughness", "distribution", "reflectance", "transmittance"], read: read_toml };

fn read_toml(t: &Table, _: &mut Vec<Texture>) -> Result<MaterialKind> {
    Ok(MaterialKind::Dielectric {
        ior: t.req("ior", |v| v.f32_in(Bound::Any))?,
        roughness: t.or("roughness", 0.0, |v| v.f32_in(Bound::Any))?,
        distribution: read_distribution(t)?,
        reflectance: read_tint(t, "reflectance")?,
        transmittance: read_tint(t, "transmittance")?,
    })
}

pub(super) const MITSUBA: MitsubaPlugins = MitsubaPlugins {
    names: &["dielectric", "roughdielectric"],
    read: from_mitsuba,
    params: &[
        ("ior", "int_ior"),
        ("roughness", "alpha"),
        ("reflectance", "specular_reflectance"),
        ("transmittance", "specular_transmittance"),
    ],
};

fn from_mitsuba(p: &mut dyn MitsubaBsdf, plugin: &str) -> Result<MaterialKind> {
    let ior = p.ior("int_ior", 1.5046)? / p.ior("ext_ior", 1.000277)?;
    if !(ior.is_finite() && ior > 0.0) || ior == 1.0 {
        return Err(p.error("int_ior", format!("int_ior / ext_ior = {ior}: an interface needs two different indices")));
    }
    let reflectance = p.constant_reflectance("specular_reflectance", 1.0)?;
    let transmittance = p.constant_reflectance("specular_transmittance", 1.0)?;
    let (roughness, distribution) = if plugin == "roughdielectric" { p.microfacets()? } else { (0.0, Microfacet::Ggx) };
    Ok(MaterialKind::Dielectric { ior, roughness, distribution, reflectance, transmittance })
}

pub(super) fn check(ior: f32, roughness: f32, reflectance: Vec3, transmittance: Vec3) -> std::result::Result<(), Invalid> {
    param::float("ior", ior, Bound::Positive)?;
    param::float("roughness", roughness, UNIT)?;
    param::rgb("reflectance", reflectance, UNIT)?;
    param::rgb("transmittance", transmittance, UNIT)?;
    Ok(())
}

pub(super) fn describe(roughness: f32) -> &'static str {
    if roughness > 0.0 {
        "rough dielectric"
    } else {
        "dielectric"
    }
}

pub(super) fn toml_keys(
    t: &mut toml::Table,
    ior: f32,
    roughness: f32,
    distribution: Microfacet,
    reflectance: Vec3,
    transmittance: Vec3,
) {
    put_str(t, "type", "dielectric");
    put_float(t, "ior", ior);
    put_float(t, "roughness", roughness);
    put_str(t, "distribution", distribution.name());
    put_vec3(t, "reflectance", reflectance);
    put_vec3(t, "transmittance", transmittance);
}

pub(super) fn gpu(ior: f32, roughness: f32, distribution: Microfacet, reflectance: Vec3, transmittance: Vec3) -> GpuMaterial {
    GpuMaterial {
        kind: MATERIAL_DIELECTRIC,
        albedo: [1.0; 3],
        ior,
        roughness,
        distribution: microfacet(distribution),
        specular: reflectance.into(),
        transmittance: transmittance.into(),
        texture: NO_TEXTURE,
        ..GpuMaterial::default()
    }
}

/// `USES_SMOOTH_DIELECTRIC` and `USES_ROUGH_DIELECTRIC`, `USES_BECKMANN`.
pub(super) fn turn_on(m: &GpuMaterial, f: &mut Features) {
    let rough = m.roughness > 0.0;
    f.smooth_dielectric |= !rough;
    f.rough_dielectric |= rough;
    f.beckmann |= rough && m.distribution == MICROFACET_BECKMANN;
}
