//! Plastics (`plastic` in TOML; Mitsuba 3's `plastic` and `roughplastic`): a dielectric
//! coating, smooth (roughness 0) or of microfacets, over a Lambertian base, with the light
//! trapped between them summed ([`crate::scene::coating`] computes what the kernels look up:
//! Fdr, and a rough coating's transmittance table).
//!
//! Parameters: `albedo` (Mitsuba's `diffuse_reflectance`, 0.5), linear RGB in [0, 1], or a
//! `texture` in its place; `specular` in [0, 1] (`specular_reflectance`, 1); `ior` > 0 of the
//! coating (`int_ior` / `ext_ior`, polypropylene over air), other than 1 for a rough coating;
//! `roughness` (alpha in [0, 1], 0 smooth; Mitsuba's `alpha`, 0.1) and `distribution`;
//! `nonlinear` (false); `thickness` (0) of an absorbing layer under the coating and
//! `scatterings` (0, no limit) of the light trapped there, pbrt-v4's `coateddiffuse`
//! ([`crate::scene::coating`]); `one_sided`.
//! Kernel: `shaders/shared/bsdf/plastic.wgsl`.

use super::{
    microfacet, put_float, put_str, put_vec3, read_albedo, read_distribution, read_tint, Features, GpuMaterial, MaterialKind,
    Microfacet, MitsubaBsdf, MitsubaPlugins, Named, Result, TomlType,
};
use crate::layout::{MICROFACET_BECKMANN, NO_TEXTURE};
use crate::scene::coating::{attenuated_internal_reflectance, fresnel_diffuse_reflectance, rough_coating_through, RoughCoating};
use crate::scene::param::{self, Bound, Invalid, UNIT};
use crate::scene::toml_table::{Table, Value};
use crate::scene::Texture;
use glam::Vec3;

/// The most `scatterings` a plastic may set (pbrt-v4's `maxdepth` of twice as many).
pub const MAX_SCATTERINGS: u32 = 1 << 16;

/// [`GpuMaterial::kind`] of a plastic, its coating smooth (roughness 0) or rough.
pub const MATERIAL_PLASTIC: u32 = 4;

/// The plastic's parameters, as [`super::MaterialKind::Plastic`] holds them.
pub(super) struct Plastic {
    pub albedo: Vec3,
    pub texture: Option<u32>,
    pub specular: Vec3,
    pub ior: f32,
    pub roughness: f32,
    pub distribution: Microfacet,
    pub nonlinear: bool,
    pub thickness: f32,
    pub scatterings: u32,
}

pub(super) const TOML: TomlType = TomlType {
    name: "plastic",
    keys: &["albedo", "texture", "specular", "ior", "roughness", "distribution", "nonlinear", "thickness", "scatterings"],
    read: read_toml,
};

fn read_toml(t: &Table, textures: &mut Vec<Texture>) -> Result<MaterialKind> {
    let (albedo, texture) = read_albedo(t, textures)?;
    Ok(MaterialKind::Plastic {
        albedo,
        texture,
        specular: read_tint(t, "specular")?,
        ior: t.req("ior", |v| v.f32_in(Bound::Any))?,
        roughness: t.or("roughness", 0.0, |v| v.f32_in(Bound::Any))?,
        distribution: read_distribution(t)?,
        nonlinear: t.or("nonlinear", false, Value::bool)?,
        thickness: t.or("thickness", 0.0, |v| v.f32_in(Bound::NonNegative))?,
        scatterings: t.or("scatterings", 0, |v| v.u32_in(0, MAX_SCATTERINGS))?,
    })
}

pub(super) const MITSUBA: MitsubaPlugins = MitsubaPlugins {
    names: &["plastic", "roughplastic"],
    read: from_mitsuba,
    params: &[
        ("albedo", "diffuse_reflectance"),
        ("specular", "specular_reflectance"),
        ("ior", "int_ior"),
        ("roughness", "alpha"),
    ],
};

fn from_mitsuba(p: &mut dyn MitsubaBsdf, plugin: &str) -> Result<MaterialKind> {
    let rough = plugin == "roughplastic";
    let ior = p.ior("int_ior", 1.49)? / p.ior("ext_ior", 1.000277)?;
    // Mitsuba refuses a rough coating of matched indices; a smooth one is then invisible, and
    // allowed.
    if !(ior.is_finite() && ior > 0.0) || (ior == 1.0 && rough) {
        return Err(p.error("int_ior", format!("int_ior / ext_ior = {ior}: an interface needs two different indices")));
    }
    let (albedo, texture) = p.reflectance("diffuse_reflectance", 0.5)?;
    let specular = p.constant_reflectance("specular_reflectance", 1.0)?;
    let nonlinear = p.boolean_or("nonlinear", false)?;
    let (roughness, distribution) = if rough { p.microfacets()? } else { (0.0, Microfacet::Ggx) };
    Ok(MaterialKind::Plastic {
        albedo,
        texture,
        specular,
        ior,
        roughness,
        distribution,
        nonlinear,
        thickness: 0.0,
        scatterings: 0,
    })
}

pub(super) fn check(p: &Plastic) -> std::result::Result<(), Invalid> {
    param::rgb("albedo", p.albedo, UNIT)?;
    param::rgb("specular", p.specular, UNIT)?;
    param::float("ior", p.ior, Bound::Positive)?;
    param::float("roughness", p.roughness, UNIT)?;
    param::float("thickness", p.thickness, Bound::NonNegative)?;
    if p.ior == 1.0 && p.roughness > 0.0 {
        return Err(Invalid::new("ior", "a rough coating needs an index other than 1"));
    }
    Ok(())
}

pub(super) fn describe(roughness: f32) -> &'static str {
    if roughness > 0.0 {
        "rough plastic"
    } else {
        "plastic"
    }
}

pub(super) fn toml_keys(t: &mut toml::Table, p: &Plastic) {
    put_str(t, "type", "plastic");
    put_vec3(t, "specular", p.specular);
    put_float(t, "ior", p.ior);
    put_float(t, "roughness", p.roughness);
    put_str(t, "distribution", p.distribution.name());
    t.insert("nonlinear".into(), toml::Value::Boolean(p.nonlinear));
    if p.thickness > 0.0 {
        put_float(t, "thickness", p.thickness);
    }
    if p.scatterings > 0 {
        t.insert("scatterings".into(), toml::Value::Integer(p.scatterings.into()));
    }
}

/// On the GPU (Mitsuba 3's `parameters_changed`): the probability weight of its coating's
/// lobe, mean(specular) / (mean(albedo) + mean(specular)); Fdr, the coating's diffuse
/// reflectance from inside, by the fit for a smooth coating and by quadrature for a rough one
/// or one over an absorbing layer (Fdr', attenuated), a rough one's transmittance table at the
/// end of `attributes`.
pub(super) fn gpu(p: &Plastic, textures: &[Texture], attributes: &mut Vec<[f32; 4]>) -> GpuMaterial {
    let mut g = GpuMaterial {
        kind: MATERIAL_PLASTIC,
        albedo: p.albedo.into(),
        specular: p.specular.into(),
        ior: p.ior,
        roughness: p.roughness,
        distribution: microfacet(p.distribution),
        nonlinear: p.nonlinear as u32,
        coat_thickness: p.thickness,
        coat_scatterings: p.scatterings,
        texture: NO_TEXTURE,
        ..GpuMaterial::default()
    };
    // Mitsuba's weight takes a texture's mean over its texels.
    let base = match p.texture {
        Some(t) => textures[t as usize].texels.iter().sum::<Vec3>() / textures[t as usize].texels.len().max(1) as f32,
        None => p.albedo,
    };
    let (d_mean, s_mean) = (base.element_sum() / 3.0, p.specular.element_sum() / 3.0);
    g.coat_weight = s_mean / (d_mean + s_mean);
    if p.roughness == 0.0 {
        g.coat_fdr = if p.thickness > 0.0 {
            attenuated_internal_reflectance(p.ior, p.thickness)
        } else {
            fresnel_diffuse_reflectance(1.0 / p.ior)
        };
        return g;
    }
    let coat = rough_coating_cached(p.ior, p.roughness, p.distribution, p.thickness);
    g.coat_fdr = coat.internal_reflectance;
    g.coat_table = attributes.len() as u32;
    attributes.extend(coat.transmittance.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]));
    g
}

/// [`rough_coating`], computed once per process for each coating (a quadrature of a million
/// points for the internal reflectance).
fn rough_coating_cached(ior: f32, alpha: f32, distribution: Microfacet, thickness: f32) -> RoughCoating {
    use std::sync::Mutex;
    type Key = (u32, u32, bool, u32);
    static CACHE: Mutex<Vec<(Key, RoughCoating)>> = Mutex::new(Vec::new());
    let key = (ior.to_bits(), alpha.to_bits(), distribution == Microfacet::Beckmann, thickness.to_bits());
    if let Some((_, c)) = CACHE.lock().unwrap().iter().find(|(k, _)| *k == key) {
        return c.clone();
    }
    let c = rough_coating_through(ior, alpha, distribution, thickness);
    CACHE.lock().unwrap().push((key, c.clone()));
    c
}

/// `USES_PLASTIC` and `USES_ROUGH_PLASTIC` (a smooth and a rough coating), `USES_BECKMANN`.
pub(super) fn turn_on(m: &GpuMaterial, f: &mut Features) {
    let rough = m.roughness > 0.0;
    f.plastic |= !rough;
    f.rough_plastic |= rough;
    f.beckmann |= rough && m.distribution == MICROFACET_BECKMANN;
}
