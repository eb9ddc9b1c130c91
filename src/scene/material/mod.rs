//! Materials: the scattering models a surface can have, one file a BSDF family, as the
//! kernels have them (`shaders/shared/bsdf/<family>.wgsl`, called through the dispatcher
//! `shaders/shared/bsdf.wgsl`). Each family's file holds what the host does with it: its
//! GPU packing ([`GpuMaterial`]), the kernel features it turns on ([`Features`]), its name
//! in `info` and its keys in a written TOML scene. The readers (`scene/load.rs`,
//! `scene/mitsuba/bsdf.rs`) build the [`MaterialKind`]s.
//!
//! Adding a family: its variant here and a branch in each dispatcher below, its file in this
//! folder, its WGSL file and a branch in `bsdf.wgsl`'s functions, a `MATERIAL_*` kind
//! (`layout/records.rs` and `types.wgsl`), and the readers.

mod conductor;
mod dielectric;
mod diffuse;
mod plastic;
mod thin_dielectric;

use super::Named;
use crate::layout::Features;
use crate::layout::{GpuMaterial, MATERIAL_DIELECTRIC, MATERIAL_THIN_DIELECTRIC, MICROFACET_BECKMANN, MICROFACET_GGX};
use glam::Vec3;
use toml::{Table, Value};

/// A material's scattering model.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialKind {
    /// Lambertian; `texture` (index into `Scene::textures`) replaces `albedo` when present.
    Diffuse {
        /// Reflectance, linear RGB in [0, 1] (`[1, 1, 1]` when textured).
        albedo: Vec3,
        /// Index into [`Scene::textures`](super::Scene::textures).
        texture: Option<u32>,
    },
    /// Perfect specular reflector.
    Mirror {
        /// Reflectance, linear RGB in [0, 1], times the Fresnel term when there is one.
        albedo: Vec3,
        /// Index into [`Scene::textures`](super::Scene::textures) of a texture that replaces `albedo` (Mitsuba's
        /// textured `specular_reflectance`).
        texture: Option<u32>,
        /// The conductor's complex index of refraction, whose Fresnel reflectance scales
        /// `albedo`; `None` is Fresnel 1 (a perfect mirror; every TOML material).
        fresnel: Option<ComplexIor>,
    },
    /// Microfacet conductor; roughness is the distribution's alpha.
    Glossy {
        /// Reflectance, linear RGB in [0, 1], times the Fresnel term when there is one.
        albedo: Vec3,
        /// Index into [`Scene::textures`](super::Scene::textures) of a texture that replaces `albedo`.
        texture: Option<u32>,
        /// Alpha in [0, 1].
        roughness: f32,
        /// The distribution of microfacet normals.
        distribution: Microfacet,
        /// The conductor's complex index of refraction, whose Fresnel reflectance at the
        /// microfacet normal scales `albedo`; `None` is Fresnel 1.
        fresnel: Option<ComplexIor>,
    },
    /// Dielectric interface; roughness 0 is smooth, otherwise the microfacet alpha (Walter et
    /// al. 2007).
    Dielectric {
        /// Index of refraction of the inside relative to the outside.
        ior: f32,
        /// Alpha in [0, 1]; 0 is smooth.
        roughness: f32,
        /// The distribution of microfacet normals of a rough interface.
        distribution: Microfacet,
        /// Factor on reflected light (Mitsuba's `specular_reflectance`; 1 is physical), linear
        /// RGB in [0, 1]. The lobe is still chosen with the Fresnel probability.
        reflectance: Vec3,
        /// Factor on refracted light (`specular_transmittance`; 1 is physical), [0, 1].
        transmittance: Vec3,
    },
    /// Mitsuba 3's `plastic` (roughness 0) and `roughplastic`: a dielectric coating, smooth or
    /// of microfacets, over a Lambertian base, with the light trapped between them summed
    /// ([`crate::scene::coating`]).
    Plastic {
        /// The base's reflectance, linear RGB in [0, 1] (`diffuse_reflectance`; `[1, 1, 1]`
        /// when textured).
        albedo: Vec3,
        /// Index into [`Scene::textures`](super::Scene::textures) of the texture that replaces `albedo`.
        texture: Option<u32>,
        /// The coating's reflection is scaled by it (`specular_reflectance`, [0, 1]).
        specular: Vec3,
        /// Index of refraction of the coating relative to the outside.
        ior: f32,
        /// Alpha in (0, 1] of a rough coating; 0 is smooth.
        roughness: f32,
        /// The distribution of microfacet normals of a rough coating.
        distribution: Microfacet,
        /// Mitsuba's `nonlinear`: the base's light trapped in the coating darkens and
        /// saturates its colour, 1 / (1 - albedo Fdr), rather than 1 / (1 - Fdr).
        nonlinear: bool,
    },
    /// Mitsuba 3's `thindielectric`: a slab too thin to see, reflecting with the slab's summed
    /// reflectance R' = R + T^2 R / (1 - R^2) = 2R / (1 + R) and transmitting the rest
    /// straight through, unbent.
    ThinDielectric {
        /// Index of refraction of the slab relative to the outside.
        ior: f32,
        /// Scales the reflection (`specular_reflectance`, [0, 1]).
        reflectance: Vec3,
        /// Scales the transmission (`specular_transmittance`, [0, 1]).
        transmittance: Vec3,
    },
    /// Mitsuba 3's `null`: an invisible surface. Rays and photons pass straight through it
    /// with weight 1 (a forward delta, null.cpp), counting a bounce; no light is sampled
    /// there, and shadow rays stop at it like at any surface. The kernels draw it as a
    /// thin dielectric of index 1, which reflects nothing.
    Null,
}

impl MaterialKind {
    /// The texture that replaces the kind's albedo (a diffuse reflectance, a conductor's
    /// specular reflectance), if any: on the GPU, any material's albedo may come from one.
    pub fn texture(&self) -> Option<u32> {
        self.albedo().and_then(|(_, texture)| texture)
    }

    /// The reflectance of the kinds that have one (a diffuse reflectance, a conductor's
    /// specular reflectance, a plastic's base), with the texture that replaces it, if any.
    pub fn albedo(&self) -> Option<(Vec3, Option<u32>)> {
        match *self {
            MaterialKind::Diffuse { albedo, texture }
            | MaterialKind::Mirror { albedo, texture, .. }
            | MaterialKind::Glossy { albedo, texture, .. }
            | MaterialKind::Plastic { albedo, texture, .. } => Some((albedo, texture)),
            MaterialKind::Dielectric { .. } | MaterialKind::ThinDielectric { .. } | MaterialKind::Null => None,
        }
    }

    /// Whether the kind is two-sided by nature, ignoring [`Material::one_sided`]: dielectrics,
    /// thin or not (Mitsuba 3's ignore `twosided`), and `null`.
    pub fn two_sided_by_nature(&self) -> bool {
        matches!(self, MaterialKind::Dielectric { .. } | MaterialKind::ThinDielectric { .. } | MaterialKind::Null)
    }

    /// Whether the kind hides lights from path tracing's next-event estimation, as
    /// `integrators::limitations` warns: mirrors, glass, smooth or rough (light behind it is
    /// found by hitting the light), thin glass, null and smooth plastics' coatings.
    pub fn hides_lights(&self) -> bool {
        match *self {
            MaterialKind::Mirror { .. }
            | MaterialKind::Dielectric { .. }
            | MaterialKind::ThinDielectric { .. }
            | MaterialKind::Null => true,
            MaterialKind::Plastic { roughness, .. } => roughness == 0.0,
            MaterialKind::Diffuse { .. } | MaterialKind::Glossy { .. } => false,
        }
    }

    /// The kind as `info` names it.
    pub fn describe(&self) -> &'static str {
        match *self {
            MaterialKind::Diffuse { texture, .. } => diffuse::describe(texture),
            MaterialKind::Mirror { texture, .. } => conductor::describe(false, texture),
            MaterialKind::Glossy { texture, .. } => conductor::describe(true, texture),
            MaterialKind::Dielectric { roughness, .. } => dielectric::describe(roughness),
            MaterialKind::Plastic { roughness, .. } => plastic::describe(roughness),
            MaterialKind::ThinDielectric { .. } => "thin dielectric",
            MaterialKind::Null => "null",
        }
    }

    /// The kind's keys in a TOML `[materials]` entry: `type` and its parameters, but for the
    /// albedo or the texture in its place ([`MaterialKind::albedo`]), which the writer puts
    /// with the texture's file.
    pub fn toml_keys(&self, t: &mut Table) {
        match *self {
            MaterialKind::Diffuse { .. } => diffuse::toml_keys(t),
            MaterialKind::Mirror { fresnel, .. } => conductor::toml_keys(t, None, fresnel),
            MaterialKind::Glossy { roughness, distribution, fresnel, .. } => {
                conductor::toml_keys(t, Some((roughness, distribution)), fresnel)
            }
            MaterialKind::Dielectric { ior, roughness, distribution, reflectance, transmittance } => {
                dielectric::toml_keys(t, ior, roughness, distribution, reflectance, transmittance)
            }
            MaterialKind::Plastic { .. } => plastic::toml_keys(t, &self.plastic()),
            MaterialKind::ThinDielectric { ior, reflectance, transmittance } => {
                thin_dielectric::toml_keys(t, ior, reflectance, transmittance)
            }
            MaterialKind::Null => put_str(t, "type", "null"),
        }
    }

    /// The kind on the GPU: its `MATERIAL_*` kind and parameters, without a texture (the
    /// caller sets [`GpuMaterial::texture`] and `one_sided`). A rough plastic's table of
    /// coating transmittance goes at the end of `attributes`.
    pub fn gpu(&self, textures: &[super::Texture], attributes: &mut Vec<[f32; 4]>) -> GpuMaterial {
        match *self {
            MaterialKind::Diffuse { albedo, .. } => diffuse::gpu(albedo),
            MaterialKind::Mirror { albedo, fresnel, .. } => conductor::gpu_mirror(albedo, fresnel),
            MaterialKind::Glossy { albedo, roughness, distribution, fresnel, .. } => {
                conductor::gpu_glossy(albedo, roughness, distribution, fresnel)
            }
            MaterialKind::Dielectric { ior, roughness, distribution, reflectance, transmittance } => {
                dielectric::gpu(ior, roughness, distribution, reflectance, transmittance)
            }
            MaterialKind::Plastic { .. } => plastic::gpu(&self.plastic(), textures, attributes),
            MaterialKind::ThinDielectric { ior, reflectance, transmittance } => {
                thin_dielectric::gpu(ior, reflectance, transmittance)
            }
            MaterialKind::Null => thin_dielectric::gpu_null(),
        }
    }

    /// A plastic's parameters (defaults for any other kind).
    fn plastic(&self) -> plastic::Plastic {
        match *self {
            MaterialKind::Plastic { albedo, texture, specular, ior, roughness, distribution, nonlinear } => {
                plastic::Plastic { albedo, texture, specular, ior, roughness, distribution, nonlinear }
            }
            _ => plastic::Plastic {
                albedo: Vec3::ZERO,
                texture: None,
                specular: Vec3::ZERO,
                ior: 1.0,
                roughness: 0.0,
                distribution: Microfacet::Ggx,
                nonlinear: false,
            },
        }
    }
}

/// Turn on the kernel features ([`Features`]) that material `m`, as on the GPU, needs: its
/// family's `USES_*` overrides.
pub fn turn_on_features(m: &GpuMaterial, f: &mut Features) {
    use crate::layout::{MATERIAL_DIFFUSE, MATERIAL_GLOSSY, MATERIAL_MIRROR, MATERIAL_PLASTIC};
    match m.kind {
        MATERIAL_DIFFUSE => diffuse::turn_on(m, f),
        MATERIAL_MIRROR | MATERIAL_GLOSSY => conductor::turn_on(m, f),
        MATERIAL_DIELECTRIC => dielectric::turn_on(m, f),
        MATERIAL_THIN_DIELECTRIC => thin_dielectric::turn_on(m, f),
        MATERIAL_PLASTIC => plastic::turn_on(m, f),
        _ => {}
    }
    // Dielectrics, thin ones too, are two-sided by nature and pack one_sided as 0.
    f.one_sided |= m.one_sided != 0 && m.kind != MATERIAL_DIELECTRIC;
}

/// [`GpuMaterial::distribution`] of a microfacet distribution.
fn microfacet(distribution: Microfacet) -> u32 {
    match distribution {
        Microfacet::Ggx => MICROFACET_GGX,
        Microfacet::Beckmann => MICROFACET_BECKMANN,
    }
}

fn put_str(t: &mut Table, key: &str, value: &str) {
    t.insert(key.into(), Value::String(value.into()));
}

fn put_float(t: &mut Table, key: &str, x: f32) {
    t.insert(key.into(), Value::Float(x as f64));
}

fn put_vec3(t: &mut Table, key: &str, v: Vec3) {
    t.insert(key.into(), Value::Array(v.to_array().iter().map(|&x| Value::Float(x as f64)).collect()));
}

/// A distribution of microfacet normals, isotropic, with Smith's separable masking (as
/// Mitsuba 3's `MicrofacetDistribution`, sampled by visible normals).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Microfacet {
    /// GGX (Trowbridge-Reitz; Walter et al. 2007, eq. 33): every TOML material.
    #[default]
    Ggx,
    /// Beckmann (Walter et al. 2007, eq. 25): Mitsuba's default for its rough BSDFs.
    Beckmann,
}

impl super::Named for Microfacet {
    const WHAT: &'static str = "distribution";
    const NAMES: &'static [(&'static str, Self)] = &[("ggx", Microfacet::Ggx), ("beckmann", Microfacet::Beckmann)];
}

/// A conductor's complex index of refraction eta + i k relative to the outside, per RGB
/// channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplexIor {
    /// Real part, >= 0.
    pub eta: Vec3,
    /// Imaginary part (the absorption coefficient), >= 0.
    pub k: Vec3,
}

/// One `[materials]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The entry's key, which shapes name it by.
    pub name: String,
    /// Its scattering model and parameters.
    pub kind: MaterialKind,
    /// Black when seen from behind its shading normal, as Mitsuba's BSDFs are unless
    /// wrapped in `twosided`. TOML materials are two-sided; dielectrics ignore it.
    pub one_sided: bool,
    /// Line of the material's entry in `[materials]`.
    pub line: usize,
}
