//! Spectra given by wavelengths (`<spectrum value="400:0.2, 500:0.5, ..."/>`), as Mitsuba 3's
//! RGB variants read them (`spectrum_list_to_srgb` in its `src/core/spectrum.cpp`): the
//! piecewise-linear spectrum is integrated against the CIE 1931 colour matching functions
//! over 360-830 nm at 1000 evenly spaced wavelengths (zero outside the given range), under
//! the D65 illuminant for a reflectance and without it for an emitter, and the CIE XYZ taken
//! to linear sRGB. A reflectance's colour is clamped to [0, 1], any other's to >= 0, with a
//! warning, as Mitsuba does.
//!
//! A scene of version 0.5/0.6 is read as Mitsuba 0.5/0.6 read it (`Spectrum::
//! fromContinuousSpectrum` of their RGB build, the default and the papers' builds): the same
//! integral, but without an illuminant whatever the spectrum is, so that a flat reflectance is
//! the colour of a flat spectrum (1.2, 0.95, 0.90 per unit), not white. Their images show it:
//! the Cornell box of Mueller et al.'s path-guiding repository (reflectances and light given by
//! wavelengths), as its authors rendered it with their Mitsuba 0.6 fork, is 1.32, 0.92, 0.84
//! times Mitsuba 3's render of the same file in its channel means, and ours is within 0.5% of
//! it once its light is corrected for a fault of Mitsuba 0.5.0 and 0.6.0 as released: they
//! interpolated a spectrum's values backwards between two given wavelengths
//! (`InterpolatedSpectrum::eval`, fixed in Mitsuba 0.6's source in 2020, cfeb7766). We read a
//! spectrum as written, as that source does now; the releases' renders differ where the given
//! wavelengths are far apart (that box's light, given every 100 nm, is 1.129, 0.988, 1.005
//! times theirs in ours; its reflectances, given every 4 nm, within 1%).

use glam::{Mat3, Vec3};

/// CIE XYZ to linear sRGB (ITU-R BT.709 primaries, D65 white), as Mitsuba 3's `xyz_to_srgb`.
pub const XYZ_TO_SRGB: Mat3 = Mat3::from_cols_array(&[
    3.240479, -0.969256, 0.055648, // column X
    -1.53715, 1.875991, -0.204043, // column Y
    -0.498535, 0.041556, 1.057311, // column Z
]);

/// What a spectrum-valued parameter is, which decides how its wavelengths become a colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumUse {
    /// A reflectance or transmittance: under D65, clamped to [0, 1].
    Reflectance,
    /// An unbounded non-emissive quantity (a conductor's eta and k): under D65, >= 0.
    Unbounded,
    /// Emitted radiance, intensity or irradiance: without an illuminant, >= 0.
    Emitter,
}

/// The linear sRGB colour of the spectrum through (wavelength nm, value) points in increasing
/// wavelength, and whether it had to be clamped (out of the sRGB gamut). `legacy`: as Mitsuba
/// 0.5/0.6 read it, without an illuminant whatever `used` is.
pub fn spectrum_to_srgb(points: &[(f32, f32)], used: SpectrumUse, legacy: bool) -> (Vec3, bool) {
    const STEPS: usize = 1000;
    let (lo, hi) = (CIE_1931[0].0 as f64, CIE_1931[CIE_1931.len() - 1].0 as f64);
    let mut xyz = [0.0f64; 3];
    for i in 0..STEPS {
        let w = lo + (i as f64 / (STEPS - 1) as f64) * (hi - lo);
        if w < points[0].0 as f64 || w > points[points.len() - 1].0 as f64 {
            continue;
        }
        // The given spectrum's segment holding w, linearly interpolated.
        let k = points.windows(2).position(|p| (p[1].0 as f64) >= w).unwrap_or(points.len() - 2);
        let ((w0, v0), (w1, v1)) = (points[k], points[k + 1]);
        let t = if w1 > w0 { (w - w0 as f64) / (w1 - w0) as f64 } else { 0.0 };
        let v = v0 as f64 + t * (v1 - v0) as f64;
        let (cmf, d65) = cie_at(w);
        let illuminant = if used == SpectrumUse::Emitter || legacy { 1.0 } else { d65 * D65_NORMALIZATION };
        for c in 0..3 {
            xyz[c] += cmf[c] * v * illuminant;
        }
    }
    // The Riemann sum's width, and Y normalized so that a flat spectrum 1 has Y = 1.
    let scale = (hi - lo) * Y_NORMALIZATION / STEPS as f64;
    let rgb = XYZ_TO_SRGB * Vec3::new((xyz[0] * scale) as f32, (xyz[1] * scale) as f32, (xyz[2] * scale) as f32);
    let clamped = match used {
        SpectrumUse::Reflectance => rgb.clamp(Vec3::ZERO, Vec3::ONE),
        _ => rgb.max(Vec3::ZERO),
    };
    (clamped, clamped != rgb)
}

/// The colour matching functions and D65 at wavelength w, linearly interpolated in the 5 nm
/// table.
fn cie_at(w: f64) -> ([f64; 3], f64) {
    let t = (w - CIE_1931[0].0 as f64) / 5.0;
    let i = (t.max(0.0) as usize).min(CIE_1931.len() - 2);
    let f = t - i as f64;
    let (a, b) = (&CIE_1931[i], &CIE_1931[i + 1]);
    let mix = |x: f32, y: f32| x as f64 * (1.0 - f) + y as f64 * f;
    ([mix(a.1[0], b.1[0]), mix(a.1[1], b.1[1]), mix(a.1[2], b.1[2])], mix(a.2, b.2))
}

/// 1 / the integral of the table's y over 360-830 nm by Mitsuba's sum (Mitsuba 3's
/// `MI_CIE_Y_NORMALIZATION`).
const Y_NORMALIZATION: f64 = 1.0 / 106.75025939941406;

/// 1 / D65's mean over the table, so that D65 averages 1 (Mitsuba 3's
/// `MI_CIE_D65_NORMALIZATION`).
const D65_NORMALIZATION: f64 = 1.0 / 98.99741751876255;

/// (wavelength nm, CIE 1931 2-degree colour matching functions x, y, z, CIE illuminant D65's
/// relative spectral power): the CIE's standard tables at 5 nm, 360-830 nm (CIE 015:2004,
/// tables T.1 and T.4), as Mitsuba 3 tabulates them.
#[rustfmt::skip]
const CIE_1931: [(u32, [f32; 3], f32); 95] = [
    (360, [0.0001299, 3.917e-06, 0.0006061], 46.6383),
    (365, [0.0002321, 6.965e-06, 0.001086], 49.3637),
    (370, [0.0004149, 1.239e-05, 0.001946], 52.0891),
    (375, [0.0007416, 2.202e-05, 0.003486], 51.0323),
    (380, [0.001368, 3.9e-05, 0.00645], 49.9755),
    (385, [0.002236, 6.4e-05, 0.01055], 52.3118),
    (390, [0.004243, 0.00012, 0.02005], 54.6482),
    (395, [0.00765, 0.000217, 0.03621], 68.7015),
    (400, [0.01431, 0.000396, 0.06785], 82.7549),
    (405, [0.02319, 0.00064, 0.1102], 87.1204),
    (410, [0.04351, 0.00121, 0.2074], 91.486),
    (415, [0.07763, 0.00218, 0.3713], 92.4589),
    (420, [0.13438, 0.004, 0.6456], 93.4318),
    (425, [0.21477, 0.0073, 1.03905], 90.057),
    (430, [0.2839, 0.0116, 1.3856], 86.6823),
    (435, [0.3285, 0.01684, 1.62296], 95.7736),
    (440, [0.34828, 0.023, 1.74706], 104.865),
    (445, [0.34806, 0.0298, 1.7826], 110.936),
    (450, [0.3362, 0.038, 1.77211], 117.008),
    (455, [0.3187, 0.048, 1.7441], 117.41),
    (460, [0.2908, 0.06, 1.6692], 117.812),
    (465, [0.2511, 0.0739, 1.5281], 116.336),
    (470, [0.19536, 0.09098, 1.28764], 114.861),
    (475, [0.1421, 0.1126, 1.0419], 115.392),
    (480, [0.09564, 0.13902, 0.81295], 115.923),
    (485, [0.05795, 0.1693, 0.6162], 112.367),
    (490, [0.03201, 0.20802, 0.46518], 108.811),
    (495, [0.0147, 0.2586, 0.3533], 109.082),
    (500, [0.0049, 0.323, 0.272], 109.354),
    (505, [0.0024, 0.4073, 0.2123], 108.578),
    (510, [0.0093, 0.503, 0.1582], 107.802),
    (515, [0.0291, 0.6082, 0.1117], 106.296),
    (520, [0.06327, 0.71, 0.07825], 104.79),
    (525, [0.1096, 0.7932, 0.05725], 106.239),
    (530, [0.1655, 0.862, 0.04216], 107.689),
    (535, [0.22575, 0.91485, 0.02984], 106.047),
    (540, [0.2904, 0.954, 0.0203], 104.405),
    (545, [0.3597, 0.9803, 0.0134], 104.225),
    (550, [0.43345, 0.99495, 0.00875], 104.046),
    (555, [0.51205, 1.0, 0.00575], 102.023),
    (560, [0.5945, 0.995, 0.0039], 100.0),
    (565, [0.6784, 0.9786, 0.00275], 98.1671),
    (570, [0.7621, 0.952, 0.0021], 96.3342),
    (575, [0.8425, 0.9154, 0.0018], 96.0611),
    (580, [0.9163, 0.87, 0.00165], 95.788),
    (585, [0.9786, 0.8163, 0.0014], 92.2368),
    (590, [1.0263, 0.757, 0.0011], 88.6856),
    (595, [1.0567, 0.6949, 0.001], 89.3459),
    (600, [1.0622, 0.631, 0.0008], 90.0062),
    (605, [1.0456, 0.5668, 0.0006], 89.8026),
    (610, [1.0026, 0.503, 0.00034], 89.5991),
    (615, [0.9384, 0.4412, 0.00024], 88.6489),
    (620, [0.85445, 0.381, 0.00019], 87.6987),
    (625, [0.7514, 0.321, 0.0001], 85.4936),
    (630, [0.6424, 0.265, 5e-05], 83.2886),
    (635, [0.5419, 0.217, 3e-05], 83.4939),
    (640, [0.4479, 0.175, 2e-05], 83.6992),
    (645, [0.3608, 0.1382, 1e-05], 81.863),
    (650, [0.2835, 0.107, 0.0], 80.0268),
    (655, [0.2187, 0.0816, 0.0], 80.1207),
    (660, [0.1649, 0.061, 0.0], 80.2146),
    (665, [0.1212, 0.04458, 0.0], 81.2462),
    (670, [0.0874, 0.032, 0.0], 82.2778),
    (675, [0.0636, 0.0232, 0.0], 80.281),
    (680, [0.04677, 0.017, 0.0], 78.2842),
    (685, [0.0329, 0.01192, 0.0], 74.0027),
    (690, [0.0227, 0.00821, 0.0], 69.7213),
    (695, [0.01584, 0.005723, 0.0], 70.6652),
    (700, [0.0113592, 0.004102, 0.0], 71.6091),
    (705, [0.00811092, 0.002929, 0.0], 72.979),
    (710, [0.00579035, 0.002091, 0.0], 74.349),
    (715, [0.00410946, 0.001484, 0.0], 67.9765),
    (720, [0.00289933, 0.001047, 0.0], 61.604),
    (725, [0.00204919, 0.00074, 0.0], 65.7448),
    (730, [0.00143997, 0.00052, 0.0], 69.8856),
    (735, [0.000999949, 0.0003611, 0.0], 72.4863),
    (740, [0.000690079, 0.0002492, 0.0], 75.087),
    (745, [0.000476021, 0.0001719, 0.0], 69.3398),
    (750, [0.000332301, 0.00012, 0.0], 63.5927),
    (755, [0.000234826, 8.48e-05, 0.0], 55.0054),
    (760, [0.00016615, 6e-05, 0.0], 46.4182),
    (765, [0.000117413, 4.24e-05, 0.0], 56.6118),
    (770, [8.30753e-05, 3e-05, 0.0], 66.8054),
    (775, [5.87065e-05, 2.12e-05, 0.0], 65.0941),
    (780, [4.15099e-05, 1.499e-05, 0.0], 63.3828),
    (785, [2.93533e-05, 1.06e-05, 0.0], 63.8434),
    (790, [2.06738e-05, 7.4657e-06, 0.0], 64.304),
    (795, [1.45598e-05, 5.2578e-06, 0.0], 61.8779),
    (800, [1.0254e-05, 3.7029e-06, 0.0], 59.4519),
    (805, [7.22146e-06, 2.6078e-06, 0.0], 55.7054),
    (810, [5.08587e-06, 1.8366e-06, 0.0], 51.959),
    (815, [3.58165e-06, 1.2934e-06, 0.0], 54.6998),
    (820, [2.52252e-06, 9.1093e-07, 0.0], 57.4406),
    (825, [1.77651e-06, 6.4153e-07, 0.0], 58.8765),
    (830, [1.25114e-06, 4.5181e-07, 0.0], 60.3125),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// A spectrum's colour as Mitsuba 3.9.1 prints it (`mi.spectrum_list_to_srgb`), as a
    /// reflectance (bounded, D65) and as an emitter.
    #[test]
    fn wavelengths_give_mitsubas_srgb() {
        let points = [(400.0, 0.2), (500.0, 0.5), (600.0, 0.8), (700.0, 0.3)];
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 2e-5;
        let (rgb, clamped) = spectrum_to_srgb(&points, SpectrumUse::Reflectance, false);
        assert!(close(rgb, Vec3::new(0.755029, 0.641416, 0.323239)) && !clamped, "{rgb}");
        let (rgb, _) = spectrum_to_srgb(&points, SpectrumUse::Emitter, false);
        assert!(close(rgb, Vec3::new(0.886932, 0.614419, 0.285147)), "{rgb}");
        // A flat reflectance 1 over the whole range is white under D65.
        let (rgb, _) = spectrum_to_srgb(&[(360.0, 1.0), (830.0, 1.0)], SpectrumUse::Reflectance, false);
        assert!((rgb - Vec3::ONE).abs().max_element() < 2e-3, "{rgb}");
        // As Mitsuba 0.5/0.6 read it, a reflectance is integrated as an emitter is, and a flat
        // one is the colour of a flat spectrum (Mitsuba 3.9.1's spectrum_list_to_srgb of
        // 400:1, 700:1 without D65: 1.19969 0.949521 0.903443).
        let (rgb, clamped) = spectrum_to_srgb(&points, SpectrumUse::Reflectance, true);
        assert!(close(rgb, Vec3::new(0.886932, 0.614419, 0.285147)) && !clamped, "{rgb}");
        let (rgb, _) = spectrum_to_srgb(&[(400.0, 0.5), (700.0, 0.5)], SpectrumUse::Reflectance, true);
        assert!(close(rgb, Vec3::new(1.19969, 0.949521, 0.903443) * 0.5), "{rgb}");
    }
}
