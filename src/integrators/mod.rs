//! Integrators: SPPM and the path tracers (naive, and with next-event estimation) share the
//! scene, its GPU buffers, the camera, the shutter and the kernels' shared WGSL; each one is
//! driven through [`Integrator`].

pub mod bands;
pub mod check;
pub mod filter;
mod frame;
pub mod light;
mod memory;
pub mod path;
mod pixel_sums;
mod resolve;
pub mod shares;
pub mod sppm;
mod state;

pub use bands::Bands;
pub use filter::set_pixel_filter;
pub use frame::{camera_frame, camera_frame_for, shutter_time};
pub use light::LightTracer;
pub use memory::{check_memory, max_rows, memory_need, GpuMemory, MemoryNeed};
pub use path::PathTracer;
pub use pixel_sums::SplatSums;
pub use sppm::{Deposits, Sppm};

use frame::{band_frame, record_upload, set_frame_camera, specialization};
use memory::sizes;
use resolve::{check_resolve_target, resolve_kernel};
use state::{decode_state, encode_state};

use crate::error::Error;
use crate::gpu::scene_buffers::{SceneBuffers, SceneData};
use crate::image_io::Rgb32Image;
use crate::scene::{Method, Scene};
use std::sync::Arc;

/// How much of a pass one [`Integrator::record_pass_part`] may record: at most `points`
/// camera paths (visible points for SPPM, pixel samples for the path tracers) or `photons`
/// photons. An application that draws between parts, such as a preview window, keeps each
/// part's GPU time bounded with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PartSize {
    /// Camera paths a part may trace.
    pub points: u32,
    /// Photons a part may trace.
    pub photons: u32,
}

/// What one [`Integrator::record_pass_part`] recorded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Part {
    /// Camera paths or photons.
    pub work: Work,
    /// How many of them.
    pub items: u32,
    /// Whether the part completed the pass.
    pub pass_done: bool,
}

/// The kind of work in a [`Part`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Work {
    /// Camera paths: SPPM's visible points (with the grid build after the last), or the path
    /// tracers' pixel samples.
    CameraPaths,
    /// SPPM's photons (with the statistics update after the last).
    Photons,
}

impl PartSize {
    /// No bound: a pass in two parts for SPPM (camera paths and grid, then photons and
    /// statistics), one for the path tracers.
    pub const WHOLE: PartSize = PartSize { points: u32::MAX, photons: u32::MAX };
}

/// A progressive renderer: each pass refines the estimate, which can be read at any time.
///
/// Applications with a device of their own record passes into their own encoders
/// ([`Integrator::record_pass`], or [`Integrator::record_pass_part`] for bounded pieces) and
/// the estimate into their own texture ([`Integrator::record_resolve_to_texture`]); nothing
/// is submitted but by them. [`Integrator::set_camera`] and [`Integrator::reset`] start over.
pub trait Integrator {
    /// Record one more pass and submit it, first waiting for the oldest of this integrator's
    /// submissions if [`crate::pacing::MAX_IN_FLIGHT`] are in flight, so that a loop of
    /// `run_pass` never queues more than that on the device. [`Integrator::image`] waits for
    /// it. A render loop that keeps a fast device busy and judges time on completed passes
    /// drives [`Integrator::record_pass`] through a [`crate::pacing::Pacer`] instead.
    fn run_pass(&mut self) -> Result<(), Error>;
    /// Passes recorded: once [`Integrator::image`] or [`Integrator::state`] has waited for
    /// them, passes completed.
    fn passes(&self) -> u32;
    /// What one pass adds, for progress and reports: photons for SPPM, camera samples (one
    /// per pixel) for the path tracers.
    fn work_per_pass(&self) -> u64;
    /// Unit of [`Integrator::work_per_pass`]: "photons" or "samples".
    fn work_unit(&self) -> &'static str;
    /// The current estimate, read back (waits for the submitted passes).
    fn image(&mut self) -> Result<Rgb32Image, Error>;
    /// Under a splatting filter, the sums the image is the ratio of ([`SplatSums`]), for a
    /// batch's partial image to merge exactly; `None` where each pass's estimate counts 1.
    fn splat_sums(&mut self) -> Result<Option<SplatSums>, Error> {
        Ok(None)
    }
    /// The GPU buffers it holds.
    fn gpu_memory(&self) -> GpuMemory;
    /// Everything later passes depend on, as bytes (waits for the submitted passes): the
    /// pass count and the per-point statistics (SPPM) or per-pixel sums (path tracers).
    /// Passes draw their random numbers by pass index, so an integrator of the same scene and
    /// settings that [`Integrator::restore`]s it goes on exactly as this one would.
    fn state(&mut self) -> Result<Vec<u8>, Error>;
    /// Continue from bytes of [`Integrator::state`] of the same scene and settings.
    fn restore(&mut self, state: &[u8]) -> Result<(), Error>;
    /// The image of bytes of [`Integrator::state`], computed on the host without the device:
    /// what a lost device's render still gives from its last saved state.
    fn image_of_state(&self, state: &[u8]) -> Result<Rgb32Image, Error>;
    /// Record the next part of the pass under way into `encoder`, or the first part of a new
    /// pass, no larger than `size`, without submitting it. A pass counts in
    /// [`Integrator::passes`] once its last part is recorded ([`Part::pass_done`]). Parts draw the random numbers a whole
    /// pass does, so the image does not depend on how passes are cut into parts, bit for bit.
    /// What it recorded comes back, so that a caller can fit the next part to a time budget.
    /// SPPM's parts: slices of the camera paths (the grid is built after the last), then
    /// slices of the photons, ending on a multiple of 16 photons (a photon thread's) where the
    /// size allows (the statistics are updated after the last). The path tracers':
    /// slices of the pixels.
    fn record_pass_part(&mut self, encoder: &mut wgpu::CommandEncoder, size: PartSize) -> Part;
    /// Record one whole pass (or the rest of the pass under way) into `encoder`, without
    /// submitting it: the caller may record several, or interleave its own work. The pass
    /// counts as done once recorded.
    fn record_pass(&mut self, encoder: &mut wgpu::CommandEncoder) {
        while !self.record_pass_part(encoder, PartSize::WHOLE).pass_done {}
    }
    /// Record the estimate of the completed passes into the caller's 2D texture: `width` x
    /// `height`, `Rgba16Float` or `Rgba32Float`, with `STORAGE_BINDING`; alpha 1. An error for
    /// SPPM while a pass is under way (its camera paths have already added their light).
    fn record_resolve_to_texture(&mut self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) -> Result<(), Error>;
    /// Move the camera and start over ([`Integrator::reset`]). The image size stays.
    fn set_camera(&mut self, camera: &crate::scene::Camera) -> Result<(), Error>;
    /// Start over: no pass done, the pass under way (if any) dropped; the next pass draws the
    /// random numbers the first did.
    fn reset(&mut self);
    /// Render the passes of a batch: the passes this integrator runs are passes `first`,
    /// `first + 1`, ... of the whole render, each drawing the random numbers it draws there,
    /// and the estimate is their mean. Batches of a render split this way merge into the
    /// whole render's image (`sppm-gpu merge`). Only before any pass; an error for SPPM with
    /// a radius per point, whose passes depend on every pass before them.
    fn start_at_pass(&mut self, first: u32) -> Result<(), Error>;
    /// What vcm's pilot ([`shares`]) said of its choice for the render (empty where none chose).
    fn pilot(&self) -> &PilotReport {
        static NONE: PilotReport = PilotReport { notes: Vec::new(), seconds: 0.0, choice: None };
        &NONE
    }
    /// Replace what the integrator reports of vcm's pilot (the check of the render's first
    /// passes, [`check`], adds to it). Integrators that keep no report ignore it.
    fn set_pilot(&mut self, _report: PilotReport) {}
    /// What the integrator chose for the render before its first pass, one sentence each, for
    /// the user to read (vcm's pilot).
    fn notes(&self) -> Vec<String> {
        self.pilot().notes()
    }
    /// Seconds spent before the first pass on work that belongs to the render (vcm's pilot),
    /// which a time limit counts.
    fn setup_seconds(&self) -> f64 {
        self.pilot().seconds()
    }
    /// vcm's pilot's choice for the render, where one chose: a checkpoint keeps it, and the
    /// strategy images render it.
    fn pilot_choice(&self) -> Option<shares::Choice> {
        self.pilot().choice()
    }
    /// SPPM's gather radii over the visible points (read back); `None` for the path tracers.
    fn radius_stats(&self) -> Result<Option<sppm::RadiusStats>, Error> {
        Ok(None)
    }
    /// Whether the image is a sum of strategies' weighted shares that `RenderSettings::strategies`
    /// can keep one of (`--strategy-images`): not SPPM's, which renders vcm's photon mapping.
    fn splits_strategies(&self) -> bool {
        true
    }
    /// What the passes so far did that the image does not show and the user should know, one
    /// sentence each (read back once the render ends: bpt's and vcm's light vertices that the
    /// store had no room for).
    fn warnings(&mut self) -> Result<Vec<String>, Error> {
        Ok(Vec::new())
    }
}

/// The integrator for `scene.render.method`, on the caller's device.
pub fn create(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<Box<dyn Integrator>, Error> {
    check_device_for(device, scene)?;
    let data = SceneData::new(scene)?;
    let buffers = Arc::new(SceneBuffers::upload(device, scene, &data)?);
    let (scene, pilot) = resolve(device, queue, scene, &data, &buffers)?;
    let report = pilot.as_ref().map(PilotReport::of).unwrap_or_default();
    create_on(device, queue, &scene, &data, buffers, report)
}

/// `scene` with vcm's shares chosen where its pilot chooses them, and the pilot; else `scene`.
fn resolve<'a>(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &'a Scene,
    data: &SceneData,
    buffers: &Arc<SceneBuffers>,
) -> Result<(std::borrow::Cow<'a, Scene>, Option<shares::Pilot>), Error> {
    Ok(match shares::resolve(device, queue, scene, data, buffers)? {
        Some((resolved, pilot)) => (std::borrow::Cow::Owned(resolved), Some(pilot)),
        None => (std::borrow::Cow::Borrowed(scene), None),
    })
}

/// SPPM, and any method in bands, need the device's storage buffers and workgroups
/// ([`crate::gpu::check_device`]): refused before the scene is built.
fn check_device_for(device: &wgpu::Device, scene: &Scene) -> Result<(), Error> {
    if Renderer::of(&scene.render) == Renderer::Sppm || max_rows(device, scene) < scene.render.height {
        crate::gpu::check_device(device)?;
    }
    Ok(())
}

/// [`create`] on `scene`'s records and buffers already made (and its device checked).
fn create_on(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    data: &SceneData,
    buffers: Arc<SceneBuffers>,
    report: PilotReport,
) -> Result<Box<dyn Integrator>, Error> {
    let (rows, height) = (max_rows(device, scene), scene.render.height);
    Ok(match Renderer::of(&scene.render) {
        // An image whose per-pixel buffers do not fit in one storage buffer goes in bands.
        _ if rows < height => Box::new(Bands::with_scene_buffers(device, queue, scene, data, buffers, rows)?.reporting(report)),
        Renderer::Sppm => {
            Box::new(Sppm::with_scene_buffers(device, queue, scene, data, buffers, 0..height, Deposits::Auto)?.reporting(report))
        }
        Renderer::Path => {
            Box::new(PathTracer::with_scene_buffers(device, queue, scene, data, buffers, 0..height)?.reporting(report))
        }
        Renderer::Light if report.is_some() => Box::new(LightTracer::with_pilot(device, queue, scene, data, buffers, report)?),
        Renderer::Light => Box::new(LightTracer::with_scene_buffers(device, queue, scene, data, buffers, 0..height)?),
    })
}

/// What vcm's pilot said of its choice and the seconds it took, kept by the integrator that
/// renders the choice for [`Integrator::notes`] and [`Integrator::setup_seconds`] (empty where
/// no pilot chose); under a time limit also what the render's first passes said of it
/// ([`check`]).
#[derive(Clone, Debug, Default)]
pub struct PilotReport {
    notes: Vec<String>,
    seconds: f64,
    choice: Option<shares::Choice>,
}

impl PilotReport {
    /// The report of `pilot`.
    pub fn of(pilot: &shares::Pilot) -> Self {
        Self { notes: vec![pilot.to_string()], seconds: pilot.seconds, choice: Some(pilot.chosen) }
    }

    /// This report with the check of the render's first passes: its `note`, the `seconds` it
    /// took and the choice that renders after it.
    pub fn checked(mut self, note: String, seconds: f64, choice: shares::Choice) -> Self {
        self.notes.push(note);
        self.seconds += seconds;
        self.choice = Some(choice);
        self
    }

    /// The pilot's notes, where one chose.
    pub fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    /// The pilot's seconds, and its check's (0 where none chose).
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// The choice that renders, where a pilot chose.
    pub fn choice(&self) -> Option<shares::Choice> {
        self.choice
    }

    /// Whether a pilot chose.
    pub fn is_some(&self) -> bool {
        self.choice.is_some()
    }
}

/// The integrator that renders a scene's settings: [`Sppm`] (sppm, and vcm as photon mapping,
/// [`crate::scene::RenderSettings::photon_mapping`], which is SPPM's estimator), [`PathTracer`]
/// (pt, pt-nee, and vcm without light subpaths, [`light::camera_subpaths_alone`], which is
/// pt-nee's estimator) or [`LightTracer`] (lt, bpt, vcm).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Renderer {
    Sppm,
    Path,
    Light,
}

impl Renderer {
    /// The integrator of the render settings `r`.
    pub(crate) fn of(r: &crate::scene::RenderSettings) -> Self {
        match r.method {
            Method::Sppm => Self::Sppm,
            Method::Vcm if r.photon_mapping => Self::Sppm,
            Method::Pt | Method::PtNee => Self::Path,
            Method::Vcm if light::camera_subpaths_alone(r) => Self::Path,
            Method::Lt | Method::Bpt | Method::Vcm => Self::Light,
        }
    }
}

/// What `scene.render.method` cannot render of this scene, or renders badly, one sentence
/// each, for the user to read before the image (the command line prints them as warnings).
/// Empty when the method suits the scene.
pub fn limitations(scene: &Scene) -> Vec<String> {
    // Environments are found by escaping rays, by every method.
    let delta_lights = scene.lights.iter().filter(|l| !l.kind.is_environment()).count();
    // Surfaces where pt-nee samples no light: mirrors and glass, smooth or rough, thin glass
    // and smooth plastics' coatings.
    let specular = scene.materials.iter().any(|m| m.kind.hides_lights());
    let mut out = Vec::new();
    match scene.render.method {
        Method::Pt if delta_lights > 0 => out.push(format!(
            "method pt finds light only by hitting an emitting surface, so the scene's {delta_lights} point, spot or \
             directional light(s) add nothing to the image; use sppm or pt-nee"
        )),
        Method::PtNee if delta_lights > 0 && specular => out.push(format!(
            "method pt-nee cannot carry light from the scene's {delta_lights} point, spot or directional light(s) through mirror or \
             glass surfaces: their caustics are missing from the image; use sppm"
        )),
        Method::Lt if specular => out.push(
            "method lt joins light to the camera only at surfaces it can evaluate: mirrors and glass (and smooth plastics' \
             coatings) show nothing of what they reflect or refract; use pt-nee or sppm"
                .into(),
        ),
        Method::Sppm => {
            let (lo, hi) = scene.bounds();
            let diagonal = (hi - lo).length();
            if let Some(r) = scene.render.radius {
                if diagonal > 0.0 && r > 0.05 * diagonal {
                    out.push(format!(
                        "radius {r} is over 5% of the scene's size ({diagonal:.3}): until it shrinks over the \
                         passes, light spreads across corners and thin walls and small features blur"
                    ));
                }
            }
        }
        _ => {}
    }
    out
}

/// Whether a render made by [`create_compiled`] may run its first passes before it is
/// returned, to check vcm's pilot's choice against them ([`check`]): a whole image's render,
/// or a batch's, whose [`Integrator::start_at_pass`] must come before any pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FirstPasses {
    /// Under a time limit, where vcm's pilot chose, the render's first passes check the choice
    /// (kept, or the render starts over with another candidate) within the limit.
    Checked,
    /// No pass is run.
    NotRun,
}

/// [`create`], with its kernels compiled first by one pass of a tiny copy of `scene` (8x8
/// pixels, at most a thousand photons) sharing its pipelines ([`crate::gpu::share_kernels`]);
/// also the seconds that took. Drivers compile a kernel when it is made (NVIDIA) or first
/// dispatched (lavapipe), so the renderer's own first pass, a time limit and a rate then
/// measure rendering alone. Under a time limit, where vcm's pilot chose and `first` allows,
/// the render's first passes check its choice ([`check`]): the integrator comes back with
/// them done, or started over with another candidate, the check's seconds in
/// [`Integrator::setup_seconds`].
pub fn create_compiled(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    first: FirstPasses,
) -> Result<(Box<dyn Integrator>, f64), Error> {
    crate::gpu::share_kernels(|| {
        let start = std::time::Instant::now();
        check_device_for(device, scene)?;
        // The scene's records depend on its shapes, materials, lights and camera medium, not
        // on the image: one BVH and one upload serve both renderers.
        let data = SceneData::new(scene)?;
        let buffers = Arc::new(SceneBuffers::upload(device, scene, &data)?);
        let warm_up = |scene: &Scene| {
            let mut tiny = scene.clone();
            let r = &mut tiny.render;
            (r.width, r.height, r.photons, r.iterations, r.time_limit) = (8, 8, r.photons.min(1024), 1, None);
            let mut warm_up = create_on(device, queue, &tiny, &data, buffers.clone(), PilotReport::default())?;
            warm_up.run_pass()?;
            warm_up.image().map(|_| ())
        };
        // vcm's shares are the kernels' data: the warm-up's (1, 1) compiles the kernels its pilot
        // and its render use (the render keeps the pilot's kernels whatever shares it chose).
        warm_up(scene)?;
        // Where the pilot may weigh photon mapping, SPPM's kernels too (for photon mapping),
        // so that the pilot's time, which the time limit counts, is its passes'.
        if shares::weighs_photon_mapping(scene) {
            let mut mapping = scene.clone();
            shares::Choice::PHOTON_MAPPING.apply(&mut mapping.render);
            warm_up(&mapping)?;
        }
        let mut seconds = start.elapsed().as_secs_f64();
        let (resolved, pilot) = resolve(device, queue, scene, &data, &buffers)?;
        // Where the pilot chose no light subpaths the render runs pt-nee's kernel, which no
        // kernel made so far is (photon mapping's, SPPM's, were made above).
        if pilot.is_some() && Renderer::of(&resolved.render) == Renderer::Path {
            let start = std::time::Instant::now();
            warm_up(&resolved)?;
            seconds += start.elapsed().as_secs_f64();
        }
        let report = pilot.as_ref().map(PilotReport::of).unwrap_or_default();
        let mut integrator = create_on(device, queue, &resolved, &data, buffers.clone(), report.clone())?;
        let (Some(pilot), Some(limit), FirstPasses::Checked) = (pilot, scene.render.time_limit, first) else {
            return Ok((integrator, seconds));
        };
        let check_start = std::time::Instant::now();
        let render_seconds = (limit - pilot.seconds).max(0.0);
        let Some((rel_variance, k)) = check::first_passes(integrator.as_mut(), render_seconds, scene.render.iterations)? else {
            let note = format!(
                "vcm's first passes did not check its pilot's choice: twice {} of them did not fit in {:.0}% of the render's time \
                 (at most {} s) or in its passes (the {} that ran are kept)",
                check::MIN_CHECK_PASSES,
                100.0 * check::MAX_CHECK_SHARE,
                check::MAX_CHECK_SECONDS,
                integrator.passes()
            );
            integrator.set_pilot(report.checked(note, check_start.elapsed().as_secs_f64(), pilot.chosen));
            return Ok((integrator, seconds));
        };
        let spent = check_start.elapsed().as_secs_f64();
        // A test hook: passes that varied this many times more than they did.
        let scale = std::env::var("SPPM_GPU_CHECK_RATIO").ok().and_then(|v| v.parse::<f64>().ok()).unwrap_or(1.0);
        let rel_variance = rel_variance * scale;
        let verdict = check::decide(&pilot.candidates, pilot.chosen, rel_variance, render_seconds, render_seconds - spent);
        let said = format!(
            "vcm's first {} passes ({spent:.2} s) varied {:.2}x what its pilot read of them (relative variance a pass {rel_variance:.3e})",
            2 * k,
            verdict.ratio
        );
        let Some(choice) = verdict.switch_to else {
            integrator.set_pilot(report.checked(format!("{said}: kept, the render goes on"), spent, pilot.chosen));
            return Ok((integrator, seconds));
        };
        // Another candidate renders less error in the time left: the render starts over with
        // it, on the device's memory the first one leaves.
        drop(integrator);
        let mut switched = scene.clone();
        choice.apply(&mut switched.render);
        if Renderer::of(&switched.render) == Renderer::Path {
            warm_up(&switched)?;
        }
        let note =
            format!("{said}: {} renders less error in the time left; the render starts over with it", choice.description());
        let report = report.checked(note, check_start.elapsed().as_secs_f64(), choice);
        Ok((create_on(device, queue, &switched, &data, buffers.clone(), report)?, seconds))
    })
}
