//! `sppm-gpu diff IMAGE REFERENCE`: error metrics between two images.

use super::output::{self, Inputs, Kind};
use sppm_gpu::{experiments, image_io, say, Error};
use std::path::Path;

/// Print relMSE = mean((x - ref)^2 / (ref^2 + 0.01)), RMSE and the channel mean ratios.
pub(crate) fn diff(image: &Path, reference: &Path, downsample: u32, error_image: Option<&Path>) -> Result<(), Error> {
    if let Some(path) = error_image {
        output::check(path, Kind::Image, &Inputs::of([image, reference]))?;
    }
    let a = image_io::read_image(image)?;
    let b = image_io::read_image(reference)?;
    let c = sppm_gpu::metrics::compare(&a, &b, downsample).map_err(Error::Setting)?;
    say!(
        "relMSE {:.3e}  RMSE {:.3e}  mean ratio {:.4} {:.4} {:.4}  (downsample {downsample})",
        c.rel_mse,
        c.rmse,
        c.mean_ratio[0],
        c.mean_ratio[1],
        c.mean_ratio[2]
    );
    if let Some(path) = error_image {
        experiments::plot::write_error_image(path, &a, &b, downsample)?;
    }
    Ok(())
}
