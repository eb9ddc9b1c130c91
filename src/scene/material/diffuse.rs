//! Lambertian reflection (`diffuse` in TOML and Mitsuba): f = albedo / pi, sampled by cosine;
//! SPPM's visible points lie on it. Parameters: `albedo` (linear RGB in [0, 1]) or a texture
//! in its place; `one_sided`. Kernel: `shaders/shared/bsdf/diffuse.wgsl`.

use super::{put_str, Features, GpuMaterial, Table, Vec3};
use crate::layout::{MATERIAL_DIFFUSE, NO_TEXTURE};

pub(super) fn gpu(albedo: Vec3) -> GpuMaterial {
    GpuMaterial { kind: MATERIAL_DIFFUSE, albedo: albedo.into(), texture: NO_TEXTURE, ..GpuMaterial::default() }
}

/// Every kernel handles it: no feature to turn on.
pub(super) fn turn_on(_m: &GpuMaterial, _f: &mut Features) {}

pub(super) fn describe(texture: Option<u32>) -> &'static str {
    if texture.is_some() {
        "textured diffuse"
    } else {
        "diffuse"
    }
}

pub(super) fn toml_keys(t: &mut Table) {
    put_str(t, "type", "diffuse");
}
