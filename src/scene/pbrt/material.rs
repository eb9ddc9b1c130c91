//! pbrt-v4's materials and textures, as our material families ([`crate::scene::material`]).
//! pbrt's materials scatter alike from both sides (two-sided).
//!
//! Materials (`Material`, `MakeNamedMaterial` with `"string type"`):
//! - `diffuse`: `reflectance` (0.5; a colour or a texture).
//! - `conductor`: `eta` (`metal-Cu-eta`) and `k` (`metal-Cu-k`), or `reflectance` (then eta 1
//!   and k = 2 sqrt(r) / sqrt(1 - r), as pbrt-v4 does); `roughness` (0) or `uroughness` =
//!   `vroughness`, `remaproughness` (true: alpha = sqrt(roughness)); GGX, as pbrt's
//!   Trowbridge-Reitz; alpha below 1e-3 is smooth, as in pbrt.
//! - `dielectric`: `eta` (1.5; a number or a named glass), roughness as a conductor's.
//!   `thindielectric`: `eta` (1.5).
//! - `coateddiffuse`: our plastic with the base's light trapped in the coating
//!   (`nonlinear`): `reflectance` (0.5), `eta` (1.5), roughness as above; `thickness` (0.01)
//!   of the layer under the coating, which absorbs as pbrt-v4's walk does with no medium in
//!   it (exp(-thickness / cos) a crossing), and `maxdepth` (10), whose walk lets the base
//!   scatter ceil(maxdepth / 2) times ([`crate::scene::coating`]); a medium in the layer
//!   (`albedo`, `g` other than 0) is refused; `nsamples` (how pbrt estimates the layers) is
//!   read.
//! - `interface`: an invisible surface (our `null`).
//! - `mix`: `materials` (two named materials), `amount` (0.5, a constant): pbrt-v4 picks
//!   the first where amount <= 0 and the second where amount >= 1, which is that material;
//!   an amount between picks one at random per point (a hash of it), refused.
//! - `coatedconductor`, `diffusetransmission`, `hair`, `measured`, `subsurface`, and
//!   any material's `displacement` or `normalmap`, are refused.
//!
//! Textures (`Texture "name" "spectrum"|"float" "class"`): `imagemap` (`filename`; `wrap`
//! `repeat` or `clamp`; `scale`; `invert`; `encoding` `sRGB` or `linear`, by default sRGB
//! for PNG files and linear for others, as pbrt-v4; `filter` `point` is nearest, the others
//! bilinear, the pixel's samples averaging over its footprint), `constant` (`value`), `scale`
//! (`tex` times `scale`, of constants or an image and a constant), `mix` of constants, and
//! `checkerboard` (2D, of constant `tex1` and `tex2`). Every texture maps uv (`mapping`
//! `uv`, with `uscale`, `vscale`, `udelta`, `vdelta`). A texture is looked up at (s, 1 - t)
//! of the image, row 0 at its top, as pbrt-v4 does. Where sppm-gpu textures a material
//! (a diffuse reflectance, a coated diffuse's reflectance, a conductor's reflectance) an
//! image texture is read; elsewhere only constant textures are. Textures of other classes
//! are refused where a material uses them.

use super::params::{FloatParam, Params, Spectrum};
use super::spectra::{self, SpectrumUse};
use super::{Reader, Result};
use crate::scene::material::MAX_SCATTERINGS;
use crate::scene::{mesh, ComplexIor, Material, MaterialKind, Microfacet, SceneError, Texture, TextureFilter, TextureWrap};
use glam::{Affine2, Vec2, Vec3};

/// A named float texture.
#[derive(Clone, Debug)]
pub(super) enum FloatTexture {
    Const(f32),
    /// A class sppm-gpu cannot use here, and why, refused where it is used.
    Refused(SceneError),
}

/// A named spectrum texture.
#[derive(Clone, Debug)]
pub(super) enum SpectrumTexture {
    Const(Vec3),
    Image(Box<Texture>),
    Refused(SceneError),
}

impl Reader {
    /// `Texture "name" "type" "class"`.
    pub(super) fn texture(&mut self, name: &str, ty: &str, class: &str, p: &Params) -> Result<()> {
        match ty {
            "float" => {
                let t = match self.float_class(class, p) {
                    Ok(t) => t,
                    Err(e) if is_refusal(&e) => FloatTexture::Refused(e),
                    Err(e) => return Err(e),
                };
                self.float_textures.insert(name.to_owned(), t);
            }
            "spectrum" | "color" => {
                let t = match self.spectrum_class(class, p) {
                    Ok(t) => t,
                    Err(e) if is_refusal(&e) => SpectrumTexture::Refused(e),
                    Err(e) => return Err(e),
                };
                self.texture_index.remove(name);
                self.spectrum_textures.insert(name.to_owned(), t);
            }
            other => return Err(p.directive_error(format!("\"{other}\": a texture is of type \"float\" or \"spectrum\""))),
        }
        Ok(())
    }

    fn float_class(&self, class: &str, p: &Params) -> Result<FloatTexture> {
        let t = match class {
            "constant" => FloatTexture::Const(p.float_or("value", 1.0)?),
            "scale" => {
                let a = self.float_value(p, "tex", 1.0)?;
                let b = self.float_value(p, "scale", 1.0)?;
                FloatTexture::Const(a * b)
            }
            "mix" => {
                let a = self.float_value(p, "tex1", 0.0)?;
                let b = self.float_value(p, "tex2", 1.0)?;
                let t = self.float_value(p, "amount", 0.5)?;
                FloatTexture::Const(a + (b - a) * t)
            }
            other => return Err(refusal(p, other)),
        };
        p.finish()?;
        Ok(t)
    }

    fn spectrum_class(&self, class: &str, p: &Params) -> Result<SpectrumTexture> {
        let t = match class {
            "constant" => SpectrumTexture::Const(self.spectrum_value(p, "value", Vec3::ONE)?),
            "imagemap" => SpectrumTexture::Image(Box::new(image_texture(p)?)),
            "scale" => {
                let s = self.float_value(p, "scale", 1.0)?;
                match p.spectrum("tex", SpectrumUse::Unbounded)? {
                    None => SpectrumTexture::Const(Vec3::splat(s)),
                    Some(Spectrum::Rgb(c)) => SpectrumTexture::Const(c * s),
                    Some(Spectrum::Texture(n)) => match self.spectrum_textures.get(&n) {
                        Some(SpectrumTexture::Const(c)) => SpectrumTexture::Const(*c * s),
                        Some(SpectrumTexture::Image(t)) => {
                            let mut t = t.clone();
                            std::sync::Arc::make_mut(&mut t.texels).iter_mut().for_each(|c| *c *= s);
                            SpectrumTexture::Image(t)
                        }
                        Some(SpectrumTexture::Refused(e)) => return Err(e.clone()),
                        None => return Err(p.error("tex", format!("{n}: spectrum texture not defined"))),
                    },
                }
            }
            "mix" => {
                let a = self.spectrum_value(p, "tex1", Vec3::ZERO)?;
                let b = self.spectrum_value(p, "tex2", Vec3::ONE)?;
                let t = self.float_value(p, "amount", 0.5)?;
                SpectrumTexture::Const(a + (b - a) * t)
            }
            "checkerboard" => {
                if p.int_or("dimension", 2)? != 2 {
                    return Err(p.error("dimension", "a 3D checkerboard is not modelled by sppm-gpu"));
                }
                let a = self.spectrum_value(p, "tex1", Vec3::ONE)?;
                let b = self.spectrum_value(p, "tex2", Vec3::ZERO)?;
                let (scale, delta) = uv_mapping(p)?;
                // One unit square of (s, t) a check: half a tile of a 2x2 texture.
                let to_uv = Affine2::from_scale(Vec2::splat(0.5)) * Affine2::from_scale_angle_translation(scale, 0.0, delta);
                SpectrumTexture::Image(Box::new(Texture {
                    path: p.file.as_ref().clone(),
                    width: 2,
                    height: 2,
                    texels: std::sync::Arc::new(vec![a, b, b, a]),
                    filter: TextureFilter::Nearest,
                    wrap: TextureWrap::Repeat,
                    to_uv,
                }))
            }
            other => return Err(refusal(p, other)),
        };
        p.finish()?;
        Ok(t)
    }

    /// A float parameter that may name a float texture, as a constant.
    fn float_value(&self, p: &Params, name: &str, default: f32) -> Result<f32> {
        match p.float_texture(name)? {
            None => Ok(default),
            Some(FloatParam::Const(v)) => Ok(v),
            Some(FloatParam::Texture(n)) => match self.float_textures.get(&n) {
                Some(FloatTexture::Const(v)) => Ok(*v),
                Some(FloatTexture::Refused(e)) => Err(e.clone()),
                None => Err(p.error(name, format!("{n}: float texture not defined"))),
            },
        }
    }

    /// A spectrum parameter that may name a texture, as a constant colour.
    fn spectrum_value(&self, p: &Params, name: &str, default: Vec3) -> Result<Vec3> {
        match self.spectrum_or_image(p, name, SpectrumUse::Unbounded)? {
            None => Ok(default),
            Some(Ok(c)) => Ok(c),
            Some(Err(_)) => Err(p.error(name, format!("an image texture as \"{name}\" is not modelled by sppm-gpu: a constant"))),
        }
    }

    /// A spectrum parameter: a colour, or the image texture it names (`Err`).
    fn spectrum_or_image(&self, p: &Params, name: &str, used: SpectrumUse) -> Result<Option<std::result::Result<Vec3, String>>> {
        match p.spectrum(name, used)? {
            None => Ok(None),
            Some(Spectrum::Rgb(c)) => Ok(Some(Ok(c))),
            Some(Spectrum::Texture(n)) => match self.spectrum_textures.get(&n) {
                Some(SpectrumTexture::Const(c)) => Ok(Some(Ok(*c))),
                Some(SpectrumTexture::Image(_)) => Ok(Some(Err(n))),
                Some(SpectrumTexture::Refused(e)) => Err(e.clone()),
                None => Err(p.error(name, format!("{n}: spectrum texture not defined"))),
            },
        }
    }

    /// A reflectance that may be an image: the colour and the scene texture in its place.
    fn reflectance(&mut self, p: &Params, name: &str, default: f32) -> Result<(Vec3, Option<u32>)> {
        match self.spectrum_or_image(p, name, SpectrumUse::Albedo)? {
            None => Ok((Vec3::splat(default), None)),
            Some(Ok(c)) => {
                if c.min_element() < 0.0 || c.max_element() > 1.0 {
                    return Err(p.error(name, format!("reflectance {c} is outside [0, 1]")));
                }
                Ok((c, None))
            }
            Some(Err(texture)) => {
                if let Some(&index) = self.texture_index.get(&texture) {
                    return Ok((Vec3::ONE, Some(index)));
                }
                let Some(SpectrumTexture::Image(t)) = self.spectrum_textures.get(&texture) else { unreachable!() };
                let index = self.textures.len() as u32;
                self.textures.push(t.as_ref().clone());
                self.texture_index.insert(texture, index);
                Ok((Vec3::ONE, Some(index)))
            }
        }
    }

    /// Microfacet alpha from `roughness` or `uroughness`/`vroughness` and `remaproughness`.
    fn alpha(&self, p: &Params) -> Result<f32> {
        let r = self.float_value(p, "roughness", 0.0)?;
        let u = self.float_value(p, "uroughness", r)?;
        let v = self.float_value(p, "vroughness", r)?;
        if u != v {
            let key = if p.has("vroughness") { "vroughness" } else { "uroughness" };
            return Err(p.error(key, "anisotropic roughness (uroughness != vroughness) is not modelled by sppm-gpu"));
        }
        if u.is_nan() || u < 0.0 {
            return Err(p.error("roughness", format!("roughness {u} is negative")));
        }
        let alpha = if p.bool_or("remaproughness", true)? { u.sqrt() } else { u };
        // pbrt's Trowbridge-Reitz is smooth below 1e-3; ours takes alpha up to 1.
        Ok(if alpha < 1e-3 { 0.0 } else { alpha.min(1.0) })
    }

    /// An index of refraction: a number, a named glass, a constant texture or a spectrum.
    fn eta(&self, p: &Params, default: f32) -> Result<f32> {
        if p.list.iter().any(|x| x.name == "eta" && x.ty == "float") {
            return Ok(p.float("eta")?.unwrap());
        }
        if let Some(x) = p.list.iter().find(|x| x.name == "eta" && x.ty == "spectrum") {
            if let [super::params::Value::Str(s)] = x.values.as_slice() {
                if let Some(ior) = spectra::glass_ior(s) {
                    p.get("eta");
                    return Ok(ior);
                }
            }
        }
        let eta = match self.spectrum_or_image(p, "eta", SpectrumUse::Unbounded)? {
            None => Vec3::splat(default),
            Some(Ok(c)) => c,
            Some(Err(_)) => return Err(p.error("eta", "an image texture as eta is not modelled by sppm-gpu")),
        };
        Ok(spectra::luminance(eta))
    }

    /// Makes the material of `ty` (the material's `name` for `MakeNamedMaterial`) and gives
    /// its index.
    pub(super) fn material(&mut self, ty: &str, p: &Params, name: Option<&str>) -> Result<u32> {
        for key in ["displacement", "normalmap"] {
            if p.has(key) {
                return Err(p.error(key, format!("{key} is not modelled by sppm-gpu")));
            }
        }
        if ty == "mix" {
            return self.mix_material(p, name);
        }
        let kind = match ty {
            "diffuse" => {
                let (albedo, texture) = self.reflectance(p, "reflectance", 0.5)?;
                MaterialKind::Diffuse { albedo, texture }
            }
            "conductor" => {
                let roughness = self.alpha(p)?;
                let (albedo, texture, fresnel) = if p.has("reflectance") {
                    if p.has("eta") || p.has("k") {
                        return Err(p.error("reflectance", "a conductor takes reflectance or eta and k, not both"));
                    }
                    match self.spectrum_or_image(p, "reflectance", SpectrumUse::Albedo)?.unwrap() {
                        Ok(r) => {
                            let r = r.clamp(Vec3::ZERO, Vec3::splat(0.9999));
                            let k = 2.0 * r.map(f32::sqrt) / (Vec3::ONE - r).map(f32::sqrt);
                            (Vec3::ONE, None, Some(ComplexIor { eta: Vec3::ONE, k }))
                        }
                        Err(_) => {
                            let (_, texture) = self.reflectance(p, "reflectance", 1.0)?;
                            (Vec3::ONE, texture, None)
                        }
                    }
                } else {
                    let eta =
                        self.unbounded(p, "eta", spectra::named_or_file("metal-Cu-eta", SpectrumUse::Unbounded, &|n| n.into()))?;
                    let k =
                        self.unbounded(p, "k", spectra::named_or_file("metal-Cu-k", SpectrumUse::Unbounded, &|n| n.into()))?;
                    (Vec3::ONE, None, Some(ComplexIor { eta, k }))
                };
                MaterialKind::Conductor { albedo, texture, roughness, distribution: Microfacet::Ggx, fresnel }
            }
            "dielectric" => {
                let ior = self.eta(p, 1.5)?;
                let roughness = self.alpha(p)?;
                let one = Vec3::ONE;
                MaterialKind::Dielectric { ior, roughness, distribution: Microfacet::Ggx, reflectance: one, transmittance: one }
            }
            "thindielectric" => {
                MaterialKind::ThinDielectric { ior: self.eta(p, 1.5)?, reflectance: Vec3::ONE, transmittance: Vec3::ONE }
            }
            "coateddiffuse" => {
                let (albedo, texture) = self.reflectance(p, "reflectance", 0.5)?;
                let ior = self.eta(p, 1.5)?;
                let roughness = self.alpha(p)?;
                if self.spectrum_value(p, "albedo", Vec3::ZERO)? != Vec3::ZERO || self.float_value(p, "g", 0.0)? != 0.0 {
                    let key = if p.has("albedo") { "albedo" } else { "g" };
                    return Err(p.error(key, "a medium inside the coating (albedo, g) is not modelled by sppm-gpu"));
                }
                let thickness = self.float_value(p, "thickness", 0.01)?;
                if !(thickness >= 0.0 && thickness.is_finite()) {
                    return Err(p.error("thickness", format!("{thickness}: the coating's thickness must be at least 0")));
                }
                // The walk scatters at the base at steps 0, 2, 4, ...: ceil(maxdepth / 2)
                // times; none where it takes no step, a black base.
                let max_depth = p.int_or("maxdepth", 10)?;
                let scatterings = ((max_depth.max(0) + 1) / 2).min(MAX_SCATTERINGS as i64) as u32;
                let (albedo, texture) = if scatterings == 0 { (Vec3::ZERO, None) } else { (albedo, texture) };
                p.pass_over(&["nsamples", "seed"]);
                MaterialKind::Plastic {
                    albedo,
                    texture,
                    specular: Vec3::ONE,
                    ior,
                    roughness,
                    distribution: Microfacet::Ggx,
                    nonlinear: true,
                    thickness,
                    scatterings,
                }
            }
            "interface" | "none" | "" => MaterialKind::Null,
            "coatedconductor" | "diffusetransmission" | "hair" | "measured" | "subsurface" => {
                return Err(p.directive_error(format!("the \"{ty}\" material is not modelled by sppm-gpu")))
            }
            other => return Err(p.directive_error(format!("\"{other}\": unknown material"))),
        };
        if name.is_some() {
            p.get("type");
        }
        p.finish()?;
        kind.check().map_err(|e| p.error(e.key, e.message))?;
        let index = self.materials.len() as u32;
        let name = name.map_or_else(|| format!("{}:{}", p.file.display(), p.line), str::to_owned);
        self.materials.push(Material { name, kind, one_sided: false, line: p.line });
        Ok(index)
    }

    /// pbrt-v4's `mix` (MixMaterial::ChooseMaterial): with a constant `amount` of 0 or less
    /// the first of `materials`, of 1 or more the second; the index of that material.
    fn mix_material(&mut self, p: &Params, name: Option<&str>) -> Result<u32> {
        let names = p.strings("materials")?.ok_or_else(|| p.error("materials", "a mix needs \"materials\""))?;
        let [a, b] = names.as_slice() else {
            return Err(p.error("materials", format!("must provide two values for \"string materials\" (got {})", names.len())));
        };
        let amount = self.float_value(p, "amount", 0.5)?;
        if name.is_some() {
            p.get("type");
        }
        p.finish()?;
        let chosen = if amount <= 0.0 {
            a
        } else if amount >= 1.0 {
            b
        } else if a == b {
            a
        } else {
            return Err(p.error(
                "amount",
                format!(
                    "a mix of \"{a}\" and \"{b}\" with amount {amount} is not modelled by sppm-gpu: pbrt-v4 picks one \
                     of them at random at each point (amount 0 or 1 picks one everywhere)"
                ),
            ));
        };
        // pbrt-v4 looks the names up among the named materials ("" for none: interface).
        if chosen.is_empty() {
            let index = self.materials.len() as u32;
            let name = name.map_or_else(|| format!("{}:{}", p.file.display(), p.line), str::to_owned);
            self.materials.push(Material { name, kind: MaterialKind::Null, one_sided: false, line: p.line });
            return Ok(index);
        }
        self.named_materials
            .get(chosen.as_str())
            .copied()
            .ok_or_else(|| p.error("materials", format!("{chosen}: named material not found")))
    }

    /// A non-negative spectrum (eta, k) as RGB, `default` when not given.
    fn unbounded(&self, p: &Params, name: &str, default: std::result::Result<Vec3, String>) -> Result<Vec3> {
        let c = match self.spectrum_or_image(p, name, SpectrumUse::Unbounded)? {
            None => default.map_err(|e| p.error(name, e))?,
            Some(Ok(c)) => c,
            Some(Err(_)) => return Err(p.error(name, format!("an image texture as {name} is not modelled by sppm-gpu"))),
        };
        if !(c.is_finite() && c.min_element() >= 0.0) {
            return Err(p.error(name, format!("{name} {c}: each channel is a number >= 0")));
        }
        Ok(c)
    }

    /// The material index of `state`'s material, making pbrt-v4's default (diffuse, 0.5).
    pub(super) fn material_index(&mut self, material: Option<u32>) -> u32 {
        if let Some(m) = material {
            return m;
        }
        *self.default_material.get_or_insert_with(|| {
            self.materials.push(Material {
                name: "default".into(),
                kind: MaterialKind::Diffuse { albedo: Vec3::splat(0.5), texture: None },
                one_sided: false,
                line: 0,
            });
            self.materials.len() as u32 - 1
        })
    }
}

/// The marker of a texture class refused where it is used.
const REFUSED: &str = "texture class is not modelled by sppm-gpu";

fn refusal(p: &Params, class: &str) -> SceneError {
    p.directive_error(format!("the \"{class}\" {REFUSED}"))
}

fn is_refusal(e: &SceneError) -> bool {
    e.message.contains(REFUSED) || e.message.contains("is not modelled by sppm-gpu")
}

/// A texture's uv mapping: (`uscale`, `vscale`) and (`udelta`, `vdelta`).
fn uv_mapping(p: &Params) -> Result<(Vec2, Vec2)> {
    if let Some(m) = p.string("mapping")?.filter(|m| *m != "uv") {
        return Err(p.error("mapping", format!("the \"{m}\" mapping is not modelled by sppm-gpu: uv")));
    }
    let scale = Vec2::new(p.float_or("uscale", 1.0)?, p.float_or("vscale", 1.0)?);
    let delta = Vec2::new(p.float_or("udelta", 0.0)?, p.float_or("vdelta", 0.0)?);
    Ok((scale, delta))
}

/// An `imagemap` texture (see the module's notes).
fn image_texture(p: &Params) -> Result<Texture> {
    let name = p.string("filename")?.ok_or_else(|| p.error("filename", "an imagemap needs a \"filename\""))?;
    let path = p.resolve(name);
    let png = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
    let raw = match p.string("encoding")?.unwrap_or(if png { "sRGB" } else { "linear" }) {
        "sRGB" => false,
        "linear" => true,
        other => return Err(p.error("encoding", format!("the \"{other}\" encoding is not modelled by sppm-gpu: sRGB, linear"))),
    };
    let wrap = match p.string("wrap")?.unwrap_or("repeat") {
        "repeat" => TextureWrap::Repeat,
        "clamp" => TextureWrap::Clamp,
        other => return Err(p.error("wrap", format!("the \"{other}\" wrap mode is not modelled by sppm-gpu: repeat, clamp"))),
    };
    let filter = match p.string("filter")?.unwrap_or("bilinear") {
        "point" => TextureFilter::Nearest,
        "bilinear" | "trilinear" | "ewa" | "EWA" => TextureFilter::Bilinear,
        other => return Err(p.error("filter", format!("\"{other}\": unknown filter"))),
    };
    p.pass_over(&["maxanisotropy"]);
    let scale = p.float_or("scale", 1.0)?;
    let invert = p.bool_or("invert", false)?;
    let (uv_scale, delta) = uv_mapping(p)?;
    let mut texture = mesh::read_image(&path, raw).map_err(|e| p.error("filename", format!("{}: {e}", path.display())))?;
    if texture.width == 0 || texture.height == 0 {
        return Err(p.error("filename", format!("{}: the image has no texels", path.display())));
    }
    for c in std::sync::Arc::make_mut(&mut texture.texels) {
        *c *= scale;
        if invert {
            *c = (Vec3::ONE - *c).max(Vec3::ZERO);
        }
    }
    texture.filter = filter;
    texture.wrap = wrap;
    // (s, t) = scale uv + delta, looked up at (s, 1 - t).
    texture.to_uv =
        Affine2::from_cols(Vec2::new(uv_scale.x, 0.0), Vec2::new(0.0, -uv_scale.y), Vec2::new(delta.x, 1.0 - delta.y));
    Ok(texture)
}
