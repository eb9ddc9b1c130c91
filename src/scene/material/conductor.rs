//! Conductors (`mirror` and `glossy` in TOML; Mitsuba 3's `conductor` and `roughconductor`;
//! pbrt-v4's ConductorBxDF): one family, smooth when its roughness is 0.
//! - Smooth: a mirror, weight albedo F(cos_o).
//! - Rough: microfacets, f = albedo F(wo.h) D G / (4 cos_o cos_i) (Walter et al. 2007, eq. 20).
//!
//! F is the Fresnel reflectance of the complex index of refraction eta + i k; without one it
//! is 1.
//!
//! Parameters: `albedo` (Mitsuba's `specular_reflectance`, default 1), linear RGB in [0, 1], or
//! a `texture` in its place; `roughness` (alpha in [0, 1], Mitsuba's `alpha`, default 0.1) and
//! `distribution` (`ggx`, the TOML default, or `beckmann`, Mitsuba's); `eta` and `k`, each >= 0,
//! given together (Mitsuba: `eta` and `k`, or a named metal as `material`); a
//! `mirror` has no roughness, a `glossy` needs one; `one_sided`.
//! Kernel: `shaders/shared/bsdf/conductor.wgsl`.

use super::{
    microfacet, put_float, put_str, put_vec3, read_albedo, read_distribution, ComplexIor, Features, GpuMaterial, MaterialKind,
    Microfacet, MitsubaBsdf, MitsubaPlugins, Named, Result, TomlType,
};
use crate::layout::{MICROFACET_BECKMANN, NO_TEXTURE};
use crate::scene::param::{self, Bound, Invalid, UNIT};
use crate::scene::toml_table::Table;
use crate::scene::Texture;
use glam::Vec3;

/// [`GpuMaterial::kind`] of a conductor, smooth (roughness 0) or rough.
pub const MATERIAL_CONDUCTOR: u32 = 1;

/// A smooth conductor.
pub(super) const MIRROR: TomlType = TomlType { name: "mirror", keys: &["albedo", "texture", "eta", "k"], read: read_mirror };

/// A rough conductor.
pub(super) const GLOSSY: TomlType =
    TomlType { name: "glossy", keys: &["albedo", "texture", "roughness", "distribution", "eta", "k"], read: read_glossy };

fn read_mirror(t: &Table, textures: &mut Vec<Texture>) -> Result<MaterialKind> {
    let (albedo, texture) = read_albedo(t, textures)?;
    Ok(MaterialKind::Conductor { albedo, texture, roughness: 0.0, distribution: Microfacet::Ggx, fresnel: read_fresnel(t)? })
}

fn read_glossy(t: &Table, textures: &mut Vec<Texture>) -> Result<MaterialKind> {
    let (albedo, texture) = read_albedo(t, textures)?;
    Ok(MaterialKind::Conductor {
        albedo,
        texture,
        roughness: t.req("roughness", |v| v.f32_in(Bound::Any))?,
        distribution: read_distribution(t)?,
        fresnel: read_fresnel(t)?,
    })
}

/// `eta` and `k` together, or neither (no Fresnel term: the albedo alone).
fn read_fresnel(t: &Table) -> Result<Option<ComplexIor>> {
    let eta = t.opt("eta", |v| v.rgb(Bound::Any))?;
    let k = t.opt("k", |v| v.rgb(Bound::Any))?;
    match (eta, k) {
        (Some(eta), Some(k)) => Ok(Some(ComplexIor { eta, k })),
        (None, None) => Ok(None),
        (Some(_), None) => Err(t.error_at("eta", "a conductor's `eta` needs its `k`")),
        (None, Some(_)) => Err(t.error_at("k", "a conductor's `k` needs its `eta`")),
    }
}

pub(super) const MITSUBA: MitsubaPlugins = MitsubaPlugins {
    names: &["conductor", "roughconductor"],
    read: from_mitsuba,
    params: &[("albedo", "specular_reflectance"), ("roughness", "alpha")],
};

fn from_mitsuba(p: &mut dyn MitsubaBsdf, plugin: &str) -> Result<MaterialKind> {
    let fresnel = p.complex_ior()?;
    let (albedo, texture) = p.reflectance("specular_reflectance", 1.0)?;
    let (roughness, distribution) = if plugin == "roughconductor" { p.microfacets()? } else { (0.0, Microfacet::Ggx) };
    Ok(MaterialKind::Conductor { albedo, texture, roughness, distribution, fresnel })
}

pub(super) fn check(albedo: Vec3, roughness: f32, fresnel: Option<ComplexIor>) -> std::result::Result<(), Invalid> {
    param::rgb("albedo", albedo, UNIT)?;
    param::float("roughness", roughness, UNIT)?;
    if let Some(ComplexIor { eta, k }) = fresnel {
        param::rgb("eta", eta, Bound::NonNegative)?;
        param::rgb("k", k, Bound::NonNegative)?;
    }
    Ok(())
}

pub(super) fn describe(roughness: f32, texture: Option<u32>) -> &'static str {
    match (roughness > 0.0, texture.is_some()) {
        (false, false) => "mirror",
        (false, true) => "textured mirror",
        (true, false) => "glossy conductor",
        (true, true) => "textured glossy conductor",
    }
}

/// A smooth conductor as a `mirror`, a rough one as a `glossy` with its roughness and
/// distribution.
pub(super) fn toml_keys(t: &mut toml::Table, roughness: f32, distribution: Microfacet, fresnel: Option<ComplexIor>) {
    put_str(t, "type", if roughness > 0.0 { "glossy" } else { "mirror" });
    if roughness > 0.0 {
        put_float(t, "roughness", roughness);
        put_str(t, "distribution", distribution.name());
    }
    if let Some(ComplexIor { eta, k }) = fresnel {
        put_vec3(t, "eta", eta);
        put_vec3(t, "k", k);
    }
}

/// On the GPU the Fresnel term is left out (F = 1, nothing computed) for no complex IOR, and
/// for eta 0, k 1 exactly: Mitsuba's `none`, whose Fresnel term is 1.
pub(super) fn gpu(albedo: Vec3, roughness: f32, distribution: Microfacet, fresnel: Option<ComplexIor>) -> GpuMaterial {
    let mut g = GpuMaterial { kind: MATERIAL_CONDUCTOR, albedo: albedo.into(), texture: NO_TEXTURE, ..GpuMaterial::default() };
    if roughness > 0.0 {
        g.roughness = roughness;
        g.distribution = microfacet(distribution);
    }
    if let Some(ComplexIor { eta, k }) = fresnel {
        if eta != Vec3::ZERO || k != Vec3::ONE {
            g.fresnel = 1;
            g.eta = eta.into();
            g.k = k.into();
        }
    }
    g
}

/// `USES_MIRROR` and `USES_GLOSSY` (the smooth and the rough lobe), `USES_CONDUCTOR_FRESNEL`,
/// `USES_BECKMANN`.
pub(super) fn turn_on(m: &GpuMaterial, f: &mut Features) {
    let rough = m.roughness > 0.0;
    f.mirror |= !rough;
    f.glossy |= rough;
    f.conductor_fresnel |= m.fresnel != 0;
    f.beckmann |= rough && m.distribution == MICROFACET_BECKMANN;
}
