//! Lambertian reflection (`diffuse` in TOML and Mitsuba 3; pbrt-v4's DiffuseBxDF):
//! f = albedo / pi, sampled by cosine; SPPM's visible points lie on it.
//!
//! Parameters: `albedo`, linear RGB in [0, 1] (Mitsuba's `reflectance`, default 0.5; in a 0.x
//! scene also `diffuse_reflectance`), or a `texture` in its place; `one_sided`.
//! Kernel: `shaders/shared/bsdf/diffuse.wgsl`.

use super::{put_str, read_albedo, Features, GpuMaterial, MaterialKind, MitsubaBsdf, MitsubaPlugins, Result, TomlType};
use crate::layout::NO_TEXTURE;
use crate::scene::param::{self, Invalid, UNIT};
use crate::scene::toml_table::Table;
use crate::scene::Texture;
use glam::Vec3;

/// [`GpuMaterial::kind`] of a Lambertian surface.
pub const MATERIAL_DIFFUSE: u32 = 0;

pub(super) const TOML: TomlType = TomlType { name: "diffuse", keys: &["albedo", "texture"], read: read_toml };

fn read_toml(t: &Table, textures: &mut Vec<Texture>) -> Result<MaterialKind> {
    let (albedo, texture) = read_albedo(t, textures)?;
    Ok(MaterialKind::Diffuse { albedo, texture })
}

pub(super) const MITSUBA: MitsubaPlugins =
    MitsubaPlugins { names: &["diffuse"], read: from_mitsuba, params: &[("albedo", "reflectance")] };

fn from_mitsuba(p: &mut dyn MitsubaBsdf, _: &str) -> Result<MaterialKind> {
    // Mitsuba 0.6's diffuse takes its reflectance under either name.
    let legacy_name = p.legacy() && !p.has("reflectance") && p.has("diffuse_reflectance");
    let (albedo, texture) = p.reflectance(if legacy_name { "diffuse_reflectance" } else { "reflectance" }, 0.5)?;
    Ok(MaterialKind::Diffuse { albedo, texture })
}

pub(super) fn check(albedo: Vec3) -> std::result::Result<(), Invalid> {
    param::rgb("albedo", albedo, UNIT).map(drop)
}

pub(super) fn describe(texture: Option<u32>) -> &'static str {
    if texture.is_some() {
        "textured diffuse"
    } else {
        "diffuse"
    }
}

pub(super) fn toml_keys(t: &mut toml::Table) {
    put_str(t, "type", "diffuse");
}

pub(super) fn gpu(albedo: Vec3) -> GpuMaterial {
    GpuMaterial { kind: MATERIAL_DIFFUSE, albedo: albedo.into(), texture: NO_TEXTURE, ..GpuMaterial::default() }
}

/// Every kernel handles it: no feature to turn on.
pub(super) fn turn_on(_m: &GpuMaterial, _f: &mut Features) {}
