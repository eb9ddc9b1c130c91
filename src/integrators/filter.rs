//! Pixel filters, Mitsuba 3's: box (radius 1/2), tent and its windowed gaussian. A pixel
//! converges to `∫ f L / ∫ f` about its centre, by one of two estimators:
//!
//! - filter importance sampling (pbrt-v4 sec. 8.8.3), SPPM's and light subpaths' methods: each
//!   camera sample's offset from its pixel's centre is drawn from the filter's density,
//!   separably in x and y (`sample_filter` in `shaders/shared/camera.wgsl`), and weighs 1;
//! - weighted splatting, Mitsuba's (pbrt-v3 sec. 7.8), the path tracers' under a filter wider
//!   than the box: each sample lies uniformly in its pixel and counts in every pixel the filter
//!   reaches from it, weighted by the filter, and a pixel is the ratio of its weighted sum to
//!   its weights' (`shaders/filter_splat.wgsl`). Under Mitsuba's default gaussian (standard
//!   deviation 1/2) a pixel so averages the samples of about pi pixels (`(∫ f)^2 / ∫ f^2`),
//!   and its variance at equal samples is about a third of importance sampling's.
//!
//! Here: the [`Frame`] fields of a [`PixelFilter`] and the kernel constants that leave out the
//! code of filters a scene does not use.

use crate::error::Error;
use crate::layout::{Frame, FILTER_BOX, FILTER_GAUSSIAN, FILTER_TABLE_SIZE, FILTER_TENT};
use crate::scene::{PixelFilter, GAUSSIAN_CUTOFF};

/// Mitsuba 3's gaussian filter in standard deviations `t`, unnormalized:
/// `max(0, exp(-t^2 / 2) - exp(-8))` (the value at the cutoff subtracted, so it falls to 0
/// there).
pub fn gaussian_filter(t: f64) -> f64 {
    ((-0.5 * t * t).exp() - (-0.5 * GAUSSIAN_CUTOFF * GAUSSIAN_CUTOFF).exp()).max(0.0)
}

/// The gaussian's table ([`Frame::filter_cdf`]): the CDF of its density on `[0, 4]` standard
/// deviations, `C_j` at `t_j = 4 j / 256` for `j = 1..=256`, four an entry. Each interval's mass
/// is integrated exactly (Simpson's rule on 16 panels, good to 1e-13), so the CDF is exact at
/// the nodes to f32 rounding; between them the kernel takes the density as linear. The
/// filter's shape does not depend on its standard deviation, which only scales `t`, so one
/// table serves every gaussian.
pub fn gaussian_filter_cdf() -> [[f32; 4]; FILTER_TABLE_SIZE as usize / 4] {
    let n = FILTER_TABLE_SIZE as usize;
    let h = GAUSSIAN_CUTOFF / n as f64;
    const PANELS: usize = 16;
    let mass = |i: usize| {
        let (a, dt) = (h * i as f64, h / PANELS as f64);
        let inner: f64 = (1..PANELS).map(|k| if k % 2 == 1 { 4.0 } else { 2.0 } * gaussian_filter(a + dt * k as f64)).sum();
        dt / 3.0 * (gaussian_filter(a) + inner + gaussian_filter(a + h))
    };
    let masses: Vec<f64> = (0..n).map(mass).collect();
    let total: f64 = masses.iter().sum();
    let mut table = [[0.0f32; 4]; FILTER_TABLE_SIZE as usize / 4];
    let mut sum = 0.0;
    for (j, m) in masses.iter().enumerate() {
        sum += m;
        // C_{j+1}; the last exactly 1.
        table[j / 4][j % 4] = if j + 1 == n { 1.0 } else { (sum / total) as f32 };
    }
    table
}

/// Set `frame`'s filter fields for `filter`; an error for a radius or standard deviation that
/// is not a positive number.
pub fn set_pixel_filter(frame: &mut Frame, filter: PixelFilter) -> Result<(), Error> {
    let positive = |name: &str, v: f32| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(Error::Setting(format!("filter {name} {v}: must be a positive number of pixels")))
        }
    };
    let zeros = [[0.0; 4]; FILTER_TABLE_SIZE as usize / 4];
    (frame.pixel_filter, frame.filter_width, frame.filter_cdf) = match filter {
        PixelFilter::Box => (FILTER_BOX, 0.0, zeros),
        PixelFilter::Tent { radius } => (FILTER_TENT, positive("radius", radius)?, zeros),
        PixelFilter::Gaussian { stddev } => (FILTER_GAUSSIAN, positive("stddev", stddev)?, gaussian_filter_cdf()),
    };
    Ok(())
}

/// More than a pass's splats can weigh in one pixel of `frame`: every sample within the
/// filter's reach at the filter's peak density per axis (the tent's 1 / radius; the
/// gaussian's 1 / (2 m stddev), m = 1.2519 its mass on [0, 4] standard deviations, here 1.25).
pub fn splat_weight_bound(frame: &Frame) -> f32 {
    let side = 2 * frame.filter_reach + 1;
    let peak = match frame.pixel_filter {
        FILTER_TENT => 1.0 / frame.filter_width,
        _ => 1.0 / (2.5 * frame.filter_width),
    };
    (side * side) as f32 * peak * peak
}

/// The kernels' `USES_*_FILTER` constants for `filter`: only its own code is compiled in, and
/// none for the box (`camera_ray` in `shaders/shared/camera.wgsl`).
pub fn pixel_filter_constants(filter: PixelFilter) -> [(&'static str, f64); 2] {
    let tent = matches!(filter, PixelFilter::Tent { .. });
    let gaussian = matches!(filter, PixelFilter::Gaussian { .. });
    [("USES_TENT_FILTER", tent as u32 as f64), ("USES_GAUSSIAN_FILTER", gaussian as u32 as f64)]
}
