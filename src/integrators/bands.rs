//! SPPM for images whose visible points do not fit in one set of buffers: the image is split
//! into bands of rows, each an [`Sppm`] of its own over the same scene buffers, and every
//! pass runs a pass of each band. Each band traces the pass's photons anew, so a pass costs
//! about as many photon passes as there are bands; the stitched image equals the one a
//! single renderer would give, bit for bit.

use std::sync::Arc;

use super::{Integrator, Sppm};
use crate::error::Error;
use crate::gpu::scene_buffers::{SceneBuffers, SceneData};
use crate::image_io::Rgb32Image;
use crate::scene::Scene;

/// SPPM over bands of at most `rows_per_band` rows.
pub struct Bands {
    bands: Vec<Sppm>,
    width: u32,
    height: u32,
}

impl Bands {
    /// Split `scene`'s image into bands of at most `rows_per_band` rows (the last may be
    /// shorter), sharing one upload of the scene.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, rows_per_band: u32) -> Result<Self, Error> {
        crate::gpu::check_device(device)?;
        if rows_per_band == 0 {
            return Err(Error::Setting(format!(
                "one row of {} pixels with spp {} needs more visible points than this device's buffers hold",
                scene.render.width, scene.render.spp
            )));
        }
        let data = SceneData::new(scene)?;
        let scene_buffers = Arc::new(SceneBuffers::new(device, &data));
        let height = scene.render.height;
        let bands = (0..height)
            .step_by(rows_per_band as usize)
            .map(|y0| {
                let rows = y0..(y0 + rows_per_band).min(height);
                Sppm::with_scene_buffers(device, queue, scene, &data, scene_buffers.clone(), rows)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { bands, width: scene.render.width, height })
    }

    /// Number of bands.
    pub fn band_count(&self) -> usize {
        self.bands.len()
    }
}

impl Integrator for Bands {
    fn run_pass(&mut self) -> Result<(), Error> {
        for band in &mut self.bands {
            band.run_pass()?;
        }
        Ok(())
    }
    fn passes(&self) -> u32 {
        self.bands[0].passes()
    }
    /// Photons traced in a pass: the pass's photons once per band.
    fn work_per_pass(&self) -> u64 {
        self.bands[0].work_per_pass() * self.bands.len() as u64
    }
    fn work_unit(&self) -> &'static str {
        "photons"
    }
    fn image(&mut self) -> Result<Rgb32Image, Error> {
        let mut out = Rgb32Image::new(self.width, self.height);
        let mut offset = 0;
        for band in &mut self.bands {
            let img = band.image()?;
            out.pixels[offset..offset + img.pixels.len()].copy_from_slice(&img.pixels);
            offset += img.pixels.len();
        }
        Ok(out)
    }
    /// The scene's buffers once (the bands share them), the bands' own summed by name.
    fn gpu_memory(&self) -> super::GpuMemory {
        let mut total = self.bands[0].gpu_memory();
        for band in &self.bands[1..] {
            for ((_, sum), (_, bytes)) in total.renderer.iter_mut().zip(band.gpu_memory().renderer) {
                *sum += bytes;
            }
        }
        total
    }
}
