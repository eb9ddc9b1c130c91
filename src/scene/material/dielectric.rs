//! Dielectric interfaces (`dielectric`; Mitsuba's `dielectric` and `roughdielectric`):
//! reflection and refraction with the Fresnel probability, smooth or of microfacets (Walter
//! et al. 2007, eq. 20 and 21). Parameters: `ior` of the inside relative to the outside;
//! `roughness` (alpha, 0 smooth) and `distribution`; `reflectance` and `transmittance`
//! (Mitsuba's specular_reflectance and specular_transmittance) scaling each lobe. Two-sided
//! by nature. Kernel: `shaders/shared/bsdf/dielectric.wgsl`.

use super::{microfacet, put_float, put_str, put_vec3, Features, GpuMaterial, Microfacet, Named, Table, Vec3};
use crate::layout::{MATERIAL_DIELECTRIC, MICROFACET_BECKMANN, NO_TEXTURE};

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

pub(super) fn turn_on(m: &GpuMaterial, f: &mut Features) {
    let rough = m.kind == MATERIAL_DIELECTRIC && m.roughness > 0.0;
    f.smooth_dielectric |= m.kind == MATERIAL_DIELECTRIC && m.roughness == 0.0;
    f.rough_dielectric |= rough;
    f.beckmann |= rough && m.distribution == MICROFACET_BECKMANN;
}

pub(super) fn describe(roughness: f32) -> &'static str {
    if roughness > 0.0 {
        "rough dielectric"
    } else {
        "dielectric"
    }
}

pub(super) fn toml_keys(
    t: &mut Table,
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
