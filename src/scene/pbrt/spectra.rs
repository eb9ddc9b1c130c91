//! pbrt-v4's spectra as the linear sRGB colours sppm-gpu renders with:
//!
//! - lights' spectra (`L`, `I`) are scaled by pbrt-v4 to one nit of luminance (its
//!   `SpectrumToPhotometric`): an `rgb` colour stays as given (only its illuminant, D65, is
//!   normalized), a `blackbody`, a named illuminant or a sampled spectrum becomes the colour of
//!   luminance Y = 1;
//! - reflectances given by wavelengths are integrated under D65 and clamped to [0, 1], as the
//!   Mitsuba reader's [`spectrum_to_srgb`] does; `blackbody` reflectances are pbrt-v4's, peak 1;
//! - named spectra: `metal-<M>-eta` and `metal-<M>-k` for Ag, Al, Au, Cu, MgO and TiO2 take
//!   the RGB values of Mitsuba 3's RGB rendering of the same metals ([`NAMED_CONDUCTORS`]);
//!   `glass-*` are the glass's index at the d line (587.6 nm, Schott's catalogue), as the RGB
//!   renderer cannot disperse; `stdillum-D65` is white and `stdillum-A` a 2856 K blackbody.
//!   Brass (`metal-CuZn-*`) and the other named illuminants and sensors are refused;
//! - a spectrum file (`"spectrum L" "file.spd"`, pairs of wavelength and value) as a sampled
//!   spectrum.

use crate::scene::mitsuba::spectra::{spectrum_to_srgb, SpectrumUse as MitsubaUse};
use crate::scene::mitsuba::NAMED_CONDUCTORS;
use glam::Vec3;
use std::path::PathBuf;

/// What a spectrum parameter is, which decides how it becomes a colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumUse {
    /// A reflectance: in [0, 1].
    Albedo,
    /// Any other non-emissive quantity (eta, k, a medium's coefficients): >= 0.
    Unbounded,
    /// Emitted radiance or intensity: normalized to luminance 1 but for `rgb`.
    Illuminant,
}

/// Indices of refraction at the d line of pbrt-v4's named glasses.
const GLASSES: &[(&str, f32)] = &[
    ("glass-BK7", 1.5168),
    ("glass-BAF10", 1.6700),
    ("glass-FK51A", 1.4866),
    ("glass-LASF9", 1.8503),
    ("glass-F5", 1.6727),
    ("glass-F10", 1.7283),
    ("glass-F11", 1.7847),
];

/// Luminance Y of a linear sRGB colour.
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The index of refraction of a named glass, if `name` is one.
pub fn glass_ior(name: &str) -> Option<f32> {
    GLASSES.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
}

/// The colour of a blackbody of `kelvin` for its use.
pub fn blackbody_rgb(kelvin: f32, used: SpectrumUse) -> Vec3 {
    let planck = |nm: f64| {
        let (c, h, kb) = (299_792_458.0f64, 6.626_070_15e-34f64, 1.380_649e-23f64);
        let l = nm * 1e-9;
        2.0 * h * c * c / (l.powi(5) * ((h * c / (l * kb * kelvin as f64)).exp() - 1.0))
    };
    // Peak 1 (Wien's law), as pbrt-v4's BlackbodySpectrum.
    let peak = planck(2.897_771_955e-3 / kelvin as f64 * 1e9).max(f64::MIN_POSITIVE);
    let points: Vec<(f32, f32)> =
        (0..=94).map(|i| 360.0 + 5.0 * i as f64).map(|w| (w as f32, (planck(w) / peak) as f32)).collect();
    sampled_rgb(&points, used).unwrap_or(Vec3::ZERO)
}

/// The colour of the spectrum through (wavelength, value) points for its use.
pub fn sampled_rgb(points: &[(f32, f32)], used: SpectrumUse) -> Result<Vec3, String> {
    if points.len() < 2 || points.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err("a spectrum's wavelengths must increase, two at least".into());
    }
    if points.iter().any(|p| !p.0.is_finite() || !p.1.is_finite() || p.1 < 0.0) {
        return Err("a spectrum's values are finite numbers >= 0".into());
    }
    let (rgb, _) = match used {
        SpectrumUse::Albedo => spectrum_to_srgb(points, MitsubaUse::Reflectance, false),
        SpectrumUse::Unbounded => spectrum_to_srgb(points, MitsubaUse::Unbounded, false),
        SpectrumUse::Illuminant => spectrum_to_srgb(points, MitsubaUse::Emitter, false),
    };
    if used == SpectrumUse::Illuminant {
        let y = luminance(rgb);
        return Ok(if y > 0.0 { rgb / y } else { Vec3::ZERO });
    }
    Ok(rgb)
}

/// A named spectrum, or else a spectrum file (`resolve` finds it).
pub fn named_or_file(name: &str, used: SpectrumUse, resolve: &dyn Fn(&str) -> PathBuf) -> Result<Vec3, String> {
    if let Some(ior) = glass_ior(name) {
        return Ok(Vec3::splat(ior));
    }
    if let Some(metal) = name.strip_prefix("metal-") {
        let (metal, part) = metal.rsplit_once('-').unwrap_or((metal, ""));
        let found = NAMED_CONDUCTORS.iter().find(|(n, _, _)| *n == metal && ["Ag", "Al", "Au", "Cu", "MgO", "TiO2"].contains(n));
        return match (found, part) {
            (Some((_, eta, _)), "eta") => Ok(Vec3::from(*eta)),
            (Some((_, _, k)), "k") => Ok(Vec3::from(*k)),
            _ => Err(format!(
                "\"{name}\": no RGB values for this named spectrum in sppm-gpu (metal-<M>-eta and -k for Ag, Al, Au, Cu, MgO, \
                 TiO2)"
            )),
        };
    }
    match name {
        "stdillum-D65" if used == SpectrumUse::Illuminant => return Ok(Vec3::ONE),
        "stdillum-A" if used == SpectrumUse::Illuminant => return Ok(blackbody_rgb(2856.0, used)),
        _ => {}
    }
    if name.starts_with("stdillum-") || name.starts_with("canon_") || name.starts_with("nikon_") || name.starts_with("sony_") {
        return Err(format!("\"{name}\": this named spectrum is not read by sppm-gpu (stdillum-D65 and stdillum-A are)"));
    }
    let path = resolve(name);
    let text =
        crate::scene::files::read_text(&path).map_err(|e| format!("\"{name}\" is no named spectrum, and as a file: {e}"))?;
    let numbers: Result<Vec<f32>, _> =
        text.lines().map(|l| l.split('#').next().unwrap_or("")).flat_map(str::split_whitespace).map(str::parse::<f32>).collect();
    let numbers = numbers.map_err(|e| format!("{}: {e}", path.display()))?;
    if numbers.len() % 2 != 0 {
        return Err(format!("{}: an odd count of numbers, not pairs of wavelength and value", path.display()));
    }
    let points: Vec<(f32, f32)> = numbers.chunks(2).map(|c| (c[0], c[1])).collect();
    sampled_rgb(&points, used).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn illuminants_have_unit_luminance() {
        for t in [2000.0, 2856.0, 6500.0, 10000.0] {
            let c = blackbody_rgb(t, SpectrumUse::Illuminant);
            assert!((luminance(c) - 1.0).abs() < 0.02, "{t}: {c}");
        }
        // 6500 K is nearly white; 2856 K is orange.
        let c = blackbody_rgb(6500.0, SpectrumUse::Illuminant);
        assert!((c - Vec3::ONE).abs().max_element() < 0.1, "{c}");
        let a = blackbody_rgb(2856.0, SpectrumUse::Illuminant);
        assert!(a.x > a.y && a.y > a.z, "{a}");
    }
}
