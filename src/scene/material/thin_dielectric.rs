//! Thin dielectric slabs (`thin_dielectric` in TOML; Mitsuba 3's `thindielectric`) and the
//! invisible `null` surface (Mitsuba 3's `null`), drawn as a slab of index 1: reflection with
//! the slab's summed reflectance 2R / (1 + R), the rest passed straight through, unbent.
//! Two-sided by nature.
//!
//! Parameters: `ior` > 0 of the slab (`int_ior` / `ext_ior`, bk7 over air); `reflectance` and
//! `transmittance` in [0, 1] (`specular_reflectance`, `specular_transmittance`, 1) scaling
//! each lobe. `null` has none.
//! Kernel: `shaders/shared/bsdf/thin_dielectric.wgsl`.

use super::{
    put_float, put_str, put_vec3, read_tint, Features, GpuMaterial, MaterialKind, MitsubaBsdf, MitsubaPlugins, Result, TomlType,
};
use crate::layout::NO_TEXTURE;
use crate::scene::param::{self, Bound, Invalid, UNIT};
use crate::scene::toml_table::Table;
use crate::scene::Texture;
use glam::Vec3;

/// [`GpuMaterial::kind`] of a thin dielectric slab (and of `null`, a slab of index 1).
pub const MATERIAL_THIN_DIELECTRIC: u32 = 5;

pub(super) const TOML: TomlType =
    TomlType { name: "thin_dielectric", keys: &["ior", "reflectance", "transmittance"], read: read_toml };

pub(super) const NULL: TomlType = TomlType { name: "null", keys: &[], read: read_null };

fn read_null(_: &Table, _: &mut Vec<Texture>) -> Result<MaterialKind> {
    Ok(MaterialKind::Null)
}

fn read_toml(t: &Table, _: &mut Vec<Texture>) -> Result<MaterialKind> {
    Ok(MaterialKind::ThinDielectric {
        ior: t.req("ior", |v| v.f32_in(Bound::Any))?,
        reflectance: read_tint(t, "reflectance")?,
        transmittance: read_tint(t, "transmittance")?,
    })
}

pub(super) const MITSUBA: MitsubaPlugins = MitsubaPlugins {
    names: &["thindielectric", "null"],
    read: from_mitsuba,
    params: &[("ior", "int_ior"), ("reflectance", "specular_reflectance"), ("transmittance", "specular_transmittance")],
};

fn from_mitsuba(p: &mut dyn MitsubaBsdf, plugin: &str) -> Result<MaterialKind> {
    if plugin == "null" {
        return Ok(MaterialKind::Null);
    }
    let ior = p.ior("int_ior", 1.5046)? / p.ior("ext_ior", 1.000277)?;
    if !(ior.is_finite() && ior > 0.0) {
        return Err(p.error("int_ior", format!("int_ior / ext_ior = {ior} is not a ratio of indices")));
    }
    let reflectance = p.constant_reflectance("specular_reflectance", 1.0)?;
    let transmittance = p.constant_reflectance("specular_transmittance", 1.0)?;
    Ok(MaterialKind::ThinDielectric { ior, reflectance, transmittance })
}

pub(super) fn check(ior: f32, reflectance: Vec3, transmittance: Vec3) -> std::result::Result<(), Invalid> {
    param::float("ior", ior, Bound::Positive)?;
    param::rgb("reflectance", reflectance, UNIT)?;
    param::rgb("transmittance", transmittance, UNIT)?;
    Ok(())
}

pub(super) fn describe(null: bool) -> &'static str {
    if null {
        "null"
    } else {
        "thin dielectric"
    }
}

pub(super) fn toml_keys(t: &mut toml::Table, ior: f32, reflectance: Vec3, transmittance: Vec3) {
    put_str(t, "type", "thin_dielectric");
    put_float(t, "ior", ior);
    put_vec3(t, "reflectance", reflectance);
    put_vec3(t, "transmittance", transmittance);
}

pub(super) fn null_toml_keys(t: &mut toml::Table) {
    put_str(t, "type", "null");
}

pub(super) fn gpu(ior: f32, reflectance: Vec3, transmittance: Vec3) -> GpuMaterial {
    GpuMaterial {
        kind: MATERIAL_THIN_DIELECTRIC,
        albedo: [1.0; 3],
        ior,
        specular: reflectance.into(),
        transmittance: transmittance.into(),
        texture: NO_TEXTURE,
        ..GpuMaterial::default()
    }
}

/// Mitsuba's `null`: a slab of index 1, Fresnel reflectance 0, everything passes unbent.
pub(super) fn gpu_null() -> GpuMaterial {
    gpu(1.0, Vec3::ZERO, Vec3::ONE)
}

/// `USES_THIN_DIELECTRIC`.
pub(super) fn turn_on(_m: &GpuMaterial, f: &mut Features) {
    f.thin_dielectric = true;
}
