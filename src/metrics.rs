//! Image error metrics.
//!
//! The headline figure is relMSE, as used in the project's issues:
//! the mean over pixels and channels of `(x - ref)^2 / (ref^2 + 0.01)`, taken
//! after both images are box-downsampled the same way (8x8 for the 256x256
//! references, to average out reference noise in caustics). All sums are
//! accumulated in `f64`.

use crate::image_io::Rgb32Image;

/// Added to `ref^2` in the relMSE denominator so that black reference pixels
/// do not dominate.
pub const REL_MSE_EPSILON: f64 = 0.01;

/// Box-filters `img` by averaging each `factor` x `factor` block into one
/// pixel. Width and height must be divisible by `factor`, which must be
/// positive.
pub fn downsample_box(img: &Rgb32Image, factor: u32) -> Result<Rgb32Image, String> {
    if factor == 0 || !img.width.is_multiple_of(factor) || !img.height.is_multiple_of(factor) {
        return Err(format!(
            "cannot box-downsample a {}x{} image by {factor}: the factor must be positive \
             and divide both width and height",
            img.width, img.height
        ));
    }
    let weight = 1.0 / f64::from(factor * factor);
    Ok(Rgb32Image::from_fn(img.width / factor, img.height / factor, |bx, by| {
        let mut sum = [0.0f64; 3];
        for y in by * factor..(by + 1) * factor {
            for x in bx * factor..(bx + 1) * factor {
                let p = img.get(x, y);
                for c in 0..3 {
                    sum[c] += f64::from(p[c]);
                }
            }
        }
        sum.map(|s| (s * weight) as f32)
    }))
}

/// Errors unless `img` and `reference` have the same size.
fn check_same_size(img: &Rgb32Image, reference: &Rgb32Image) -> Result<(), String> {
    if (img.width, img.height) == (reference.width, reference.height) {
        Ok(())
    } else {
        Err(format!("image is {}x{} but the reference is {}x{}", img.width, img.height, reference.width, reference.height))
    }
}

/// Mean over all pixels of `per_pixel(x, ref)` after checking sizes match.
/// NaN for empty images.
fn mean_over_pixels(
    img: &Rgb32Image,
    reference: &Rgb32Image,
    per_pixel: impl Fn([f32; 3], [f32; 3]) -> f64,
) -> Result<f64, String> {
    check_same_size(img, reference)?;
    let sum: f64 = img.pixels.iter().zip(&reference.pixels).map(|(&x, &r)| per_pixel(x, r)).sum();
    Ok(sum / img.pixels.len() as f64)
}

/// Mean over the three channels of `(x - ref)^2 / (ref^2 + 0.01)` for one
/// pixel.
fn pixel_rel_sq_error(x: [f32; 3], r: [f32; 3]) -> f64 {
    (0..3)
        .map(|c| {
            let (x, r) = (f64::from(x[c]), f64::from(r[c]));
            (x - r).powi(2) / (r * r + REL_MSE_EPSILON)
        })
        .sum::<f64>()
        / 3.0
}

/// Mean over the three channels of `(x - ref)^2` for one pixel.
fn pixel_sq_error(x: [f32; 3], r: [f32; 3]) -> f64 {
    (0..3).map(|c| (f64::from(x[c]) - f64::from(r[c])).powi(2)).sum::<f64>() / 3.0
}

/// Relative mean squared error: mean over pixels and channels of
/// `(x - ref)^2 / (ref^2 + 0.01)`. Sizes must match.
pub fn rel_mse(img: &Rgb32Image, reference: &Rgb32Image) -> Result<f64, String> {
    mean_over_pixels(img, reference, pixel_rel_sq_error)
}

/// Root mean squared error over pixels and channels. Sizes must match.
pub fn rmse(img: &Rgb32Image, reference: &Rgb32Image) -> Result<f64, String> {
    mean_over_pixels(img, reference, pixel_sq_error).map(f64::sqrt)
}

/// Per-channel `mean(img) / mean(reference)`: 1.0 means no overall bias.
/// The images may differ in size.
pub fn channel_mean_ratio(img: &Rgb32Image, reference: &Rgb32Image) -> [f64; 3] {
    let (m, r) = (img.mean(), reference.mean());
    [m[0] / r[0], m[1] / r[1], m[2] / r[2]]
}

/// Error figures of an image against a reference; see [`compare`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// [`rel_mse`] of the downsampled images.
    pub rel_mse: f64,
    /// [`rmse`] of the downsampled images.
    pub rmse: f64,
    /// [`channel_mean_ratio`] (unaffected by downsampling).
    pub mean_ratio: [f64; 3],
}

/// Box-downsamples both images by `downsample` (1 = unchanged), then computes
/// all metrics. Sizes must match and be divisible by `downsample`.
pub fn compare(img: &Rgb32Image, reference: &Rgb32Image, downsample: u32) -> Result<Comparison, String> {
    check_same_size(img, reference)?;
    let small = downsample_box(img, downsample)?;
    let small_ref = downsample_box(reference, downsample)?;
    Ok(Comparison {
        rel_mse: rel_mse(&small, &small_ref)?,
        rmse: rmse(&small, &small_ref)?,
        mean_ratio: channel_mean_ratio(&small, &small_ref),
    })
}

/// Number of pixels with at least one NaN or infinite channel.
pub fn count_non_finite(img: &Rgb32Image) -> usize {
    img.pixels.iter().filter(|p| p.iter().any(|v| !v.is_finite())).count()
}

/// Number of pixels with at least one negative channel (NaN is not negative;
/// -0.0 is not counted).
pub fn count_negative(img: &Rgb32Image) -> usize {
    img.pixels.iter().filter(|p| p.iter().any(|&v| v < 0.0)).count()
}

/// Colour stops of [`false_colour`]'s map, evenly spaced over `[0, 1]`.
const COLOUR_STOPS: [[f32; 3]; 5] = [
    [0.0, 0.0, 0.0], // black
    [0.0, 0.0, 1.0], // blue
    [0.0, 1.0, 0.0], // green
    [1.0, 1.0, 0.0], // yellow
    [1.0, 0.0, 0.0], // red
];

/// Colour shown by [`false_colour`] for pixels whose error is NaN or infinite.
pub const NON_FINITE_COLOUR: [f32; 3] = [1.0, 1.0, 1.0];

/// Maps a per-pixel relative error to a colour: black at `<= 1e-3`, through
/// blue, green and yellow, to red at `>= 1`, logarithmically. Non-finite
/// errors map to [`NON_FINITE_COLOUR`].
fn error_colour(error: f64) -> [f32; 3] {
    if !error.is_finite() {
        return NON_FINITE_COLOUR;
    }
    // log10 maps [1e-3, 1] to [-3, 0]; rescale to [0, 1]. log10(0) = -inf
    // clamps to 0 (black).
    let t = ((error.log10() + 3.0) / 3.0).clamp(0.0, 1.0) as f32;
    let segments = (COLOUR_STOPS.len() - 1) as f32;
    let i = ((t * segments) as usize).min(COLOUR_STOPS.len() - 2);
    let frac = t * segments - i as f32;
    let (a, b) = (COLOUR_STOPS[i], COLOUR_STOPS[i + 1]);
    [0, 1, 2].map(|c| a[c] + (b[c] - a[c]) * frac)
}

/// A false-colour map of the per-pixel relative error
/// `sqrt(mean_c (x - ref)^2 / (ref^2 + 0.01))`: black for `<= 1e-3`, through
/// blue, green and yellow, to red for `>= 1`, on a log scale. Pixels whose
/// error is NaN or infinite are white. Sizes must match.
pub fn false_colour(img: &Rgb32Image, reference: &Rgb32Image) -> Result<Rgb32Image, String> {
    check_same_size(img, reference)?;
    let pixels = img.pixels.iter().zip(&reference.pixels).map(|(&x, &r)| error_colour(pixel_rel_sq_error(x, r).sqrt())).collect();
    Ok(Rgb32Image { width: img.width, height: img.height, pixels })
}
