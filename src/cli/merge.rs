//! `sppm-gpu merge PART... -o OUT`: the image of a render from its batches' partial images.

use super::output::{self, Inputs, Kind};
use sppm_gpu::{image_io, say, Error};
use std::path::{Path, PathBuf};

/// `sppm-gpu merge PART... -o OUT`.
pub(crate) fn merge(parts: &[PathBuf], output: &Path) -> Result<(), Error> {
    output::check(output, Kind::Image, &Inputs::of(parts.iter().map(PathBuf::as_path)))?;
    let partials = parts.iter().map(|p| sppm_gpu::batch::read_partial(p)).collect::<Result<Vec<_>, _>>()?;
    let (image, warnings) = sppm_gpu::batch::merge(&partials)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    if output.exists() {
        eprintln!("note: replacing {}", output.display());
    }
    image_io::write_image(output, &image)?;
    let passes: u32 = partials.iter().map(|p| p.end - p.first).sum();
    let end = partials.iter().map(|p| p.end).max().unwrap_or(0);
    say!("merged {} parts: {passes} passes of 0..{end} -> {}", partials.len(), output.display());
    Ok(())
}
