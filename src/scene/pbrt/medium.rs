//! pbrt-v4's participating media, as our [`Medium`] (the model: [`crate::scene::medium`]).
//!
//! - `MakeNamedMedium "name" "string type" "homogeneous"`: `sigma_a` (1), `sigma_s` (1),
//!   both times `scale` (1), and `g` (0: isotropic, else Henyey-Greenstein), as pbrt-v4's
//!   HomogeneousMedium; `preset` (named measured media) and an emitting medium (`Le` other
//!   than 0) are refused, as are the grid media (`uniformgrid`, `rgbgrid`, `cloud`,
//!   `nanovdb`).
//! - `MediumInterface "inside" "outside"` (one name: both): the media of the shapes that follow,
//!   inside (against their normals) our `interior`, outside our `exterior`, "" a vacuum. As
//!   in pbrt-v4, a shape whose two names are the same is no transition: a path keeps its
//!   medium there (neither is set). The camera sits in the outside medium in force at
//!   `Camera`. Names are looked up once the whole file is read.

use super::params::{Params, Spectrum};
use super::spectra::SpectrumUse;
use super::{Reader, Result};
use crate::scene::medium::{self, Medium, Phase};
use glam::Vec3;

impl Reader {
    /// `MakeNamedMedium "name"`.
    pub(super) fn named_medium(&mut self, name: &str, p: &Params) -> Result<()> {
        let ty =
            p.string("type")?.ok_or_else(|| p.error("type", format!("{name}: no \"string type\" parameter for the medium")))?;
        match ty {
            "homogeneous" => {}
            "uniformgrid" | "rgbgrid" | "cloud" | "nanovdb" => {
                return Err(p.error(
                    "type",
                    format!("the \"{ty}\" medium (densities vary in space) is not modelled by sppm-gpu: homogeneous"),
                ))
            }
            other => return Err(p.error("type", format!("{other}: medium type unknown"))),
        }
        if p.has("preset") {
            return Err(p.error("preset", "named measured media (preset) are not modelled by sppm-gpu: give sigma_a and sigma_s"));
        }
        let coefficient = |key: &str| -> Result<Vec3> {
            match p.spectrum(key, SpectrumUse::Unbounded)? {
                None => Ok(Vec3::ONE),
                Some(Spectrum::Rgb(c)) => Ok(c),
                Some(Spectrum::Texture(_)) => Err(p.error(key, format!("a texture as {key} is not modelled by sppm-gpu"))),
            }
        };
        let scale = p.float_or("scale", 1.0)?;
        let (sigma_a, sigma_s) = (coefficient("sigma_a")? * scale, coefficient("sigma_s")? * scale);
        for (key, value) in [("sigma_a", sigma_a), ("sigma_s", sigma_s)] {
            if let Some(why) = medium::check_coefficient(key, value) {
                return Err(p.error(if p.has(key) { key } else { "scale" }, why));
            }
        }
        let g = p.float_or("g", 0.0)?;
        if let Some(why) = medium::check_g(g) {
            return Err(p.error("g", why));
        }
        let le = match p.spectrum("Le", SpectrumUse::Illuminant)? {
            None => Vec3::ZERO,
            Some(Spectrum::Rgb(c)) => c,
            Some(Spectrum::Texture(_)) => Vec3::ONE,
        };
        if le != Vec3::ZERO && p.float_or("Lescale", 1.0)? != 0.0 {
            return Err(p.error("Le", "an emitting medium (Le) is not modelled by sppm-gpu"));
        }
        p.pass_over(&["Lescale"]);
        p.get("type");
        p.finish()?;
        if self.named_media.contains_key(name) {
            return Err(p.directive_error(format!("{name}: named medium redefined")));
        }
        let phase = if g == 0.0 { Phase::Isotropic } else { Phase::HenyeyGreenstein { g } };
        self.named_media.insert(name.to_owned(), self.media.len() as u32);
        self.media.push(Medium { name: name.to_owned(), sigma_a, sigma_s, phase, line: p.line });
        Ok(())
    }
}
