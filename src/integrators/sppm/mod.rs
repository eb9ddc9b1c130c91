//! Stochastic progressive photon mapping (Hachisuka & Jensen 2009) on the GPU.
//!
//! One pass, recorded into one command encoder with no trip to the host: `camera_pass` traces
//! a path per visible-point slot to its visible point, sampling direct light on the way
//! (and `direct_samples` paths in all gathering it); `grid_setup` sizes a hashed grid's cells
//! to the points' radii; `photon_pass` traces photons and stores their diffuse hits in a
//! list per grid bucket; `photon_gather` adds the stored hits within each point's radius to
//! it. A photon thread whose hit finds no room stops; `photon_resume_setup` then sizes
//! indirect dispatches that list the points in the grid's buckets (`grid_count`, `grid_scan`,
//! `grid_fill`; src/accel/grid.rs is their CPU oracle) and resume those threads, which add
//! their hits to the points within radius at once. Where photons outnumber visible points
//! ([`deposits_at_once`]) the grid's lists are built before the photons, and every hit is
//! added at once. `update_stats` folds the pass's photons
//! into each point's statistics (N, radius, tau). `resolve` turns the statistics into an
//! image at any time. With a global radius schedule under a filter wider than the box, each
//! pass's estimate of a point is instead a camera sample that `filter_splat` splats into the
//! pixels its filter reaches, as the path tracers' are ([`splat_reach_of`]).

mod buffers;

pub use buffers::{
    accum_stride, deposits_at_once, photon_hit_capacity, BufferSizes, Deposits, ARGS_COUNTS, ARGS_GRID, ARGS_RESUME, ARGS_SCAN,
    AT_ONCE_PHOTONS_PER_POINT,
};

use super::{Integrator, Part, PartSize, Work};
use crate::error::Error;
use crate::gpu::readback::{read_buffer, read_whole, staging_buffer};
use crate::gpu::scene_buffers::{SceneBuffers, SceneData};
use crate::gpu::{Kernel, Specialization};
use crate::image_io::Rgb32Image;
use crate::layout::*;
use crate::scene::{DirectLight, RadiusRule, RadiusSchedule, RenderSettings, Scene};
use buffers::{largest_point_bytes, Buffers, GRID_POINT_WORDS_BYTES, SUSPENDED_STATE_BYTES};
use std::ops::Range;
use std::sync::Arc;

/// The share of an environment light's photons aimed at each pass's visible points
/// ([`Frame::env_aim`], `environment_origin` in `photon_pass.wgsl`): drawn from a disk covering
/// the sphere about the points' bounds rather than from the disk covering the whole scene,
/// with weights that keep the estimate unbiased. The environment variable `SPPM_ENV_AIM`
/// (a number in [0, 1)) overrides it, for experiments; 0 turns it off.
pub const ENV_AIM: f32 = 0.9;

/// The filter's reach in pixels where SPPM splats its passes' estimates (Mitsuba's weighted
/// splatting, [`super::filter`]): under a filter wider than the box, with a global radius
/// schedule (each pass an estimate of its own, Knaus & Zwicker 2011) and one visible point a
/// pixel; 0 otherwise, where camera rays sample the filter (filter importance sampling). On
/// Mitsuba's tent-filtered scenes a pixel then averages about 2.25 pixels' estimates.
pub fn splat_reach_of(r: &RenderSettings) -> u32 {
    if r.radius_schedule == RadiusSchedule::Global {
        r.global_splat_reach()
    } else {
        0
    }
}

/// The rows of the visible points of band `rows` of `r`'s image: its own, and those a
/// splatting filter reaches beyond them within the image ([`splat_reach_of`]; `splat_rows` in
/// shaders/shared/camera.wgsl).
fn point_rows(r: &RenderSettings, rows: &Range<u32>) -> Range<u32> {
    let reach = splat_reach_of(r);
    rows.start.saturating_sub(reach)..(rows.end + reach).min(r.height)
}

/// Photons each `photon_pass` thread traces (`PHOTONS_PER_THREAD` in the kernel).
pub const PHOTONS_PER_THREAD: u32 = 16;

/// Pixel footprints across the automatic initial radius when photons carry all light
/// (`direct = "photons"`, the study's setting).
pub const AUTO_RADIUS_PIXELS: f32 = 2.0;

/// Pixel footprints across the automatic initial radius when direct light is sampled: the
/// photons then carry only indirect light, which is smoother, and a wider radius trades a
/// little blur of it for less noise. At equal time 3 footprints beat 2 on cornell-box and
/// cornell-glossy (`scripts/measure/direct-light-defaults.sh`, docs/journal/session-04.md "The defaults: direct_samples and the radius").
pub const AUTO_RADIUS_PIXELS_INDIRECT: f32 = 3.0;

/// Refuses a gather radius whose disc area pi r^2, in 32-bit floats against the scene's size,
/// leaves no estimate: past ten times the scene's diagonal a photon's flux over the disc
/// (area up to 1e60 and more) vanishes and the image is black; under a millionth of it the
/// disc is below the precision of the positions (1e-30: the area underflows to 0 and every
/// estimate is 0/0).
pub fn check_radius(scene: &Scene, radius: f32) -> Result<(), Error> {
    let (lo, hi) = scene.bounds();
    let diagonal = (hi - lo).length();
    if !(diagonal > 0.0 && diagonal.is_finite()) {
        return Ok(());
    }
    let (least, most) = (1e-6 * diagonal, 10.0 * diagonal);
    if !(least..=most).contains(&radius) {
        let shown = crate::scene::number(radius);
        return Err(Error::Setting(format!(
            "{}: radius {shown} is outside what SPPM can estimate with in this scene (diagonal {diagonal:.4}): from a \
             millionth of the diagonal ({least:.3e}: below it the disc is under the positions' precision and its area \
             underflows) to ten times it ({most:.3e}: beyond it every point gathers every photon); or give none for the \
             automatic radius",
            scene.path.display()
        )));
    }
    Ok(())
}

/// The automatic initial radius: [`AUTO_RADIUS_PIXELS_INDIRECT`] (or, with direct light from
/// photons, [`AUTO_RADIUS_PIXELS`]) times the side of a pixel's footprint on a plane facing
/// the camera at the focus distance (the look-at point for a pinhole),
/// 2 d tan(fov / 2) / height. Tying it to the pixel keeps the blur of the density estimate
/// near the image's own resolution and the work per photon the same at any resolution; it
/// scales with the scene.
pub fn auto_radius(scene: &Scene) -> f32 {
    let c = &scene.camera;
    let d = if c.aperture_radius > 0.0 { c.focus_distance } else { (c.look_at - c.position).length() };
    // A crop window's pixels are the whole film's.
    let film_height = scene.render.height as f32 / c.crop.map_or(1.0, |w| w.max.y - w.min.y);
    let footprint = 2.0 * d * (0.5 * c.fov.to_radians()).tan() / film_height;
    let pixels = match scene.render.direct {
        DirectLight::Sampled => AUTO_RADIUS_PIXELS_INDIRECT,
        DirectLight::Photons => AUTO_RADIUS_PIXELS,
    };
    pixels * footprint
}

/// Camera paths per visible point per pass: 1 with direct light from photons; where it is
/// sampled, `render.direct_samples`, or automatically 3 photons / (2 visible points), from 1
/// to 64, so that the camera pass
/// keeps the same share of a pass whatever the photon count. On cornell-box and
/// cornell-glossy (200,000 photons, 256x256) that is 4 paths, within 10% of the best relMSE at
/// equal time (4 to 8; `scripts/measure/direct-light-defaults.sh`, docs/journal/session-04.md), and the camera
/// pass takes about 30% of a pass (a camera path with next-event estimation, three rays,
/// costs about a third of a photon path on lavapipe).
pub fn direct_samples(render: &crate::scene::RenderSettings) -> u32 {
    if render.direct == DirectLight::Photons {
        return 1;
    }
    render.direct_samples.unwrap_or_else(|| {
        let points = render.width as u64 * render.height as u64 * render.spp as u64;
        (3 * render.photons as u64 / (2 * points).max(1)).clamp(1, 64) as u32
    })
}

/// The box the grid of visible points covers: the surfaces' (swept over the shutter), where
/// every point on a surface lies. Visible points in a participating medium lie anywhere a
/// camera path scatters: in fog around an open scene, in front of it and past its walls, and a
/// point outside the grid would gather nothing. With media the box also holds the camera and
/// reaches MEDIUM_MARGIN mean free paths of the thinnest scattering medium past both; a path
/// scatters beyond that with probability e^-MEDIUM_MARGIN.
pub(super) fn grid_bounds(scene: &Scene, data: &SceneData) -> (glam::Vec3, glam::Vec3) {
    const MEDIUM_MARGIN: f32 = 12.0;
    let (mut lo, mut hi) = data.swept_bounds();
    let thinnest = scene
        .media
        .iter()
        .filter(|m| m.sigma_s.max_element() > 0.0)
        .flat_map(|m| m.sigma_t().to_array())
        .filter(|&sigma| sigma > 0.0)
        .fold(f32::INFINITY, f32::min);
    if thinnest.is_finite() && thinnest > 0.0 {
        let margin = glam::Vec3::splat(MEDIUM_MARGIN / thinnest);
        lo = lo.min(scene.camera.position) - margin;
        hi = hi.max(scene.camera.position) + margin;
    }
    (lo, hi)
}

/// The squared radius of pass `pass` (from 0) under the global schedule of Knaus & Zwicker
/// 2011 (eq. 14 there, with their pass i = `pass + 1`): r_i^2 = r_1^2 prod_{k=1}^{i-1} (k +
/// alpha) / (k + 1). In f64, one product after another, so that a batch starting at any
/// pass gets the radius a whole render has there, bit for bit.
pub fn global_radius_sq(initial_radius: f32, alpha: f32, pass: u32) -> f64 {
    let mut r2 = initial_radius as f64 * initial_radius as f64;
    for k in 1..=pass {
        r2 *= global_radius_factor(k, alpha);
    }
    r2
}

/// r_{k+1}^2 / r_k^2 = (k + alpha) / (k + 1).
fn global_radius_factor(k: u32, alpha: f32) -> f64 {
    (k as f64 + alpha as f64) / (k as f64 + 1.0)
}

/// [`ENV_AIM`], or `SPPM_ENV_AIM` where set.
fn env_aim() -> Result<f32, Error> {
    match std::env::var("SPPM_ENV_AIM") {
        Err(_) => Ok(ENV_AIM),
        Ok(v) => v
            .trim()
            .parse::<f32>()
            .ok()
            .filter(|f| (0.0..1.0).contains(f))
            .ok_or_else(|| Error::Setting(format!("SPPM_ENV_AIM must be a number in [0, 1), found `{v}`"))),
    }
}

/// Statistics a caller may read between passes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiusStats {
    /// Smallest gather radius over the visible points, scene units.
    pub min: f32,
    /// Mean gather radius.
    pub mean: f32,
    /// Largest gather radius.
    pub max: f32,
}

/// Where the pass under way stands: the next camera path or photon to trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum NextPart {
    Camera(u32),
    Photons(u32),
}

/// The SPPM renderer for one scene on one device: the scene's buffers, one visible point per
/// pixel sample with its statistics ([`VpStats`]), the hashed grid and the kernels.
///
/// Drive it with [`Sppm::run_pass`] and read the estimate with [`Sppm::image`], or record
/// passes and resolves into your own encoder ([`Integrator::record_pass`],
/// [`Integrator::record_pass_part`], [`Integrator::record_resolve_to_texture`],
/// [`Sppm::record_resolve_to_buffer`]). The device
/// needs the limits of [`crate::gpu::required_limits`] and no features. The same scene,
/// settings and seed give the same image bit for bit on the same device.
pub struct Sppm {
    device: wgpu::Device,
    queue: wgpu::Queue,
    frame: Frame,
    vp_count: u32,
    pixel_count: u32,
    passes: u32,
    photons_traced: u64,
    initial_radius: f32,
    /// With [`RadiusSchedule::Global`]: the squared radius of the next pass.
    global_radius_sq: Option<f64>,
    /// The first pass this renderer runs ([`Integrator::start_at_pass`]).
    first_pass: u32,
    /// The next part of the pass (see [`Integrator::record_pass_part`]).
    next: NextPart,
    /// Photon threads whose state `photon_suspended` has room for.
    suspend_room: u32,
    /// Photon threads dispatched since the hits were last gathered.
    threads_pending: u32,
    /// Gathers recorded since the renderer was made.
    gathers: u64,
    /// Whether every photon hit is added at once ([`Deposits::AtOnce`]).
    at_once: bool,
    /// Whether the radius follows the adaptive rule ([`RadiusRule::Adaptive`]): the flux
    /// accumulator holds the photons' offset moments, and `radius_tests` a test per point.
    adaptive: bool,
    /// Whether the scene has an environment light (whose photons [`Frame::env_aim`] aims).
    has_environment: bool,

    camera_pass: Stage,
    grid_setup: Stage,
    grid_count: Stage,
    grid_scan: Stage,
    grid_fill: Stage,
    photon_pass: Stage,
    photon_gather: Stage,
    photon_resume_setup: Stage,
    update_stats: Stage,
    /// Where the passes' estimates are splatted ([`splat_reach_of`]): the kernel that splats
    /// them into `radiance`.
    filter_splat: Option<Stage>,
    resolve: Stage,
    /// `resolve_texture` for Rgba32Float and Rgba16Float targets, made when first used.
    resolve_texture: [Option<Kernel>; 2],

    buffers: Buffers,
    image_staging: wgpu::Buffer,
    /// [`Sppm::run_pass`]'s submissions in flight.
    submissions: crate::gpu::submissions::Submissions,
    /// What vcm's pilot said, where it chose photon mapping.
    pilot: super::PilotReport,
}

/// A kernel and its bind group.
struct Stage {
    kernel: Kernel,
    group: wgpu::BindGroup,
}

impl Stage {
    fn new(device: &wgpu::Device, name: &'static str, buffers: &Buffers, spec: &Specialization) -> Result<Self, Error> {
        let kernel = spec.kernel(device, name)?;
        let group = kernel.bind_group(device, &buffers.resources())?;
        Ok(Self { kernel, group })
    }

    fn dispatch(&self, encoder: &mut wgpu::CommandEncoder, threads: u32) {
        self.kernel.dispatch(encoder, &self.group, threads);
    }
}

impl Sppm {
    /// Set up the renderer for `scene` on the caller's device.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<Self, Error> {
        Self::new_rows(device, queue, scene, 0..scene.render.height)
    }

    /// [`Sppm::new`] adding photons to the visible points as `deposits` says rather than as
    /// the photon count suggests: the same image bit for bit, found another way (for tests,
    /// and to compare the two).
    pub fn with_deposits(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, deposits: Deposits) -> Result<Self, Error> {
        crate::gpu::check_device(device)?;
        let data = SceneData::new(scene)?;
        let scene_buffers = Arc::new(SceneBuffers::upload(device, scene, &data)?);
        Self::with_scene_buffers(device, queue, scene, &data, scene_buffers, 0..scene.render.height, deposits)
    }

    /// The renderer for rows `rows` of `scene`'s image only: a band of an image whose
    /// visible points do not fit in one set of buffers (see [`Sppm::max_rows`] and
    /// [`Bands`](super::Bands)). Its image is `width` x `rows.len()`, and equals those rows of
    /// the whole image's bit for bit: random numbers are keyed by the point's place in the
    /// whole image, and every band traces the same photons.
    pub fn new_rows(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, rows: Range<u32>) -> Result<Self, Error> {
        crate::gpu::check_device(device)?;
        let data = SceneData::new(scene)?;
        let scene_buffers = Arc::new(SceneBuffers::upload(device, scene, &data)?);
        Self::with_scene_buffers(device, queue, scene, &data, scene_buffers, rows, Deposits::Auto)
    }

    /// Rows of `scene`'s image whose visible points fit in one set of this device's buffers;
    /// 0 when not even one row fits.
    pub fn max_rows(device: &wgpu::Device, scene: &Scene) -> u32 {
        // The largest per-point buffers hold 32 bytes a point (flux, statistics, grid; 48 for
        // the flux of the adaptive radius rule).
        let points = device.limits().max_storage_buffer_binding_size / largest_point_bytes(scene);
        let per_row = scene.render.width as u64 * scene.render.spp as u64;
        let rows = (points / per_row.max(1)).min(u32::MAX as u64) as u32;
        rows.saturating_sub(2 * splat_reach_of(&scene.render))
    }

    /// Bytes of the renderer's own buffers for the band `rows` of `scene`'s image on a
    /// device whose storage buffers hold `max_binding` bytes, as
    /// [`Integrator::gpu_memory`] reports them once allocated ([`BufferSizes`]), computed
    /// before allocating, for the memory check.
    pub fn renderer_bytes(scene: &Scene, rows: Range<u32>, max_binding: u64) -> u64 {
        let r = &scene.render;
        let pixels = r.width as u64 * rows.len() as u64;
        let points = r.width as u64 * point_rows(r, &rows).len() as u64 * r.spp as u64;
        BufferSizes::new(r, points, pixels, deposits_at_once(r, points), max_binding).total()
    }

    /// [`Sppm::new_rows`] on scene buffers already uploaded (shared between bands).
    pub(crate) fn with_scene_buffers(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        data: &SceneData,
        scene_buffers: Arc<SceneBuffers>,
        rows: Range<u32>,
        deposits: Deposits,
    ) -> Result<Self, Error> {
        let r = &scene.render;
        let mut frame = super::band_frame(scene, data, &rows)?;
        frame.filter_reach = splat_reach_of(r);
        let band_height = frame.height;
        let point_rows = point_rows(r, &rows).len() as u32;
        // Random streams are keyed by a point's u32 index in the whole image.
        if r.width as u64 * r.height as u64 * r.spp as u64 > u32::MAX as u64 {
            return Err(Error::Setting(format!(
                "{}x{} pixels with spp {} are more than 2^32 visible points",
                r.width, r.height, r.spp
            )));
        }
        let pixel_count = r.width.checked_mul(band_height).ok_or_else(|| Error::Setting("image too large".into()))?;
        let vp_count = (r.width as u64 * point_rows as u64 * r.spp as u64)
            .try_into()
            .ok()
            .filter(|n| (*n as u64) * largest_point_bytes(scene) <= device.limits().max_storage_buffer_binding_size)
            .ok_or_else(|| {
                Error::Setting(format!(
                    "{}x{} pixels with spp {} need more visible points than this device's buffers hold; \
                     render it in bands of at most {} rows (sppm_gpu::integrators::Bands)",
                    r.width,
                    band_height,
                    r.spp,
                    Self::max_rows(device, scene)
                ))
            })?;
        let initial_radius = r.radius.unwrap_or_else(|| auto_radius(scene));
        check_radius(scene, initial_radius)?;
        let adaptive = r.radius_rule == RadiusRule::Adaptive;
        if adaptive && r.radius_schedule == RadiusSchedule::Global {
            return Err(Error::Setting("radius_rule = \"adaptive\" needs radius_schedule = \"per-point\"".into()));
        }

        frame.photon_count = r.photons;
        frame.vp_count = vp_count;
        let has_environment = scene.lights.iter().any(|l| l.kind.is_environment());
        frame.env_aim = if has_environment { env_aim()? } else { 0.0 };

        let n = vp_count as u64;
        let max_binding = device.limits().max_storage_buffer_binding_size;
        let at_once = match deposits {
            Deposits::Auto => deposits_at_once(r, n),
            Deposits::Gathered => false,
            Deposits::AtOnce => true,
        };
        frame.at_once = at_once as u32;
        let hit_capacity = photon_hit_capacity(r, at_once, max_binding);
        frame.hit_capacity = hit_capacity;
        // Each point is listed in at most 8 buckets (2 cells per axis); the table has a bucket
        // per point, rounded up to a power of two.
        let table_size = vp_count.next_power_of_two();
        let (lo, hi) = grid_bounds(scene, data);
        let grid_scene = GridScene { lo: lo.into(), table_size, hi: hi.into(), _pad: 0 };
        let stats: Vec<VpStats> = vec![VpStats { radius: initial_radius, ..VpStats::default() }; vp_count as usize];
        let sizes = BufferSizes::new(r, n, pixel_count as u64, at_once, max_binding);
        let buffers = Buffers::new(device, &sizes, scene_buffers, &stats, grid_scene);
        queue.write_buffer(&buffers.frame, 0, bytemuck::bytes_of(&frame));
        // The tracing kernels, compiled for what this scene has.
        let spec = super::specialization(scene, data);
        // The two large kernels compile side by side: the driver may do its work when a
        // pipeline is created (lavapipe runs Mesa's NIR passes then), on the calling thread.
        let (camera_pass, photon_pass) = crate::gpu::join_sharing_kernels(
            || Stage::new(device, "camera_pass", &buffers, &spec),
            || Stage::new(device, "photon_pass", &buffers, &spec),
        );

        Ok(Self {
            device: device.clone(),
            queue: queue.clone(),
            frame,
            vp_count,
            pixel_count,
            passes: 0,
            photons_traced: 0,
            next: NextPart::Camera(0),
            suspend_room: (buffers.photon_suspended.size() / SUSPENDED_STATE_BYTES) as u32,
            threads_pending: 0,
            gathers: 0,
            at_once,
            adaptive,
            has_environment,
            initial_radius,
            global_radius_sq: (r.radius_schedule == RadiusSchedule::Global).then(|| global_radius_sq(initial_radius, r.alpha, 0)),
            first_pass: 0,
            camera_pass: camera_pass?,
            grid_setup: Stage::new(device, "grid_setup", &buffers, &spec)?,
            grid_count: Stage::new(device, "grid_count", &buffers, &spec)?,
            grid_scan: Stage::new(device, "grid_scan", &buffers, &spec)?,
            grid_fill: Stage::new(device, "grid_fill", &buffers, &spec)?,
            photon_pass: photon_pass?,
            photon_gather: Stage::new(device, "photon_gather", &buffers, &spec)?,
            photon_resume_setup: Stage::new(device, "photon_resume_setup", &buffers, &spec)?,
            update_stats: Stage::new(device, "update_stats", &buffers, &spec)?,
            filter_splat: match frame.filter_reach {
                0 => None,
                _ => Some(Stage::new(device, "filter_splat", &buffers, &spec)?),
            },
            resolve: Stage::new(device, "resolve", &buffers, &spec)?,
            resolve_texture: [None, None],
            image_staging: staging_buffer(device, "image_staging", sizes.image_staging),
            buffers,
            submissions: crate::gpu::submissions::Submissions::new(),
            pilot: Default::default(),
        })
    }

    /// The renderer reporting what vcm's pilot said of its choice of photon mapping and the
    /// seconds it took ([`Integrator::notes`], [`Integrator::setup_seconds`]).
    pub(super) fn reporting(mut self, pilot: super::PilotReport) -> Self {
        self.pilot = pilot;
        self
    }

    /// Passes completed.
    pub fn passes(&self) -> u32 {
        self.passes
    }

    /// Photons emitted over all completed passes.
    pub fn photons_traced(&self) -> u64 {
        self.photons_traced
    }

    /// The radius every visible point started with.
    pub fn initial_radius(&self) -> f32 {
        self.initial_radius
    }

    /// Run one SPPM pass: record it (the four stages below) and submit it, first waiting for
    /// the oldest pass in flight if [`crate::pacing::MAX_IN_FLIGHT`] are.
    pub fn run_pass(&mut self) -> Result<(), Error> {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("sppm pass") });
        Integrator::record_pass(self, &mut encoder);
        self.submissions.submit(&self.device, &self.queue, encoder.finish())
    }

    /// Bytes of [`Integrator::state`]'s buffers: the statistics and, under the adaptive radius
    /// rule, the uniformity tests; where the passes' estimates are splatted, the pixels' sums.
    fn state_bytes(&self) -> u64 {
        if self.filter_splat.is_some() {
            return self.buffers.radiance.size() + self.buffers.direct_sums.size();
        }
        self.buffers.vp_stats.size() + if self.adaptive { self.buffers.radius_tests.size() } else { 0 }
    }

    /// After a state of `passes` passes and `photons` photons is loaded: go on from there.
    fn restored(&mut self, passes: u32, photons: u64) {
        self.drop_pass_under_way();
        self.passes = passes;
        if self.global_radius_sq.is_some() {
            self.global_radius_sq = Some(global_radius_sq(self.initial_radius, self.frame.alpha, passes));
        }
        self.photons_traced = photons;
    }

    /// Forget the parts recorded of a pass not completed, and the photons they deposited.
    fn drop_pass_under_way(&mut self) {
        if let NextPart::Photons(_) = self.next {
            let zeros = vec![0u8; self.buffers.flux_accum.size() as usize];
            self.queue.write_buffer(&self.buffers.flux_accum, 0, &zeros);
        }
        self.next = NextPart::Camera(0);
    }

    /// Copy `frame` into the `frame` uniform from within the encoder, so that passes and
    /// parts recorded into one encoder each see their own.
    fn upload_frame(&self, encoder: &mut wgpu::CommandEncoder, frame: &Frame) {
        super::record_upload(&self.device, &self.queue, encoder, &self.buffers.frame, bytemuck::bytes_of(frame));
    }

    /// This pass's frame constants, for the dispatch of items `first..end` of its stage.
    fn record_frame(&mut self, encoder: &mut wgpu::CommandEncoder, first: u32, end: u32) {
        self.frame.global_radius = self.global_radius_sq.map_or(0.0, |r2| r2.sqrt() as f32);
        self.frame.first_pass = self.first_pass;
        self.frame.pass_index = self.passes;
        self.frame.time = super::shutter_time(self.frame.seed, self.passes);
        self.frame.work_first = first;
        self.frame.work_end = end;
        self.upload_frame(encoder, &self.frame);
    }

    fn record_camera_paths(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.record_camera_slice(encoder, 0, self.vp_count);
    }

    /// Camera paths of visible points `first..end`; the first slice of a pass clears the
    /// radius that the grid is sized by.
    fn record_camera_slice(&mut self, encoder: &mut wgpu::CommandEncoder, first: u32, end: u32) {
        if first == 0 {
            encoder.clear_buffer(&self.buffers.grid_max_radius, 0, None);
        }
        self.record_frame(encoder, first, end);
        self.camera_pass.dispatch(encoder, end - first);
    }

    /// The grid's cells for this pass's points, and empty photon hit lists. The grid's lists
    /// of points are built here where every hit is added at once, otherwise only when a
    /// photon thread finds no room for a hit (see [`Sppm::record_photon_slice`]).
    fn record_grid(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let b = &self.buffers;
        self.grid_setup.kernel.dispatch_groups(encoder, &self.grid_setup.group, 1);
        if !self.at_once {
            encoder.clear_buffer(&b.photon_hit_lists, 0, None);
        }
        encoder.clear_buffer(&b.photon_resume_args, ARGS_COUNTS, None);
        self.threads_pending = 0;
        // The photon pass reads the parameters as a uniform, and after them the visible
        // points' bounds where it aims environment photons at them.
        encoder.copy_buffer_to_buffer(&b.grid_params, 0, &b.grid, 0, size_of::<GridParams>() as u64);
        if self.frame.env_aim > 0.0 {
            encoder.copy_buffer_to_buffer(&b.grid_max_radius, 0, &b.grid, size_of::<GridParams>() as u64, GRID_POINT_WORDS_BYTES);
        }
        if self.at_once {
            self.record_point_grid(encoder, false);
        }
    }

    /// The grid's lists of visible points (a counting sort into its buckets), with workgroup
    /// counts from `photon_resume_args` when `indirect` (none when no thread stopped).
    fn record_point_grid(&mut self, encoder: &mut wgpu::CommandEncoder, indirect: bool) {
        let b = &self.buffers;
        encoder.clear_buffer(&b.grid_cell_count, 0, None);
        if indirect {
            self.grid_count.kernel.dispatch_indirect(encoder, &self.grid_count.group, &b.photon_resume_args, ARGS_GRID);
            self.grid_scan.kernel.dispatch_indirect(encoder, &self.grid_scan.group, &b.photon_resume_args, ARGS_SCAN);
            self.grid_fill.kernel.dispatch_indirect(encoder, &self.grid_fill.group, &b.photon_resume_args, ARGS_GRID);
        } else {
            self.grid_count.dispatch(encoder, self.vp_count);
            self.grid_scan.kernel.dispatch_groups(encoder, &self.grid_scan.group, 1);
            self.grid_fill.dispatch(encoder, self.vp_count);
        }
    }

    fn record_photons(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.record_photon_slice(encoder, 0, self.frame.photon_count);
    }

    /// Photons `first..end` of this pass, in dispatches of at most as many threads as there
    /// is room to save the state of. After the last photon of the pass, or when that room is
    /// taken, the hits stored so far are gathered ([`Sppm::record_photon_flush`]).
    fn record_photon_slice(&mut self, encoder: &mut wgpu::CommandEncoder, first: u32, end: u32) {
        if self.at_once {
            // Nothing stored, nothing to gather.
            self.record_frame(encoder, first, end);
            self.photon_pass.dispatch(encoder, (end - first).div_ceil(PHOTONS_PER_THREAD));
            return;
        }
        let mut at = first;
        while at < end {
            if self.threads_pending == self.suspend_room {
                self.record_photon_flush(encoder);
            }
            let threads = (self.suspend_room - self.threads_pending).min((end - at).div_ceil(PHOTONS_PER_THREAD));
            let to = end.min(at.saturating_add(threads.saturating_mul(PHOTONS_PER_THREAD)));
            self.record_frame(encoder, at, to);
            self.photon_pass.dispatch(encoder, threads);
            self.threads_pending += threads;
            at = to;
        }
        if end == self.frame.photon_count {
            self.record_photon_flush(encoder);
        }
    }

    /// The visible points gather the hits stored; then, for the photon threads that stopped
    /// for want of room (if any: the dispatches are sized on the GPU), the grid's lists of
    /// points are built and the threads resumed, to deposit at once. The hit lists are then
    /// empty again.
    fn record_photon_flush(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.photon_gather.dispatch(encoder, self.vp_count);
        self.gathers += 1;
        self.photon_resume_setup.kernel.dispatch_groups(encoder, &self.photon_resume_setup.group, 1);
        self.record_point_grid(encoder, true);
        self.frame.resume = 1;
        self.frame.at_once = 1;
        self.upload_frame(encoder, &self.frame);
        let args = &self.buffers.photon_resume_args;
        self.photon_pass.kernel.dispatch_indirect(encoder, &self.photon_pass.group, args, ARGS_RESUME);
        self.frame.resume = 0;
        self.frame.at_once = 0;
        encoder.clear_buffer(&self.buffers.photon_hit_lists, 0, None);
        self.threads_pending = 0;
    }

    fn record_statistics(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.update_stats.dispatch(encoder, self.vp_count);
        if let Some(stage) = &self.filter_splat {
            stage.dispatch(encoder, self.pixel_count);
        }
        self.passes += 1;
        self.photons_traced += self.frame.photon_count as u64;
        // r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1) for the pass i (from 1) just done; the
        // same products in the same order as global_radius_sq, so batches agree bit for bit.
        if let Some(r2) = self.global_radius_sq.as_mut() {
            *r2 *= global_radius_factor(self.passes, self.frame.alpha);
        }
    }

    /// Run `record` in an encoder of its own and submit it.
    fn submit(&mut self, label: &str, record: impl FnOnce(&mut Self, &mut wgpu::CommandEncoder)) {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        record(self, &mut encoder);
        self.queue.submit([encoder.finish()]);
    }

    /// Stage 1 of a pass, submitted alone (for tests and stage timings): camera paths to this
    /// pass's visible points.
    pub fn trace_camera_paths(&mut self) {
        self.submit("camera_pass", Self::record_camera_paths);
    }

    /// Stage 2: size the hashed grid's cells to the visible points' radii, and empty the
    /// photon hit lists.
    pub fn build_grid(&mut self) -> Result<(), Error> {
        self.submit("grid", Self::record_grid);
        Ok(())
    }

    /// The grid's lists of visible points, which a pass builds only for photons that find no
    /// room for their hits (for tests of the grid, after [`Sppm::build_grid`]).
    pub fn build_point_grid(&mut self) {
        self.submit("grid", |s, encoder| s.record_point_grid(encoder, false));
    }

    /// Stage 3: trace this pass's photons, adding their flux to the visible points around
    /// their diffuse hits.
    pub fn trace_photons(&mut self) {
        self.submit("photon_pass", Self::record_photons);
    }

    /// Stage 4: fold the pass's photons into each visible point's N, radius and tau; the pass
    /// is then complete.
    pub fn update_statistics(&mut self) {
        self.submit("update_stats", Self::record_statistics);
    }

    /// Store at most `capacity` photon hits a pass for the gather (no more than there is room
    /// for, [`photon_hit_capacity`]), depositing the rest at once: the same sums bit for bit,
    /// found another way (for tests, and to compare the two).
    pub fn set_photon_hit_capacity(&mut self, capacity: u32) {
        let room = self.buffers.photon_hits.size() / size_of::<PhotonHit>() as u64;
        self.frame.hit_capacity = capacity.min(room as u32);
    }

    /// Of the last photon stage: the hits gathered, and the photon threads that found no room
    /// for a hit and were resumed to deposit at once (for `bench` and tests).
    pub fn photon_hits_gathered(&self) -> Result<(u32, u32), Error> {
        let words: Vec<u32> = read_whole(&self.device, &self.queue, &self.buffers.photon_resume_args)?;
        let first = (ARGS_COUNTS / 4) as usize;
        Ok((words[first], words[first + 1]))
    }

    /// Gathers recorded since the renderer was made: one a pass, unless the room for hits or
    /// for the states of photon threads ran out within one (for tests).
    pub fn gathers(&self) -> u64 {
        self.gathers
    }

    /// Whether every photon hit is added at once rather than gathered ([`Deposits`]).
    pub fn deposits_at_once(&self) -> bool {
        self.at_once
    }

    /// The share of the environment's photons aimed at the visible points ([`ENV_AIM`]); 0
    /// without an environment.
    pub fn environment_aim(&self) -> f32 {
        self.frame.env_aim
    }

    /// Aim `share` (in [0, 1)) of the environment's photons at the visible points from the
    /// next pass on (for tests and experiments; no effect without an environment).
    pub fn set_environment_aim(&mut self, share: f32) {
        if self.has_environment {
            self.frame.env_aim = share.clamp(0.0, 0.999);
        }
    }

    /// Photon hits a pass may store for the gather at a time.
    pub fn photon_hit_capacity(&self) -> u32 {
        self.frame.hit_capacity
    }

    /// Block until the GPU has finished all submitted work (for stage timings).
    pub fn wait(&self) -> Result<(), Error> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::Gpu(crate::gpu::GpuError(format!("waiting for the GPU failed: {e}"))))?;
        Ok(())
    }

    /// The grid as the GPU built it: parameters, bucket offsets and entries, the last two as
    /// of the last time its lists of points were built ([`Sppm::build_point_grid`], or a pass
    /// that resumed photon threads; for tests against the CPU oracle).
    pub fn grid(&self) -> Result<(GridParams, Vec<u32>, Vec<u32>), Error> {
        let read = |b: &wgpu::Buffer| -> Result<Vec<u32>, Error> { Ok(read_whole(&self.device, &self.queue, b)?) };
        let params: GridParams = bytemuck::pod_read_unaligned(bytemuck::cast_slice(&read(&self.buffers.grid_params)?[..8]));
        Ok((params, read(&self.buffers.grid_cell_start)?, read(&self.buffers.grid_entries)?))
    }

    /// Point the frame's pass count at the last completed pass, from within the encoder, for
    /// the resolve kernels.
    fn record_resolve_frame(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), Error> {
        if self.passes == self.first_pass {
            return Err(Error::Setting("no pass has run yet: record or run a pass before resolving".into()));
        }
        if self.next != NextPart::Camera(0) {
            return Err(Error::Setting("a pass is under way (record_pass_part): record the rest of it before resolving".into()));
        }
        let pass = self.passes - 1;
        let frame = Frame { pass_index: pass, time: super::shutter_time(self.frame.seed, pass), ..self.frame };
        self.upload_frame(encoder, &frame);
        Ok(())
    }

    /// Record the estimate after the passes recorded so far into the renderer's own `image`
    /// buffer (rgba32float per pixel, row-major).
    pub fn record_resolve(&mut self, encoder: &mut wgpu::CommandEncoder) -> Result<(), Error> {
        self.record_resolve_frame(encoder)?;
        self.resolve.dispatch(encoder, self.pixel_count);
        Ok(())
    }

    /// Record the estimate into the caller's buffer at `offset`: `width * height` texels of
    /// rgba32float (16 bytes), row-major, alpha 1. The buffer needs `COPY_DST`.
    pub fn record_resolve_to_buffer(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        dst: &wgpu::Buffer,
        offset: u64,
    ) -> Result<(), Error> {
        let size = self.pixel_count as u64 * 16;
        if offset + size > dst.size() || !dst.usage().contains(wgpu::BufferUsages::COPY_DST) {
            return Err(Error::Setting(format!(
                "the destination buffer needs COPY_DST and {size} bytes from offset {offset}; it has {} bytes",
                dst.size()
            )));
        }
        self.record_resolve(encoder)?;
        encoder.copy_buffer_to_buffer(&self.buffers.image, 0, dst, offset, size);
        Ok(())
    }

    /// The current estimate, read back.
    pub fn image(&mut self) -> Result<Rgb32Image, Error> {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("resolve") });
        self.record_resolve(&mut encoder)?;
        self.queue.submit([encoder.finish()]);
        let rgba: Vec<[f32; 4]> =
            read_buffer(&self.device, &self.queue, &self.buffers.image, &self.image_staging, self.pixel_count as u64 * 16)?;
        Ok(Rgb32Image::from_rgba(self.frame.width, self.frame.height, &rgba))
    }

    /// Per visible point statistics, read back (for tests and `--stats`).
    pub fn stats(&self) -> Result<Vec<VpStats>, Error> {
        Ok(read_whole(&self.device, &self.queue, &self.buffers.vp_stats)?)
    }

    /// The uniformity tests of the adaptive radius rule, read back (one a visible point; one in
    /// all under the plain rule).
    pub fn radius_tests(&self) -> Result<Vec<RadiusTest>, Error> {
        Ok(read_whole(&self.device, &self.queue, &self.buffers.radius_tests)?)
    }

    /// The photon pass's flux accumulator, read back: [`accum_stride`] words per visible point,
    /// (lo, hi) 32.32 fixed-point pairs for r, g, b of the photons' own flux relative to
    /// `power_total` (not yet times the point's weight, which `update_statistics` applies),
    /// then the photon count. It holds the current pass's photons between `trace_photons` and
    /// `update_statistics`, which clears it.
    pub fn flux_accum(&self) -> Result<Vec<u32>, Error> {
        Ok(read_whole(&self.device, &self.queue, &self.buffers.flux_accum)?)
    }

    /// Visible points of the current pass, read back (for tests).
    pub fn visible_points(&self) -> Result<Vec<VisiblePoint>, Error> {
        Ok(read_whole(&self.device, &self.queue, &self.buffers.visible_points)?)
    }

    /// Visible points' positions and radii of the current pass (xyz, radius; radius 0 where
    /// the camera path found none), read back.
    pub fn visible_point_positions(&self) -> Result<Vec<[f32; 4]>, Error> {
        Ok(self.visible_points()?.iter().map(|v| [v.p[0], v.p[1], v.p[2], v.radius]).collect())
    }

    /// The per-pass constants the kernels see (camera, counts, alpha, `power_total`).
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// Smallest, mean and largest radius over the visible points.
    pub fn radius_stats(&self) -> Result<RadiusStats, Error> {
        let stats = self.stats()?;
        let (mut min, mut max, mut sum) = (f32::INFINITY, 0.0f32, 0.0f64);
        for s in &stats {
            min = min.min(s.radius);
            max = max.max(s.radius);
            sum += s.radius as f64;
        }
        Ok(RadiusStats { min, mean: (sum / stats.len().max(1) as f64) as f32, max })
    }
}

impl Integrator for Sppm {
    fn run_pass(&mut self) -> Result<(), Error> {
        Sppm::run_pass(self)
    }
    /// Record the estimate into the caller's 2D texture, which must be `width` x `height`,
    /// `Rgba16Float` or `Rgba32Float`, with `STORAGE_BINDING` usage; alpha is 1.
    fn record_resolve_to_texture(&mut self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) -> Result<(), Error> {
        let (width, height) = (self.frame.width, self.frame.height);
        super::check_resolve_target(texture, width, height)?;
        self.record_resolve_frame(encoder)?;
        let kernel = super::resolve_kernel(&self.device, &mut self.resolve_texture, "resolve_texture", texture, width, height)?;
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let group = kernel.bind_group_with_views(&self.device, &self.buffers.resources(), &[("out_image", &view)])?;
        kernel.dispatch(encoder, &group, self.pixel_count);
        Ok(())
    }

    /// Start over: every visible point back to the initial radius with no photons, and the
    /// pass count at 0 (the next pass uses the same random numbers as the first did). A pass
    /// under way is dropped, with the photons it has deposited. The buffers are written at the
    /// next submission, so commands recorded before must have been submitted.
    fn reset(&mut self) {
        let stats = vec![VpStats { radius: self.initial_radius, ..VpStats::default() }; self.vp_count as usize];
        self.queue.write_buffer(&self.buffers.vp_stats, 0, bytemuck::cast_slice(&stats));
        let tests = vec![0u8; self.buffers.radius_tests.size() as usize];
        self.queue.write_buffer(&self.buffers.radius_tests, 0, &tests);
        for sums in [&self.buffers.radiance, &self.buffers.direct_sums] {
            self.queue.write_buffer(sums, 0, &vec![0u8; sums.size() as usize]);
        }
        self.drop_pass_under_way();
        self.passes = self.first_pass;
        self.photons_traced = 0;
        if self.global_radius_sq.is_some() {
            self.global_radius_sq = Some(global_radius_sq(self.initial_radius, self.frame.alpha, self.first_pass));
        }
    }

    fn record_pass_part(&mut self, encoder: &mut wgpu::CommandEncoder, size: PartSize) -> Part {
        match self.next {
            NextPart::Camera(first) => {
                let end = first.saturating_add(size.points.max(1)).min(self.vp_count);
                self.record_camera_slice(encoder, first, end);
                self.next = NextPart::Camera(end);
                if end == self.vp_count {
                    self.record_grid(encoder);
                    self.next = NextPart::Photons(0);
                }
                Part { work: Work::CameraPaths, items: end - first, pass_done: false }
            }
            NextPart::Photons(first) => {
                let want = first.saturating_add(size.photons.max(1)).min(self.frame.photon_count);
                // A part ends at a photon thread's block where it can, so that the parts of a
                // pass take the threads of a whole pass: parts that split blocks take a few
                // more, past the room to save their states, and the pass gathers twice.
                let block_end = want / PHOTONS_PER_THREAD * PHOTONS_PER_THREAD;
                let end = if want < self.frame.photon_count && block_end > first { block_end } else { want };
                self.record_photon_slice(encoder, first, end);
                self.next = NextPart::Photons(end);
                let pass_done = end == self.frame.photon_count;
                if pass_done {
                    self.record_statistics(encoder);
                    self.next = NextPart::Camera(0);
                }
                Part { work: Work::Photons, items: end - first, pass_done }
            }
        }
    }

    fn radius_stats(&self) -> Result<Option<RadiusStats>, Error> {
        Sppm::radius_stats(self).map(Some)
    }

    fn pilot(&self) -> &super::PilotReport {
        &self.pilot
    }

    fn set_pilot(&mut self, report: super::PilotReport) {
        self.pilot = report;
    }

    fn splits_strategies(&self) -> bool {
        false
    }

    /// Only with a global radius schedule: with a radius per point, each pass depends on all
    /// the passes before it.
    fn start_at_pass(&mut self, first: u32) -> Result<(), Error> {
        if self.global_radius_sq.is_none() && first != self.first_pass {
            return Err(Error::Setting(format!(
                "SPPM with a radius per point cannot start at pass {first}: each pass depends on every pass before it; \
                 set radius_schedule = \"global\" (--radius-schedule global) to render passes in batches"
            )));
        }
        if self.passes != self.first_pass {
            return Err(Error::Setting("start_at_pass: passes have run already".into()));
        }
        self.first_pass = first;
        Integrator::reset(self);
        Ok(())
    }

    /// Move the camera and start over ([`Integrator::reset`]): the statistics of one view do not
    /// carry over to another. The image size and samples per pixel stay as they are.
    fn set_camera(&mut self, camera: &crate::scene::Camera) -> Result<(), Error> {
        super::set_frame_camera(&mut self.frame, camera)?;
        self.queue.write_buffer(&self.buffers.frame, 0, bytemuck::bytes_of(&self.frame));
        Integrator::reset(self);
        Ok(())
    }

    fn passes(&self) -> u32 {
        self.passes
    }
    fn work_per_pass(&self) -> u64 {
        self.frame.photon_count as u64
    }
    fn work_unit(&self) -> &'static str {
        "photons"
    }
    fn image(&mut self) -> Result<Rgb32Image, Error> {
        Sppm::image(self)
    }
    fn gpu_memory(&self) -> super::GpuMemory {
        let scene = self.buffers.scene.resources();
        let own = self.buffers.resources();
        let own = own.iter().filter(|r| !scene.iter().any(|s| s.name == r.name)).map(|r| (r.name, r.buffer));
        let staging = [("image_staging", &self.image_staging)];
        super::GpuMemory {
            scene: super::sizes(scene.iter().map(|r| (r.name, r.buffer))),
            renderer: super::sizes(own.chain(staging)),
        }
    }
    /// The statistics, then (adaptive radius rule) the uniformity tests; where the passes'
    /// estimates are splatted, the pixels' sums alone (a global schedule keeps nothing else):
    /// the weighted ones, then the direct light's.
    fn state(&mut self) -> Result<Vec<u8>, Error> {
        if let Some(sums) = self.splat_sums()? {
            return Ok(sums.encode_state(self.passes, self.photons_traced));
        }
        let mut stats: Vec<u8> = read_whole(&self.device, &self.queue, &self.buffers.vp_stats)?;
        if self.adaptive {
            stats.extend(read_whole::<u8>(&self.device, &self.queue, &self.buffers.radius_tests)?);
        }
        Ok(super::encode_state(self.passes, self.photons_traced, &stats))
    }
    /// The estimate of `resolve.wgsl` (shared/estimate.wgsl), on the host.
    fn image_of_state(&self, state: &[u8]) -> Result<Rgb32Image, Error> {
        let (passes, _, stats) = super::decode_state(state, self.state_bytes())?;
        if self.filter_splat.is_some() {
            let (sums, direct) = stats.split_at(self.buffers.radiance.size() as usize);
            let (sums, direct): (Vec<[f32; 4]>, Vec<[f32; 4]>) =
                (bytemuck::pod_collect_to_vec(sums), bytemuck::pod_collect_to_vec(direct));
            return Ok(super::pixel_sums::PixelSums::mean(&sums, Some(&direct), self.frame.width, self.frame.height));
        }
        let stats: Vec<VpStats> = bytemuck::pod_collect_to_vec(&stats[..self.buffers.vp_stats.size() as usize]);
        let (k, spp) = (passes.saturating_sub(self.first_pass).max(1) as f32, self.frame.spp.max(1) as usize);
        let global = self.global_radius_sq.is_some();
        let photons = k * self.frame.photon_count as f32;
        let mut image = Rgb32Image::new(self.frame.width, self.frame.height);
        for (pixel, samples) in image.pixels.iter_mut().zip(stats.chunks(spp)) {
            let mut sum = [0.0f32; 3];
            for st in samples {
                let area = if global { 1.0 } else { std::f32::consts::PI * st.radius * st.radius };
                for (c, sum) in sum.iter_mut().enumerate() {
                    *sum += st.ld[c] / k + st.tau[c] * self.frame.power_total / (photons * area);
                }
            }
            *pixel = sum.map(|v| v / spp as f32).map(|v| if v.is_finite() { v } else { 0.0 });
        }
        Ok(image)
    }
    /// Refuses a state that no render could have left: photons other than those of its passes,
    /// or statistics not finite, or negative where they cannot be.
    fn restore(&mut self, state: &[u8]) -> Result<(), Error> {
        let (passes, photons, bytes) = super::decode_state(state, self.state_bytes())?;
        let corrupt = |what: String| Err(Error::Setting(format!("the saved state is corrupt: {what}")));
        // Each pass since first_pass traced photon_count photons.
        let per_pass = self.frame.photon_count as u64;
        if passes.checked_sub(self.first_pass).map(|k| k as u64 * per_pass) != Some(photons) {
            let first = self.first_pass;
            return corrupt(format!(
                "it holds {passes} passes and {photons} photons, where each pass from pass {first} traces {per_pass}"
            ));
        }
        if self.filter_splat.is_some() {
            let bound = super::filter::splat_weight_bound(&self.frame);
            let place = (self.frame.width, self.frame.row_offset);
            let k = passes - self.first_pass;
            let (sums, direct) = bytes.split_at(self.buffers.radiance.size() as usize);
            super::pixel_sums::check_sums(sums, k, 0.0, Some(bound), place, "sum")?;
            super::pixel_sums::check_sums(direct, k, k.min(1 << 24) as f32, None, place, "direct light's sum")?;
            self.queue.write_buffer(&self.buffers.radiance, 0, sums);
            self.queue.write_buffer(&self.buffers.direct_sums, 0, direct);
            self.restored(passes, photons);
            return Ok(());
        }
        let (stats, tests) = bytes.split_at(self.buffers.vp_stats.size() as usize);
        // The pixel of visible point i, for messages.
        let spp = self.frame.spp.max(1) as usize;
        let pixel = |i: usize| {
            (i / spp % self.frame.width as usize, self.frame.row_offset as usize + i / spp / self.frame.width as usize)
        };
        // tau, N, ld and r: finite and non-negative.
        for (i, st) in stats.chunks_exact(size_of::<VpStats>()).enumerate() {
            let st: VpStats = bytemuck::pod_read_unaligned(st);
            let mut values = st.tau.into_iter().chain([st.n]).chain(st.ld).chain([st.radius]);
            if values.any(|v| !(v.is_finite() && v >= 0.0)) {
                let (x, y) = pixel(i);
                return corrupt(format!(
                    "a visible point of pixel ({x}, {y}) holds {st:?}: each must be finite and non-negative"
                ));
            }
        }
        // The adaptive rule's sums (signed): finite; `shrinking` a flag. (No tests without it.)
        for (i, test) in tests.chunks_exact(size_of::<RadiusTest>()).enumerate() {
            let test: RadiusTest = bytemuck::pod_read_unaligned(test);
            if test.offset_sum.into_iter().chain([test.spread_sum]).any(|v| !v.is_finite()) || test.shrinking > 1 {
                let (x, y) = pixel(i);
                return corrupt(format!("the radius test of a visible point of pixel ({x}, {y}) holds {test:?}"));
            }
        }
        self.queue.write_buffer(&self.buffers.vp_stats, 0, stats);
        if self.adaptive {
            self.queue.write_buffer(&self.buffers.radius_tests, 0, tests);
        }
        self.restored(passes, photons);
        Ok(())
    }

    fn splat_sums(&mut self) -> Result<Option<super::SplatSums>, Error> {
        let Some(_) = &self.filter_splat else { return Ok(None) };
        let camera = read_whole(&self.device, &self.queue, &self.buffers.radiance)?;
        let light = Some(read_whole(&self.device, &self.queue, &self.buffers.direct_sums)?);
        Ok(Some(super::SplatSums { camera, light }))
    }
}
