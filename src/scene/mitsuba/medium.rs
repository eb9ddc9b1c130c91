//! Mitsuba's participating media, as our [`Medium`] (issue 35; the model in
//! [`crate::scene::medium`]). Where a medium is:
//!
//! - in a shape: nested `<medium type=".." name="interior">` (or `"exterior"`), or
//!   `<ref name="interior" id=".."/>`; any other name, or none, is refused (Mitsuba 3 would
//!   pass it over, and the scene would not be the one meant). Any shape, open or closed, and
//!   any BSDF may bound it, as in Mitsuba 3.
//! - in the sensor: one nested `<medium>` or `<ref>` (any name), the medium the camera sits in.
//! - at the top level, with an `id`, for the shapes and the sensor that refer to it: read and
//!   checked even where nothing does, as Mitsuba instantiates it.
//!
//! `homogeneous`, Mitsuba 3 (and 2): `sigma_t` (1) and `albedo` (0.75), a `<float>`, `<rgb>`
//! or `<spectrum>` each, times `scale` (1): sigma_s = albedo scale sigma_t, sigma_a = scale
//! sigma_t - sigma_s. Mitsuba 3 reads an `<rgb>` sigma_t as a reflectance and refuses one
//! above 1 (the magnitude goes in `scale`): so does this reader. `sample_emitters` (true):
//! false is warned, as ours samples emitters in every medium (Mitsuba's volpath then finds
//! the same light by phase sampling alone: the noise, not the image).
//! `has_spectral_extinction` (true), a hint for its distance sampling, is read and passed
//! over. A `<volume>` (a grid) as `sigma_t` or `albedo` is a heterogeneous medium: refused.
//!
//! `homogeneous`, Mitsuba 0.5/0.6 (in a 0.x scene): `sigmaA` and `sigmaS`, or `sigmaT` and
//! `albedo` (both of one pair: 0.6 fills the missing one from its `material` preset), not both
//! forms, times `scale` (1), or `densityMultiplier`, its name before 0.5 (0.5/0.6 refuse it as
//! renamed; read here as `scale`, with a warning). The named `material` presets (0.6's
//! measured table) are refused: give the coefficients. The medium's own `g` is refused (0.6
//! turns sigmaS into the reduced (1 - g) sigmaS with it; give `g` to the `hg` phase). How 0.6
//! samples distances (`strategy`, `mediumSamplingWeight`, `samplingDensity`, `channel`) is
//! warned: the noise; `monochromatic` true (one channel's coefficients for all) is refused.
//!
//! Phase functions, nested unnamed in the medium (or a `<ref>` to a top-level `<phase id>`):
//! `isotropic`, and `hg` with `g` (0.8, as Mitsuba 0.6 and 3 default) in (-1, 1). Any other
//! (`rayleigh`, `sggx`, `tabphase`, `blendphase`, 0.6's `kkay`, `microflake`,
//! `mixturephase`) is refused. No phase function is isotropic.
//!
//! `heterogeneous` media, and any other type, are refused naming the type.

use super::props::{Props, Spectrum};
use super::xml::Node;
use super::{Result, SceneReader};
use crate::scene::medium::{self, Medium, Phase};
use glam::Vec3;

/// Mitsuba's default Henyey-Greenstein mean cosine (0.6's `hg.cpp` and Mitsuba 3's alike).
const HG_DEFAULT_G: f32 = 0.8;

impl<'a> SceneReader<'a> {
    /// The index of the medium element `node` (a `<medium>`, or a `<ref>` to one) in the
    /// scene's media, read the first time it is met: a medium shared by reference is one.
    pub(super) fn medium(&mut self, node: &'a Node) -> Result<u32> {
        let target = self.deref(node, "medium")?;
        if let Some(&index) = self.medium_of.get(&(target as *const Node)) {
            return Ok(index);
        }
        let medium = self.read_medium(target)?;
        let index = self.media.len() as u32;
        self.media.push(medium);
        self.medium_of.insert(target as *const Node, index);
        Ok(index)
    }

    /// Reads medium element `node` (not a `<ref>`).
    pub(super) fn read_medium(&self, node: &'a Node) -> Result<Medium> {
        node.allow_attrs(&["type", "id", "name"])?;
        let kind = node.req_attr("type")?;
        if kind != "homogeneous" {
            let why = match kind {
                "heterogeneous" => "heterogeneous media (densities from a volume grid) are not rendered by sppm-gpu: only \
                                    `homogeneous` participating media"
                    .to_owned(),
                other => format!("`{other}` is not a medium sppm-gpu renders: only `homogeneous` participating media"),
            };
            return Err(node.error(Some("type"), why));
        }
        let p = Props::new(node)?;
        let mut phase = None;
        for object in p.all_objects() {
            let target = self.deref(object, "")?;
            match target.tag.as_str() {
                "phase" if phase.is_none() => phase = Some(read_phase(target)?),
                "phase" => return Err(object.error(None, "a second phase function in one medium")),
                "volume" => {
                    return Err(object.error(
                        None,
                        format!(
                            "{} inside a medium: a volume grid makes a heterogeneous medium, which sppm-gpu does not render",
                            target.describe()
                        ),
                    ))
                }
                _ => return Err(object.error(None, format!("{} inside a medium: it holds a <phase> only", target.describe()))),
            }
        }
        let (sigma_a, sigma_s) = if node.legacy() { legacy_coefficients(&p)? } else { coefficients(&p)? };
        p.finish()?;
        let name = match node.attr("id") {
            Some(id) => id.to_owned(),
            None => format!("{}:{}", node.file.display(), node.line),
        };
        Ok(Medium { name, sigma_a, sigma_s, phase: phase.unwrap_or(Phase::Isotropic), line: node.line })
    }
}

/// A medium's colour parameter `name` (a reflectance-like fraction when `fraction`, an
/// unbounded coefficient otherwise), refusing a texture or volume: that is a heterogeneous
/// medium.
fn colour(p: &Props, name: &str, fraction: bool) -> Result<Option<Vec3>> {
    let value = if fraction { p.spectrum(name)? } else { p.unbounded_spectrum(name)? };
    match value {
        None => Ok(None),
        Some(Spectrum::Rgb(rgb)) => Ok(Some(rgb)),
        Some(Spectrum::Texture(node)) => Err(node.error(
            Some(name),
            format!("a {} as a medium's `{name}` makes it heterogeneous, which sppm-gpu does not render", node.describe()),
        )),
    }
}

/// Checks coefficients after scaling; errors are placed at `at`'s parameter `key`.
fn checked(p: &Props, key: &str, sigma_a: Vec3, sigma_s: Vec3) -> Result<(Vec3, Vec3)> {
    for (what, value) in [("sigma_a", sigma_a), ("sigma_s", sigma_s)] {
        if let Some(why) = medium::check_coefficient(what, value) {
            return Err(p.get(key).unwrap_or(p.node).error(Some(key), why));
        }
    }
    Ok((sigma_a, sigma_s))
}

/// An albedo in [0, 1] per channel, with errors at parameter `albedo`.
fn checked_albedo(p: &Props, albedo: Vec3) -> Result<Vec3> {
    match medium::check_albedo(albedo) {
        Some(why) => Err(p.get("albedo").unwrap_or(p.node).error(Some("albedo"), why)),
        None => Ok(albedo),
    }
}

/// A coefficient at least 0 per channel, with errors at parameter `key`.
fn non_negative(p: &Props, key: &str, value: Vec3) -> Result<Vec3> {
    match medium::check_coefficient(key, value) {
        Some(why) => Err(p.get(key).unwrap_or(p.node).error(Some(key), why)),
        None => Ok(value),
    }
}

/// A scale at least 0, with errors at parameter `key`.
fn scale_of(p: &Props, key: &str) -> Result<f32> {
    let scale = p.float_or(key, 1.0)?;
    if scale < 0.0 {
        let at = p.get(key).unwrap_or(p.node);
        return Err(at.error(Some(key), format!("{key} {scale} is negative: a medium's scale is at least 0")));
    }
    Ok(scale)
}

/// Mitsuba 3's `homogeneous`: `sigma_t` (1), `albedo` (0.75), `scale` (1), `sample_emitters`,
/// `has_spectral_extinction`.
fn coefficients(p: &Props) -> Result<(Vec3, Vec3)> {
    let sigma_t = non_negative(p, "sigma_t", colour(p, "sigma_t", false)?.unwrap_or(Vec3::ONE))?;
    // Mitsuba 3 turns an RGB sigma_t into a reflectance spectrum, and refuses one above 1.
    if let Some(node) = p.get("sigma_t").filter(|n| n.tag == "rgb" || n.tag == "srgb") {
        if sigma_t.max_element() > 1.0 {
            return Err(node.error(
                Some("sigma_t"),
                format!(
                    "sigma_t {sigma_t} as <{}>: Mitsuba 3 reads an RGB sigma_t as a reflectance, within [0, 1], and \
                     refuses this one; give the colour within [0, 1] and its magnitude as `scale` (or one number as \
                     <float>)",
                    node.tag
                ),
            ));
        }
    }
    let albedo = checked_albedo(p, colour(p, "albedo", true)?.unwrap_or(Vec3::splat(0.75)))?;
    let scale = scale_of(p, "scale")?;
    if !p.boolean_or("sample_emitters", true)? {
        p.get("sample_emitters").unwrap().warn(
            Some("sample_emitters"),
            "sample_emitters false is not applied: sppm-gpu samples emitters from every medium, which changes the noise, \
             not the image",
        );
    }
    p.boolean_or("has_spectral_extinction", true)?;
    let (sigma_a, sigma_s) = medium::from_extinction(sigma_t, albedo, scale);
    checked(p, "scale", sigma_a, sigma_s)
}

/// Mitsuba 0.5/0.6's `homogeneous`, its parameters in snake_case as read from a 0.x file.
fn legacy_coefficients(p: &Props) -> Result<(Vec3, Vec3)> {
    if let Some(at) = p.get("material") {
        let name = at.attr("value").unwrap_or("");
        return Err(at.error(
            Some("material"),
            format!(
                "the medium preset \"{name}\" (Mitsuba 0.6's table of measured media) is not read by sppm-gpu: give \
                 sigmaA and sigmaS (or sigmaT and albedo) in inverse scene units"
            ),
        ));
    }
    if let Some(at) = p.get("g") {
        return Err(at.error(
            Some("g"),
            "a medium's own g (Mitsuba 0.6 scales sigmaS by 1 - g with it, the reduced scattering coefficient) is not \
             modelled: give g to a nested <phase type=\"hg\">",
        ));
    }
    if p.has("size_multiplier") {
        return Err(p.get("size_multiplier").unwrap().error(
            Some("size_multiplier"),
            "sizeMultiplier is the name Mitsuba 0.4 gave densityMultiplier, now `scale`: give `scale`",
        ));
    }
    let scale_key = match (p.has("scale"), p.has("density_multiplier")) {
        (true, true) => {
            return Err(p.get("density_multiplier").unwrap().error(
                Some("density_multiplier"),
                "densityMultiplier and scale are one parameter (renamed `scale` in Mitsuba 0.5): give one",
            ))
        }
        (false, true) => {
            p.get("density_multiplier").unwrap().warn(
                Some("density_multiplier"),
                "densityMultiplier is read as `scale`, its name since Mitsuba 0.5 (0.5/0.6 refuse densityMultiplier)",
            );
            "density_multiplier"
        }
        _ => "scale",
    };
    let scale = scale_of(p, scale_key)?;
    let pair = |names: [&'static str; 2]| names.into_iter().find(|n| p.has(n));
    let (sigma_a, sigma_s) = match (pair(["sigma_a", "sigma_s"]), pair(["sigma_t", "albedo"])) {
        (Some(_), Some(other)) => {
            return Err(p.get(other).unwrap().error(
                Some(other),
                "give sigmaA and sigmaS, or sigmaT and albedo: Mitsuba 0.6 refuses parameters of both forms",
            ))
        }
        (Some(_), None) => {
            let need = |name: &str| -> Result<Vec3> {
                let value = colour(p, name, false)?.ok_or_else(|| {
                    p.node.error(
                        Some(name),
                        "a homogeneous medium needs both sigmaA and sigmaS (Mitsuba 0.6 would take the missing one from \
                         its `skin1` preset)",
                    )
                })?;
                non_negative(p, name, value)
            };
            (need("sigma_a")? * scale, need("sigma_s")? * scale)
        }
        (None, Some(_)) => {
            let missing = |name: &str| {
                p.node.error(
                    Some(name),
                    "a homogeneous medium needs both sigmaT and albedo (Mitsuba 0.6 would take the missing one from its \
                     `skin1` preset)",
                )
            };
            let sigma_t = non_negative(p, "sigma_t", colour(p, "sigma_t", false)?.ok_or_else(|| missing("sigma_t"))?)?;
            let albedo = checked_albedo(p, colour(p, "albedo", true)?.ok_or_else(|| missing("albedo"))?)?;
            medium::from_extinction(sigma_t, albedo, scale)
        }
        (None, None) => {
            return Err(p.node.error(
                Some("sigma_a"),
                "a homogeneous medium needs sigmaA and sigmaS, or sigmaT and albedo (Mitsuba 0.6's default, its `skin1` \
                 preset, is not read)",
            ))
        }
    };
    p.legacy_ignored(
        &["strategy", "medium_sampling_weight", "sampling_density", "channel"],
        "it sets how Mitsuba 0.6 samples distances in the medium, which changes the noise, not the image",
    );
    if p.boolean_or("monochromatic", false)? {
        return Err(p.get("monochromatic").unwrap().error(
            Some("monochromatic"),
            "monochromatic true (one channel's coefficients for every channel) is not modelled by sppm-gpu",
        ));
    }
    checked(p, scale_key, sigma_a, sigma_s)
}

/// A `<phase>` element.
fn read_phase(node: &Node) -> Result<Phase> {
    node.allow_attrs(&["type", "id", "name"])?;
    let kind = node.req_attr("type")?;
    let p = Props::new(node)?;
    let phase = match kind {
        "isotropic" => Phase::Isotropic,
        "hg" => {
            let g = p.float_or("g", HG_DEFAULT_G)?;
            if let Some(why) = medium::check_g(g) {
                return Err(p.get("g").unwrap_or(node).error(Some("g"), why));
            }
            Phase::HenyeyGreenstein { g }
        }
        other => {
            return Err(node.error(
                Some("type"),
                format!("the `{other}` phase function is not modelled by sppm-gpu: `isotropic` or `hg` (Henyey-Greenstein)"),
            ))
        }
    };
    p.finish()?;
    Ok(phase)
}

/// Reads a top-level `<phase id="..">`, declared for media that refer to it, to check it.
pub(super) fn check_phase(node: &Node) -> Result<()> {
    read_phase(node).map(|_| ())
}
