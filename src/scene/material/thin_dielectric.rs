//! Thin dielectric slabs (`thin_dielectric`; Mitsuba's `thindielectric`) and the invisible
//! `null` surface, drawn as a slab of index 1: reflection with the slab's summed reflectance
//! 2R / (1 + R), the rest passed straight through. Parameters: `ior` of the slab;
//! `reflectance` and `transmittance` scaling each lobe. Two-sided by nature. Kernel:
//! `shaders/shared/bsdf/thin_dielectric.wgsl`.

use super::{put_float, put_str, put_vec3, Features, GpuMaterial, Table, Vec3};
use crate::layout::{MATERIAL_THIN_DIELECTRIC, NO_TEXTURE};

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

pub(super) fn turn_on(m: &GpuMaterial, f: &mut Features) {
    f.thin_dielectric |= m.kind == MATERIAL_THIN_DIELECTRIC;
}

pub(super) fn toml_keys(t: &mut Table, ior: f32, reflectance: Vec3, transmittance: Vec3) {
    put_str(t, "type", "thin_dielectric");
    put_float(t, "ior", ior);
    put_vec3(t, "reflectance", reflectance);
    put_vec3(t, "transmittance", transmittance);
}
