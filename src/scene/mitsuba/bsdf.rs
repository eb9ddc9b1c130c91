//! Mitsuba 3's BSDF plugins, as our materials. Each plugin's parameters and defaults are
//! Mitsuba 3's (its plugin reference, "BSDFs"):
//!
//! - `diffuse`: `reflectance` (0.5). Lambertian, albedo / pi.
//! - `twosided`: one nested BSDF, seen the same from both sides. Every other BSDF here but the
//!   dielectrics is black seen from behind its shading normal ([`Material::one_sided`]).
//! - `dielectric`: `int_ior` (`bk7`, 1.5046), `ext_ior` (`air`, 1.000277), each a number or a
//!   named medium; our `ior` is their ratio. Smooth Fresnel reflection and refraction.
//! - `roughdielectric`: as `dielectric`, with `distribution` (`beckmann`) and `alpha` (0.1);
//!   Walter et al. 2007 sampled by visible normals. GGX only, for now.
//! - `conductor`: `material` (`none`: eta 0, k 1, a perfect mirror) and
//!   `specular_reflectance` (1). Only `none`, for now: named metals need the conductor
//!   Fresnel term.
//! - `roughconductor`: as `conductor`, with `distribution` (`beckmann`) and `alpha` (0.1): a
//!   GGX conductor with Fresnel 1. GGX only, for now.

use super::props::{Props, Spectrum};
use super::xml::Node;
use super::{Result, SceneReader};
use crate::scene::{Material, MaterialKind};
use glam::Vec3;

/// Mitsuba's named indices of refraction (its plugin reference, "dielectric": "IOR values").
const NAMED_IOR: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// BSDF plugins that Mitsuba has and sppm-gpu does not model yet.
const NOT_YET: &[&str] = &[
    "thindielectric",
    "plastic",
    "roughplastic",
    "null",
    "principled",
    "principledthin",
    "blendbsdf",
    "mask",
    "bumpmap",
    "normalmap",
    "pplastic",
    "hair",
    "measured",
    "polarizer",
    "retarder",
    "circular",
    "coating",
    "roughcoating",
    "phong",
    "ward",
    "difftrans",
];

impl<'a> SceneReader<'a> {
    /// The material of a shape's BSDF element (nested or a `<ref>`), or of Mitsuba 3's
    /// default BSDF when it has none: a one-sided `diffuse` of reflectance 0.5, or 0 for a
    /// shape that emits (as Mitsuba 3.9.1 gives them, checked by printing its shapes' BSDFs).
    pub(super) fn material(&mut self, bsdf: Option<&'a Node>, shape: &Node, emits: bool) -> Result<u32> {
        let Some(bsdf) = bsdf else {
            let index = self.materials.len() as u32;
            let albedo = if emits { 0.0 } else { 0.5 };
            self.materials.push(Material {
                name: format!("default-{}:{}", shape.file.display(), shape.line),
                kind: MaterialKind::Diffuse { albedo: Vec3::splat(albedo), texture: None },
                one_sided: true,
                line: shape.line,
            });
            return Ok(index);
        };
        let bsdf = self.deref(bsdf, "bsdf")?;
        if let Some(&index) = self.material_of.get(&(bsdf as *const Node)) {
            return Ok(index);
        }
        let (kind, one_sided) = self.bsdf(bsdf)?;
        let index = self.materials.len() as u32;
        let name = match bsdf.attr("id") {
            Some(id) => id.to_owned(),
            None => format!("{}:{}", bsdf.file.display(), bsdf.line),
        };
        self.materials.push(Material { name, kind, one_sided, line: bsdf.line });
        self.material_of.insert(bsdf as *const Node, index);
        Ok(index)
    }

    /// A BSDF element's scattering model and whether it is one-sided.
    fn bsdf(&mut self, node: &'a Node) -> Result<(MaterialKind, bool)> {
        node.allow_attrs(&["type", "id", "name"])?;
        let kind = node.req_attr("type")?;
        let p = Props::new(node)?;
        let model = match kind {
            "twosided" => {
                let inner = p.all_objects();
                let [inner] = inner.as_slice() else {
                    return Err(node.error(
                        None,
                        format!("a twosided BSDF with {} nested BSDFs: sppm-gpu reads one, used on both sides", inner.len()),
                    ));
                };
                let inner = self.deref(inner, "bsdf")?;
                if inner.tag != "bsdf" || inner.attr("type") == Some("twosided") {
                    return Err(inner.error(None, "twosided wraps one BSDF that is not itself twosided"));
                }
                p.finish()?;
                let (model, _) = self.bsdf(inner)?;
                return Ok((model, false));
            }
            "diffuse" => {
                let albedo = self.reflectance(&p, "reflectance", 0.5)?;
                MaterialKind::Diffuse { albedo, texture: None }
            }
            "dielectric" | "roughdielectric" => {
                let ior = ior(&p, "int_ior", 1.5046)? / ior(&p, "ext_ior", 1.000277)?;
                if !(ior.is_finite() && ior > 0.0) || ior == 1.0 {
                    return Err(node
                        .error(Some("int_ior"), format!("int_ior / ext_ior = {ior}: an interface needs two different indices")));
                }
                for name in ["specular_reflectance", "specular_transmittance"] {
                    if self.reflectance(&p, name, 1.0)? != Vec3::ONE {
                        return Err(p
                            .get(name)
                            .unwrap()
                            .error(Some(name), format!("a dielectric's {name} other than 1 is not modelled by sppm-gpu yet")));
                    }
                }
                let roughness = if kind == "roughdielectric" { alpha(&p)? } else { 0.0 };
                MaterialKind::Dielectric { ior, roughness }
            }
            "conductor" | "roughconductor" => {
                let material = p.string("material")?.unwrap_or("none");
                if material != "none" || p.has("eta") || p.has("k") {
                    let key = if p.has("eta") {
                        "eta"
                    } else if p.has("k") {
                        "k"
                    } else {
                        "material"
                    };
                    return Err(p.get(key).unwrap().error(
                        Some(key),
                        "a conductor with a Fresnel term (a named metal, eta or k) is not modelled by sppm-gpu yet; \
                         only material = \"none\" (a perfect reflector times specular_reflectance)",
                    ));
                }
                let albedo = self.reflectance(&p, "specular_reflectance", 1.0)?;
                if kind == "conductor" {
                    MaterialKind::Mirror { albedo }
                } else {
                    MaterialKind::Glossy { albedo, roughness: alpha(&p)? }
                }
            }
            other if NOT_YET.contains(&other) => {
                return Err(node.error(Some("type"), format!("the `{other}` BSDF is not modelled by sppm-gpu yet")))
            }
            other => return Err(node.error(Some("type"), format!("`{other}` is not a Mitsuba 3 BSDF plugin"))),
        };
        p.finish()?;
        // Dielectrics scatter from both sides; the flag means nothing to them.
        let one_sided = !matches!(model, MaterialKind::Dielectric { .. });
        Ok((model, one_sided))
    }

    /// A reflectance parameter: a colour in [0, 1] (textures come later).
    fn reflectance(&mut self, p: &Props<'a>, name: &str, default: f32) -> Result<Vec3> {
        match p.spectrum(name)? {
            None => Ok(Vec3::splat(default)),
            Some(Spectrum::Rgb(rgb)) => {
                if rgb.min_element() < 0.0 || rgb.max_element() > 1.0 {
                    return Err(p.get(name).unwrap().error(Some(name), format!("{name} {rgb} is outside [0, 1]")));
                }
                Ok(rgb)
            }
            Some(Spectrum::Texture(node)) => {
                let node = self.deref(node, "texture")?;
                Err(node.error(
                    Some(name),
                    format!("{} as {name}: textures from Mitsuba scenes are not read by sppm-gpu yet", node.describe()),
                ))
            }
        }
    }
}

/// An index of refraction: a number or one of Mitsuba's named media.
fn ior(p: &Props, name: &str, default: f32) -> Result<f32> {
    let Some(node) = p.get(name) else { return Ok(default) };
    node.allow_attrs(&["name", "value"])?;
    let text = node.req_attr("value")?;
    let value = match node.tag.as_str() {
        "float" | "integer" => super::props::parse_f32(node, text, name)?,
        "string" => NAMED_IOR.iter().find(|(n, _)| *n == text.trim()).map(|(_, v)| *v).ok_or_else(|| {
            let names: Vec<&str> = NAMED_IOR.iter().map(|(n, _)| *n).collect();
            node.error(
                Some(name),
                format!("\"{text}\" is not one of Mitsuba's named indices of refraction ({})", names.join(", ")),
            )
        })?,
        _ => return Err(node.error(Some(name), format!("`{name}` is a <float> or a <string> naming a medium"))),
    };
    if value.is_nan() || value < 1.0 {
        return Err(node.error(Some(name), format!("an index of refraction below 1 ({value})")));
    }
    Ok(value)
}

/// A microfacet BSDF's roughness: `distribution` must be `ggx` (Mitsuba's default is
/// `beckmann`), `alpha` (0.1) isotropic; `sample_visible` changes only the noise.
fn alpha(p: &Props) -> Result<f32> {
    let distribution = p.string("distribution")?.unwrap_or("beckmann");
    if distribution != "ggx" {
        let at = p.get("distribution").unwrap_or(p.node);
        return Err(at.error(
            Some("distribution"),
            format!(
                "the {distribution} microfacet distribution{} is not modelled by sppm-gpu yet: only ggx",
                if p.has("distribution") { "" } else { " (Mitsuba's default)" }
            ),
        ));
    }
    p.boolean_or("sample_visible", true)?;
    if p.has("alpha_u") || p.has("alpha_v") {
        let key = if p.has("alpha_u") { "alpha_u" } else { "alpha_v" };
        let u = p.float("alpha_u")?;
        let v = p.float("alpha_v")?;
        if u != v || p.has("alpha") {
            return Err(p.node.error(Some(key), "anisotropic roughness (alpha_u != alpha_v) is not modelled by sppm-gpu"));
        }
        return check_alpha(p, u.unwrap_or(0.1));
    }
    let alpha = match p.spectrum("alpha")? {
        None => 0.1,
        Some(Spectrum::Rgb(v)) if v.x == v.y && v.y == v.z => v.x,
        Some(_) => {
            return Err(p.get("alpha").unwrap().error(Some("alpha"), "alpha is one number (textured roughness is not read)"))
        }
    };
    check_alpha(p, alpha)
}

fn check_alpha(p: &Props, alpha: f32) -> Result<f32> {
    if !(alpha > 0.0 && alpha <= 1.0) {
        let at = p.get("alpha").unwrap_or(p.node);
        return Err(at.error(Some("alpha"), format!("alpha {alpha} is outside (0, 1]")));
    }
    Ok(alpha)
}
