//! Materials: the scattering models a surface can have, one file a BSDF family, as Mitsuba 3
//! keeps one plugin a file. A family's file documents its model and parameters at the top and
//! owns what the host does with it: its TOML types and their keys, its Mitsuba plugins
//! (through `MitsubaBsdf`), the checks of its parameters (written once, for every reader
//! and [`super::SceneBuilder`]), its name in `info`, its keys in a converted TOML scene, its
//! `MATERIAL_*` kind, its GPU packing ([`GpuMaterial`]) and the kernel features it turns on
//! ([`Features`]). Its kernel is `shaders/shared/bsdf/<family>.wgsl`, called through the
//! dispatcher `shaders/shared/bsdf.wgsl`.
//!
//! This file dispatches to them: a new family is its variant, an arm in each `match` (the
//! compiler lists those that lack it) and its entries in `TOML_TYPES` and
//! `MITSUBA_PLUGINS` (`tests/suite/dispatch.rs` checks that every family is in each
//! dispatcher).

mod conductor;
mod dielectric;
mod diffuse;
mod plastic;
mod thin_dielectric;

pub use conductor::MATERIAL_CONDUCTOR;
pub use dielectric::MATERIAL_DIELECTRIC;
pub use diffuse::MATERIAL_DIFFUSE;
pub use plastic::MATERIAL_PLASTIC;
pub use plastic::MAX_SCATTERINGS;
pub use thin_dielectric::MATERIAL_THIN_DIELECTRIC;

use super::mesh;
use super::param::{Bound, Invalid};
use super::toml_table::{put_float, put_str, put_vec3, Table, Value};
use super::{Named, SceneError, Texture, TextureFilter, TextureWrap};
use crate::layout::{Features, GpuMaterial, MICROFACET_BECKMANN, MICROFACET_GGX};
use glam::Vec3;
use toml::de::DeValue;

type Result<T> = std::result::Result<T, SceneError>;

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
    /// A conductor: a mirror when `roughness` is 0, else microfacets of that alpha (pbrt-v4's
    /// ConductorBxDF, smooth when its roughness is zero).
    Conductor {
        /// Reflectance, linear RGB in [0, 1], times the Fresnel term when there is one.
        albedo: Vec3,
        /// Index into [`Scene::textures`](super::Scene::textures) of a texture that replaces
        /// `albedo` (Mitsuba's textured `specular_reflectance`).
        texture: Option<u32>,
        /// Alpha in [0, 1]; 0 is a mirror.
        roughness: f32,
        /// The distribution of microfacet normals of a rough conductor.
        distribution: Microfacet,
        /// The conductor's complex index of refraction, whose Fresnel reflectance (at the
        /// microfacet normal when rough) scales `albedo`; `None` is Fresnel 1.
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
        /// Optical thickness of an absorbing layer between coating and base, each crossing
        /// at cos_t inside keeping exp(-thickness / cos_t): pbrt-v4's `coateddiffuse`
        /// `thickness`; 0 (Mitsuba's plastics) for none.
        thickness: f32,
        /// The most times the base scatters the light trapped under the coating (pbrt-v4's
        /// walk of `maxdepth` steps scatters it ceil(maxdepth / 2) times); 0 for no limit.
        scatterings: u32,
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
            | MaterialKind::Conductor { albedo, texture, .. }
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
            MaterialKind::Conductor { roughness, .. } | MaterialKind::Plastic { roughness, .. } => roughness == 0.0,
            MaterialKind::Dielectric { .. } | MaterialKind::ThinDielectric { .. } | MaterialKind::Null => true,
            MaterialKind::Diffuse { .. } => false,
        }
    }

    /// The kind as `info` names it.
    pub fn describe(&self) -> &'static str {
        match *self {
            MaterialKind::Diffuse { texture, .. } => diffuse::describe(texture),
            MaterialKind::Conductor { roughness, texture, .. } => conductor::describe(roughness, texture),
            MaterialKind::Dielectric { roughness, .. } => dielectric::describe(roughness),
            MaterialKind::Plastic { roughness, .. } => plastic::describe(roughness),
            MaterialKind::ThinDielectric { .. } => thin_dielectric::describe(false),
            MaterialKind::Null => thin_dielectric::describe(true),
        }
    }

    /// The kind's keys in a TOML `[materials]` entry: `type` and its parameters, but for the
    /// albedo or the texture in its place ([`MaterialKind::albedo`]), which the writer puts
    /// with the texture's file.
    pub fn toml_keys(&self, t: &mut toml::Table) {
        match *self {
            MaterialKind::Diffuse { .. } => diffuse::toml_keys(t),
            MaterialKind::Conductor { roughness, distribution, fresnel, .. } => {
                conductor::toml_keys(t, roughness, distribution, fresnel)
            }
            MaterialKind::Dielectric { ior, roughness, distribution, reflectance, transmittance } => {
                dielectric::toml_keys(t, ior, roughness, distribution, reflectance, transmittance)
            }
            MaterialKind::Plastic { .. } => plastic::toml_keys(t, &self.plastic()),
            MaterialKind::ThinDielectric { ior, reflectance, transmittance } => {
                thin_dielectric::toml_keys(t, ior, reflectance, transmittance)
            }
            MaterialKind::Null => thin_dielectric::null_toml_keys(t),
        }
    }

    /// The kind's parameters checked against their ranges, whichever reader gave them: the
    /// first that is out, named as a TOML scene names it.
    pub(crate) fn check(&self) -> std::result::Result<(), Invalid> {
        match *self {
            MaterialKind::Diffuse { albedo, .. } => diffuse::check(albedo),
            MaterialKind::Conductor { albedo, roughness, fresnel, .. } => conductor::check(albedo, roughness, fresnel),
            MaterialKind::Dielectric { ior, roughness, reflectance, transmittance, .. } => {
                dielectric::check(ior, roughness, reflectance, transmittance)
            }
            MaterialKind::Plastic { .. } => plastic::check(&self.plastic()),
            MaterialKind::ThinDielectric { ior, reflectance, transmittance } => {
                thin_dielectric::check(ior, reflectance, transmittance)
            }
            MaterialKind::Null => Ok(()),
        }
    }

    /// The kind on the GPU: its `MATERIAL_*` kind and parameters, without a texture (the
    /// caller sets [`GpuMaterial::texture`] and `one_sided`). A rough plastic's table of
    /// coating transmittance goes at the end of `attributes`.
    pub fn gpu(&self, textures: &[Texture], attributes: &mut Vec<[f32; 4]>) -> GpuMaterial {
        match *self {
            MaterialKind::Diffuse { albedo, .. } => diffuse::gpu(albedo),
            MaterialKind::Conductor { albedo, roughness, distribution, fresnel, .. } => {
                conductor::gpu(albedo, roughness, distribution, fresnel)
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
            MaterialKind::Plastic {
                albedo,
                texture,
                specular,
                ior,
                roughness,
                distribution,
                nonlinear,
                thickness,
                scatterings,
            } => plastic::Plastic { albedo, texture, specular, ior, roughness, distribution, nonlinear, thickness, scatterings },
            _ => plastic::Plastic {
                albedo: Vec3::ZERO,
                texture: None,
                specular: Vec3::ZERO,
                ior: 1.0,
                roughness: 0.0,
                distribution: Microfacet::Ggx,
                nonlinear: false,
                thickness: 0.0,
                scatterings: 0,
            },
        }
    }
}

/// Turn on the kernel features ([`Features`]) that material `m`, as on the GPU, needs: its
/// family's `USES_*` overrides.
pub fn turn_on_features(m: &GpuMaterial, f: &mut Features) {
    match m.kind {
        MATERIAL_DIFFUSE => diffuse::turn_on(m, f),
        MATERIAL_CONDUCTOR => conductor::turn_on(m, f),
        MATERIAL_DIELECTRIC => dielectric::turn_on(m, f),
        MATERIAL_THIN_DIELECTRIC => thin_dielectric::turn_on(m, f),
        MATERIAL_PLASTIC => plastic::turn_on(m, f),
        _ => {}
    }
    // Dielectrics, thin ones too, are two-sided by nature and pack one_sided as 0.
    f.one_sided |= m.one_sided != 0 && m.kind != MATERIAL_DIELECTRIC;
}

/// A `type` of a TOML `[materials]` entry: its name, its keys besides `type` and `one_sided`,
/// and its family's reader of them (which may load a texture).
pub(super) struct TomlType {
    name: &'static str,
    keys: &'static [&'static str],
    read: fn(&Table, &mut Vec<Texture>) -> Result<MaterialKind>,
}

/// Every TOML material type, in the order messages list them.
const TOML_TYPES: &[TomlType] = &[
    diffuse::TOML,
    conductor::MIRROR,
    conductor::GLOSSY,
    dielectric::TOML,
    plastic::TOML,
    thin_dielectric::TOML,
    thin_dielectric::NULL,
];

/// The names of the TOML material types.
pub fn toml_types() -> Vec<&'static str> {
    TOML_TYPES.iter().map(|t| t.name).collect()
}

/// Reads the `[materials]` entry `name = { type = ..., ... }`: its family reads its keys, its
/// check refuses a parameter out of range at the parameter's line.
pub(super) fn read_toml(name: &str, entry: &Value, textures: &mut Vec<Texture>) -> Result<Material> {
    let t = entry.table()?;
    let types: Vec<_> = TOML_TYPES.iter().map(|f| (f.name, f.read, f.keys)).collect();
    let read = t.typed("material type", &types, &["type", "one_sided"])?;
    let kind = read(&t, textures)?;
    kind.check().map_err(|e| t.invalid(e))?;
    // Black seen from behind, as Mitsuba's BSDFs unless wrapped in `twosided`.
    let one_sided = t.or("one_sided", false, Value::bool)?;
    if one_sided && kind.two_sided_by_nature() {
        return Err(t.error_at("one_sided", "a dielectric or null surface is the same from both sides: one_sided does not apply"));
    }
    Ok(Material { name: name.to_owned(), kind, one_sided, line: entry.line })
}

/// The index of the material named `name`, or why there is none.
pub(super) fn index(materials: &[Material], name: &str) -> std::result::Result<u32, String> {
    if let Some(index) = materials.iter().position(|m| m.name == name) {
        return Ok(index as u32);
    }
    let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
    let defined =
        if names.is_empty() { "no materials are defined".to_owned() } else { format!("defined materials: {}", names.join(", ")) };
    Err(format!("unknown material `{name}`; {defined}"))
}

/// `albedo`, or a `texture` in its place (then the albedo is white).
fn read_albedo(t: &Table, textures: &mut Vec<Texture>) -> Result<(Vec3, Option<u32>)> {
    let albedo = t.opt("albedo", |v| v.rgb(Bound::Any))?;
    if albedo.is_some() && t.get("texture").is_some() {
        return Err(t.error_at("texture", "give either `albedo` or `texture`, not both"));
    }
    let texture = t.opt("texture", |v| texture_index(v, textures))?;
    if albedo.is_none() && texture.is_none() {
        return Err(t.error_at("albedo", "missing required key `albedo` (or `texture`)"));
    }
    Ok((albedo.unwrap_or(Vec3::ONE), texture))
}

/// `distribution` of microfacet normals: "ggx" (default) or "beckmann".
fn read_distribution(t: &Table) -> Result<Microfacet> {
    t.or("distribution", Microfacet::Ggx, Value::named)
}

/// A specular lobe's tint (Mitsuba's `specular_reflectance` and `specular_transmittance`),
/// white unless given.
fn read_tint(t: &Table, key: &str) -> Result<Vec3> {
    t.or(key, Vec3::ONE, |v| v.rgb(Bound::Any))
}

/// Index of the texture a `texture` value names, loaded once per distinct file and settings:
/// a file name, or a table `{ file, filter, wrap, uv_transform }` with `filter` "bilinear"
/// (default) or "nearest", `wrap` "repeat" (default), "mirror" or "clamp", and
/// `uv_transform` = [[a, b, tx], [c, d, ty]], the image point (x right, y down, in [0, 1]) of
/// texture coordinates (u, v): x = a u + b v + tx, y = c u + d v + ty; by default
/// [[1, 0, 0], [0, -1, 1]], v up the image.
fn texture_index(v: &Value, textures: &mut Vec<Texture>) -> Result<u32> {
    let (file, settings) = match v.value {
        DeValue::Table(_) => {
            let t = v.table()?;
            t.allow_keys(&["file", "filter", "wrap", "uv_transform"])?;
            (t.require("file")?, Some(t))
        }
        _ => (Value { source: v.source, value: v.value, key: v.key.clone(), line: v.line }, None),
    };
    let path = file.path()?;
    let mut texture = file.read_file("texture", &path, mesh::read_texture)?;
    if let Some(t) = settings {
        let filters = [("bilinear", TextureFilter::Bilinear), ("nearest", TextureFilter::Nearest)];
        let wraps = [("repeat", TextureWrap::Repeat), ("mirror", TextureWrap::Mirror), ("clamp", TextureWrap::Clamp)];
        texture.filter = t.or("filter", texture.filter, |v| v.choice("filter", &filters))?;
        texture.wrap = t.or("wrap", texture.wrap, |v| v.choice("wrap", &wraps))?;
        if let Some(rows) = t.opt("uv_transform", |v| {
            let rows = v.elements()?;
            if rows.len() != 2 {
                return Err(v.error(format!("expected two rows of three numbers, found {} rows", rows.len())));
            }
            Ok([rows[0].floats::<3>(Bound::Any)?, rows[1].floats::<3>(Bound::Any)?])
        })? {
            let [[a, b, tx], [c, d, ty]] = rows;
            texture.to_uv = glam::Affine2::from_cols_array(&[a, c, b, d, tx, ty]);
        }
    }
    let same =
        |u: &Texture| u.path == texture.path && u.filter == texture.filter && u.wrap == texture.wrap && u.to_uv == texture.to_uv;
    if let Some(index) = textures.iter().position(same) {
        return Ok(index as u32);
    }
    textures.push(texture);
    Ok(textures.len() as u32 - 1)
}

/// What a family's Mitsuba mapping reads a BSDF plugin's parameters through, with Mitsuba 3's
/// types, names and defaults (`scene/mitsuba/bsdf.rs` implements it over the plugin's
/// element). Every parameter must be read, or the plugin is refused for it.
pub(crate) trait MitsubaBsdf {
    /// Whether the file is Mitsuba 0.5/0.6's.
    fn legacy(&self) -> bool;
    /// Whether the plugin gives `name`.
    fn has(&self, name: &str) -> bool;
    /// A reflectance that may be textured: a colour in [0, 1] and no texture, or white and
    /// the texture that replaces it.
    fn reflectance(&mut self, name: &str, default: f32) -> Result<(Vec3, Option<u32>)>;
    /// A reflectance that cannot be textured here: a colour in [0, 1].
    fn constant_reflectance(&self, name: &str, default: f32) -> Result<Vec3>;
    /// An index of refraction: a number, or one of Mitsuba's named media.
    fn ior(&self, name: &str, default: f32) -> Result<f32>;
    /// A rough plugin's `alpha` (> 0) and `distribution` (Mitsuba's default Beckmann).
    fn microfacets(&self) -> Result<(f32, Microfacet)>;
    /// A conductor's complex index of refraction (`material`, or `eta` and `k`); `None` for
    /// Mitsuba's `none`, Fresnel 1.
    fn complex_ior(&self) -> Result<Option<ComplexIor>>;
    /// A boolean with its default.
    fn boolean_or(&self, name: &str, default: bool) -> Result<bool>;
    /// An error about parameter `name`, at the plugin's element.
    fn error(&self, name: &str, message: String) -> SceneError;
    /// An error about parameter `name`, at its line where it is given.
    fn error_at(&self, name: &str, message: String) -> SceneError;
}

/// A family's Mitsuba plugins: their names, the mapping that reads them, and the names Mitsuba
/// gives the parameters that the family's check names as TOML does.
pub(super) struct MitsubaPlugins {
    names: &'static [&'static str],
    read: fn(&mut dyn MitsubaBsdf, &str) -> Result<MaterialKind>,
    params: &'static [(&'static str, &'static str)],
}

/// Every Mitsuba BSDF plugin modelled here, by family.
const MITSUBA_PLUGINS: &[MitsubaPlugins] =
    &[diffuse::MITSUBA, conductor::MITSUBA, dielectric::MITSUBA, plastic::MITSUBA, thin_dielectric::MITSUBA];

/// The scattering model of Mitsuba BSDF plugin `plugin`, read through `p` by its family and
/// checked as every reader's; `None` for a plugin no family models.
pub(crate) fn from_mitsuba(plugin: &str, p: &mut dyn MitsubaBsdf) -> Option<Result<MaterialKind>> {
    let family = MITSUBA_PLUGINS.iter().find(|f| f.names.contains(&plugin))?;
    Some((family.read)(p, plugin).and_then(|kind| {
        let name = |key: &str| family.params.iter().find(|(k, _)| *k == key).map_or(key, |(_, m)| m).to_owned();
        kind.check().map_err(|e| p.error_at(&name(e.key), e.message))?;
        Ok(kind)
    }))
}

/// [`GpuMaterial::distribution`] of a microfacet distribution.
fn microfacet(distribution: Microfacet) -> u32 {
    match distribution {
        Microfacet::Ggx => MICROFACET_GGX,
        Microfacet::Beckmann => MICROFACET_BECKMANN,
    }
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

impl Named for Microfacet {
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
