//! Mitsuba 3's BSDF plugins, as our materials: `twosided` (one nested BSDF, seen the same from
//! both sides; every other BSDF here but the dielectrics is black seen from behind its shading
//! normal, [`Material::one_sided`]) and the default BSDF of a shape without one are read here;
//! every other plugin by its family in [`crate::scene::material`], whose file documents its
//! plugins' parameters and defaults (Mitsuba 3's plugin reference, "BSDFs"). This file gives
//! the families Mitsuba's types ([`MitsubaBsdf`]):
//!
//! - reflectances: colours in [0, 1], or textures where sppm-gpu textures them (texture.rs: a
//!   diffuse `reflectance`, a plastic's `diffuse_reflectance`, a conductor's
//!   `specular_reflectance`);
//! - indices of refraction: numbers >= 1 or Mitsuba's named media ([`NAMED_IOR`]);
//! - a rough plugin's `distribution` (`beckmann`, Mitsuba's default, or `ggx`) and isotropic
//!   `alpha` (0.1, more than 0); `sample_visible` changes only the noise;
//! - a conductor's `material` (`none`: eta 0, k 1, a perfect mirror; or one of Mitsuba's named
//!   metals, [`NAMED_CONDUCTORS`]) or `eta` (0) and `k` (1), not both. Mitsuba 3's conductors
//!   have no `ext_eta`.
//!
//! In a 0.x scene, Mitsuba 0.6's parameters too: `ensure_energy_conservation` of every BSDF
//! (true: Mitsuba 0.6 scales down a reflectance above 1, which is refused here unless it is
//! textured), a diffuse `diffuse_reflectance` (the name it also takes for `reflectance`), and a
//! conductor's `ext_eta` (1, Mitsuba 3's), the index outside it, which divides eta and k.

use super::props::{Props, Spectrum};
use super::xml::Node;
use super::{Result, SceneError, SceneReader};
use crate::scene::material::{self, MitsubaBsdf};
use crate::scene::{ComplexIor, Material, MaterialKind, Microfacet};
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

/// Mitsuba 3's named conductors (its plugin reference, "conductor": the table of materials,
/// spectra from its `data/ior/*.spd`) as the RGB eta and k it uses in its RGB variants: printed
/// by Mitsuba 3.9.1 itself (`mi.traverse(mi.load_dict({'type': 'conductor', 'material':
/// name}))` under `scalar_rgb` and `llvm_ad_rgb`, which agree), rounded to 6 significant
/// digits. Where Mitsuba clamps an out-of-gamut colour (it warns), its clamped values.
pub const NAMED_CONDUCTORS: &[(&str, [f32; 3], [f32; 3])] = &[
    ("a-C", [2.94405, 2.22714, 1.96816], [0.887465, 0.799299, 0.81529]),
    ("Ag", [0.155276, 0.116728, 0.138388], [4.82835, 3.12222, 2.1469]),
    ("Al", [1.6575, 0.880405, 0.521244], [9.22381, 6.2695, 4.837]),
    ("AlAs", [3.6053, 3.23294, 2.21632], [0.000679437, 0.0, 0.00751271]),
    ("AlAs_palik", [3.6053, 3.23294, 2.21632], [0.000679437, 0.0, 0.00751271]),
    ("AlSb", [0.0, 4.13937, 4.66925], [0.0, 0.0940091, 1.30057]),
    ("AlSb_palik", [0.0, 4.13937, 4.66925], [0.0, 0.0940091, 1.30057]),
    ("Au", [0.143036, 0.375307, 1.44205], [3.983, 2.38556, 1.60336]),
    ("Be", [4.18501, 3.18503, 2.78406], [3.83547, 3.01012, 2.86899]),
    ("Be_palik", [4.18501, 3.18503, 2.78406], [3.83547, 3.01012, 2.86899]),
    ("Cr", [4.36967, 2.91651, 1.6549], [5.20655, 4.23131, 3.7547]),
    ("CsI", [2.1449, 1.70232, 1.66243], [0.0, 0.0, 0.0]),
    ("CsI_palik", [2.1449, 1.70232, 1.66243], [0.0, 0.0, 0.0]),
    ("Cu", [0.201005, 0.92375, 1.10222], [3.91326, 2.45305, 2.14209]),
    ("Cu_palik", [0.213229, 0.919715, 1.10241], [3.92187, 2.45733, 2.13658]),
    ("Cu2O", [3.55177, 2.94987, 2.75188], [0.114207, 0.193897, 0.606134]),
    ("Cu2O_palik", [3.55177, 2.94987, 2.75188], [0.114207, 0.193897, 0.606134]),
    ("CuO", [3.24754, 2.44781, 2.21022], [0.52109, 0.570031, 0.722179]),
    ("CuO_palik", [3.24754, 2.44781, 2.21022], [0.52109, 0.570031, 0.722179]),
    ("d-C", [2.70872, 2.31883, 2.2289], [0.0, 0.0, 0.0]),
    ("d-C_palik", [2.70872, 2.31883, 2.2289], [0.0, 0.0, 0.0]),
    ("Hg", [2.39894, 1.44003, 0.90957], [6.32759, 4.37192, 3.42176]),
    ("Hg_palik", [2.39894, 1.44003, 0.90957], [6.32759, 4.37192, 3.42176]),
    ("HgTe", [4.77904, 3.2312, 2.6599], [1.63161, 1.58081, 1.72929]),
    ("HgTe_palik", [4.77904, 3.2312, 2.6599], [1.63161, 1.58081, 1.72929]),
    ("Ir", [3.0863, 2.08219, 1.61791], [5.59215, 4.06709, 3.26731]),
    ("Ir_palik", [3.0863, 2.08219, 1.61791], [5.59215, 4.06709, 3.26731]),
    ("K", [0.0640432, 0.0464098, 0.0381849], [2.1042, 1.34894, 0.913126]),
    ("K_palik", [0.0640432, 0.0464098, 0.0381849], [2.1042, 1.34894, 0.913126]),
    ("Li", [0.265791, 0.195618, 0.220949], [3.54015, 2.31112, 1.66861]),
    ("Li_palik", [0.265791, 0.195618, 0.220949], [3.54015, 2.31112, 1.66861]),
    ("MgO", [2.08958, 1.65072, 1.59488], [4.3327e-12, 0.0, 2.49865e-11]),
    ("MgO_palik", [2.08958, 1.65072, 1.59488], [4.3327e-12, 0.0, 2.49865e-11]),
    ("Mo", [4.48397, 3.52513, 2.77631], [4.11144, 3.42083, 3.15061]),
    ("Mo_palik", [4.48397, 3.52513, 2.77631], [4.11144, 3.42083, 3.15061]),
    ("Na_palik", [0.0602694, 0.0561409, 0.0619884], [3.17927, 2.11249, 1.57904]),
    ("Nb", [3.42007, 2.79009, 2.39563], [3.44139, 2.73767, 2.57975]),
    ("Nb_palik", [3.42007, 2.79009, 2.39563], [3.44139, 2.73767, 2.57975]),
    ("Ni_palik", [2.3673, 1.66337, 1.46708], [4.49881, 3.05015, 2.34544]),
    ("Rh", [2.58579, 1.86022, 1.55426], [6.78226, 4.70299, 3.97607]),
    ("Rh_palik", [2.58579, 1.86022, 1.55426], [6.78226, 4.70299, 3.97607]),
    ("Se", [4.05831, 2.84294, 2.82085], [0.75405, 0.638444, 0.521808]),
    ("Se_palik", [4.05831, 2.84294, 2.82085], [0.75405, 0.638444, 0.521808]),
    ("Se-e", [5.72285, 4.16574, 4.08134], [0.871136, 1.10516, 1.56532]),
    ("Se-e_palik", [5.72285, 4.16574, 4.08134], [0.871136, 1.10516, 1.56532]),
    ("SiC", [3.17234, 2.52597, 2.47937], [7.53766e-7, 0.0, 1.01925e-5]),
    ("SiC_palik", [3.17234, 2.52597, 2.47937], [7.53766e-7, 0.0, 1.01925e-5]),
    ("SnTe", [4.52425, 1.98164, 1.28159], [0.0, 0.0, 0.0]),
    ("SnTe_palik", [4.52425, 1.98164, 1.28159], [0.0, 0.0, 0.0]),
    ("Ta", [2.06272, 2.39294, 2.62793], [2.40836, 1.74149, 1.94703]),
    ("Ta_palik", [2.06272, 2.39294, 2.62793], [2.40836, 1.74149, 1.94703]),
    ("Te", [7.39023, 4.4821, 2.63711], [3.25602, 3.52706, 3.29205]),
    ("Te_palik", [7.39023, 4.4821, 2.63711], [3.25602, 3.52706, 3.29205]),
    ("Te-e", [7.50891, 4.29643, 2.36999], [5.58393, 4.94721, 3.99759]),
    ("Te-e_palik", [7.50891, 4.29643, 2.36999], [5.58393, 4.94721, 3.99759]),
    ("ThF4", [1.83071, 1.44223, 1.38765], [0.0, 0.0, 0.0]),
    ("ThF4_palik", [1.83071, 1.44223, 1.38765], [0.0, 0.0, 0.0]),
    ("TiC", [3.70053, 2.83742, 2.58229], [3.26564, 2.35159, 2.17279]),
    ("TiC_palik", [3.70053, 2.83742, 2.58229], [3.26564, 2.35159, 2.17279]),
    ("TiN", [1.64845, 1.15052, 1.37982], [3.36833, 1.9435, 1.10207]),
    ("TiN_palik", [1.64845, 1.15052, 1.37982], [3.36833, 1.9435, 1.10207]),
    ("TiO2", [3.45661, 2.80174, 2.90517], [0.000105265, 0.0, 0.000652887]),
    ("TiO2_palik", [3.45661, 2.80174, 2.90517], [0.000105265, 0.0, 0.000652887]),
    ("TiO2-e", [3.10656, 2.51317, 2.58244], [2.97516e-5, 0.0, 0.000182698]),
    ("TiO2-e_palik", [3.10656, 2.51317, 2.58244], [2.97516e-5, 0.0, 0.000182698]),
    ("V_palik", [4.27758, 3.51295, 2.76107], [3.4913, 2.88945, 3.11152]),
    ("VC", [3.65757, 2.75274, 2.53267], [3.0683, 2.19869, 1.96319]),
    ("VC_palik", [3.65757, 2.75274, 2.53267], [3.0683, 2.19869, 1.96319]),
    ("VN", [2.8656, 2.11919, 1.94009], [3.03224, 2.05612, 1.61631]),
    ("VN_palik", [2.8656, 2.11919, 1.94009], [3.03224, 2.05612, 1.61631]),
    ("W", [4.37082, 3.30025, 2.99841], [3.50064, 2.60487, 2.27323]),
];

/// BSDF plugins that Mitsuba has and sppm-gpu does not model yet.
const NOT_YET: &[&str] = &[
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

    /// A BSDF element's scattering model and whether it is one-sided: `twosided` here, every
    /// other plugin by its family ([`material::from_mitsuba`]).
    fn bsdf(&mut self, node: &'a Node) -> Result<(MaterialKind, bool)> {
        node.allow_attrs(&["type", "id", "name"])?;
        let kind = node.req_attr("type")?;
        let p = Props::new(node)?;
        if node.legacy() {
            p.boolean_or("ensure_energy_conservation", true)?;
        }
        if kind == "twosided" {
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
        let model = match material::from_mitsuba(kind, &mut BsdfProps { reader: self, p: &p }) {
            Some(model) => model?,
            None if NOT_YET.contains(&kind) => {
                return Err(node.error(Some("type"), format!("the `{kind}` BSDF is not modelled by sppm-gpu yet")))
            }
            None => return Err(node.error(Some("type"), format!("`{kind}` is not a Mitsuba 3 BSDF plugin"))),
        };
        p.finish()?;
        // Dielectrics scatter from both sides; the flag means nothing to them.
        let one_sided = !model.two_sided_by_nature();
        Ok((model, one_sided))
    }
}

/// A BSDF plugin's parameters, as its family reads them.
struct BsdfProps<'r, 'a> {
    reader: &'r mut SceneReader<'a>,
    p: &'r Props<'a>,
}

impl MitsubaBsdf for BsdfProps<'_, '_> {
    fn legacy(&self) -> bool {
        self.p.node.legacy()
    }

    fn has(&self, name: &str) -> bool {
        self.p.has(name)
    }

    fn reflectance(&mut self, name: &str, default: f32) -> Result<(Vec3, Option<u32>)> {
        if let Some(Spectrum::Texture(node)) = self.p.spectrum(name)? {
            return Ok((Vec3::ONE, Some(self.reader.texture(node)?)));
        }
        Ok((constant_reflectance(self.p, name, default)?, None))
    }

    fn constant_reflectance(&self, name: &str, default: f32) -> Result<Vec3> {
        constant_reflectance(self.p, name, default)
    }

    fn ior(&self, name: &str, default: f32) -> Result<f32> {
        ior(self.p, name, default)
    }

    fn microfacets(&self) -> Result<(f32, Microfacet)> {
        alpha(self.p)
    }

    fn complex_ior(&self) -> Result<Option<ComplexIor>> {
        ext_eta(self.p, conductor_ior(self.p)?)
    }

    fn boolean_or(&self, name: &str, default: bool) -> Result<bool> {
        self.p.boolean_or(name, default)
    }

    fn error(&self, name: &str, message: String) -> SceneError {
        self.p.node.error(Some(name), message)
    }

    fn error_at(&self, name: &str, message: String) -> SceneError {
        self.p.get(name).unwrap_or(self.p.node).error(Some(name), message)
    }
}

/// A reflectance parameter that cannot be textured here: a colour in [0, 1].
fn constant_reflectance(p: &Props, name: &str, default: f32) -> Result<Vec3> {
    match p.spectrum(name)? {
        None => Ok(Vec3::splat(default)),
        Some(Spectrum::Rgb(rgb)) => {
            if rgb.min_element() < 0.0 || rgb.max_element() > 1.0 {
                return Err(p.get(name).unwrap().error(Some(name), format!("{name} {rgb} is outside [0, 1]")));
            }
            Ok(rgb)
        }
        Some(Spectrum::Texture(node)) => Err(untexturable(p, node, name)),
    }
}

/// The error for a texture on a parameter that sppm-gpu does not texture: where the texture
/// (or its `<ref>`) is, what it is on, and what can be textured.
pub(super) fn untexturable(p: &Props, node: &Node, name: &str) -> super::SceneError {
    node.error(
        Some(name),
        format!(
            "a texture as {name} of {}: sppm-gpu textures only a diffuse `reflectance`, a plastic's \
             `diffuse_reflectance` and a conductor's `specular_reflectance`",
            p.node.describe()
        ),
    )
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

/// A microfacet BSDF's roughness and distribution: `distribution` `beckmann` (Mitsuba's
/// default) or `ggx`, `alpha` (0.1) isotropic; `sample_visible` changes only the noise.
fn alpha(p: &Props) -> Result<(f32, Microfacet)> {
    let distribution = match p.string("distribution")?.unwrap_or("beckmann") {
        "beckmann" => Microfacet::Beckmann,
        "ggx" => Microfacet::Ggx,
        other => {
            return Err(p.get("distribution").unwrap().error(
                Some("distribution"),
                format!("the {other} microfacet distribution is not modelled by sppm-gpu: beckmann or ggx"),
            ))
        }
    };
    p.boolean_or("sample_visible", true)?;
    if p.has("alpha_u") || p.has("alpha_v") {
        let key = if p.has("alpha_u") { "alpha_u" } else { "alpha_v" };
        let u = p.float("alpha_u")?;
        let v = p.float("alpha_v")?;
        if u != v || p.has("alpha") {
            return Err(p.node.error(Some(key), "anisotropic roughness (alpha_u != alpha_v) is not modelled by sppm-gpu"));
        }
        return Ok((check_alpha(p, u.unwrap_or(0.1))?, distribution));
    }
    let alpha = match p.spectrum("alpha")? {
        None => 0.1,
        Some(Spectrum::Rgb(v)) if v.x == v.y && v.y == v.z => v.x,
        Some(Spectrum::Texture(node)) => return Err(untexturable(p, node, "alpha")),
        Some(_) => return Err(p.get("alpha").unwrap().error(Some("alpha"), "alpha is one number (one value for r, g and b)")),
    };
    Ok((check_alpha(p, alpha)?, distribution))
}

/// A conductor's complex index of refraction, as Mitsuba 3's `conductor` and `roughconductor`
/// read it: `eta` (0) and `k` (1) when either `eta` is given or `material` is `none` (its
/// default), else the named metal's; naming one and giving `eta` is an error, and so (unread
/// by Mitsuba) is giving `k` with a named metal. `None` for eta 0, k 1: Fresnel 1.
fn conductor_ior(p: &Props) -> Result<Option<ComplexIor>> {
    let material = p.string("material")?.map(str::trim).unwrap_or("none");
    let (eta, k) = if p.has("eta") || material == "none" {
        if material != "none" {
            let at = p.get("material").unwrap();
            return Err(at.error(Some("material"), "a conductor takes either eta and k or a named material, not both"));
        }
        (ior_rgb(p, "eta", 0.0)?, ior_rgb(p, "k", 1.0)?)
    } else {
        if p.has("k") {
            let at = p.get("k").unwrap();
            return Err(at.error(Some("k"), "a conductor takes either eta and k or a named material, not both"));
        }
        let Some(&(_, eta, k)) = NAMED_CONDUCTORS.iter().find(|(name, _, _)| *name == material) else {
            let names: Vec<&str> = NAMED_CONDUCTORS.iter().map(|(n, _, _)| *n).collect();
            let at = p.get("material").unwrap();
            return Err(at.error(
                Some("material"),
                format!("\"{material}\" is not one of Mitsuba's named conductors (none, {})", names.join(", ")),
            ));
        };
        (Vec3::from(eta), Vec3::from(k))
    };
    Ok((eta != Vec3::ZERO || k != Vec3::ONE).then_some(ComplexIor { eta, k }))
}

/// Mitsuba 0.6's `ext_eta` of a conductor, in a 0.x scene: the index of refraction outside it
/// (a number or a named medium), which divides `fresnel`'s eta and k. Left out, 1, as in
/// Mitsuba 3, which has none (Mitsuba 0.6's default, air, is 0.03% more); in a 2/3 scene it is
/// not read ([`Props::finish`] refuses it). A perfect mirror (`None`) stays one.
fn ext_eta(p: &Props, fresnel: Option<ComplexIor>) -> Result<Option<ComplexIor>> {
    if !p.node.legacy() || !p.has("ext_eta") {
        return Ok(fresnel);
    }
    let outside = ior(p, "ext_eta", 1.0)?;
    Ok(fresnel.map(|ComplexIor { eta, k }| ComplexIor { eta: eta / outside, k: k / outside }))
}

/// A part of a conductor's index of refraction: a colour (`<rgb>`, a `<spectrum>` of one value,
/// a `<float>`) of finite numbers >= 0.
fn ior_rgb(p: &Props, name: &str, default: f32) -> Result<Vec3> {
    match p.unbounded_spectrum(name)? {
        None => Ok(Vec3::splat(default)),
        Some(Spectrum::Rgb(rgb)) => {
            if !(rgb.is_finite() && rgb.min_element() >= 0.0) {
                return Err(p.get(name).unwrap().error(Some(name), format!("{name} {rgb}: each channel is a number >= 0")));
            }
            Ok(rgb)
        }
        Some(Spectrum::Texture(node)) => Err(untexturable(p, node, name)),
    }
}

/// A rough plugin's `alpha`: more than 0 (its smooth counterpart has none); the family's
/// check takes it from there.
fn check_alpha(p: &Props, alpha: f32) -> Result<f32> {
    if alpha.is_nan() || alpha <= 0.0 {
        let at = p.get("alpha").unwrap_or(p.node);
        return Err(at.error(Some("alpha"), format!("alpha {alpha}: a rough plugin's alpha is more than 0")));
    }
    Ok(alpha)
}
