//! Images whose per-pixel buffers do not fit in one storage buffer of the device: the image
//! is split into bands of rows, each an integrator of its own over the same scene buffers,
//! and every pass runs a pass of each band. For SPPM each band traces the pass's photons
//! anew, so a pass costs about as many photon passes as there are bands. The stitched image
//! equals the one a single integrator would give, bit for bit.

use std::sync::Arc;

use super::{Deposits, Integrator, PathTracer, Renderer, Sppm};
use crate::error::Error;
use crate::gpu::scene_buffers::{SceneBuffers, SceneData};
use crate::image_io::Rgb32Image;
use crate::scene::Scene;

/// `scene.render.method` over bands of at most `rows_per_band` rows.
pub struct Bands {
    bands: Vec<Box<dyn Integrator>>,
    /// The band whose part of the pass under way comes next.
    current: usize,
    /// Whether a pass's work is the bands' own summed (camera samples, one a pixel), else the
    /// first band's (photons, light subpaths: each band traces them all).
    work_summed: bool,
    width: u32,
    height: u32,
    /// What vcm's pilot said of its choice for this render, for the whole image.
    pilot: super::PilotReport,
}

impl Bands {
    /// Split `scene`'s image into bands of at most `rows_per_band` rows (the last may be
    /// shorter), sharing one upload of the scene.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, rows_per_band: u32) -> Result<Self, Error> {
        crate::gpu::check_device(device)?;
        let data = SceneData::new(scene)?;
        let scene_buffers = Arc::new(SceneBuffers::upload(device, scene, &data)?);
        Self::with_scene_buffers(device, queue, scene, &data, scene_buffers, rows_per_band)
    }

    /// [`Bands::new`] on scene buffers already uploaded.
    pub(crate) fn with_scene_buffers(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        data: &SceneData,
        scene_buffers: Arc<SceneBuffers>,
        rows_per_band: u32,
    ) -> Result<Self, Error> {
        if rows_per_band == 0 {
            return Err(Error::Setting(format!(
                "one row of {} pixels (spp {}) needs more memory than one of this device's buffers holds",
                scene.render.width, scene.render.spp
            )));
        }
        let height = scene.render.height;
        let bands = (0..height)
            .step_by(rows_per_band as usize)
            .map(|y0| {
                let rows = y0..(y0 + rows_per_band).min(height);
                let shared = scene_buffers.clone();
                Ok::<_, Error>(match Renderer::of(&scene.render) {
                    Renderer::Sppm => {
                        Box::new(Sppm::with_scene_buffers(device, queue, scene, data, shared, rows, Deposits::Auto)?)
                            as Box<dyn Integrator>
                    }
                    Renderer::Path => Box::new(PathTracer::with_scene_buffers(device, queue, scene, data, shared, rows)?),
                    Renderer::Light => {
                        Box::new(super::LightTracer::with_scene_buffers(device, queue, scene, data, shared, rows)?)
                    }
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let r = &scene.render;
        let work_summed = Renderer::of(r) == Renderer::Path;
        Ok(Self { bands, current: 0, work_summed, width: r.width, height, pilot: Default::default() })
    }

    /// The same, reporting what vcm's pilot chose for the render (its note, its time, which a
    /// time limit counts, and its choice, which a checkpoint keeps).
    pub(super) fn reporting(mut self, pilot: super::PilotReport) -> Self {
        self.pilot = pilot;
        self
    }

    /// Number of bands.
    pub fn band_count(&self) -> usize {
        self.bands.len()
    }

    /// Each band's state in bytes of [`Integrator::state`]: one length-prefixed part a band.
    fn band_states<'a>(&self, mut state: &'a [u8]) -> Result<Vec<&'a [u8]>, Error> {
        let malformed = || Error::Setting("the saved state does not split into this render's bands".into());
        let mut parts = Vec::with_capacity(self.bands.len());
        for _ in &self.bands {
            let len = state.get(..8).ok_or_else(malformed)?;
            let len = usize::try_from(u64::from_le_bytes(len.try_into().expect("8 bytes"))).map_err(|_| malformed())?;
            parts.push(state.get(8..8 + len).ok_or_else(malformed)?);
            state = &state[8 + len..];
        }
        if !state.is_empty() {
            return Err(malformed());
        }
        Ok(parts)
    }
}

impl Integrator for Bands {
    fn run_pass(&mut self) -> Result<(), Error> {
        for band in &mut self.bands {
            band.run_pass()?;
        }
        Ok(())
    }
    /// The last band's passes: a pass is done when its last band's is.
    fn passes(&self) -> u32 {
        self.bands[self.bands.len() - 1].passes()
    }
    fn pilot(&self) -> &super::PilotReport {
        &self.pilot
    }

    fn set_pilot(&mut self, report: super::PilotReport) {
        self.pilot = report;
    }
    /// Each band's warnings, one line each where bands say the same.
    fn warnings(&mut self) -> Result<Vec<String>, Error> {
        let mut all: Vec<String> = Vec::new();
        for band in &mut self.bands {
            for warning in band.warnings()? {
                if !all.contains(&warning) {
                    all.push(warning);
                }
            }
        }
        Ok(all)
    }
    /// What a pass adds to the estimate: the pass's photons for SPPM (each band traces them
    /// again, for its own points; the light tracer's subpaths likewise, for its own pixels), a
    /// sample per pixel of every band for the path tracers (and vcm without light subpaths).
    fn work_per_pass(&self) -> u64 {
        if self.work_summed {
            self.bands.iter().map(|b| b.work_per_pass()).sum()
        } else {
            self.bands[0].work_per_pass()
        }
    }
    fn work_unit(&self) -> &'static str {
        self.bands[0].work_unit()
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
    /// The bands' sums one after another, in their rows' order.
    fn splat_sums(&mut self) -> Result<Option<super::SplatSums>, Error> {
        let mut out: Option<super::SplatSums> = None;
        for band in &mut self.bands {
            let Some(sums) = band.splat_sums()? else { return Ok(None) };
            match &mut out {
                None => out = Some(sums),
                Some(all) => {
                    all.camera.extend(sums.camera);
                    if let (Some(light), Some(more)) = (&mut all.light, sums.light) {
                        light.extend(more);
                    }
                }
            }
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
    /// The bands' states one after another, each after its length.
    fn state(&mut self) -> Result<Vec<u8>, Error> {
        let mut out = Vec::new();
        for band in &mut self.bands {
            let state = band.state()?;
            out.extend_from_slice(&(state.len() as u64).to_le_bytes());
            out.extend_from_slice(&state);
        }
        Ok(out)
    }
    fn image_of_state(&self, state: &[u8]) -> Result<Rgb32Image, Error> {
        let mut out = Rgb32Image::new(self.width, self.height);
        let mut offset = 0;
        for (band, state) in self.bands.iter().zip(self.band_states(state)?) {
            let img = band.image_of_state(state)?;
            out.pixels[offset..offset + img.pixels.len()].copy_from_slice(&img.pixels);
            offset += img.pixels.len();
        }
        Ok(out)
    }
    /// The bands' parts one after another: all of the first band's pass, then the next's.
    fn record_pass_part(&mut self, encoder: &mut wgpu::CommandEncoder, size: super::PartSize) -> super::Part {
        let mut part = self.bands[self.current].record_pass_part(encoder, size);
        if part.pass_done {
            self.current = (self.current + 1) % self.bands.len();
            part.pass_done = self.current == 0;
        }
        part
    }
    fn record_resolve_to_texture(&mut self, _: &mut wgpu::CommandEncoder, _: &wgpu::Texture) -> Result<(), Error> {
        Err(Error::Setting(format!(
            "the image is rendered in {} bands, which cannot be resolved into one texture; read it with image(), or \
             render fewer pixels",
            self.bands.len()
        )))
    }
    fn start_at_pass(&mut self, first: u32) -> Result<(), Error> {
        for band in &mut self.bands {
            band.start_at_pass(first)?;
        }
        Ok(())
    }
    fn set_camera(&mut self, camera: &crate::scene::Camera) -> Result<(), Error> {
        for band in &mut self.bands {
            band.set_camera(camera)?;
        }
        self.current = 0;
        Ok(())
    }
    fn reset(&mut self) {
        for band in &mut self.bands {
            band.reset();
        }
        self.current = 0;
    }
    fn restore(&mut self, state: &[u8]) -> Result<(), Error> {
        let states = self.band_states(state)?;
        for (band, state) in self.bands.iter_mut().zip(states) {
            band.restore(state)?;
        }
        self.current = 0;
        Ok(())
    }
}
