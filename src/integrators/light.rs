//! Light tracing (`method = "lt"`): light subpaths from the emitters, each vertex joined to
//! the camera and splatted into the pixels it lands on (`shaders/light_trace.wgsl`), then
//! added to per-pixel sums as one estimate of the image a pass (`splat_accumulate`). The
//! light half of the bidirectional family (Veach 1997 ch. 10; SmallVCM's light tracing mode):
//! it finds caustics seen directly, which a path tracer cannot, and the light arriving at the
//! camera through nothing but diffuse surfaces, as a path tracer does.
//!
//! Bidirectional path tracing (`method = "bpt"`) is the same light pass asked to keep its
//! subpaths' vertices (`shaders/shared/light_vertex.wgsl`) and MIS quantities, followed by a
//! camera pass (`shaders/bidir_camera.wgsl`) whose subpaths connect to them, every strategy
//! weighted by the balance heuristic (`shaders/shared/vcm.wgsl`, SmallVCM's recursive form).
//! Vertex connection and merging (`method = "vcm"`) adds merging: the light vertices are also
//! points of the pass's radius, listed in a hashed grid by SPPM's grid kernels, and a camera
//! subpath's first two diffuse vertices merge with those within the radius, weighted with the
//! other strategies by the power heuristic.

use super::pixel_sums::{PixelSums, Progress, PIXEL_BYTES};
use super::{Integrator, Part, PartSize, Work};
use crate::error::Error;
use crate::gpu::scene_buffers::{storage_buffer, zeroed_buffer, SceneBuffers, SceneData, STORAGE_USAGE};
use crate::gpu::{Kernel, Resource};
use crate::image_io::Rgb32Image;
use crate::layout::{Frame, GridParams, GridScene, VisiblePoint, WORK_COUNTS};
use crate::scene::{Method, RenderSettings, Scene};
use std::ops::Range;
use std::sync::Arc;
use wgpu::util::DeviceExt;

/// Bytes of a pixel's splats: r, g, b in 32.32 fixed point (`SPLAT_STRIDE` words in
/// `shaders/shared/splat.wgsl`).
const SPLAT_BYTES: u64 = 24;

/// Bytes of a stored light vertex ([`crate::layout::LightVertex`]).
pub const LIGHT_VERTEX_BYTES: u64 = size_of::<crate::layout::LightVertex>() as u64;

/// Bytes the light-vertex store of bpt may take at most: a pass has one light subpath a pixel
/// where `max_depth` vertices of each fit, fewer (pixels then share them) where not.
pub const LIGHT_VERTEX_BUDGET: u64 = 256 << 20;

/// Pixels for each light subpath of a bpt or vcm pass unless `light_paths` says otherwise.
/// Light subpaths cost as much as camera subpaths, and on the diffuse canonical scenes the
/// strategies they feed (light tracing, merging) pay less than the camera's: at one for 16
/// pixels vcm's error times CPU time at 128x128 was 1.5x to 2.7x lower than at one a pixel
/// on cornell-box, cornell-glossy, cornell-spheres and veach-bidir (BENCHMARKS.md "VCM").
pub const PIXELS_PER_LIGHT_PATH: u32 = 16;

/// Pixels for each light subpath of a vcm pass that merges without connecting (a connect
/// share of 0, as vcm's pilot chooses where merging pays most) unless `light_paths` says
/// otherwise: merging alone is SPPM's estimate weighed against next-event estimation and
/// light tracing, and like SPPM's it pays for more light subpaths. At 30 s on the two cores,
/// one for 4 pixels against one for 16: cornell-glossy 6.46e-4 against 7.23e-4, cornell-skylight
/// 2.78e-3 against 4.29e-3, cornell-spheres 1.42e-3 against 1.43e-3, Mitsuba's box.xml 1.86e-4
/// against 1.96e-4 (BENCHMARKS.md "VCM").
pub const PIXELS_PER_LIGHT_PATH_MERGING: u32 = 4;

/// Light subpaths a pass of the render `r`, within `limit` bytes a buffer: lt one a pixel
/// (of the whole image); bpt and vcm `light_paths`, or one for every
/// [`PIXELS_PER_LIGHT_PATH`] pixels ([`PIXELS_PER_LIGHT_PATH_MERGING`] for vcm merging
/// without connecting), at most as many as the light-vertex store holds ([`store_slots`] for
/// `vertices` kept a subpath on average, `None` for every subpath at full depth) within one
/// buffer of `limit` bytes (at least one but for vcm's `light_paths = 0`).
pub fn light_paths(r: &RenderSettings, limit: u64, vertices: Option<f64>) -> Result<u32, Error> {
    let pixels = r
        .width
        .checked_mul(r.height)
        .ok_or_else(|| Error::Setting(format!("{}x{} pixels are more than 2^32 light subpaths a pass", r.width, r.height)))?;
    if !is_bidirectional(r.method) {
        return Ok(pixels);
    }
    if r.light_paths == Some(0) {
        return Ok(0);
    }
    let depth = r.max_depth.max(1) as u64;
    let merging_alone = r.connect_share == Some(0.0) && merges(r);
    let per_path_pixels = if merging_alone { PIXELS_PER_LIGHT_PATH_MERGING } else { PIXELS_PER_LIGHT_PATH };
    let wanted = r.light_paths.unwrap_or((pixels / per_path_pixels).max(1));
    let slots = most_slots(limit);
    // The most subpaths whose slots fit ([`store_slots`] inverted): all at full depth, or as
    // the mean says.
    let at_full_depth = slots / depth;
    let spare = SPARE_SUBPATHS * depth + 1;
    let by_mean = match vertices {
        Some(mean) if slots > spare => ((slots - spare) as f64 / slots_a_subpath(mean)).floor() as u64,
        _ => 0,
    };
    // A light vertex's key, depth times subpaths, fits 32 bits (`light_vertex_key`).
    let keys = u32::MAX as u64 / depth;
    Ok(at_full_depth.max(by_mean).min(keys).clamp(1, wanted as u64) as u32)
}

/// Light-vertex slots the buffers hold within `limit` bytes a buffer: the store at most
/// [`LIGHT_VERTEX_BUDGET`] bytes. Its vertex is the largest part a slot has in any buffer (vcm's
/// point and merge entry are smaller), so the store's buffer is the one to fit.
fn most_slots(limit: u64) -> u64 {
    const _: () = assert!(MERGE_ENTRY_BYTES <= LIGHT_VERTEX_BYTES && size_of::<VisiblePoint>() as u64 <= LIGHT_VERTEX_BYTES);
    LIGHT_VERTEX_BUDGET.min(limit) / LIGHT_VERTEX_BYTES
}

/// Light-vertex slots of a pass of `paths` subpaths of at most `depth` stored vertices that keep
/// `vertices` each on average (`None`: each `depth`): twice the mean and one more a subpath,
/// and four subpaths at full depth beyond (a pass of few subpaths), never more than every
/// subpath at full depth. A pass's subpaths take the slots in turn
/// (`shaders/shared/light_vertex.wgsl`); the mean comes from a probe of the render's own light
/// subpaths ([`PROBE_PATHS`]), and at 16,384 subpaths of 3 to 5 vertices the store holds 8 to
/// 11 a subpath where it held `max_depth` (64, or 1,024 for Mitsuba's unbounded depth).
pub fn store_slots(paths: u32, depth: u32, vertices: Option<f64>) -> u64 {
    let (paths, depth) = (paths as u64, depth.max(1) as u64);
    let full = paths * depth;
    match vertices {
        Some(mean) => ((slots_a_subpath(mean) * paths as f64).ceil() as u64 + SPARE_SUBPATHS * depth).min(full),
        None => full,
    }
}

/// The store's slots a subpath that keeps `mean` vertices on average: twice the mean and one more.
fn slots_a_subpath(mean: f64) -> f64 {
    2.0 * mean + 1.0
}

/// Subpaths at full depth the store holds beyond its slots a subpath ([`store_slots`]).
const SPARE_SUBPATHS: u64 = 4;

/// Light subpaths of the probe that measures how many vertices a subpath of the render keeps:
/// its mean within about 2% (a subpath keeps a geometric-like number, standard deviation about
/// the mean), twice of which the store holds.
pub const PROBE_PATHS: u32 = 4096;

/// Bytes of a light-vertex slot's merge entry: a point in the bucket of its own cell, the
/// entry its position and slot (`merge_order.wgsl`).
const MERGE_ENTRY_BYTES: u64 = 16;

/// Whether the render `r` is vcm without light subpaths (`light_paths = 0`, set or chosen by
/// its pilot): camera subpaths with next-event estimation weighed by the power heuristic, which
/// is pt-nee's estimator (dVCM starts at 0 and no vertex connects or merges, so every weight
/// but next-event estimation's and emission's against each other is 0). It runs pt-nee's
/// kernel ([`super::PathTracer`]): the same image as pt-nee to the bit, without setting up the
/// bidirectional kernels (a pass of either kernel within 8% of the other's, either way by
/// scene: BENCHMARKS.md "VCM").
pub fn camera_subpaths_alone(r: &RenderSettings) -> bool {
    r.method == Method::Vcm && r.light_paths == Some(0)
}

/// Whether `method` keeps light vertices (bpt, vcm).
fn is_bidirectional(method: Method) -> bool {
    matches!(method, Method::Bpt | Method::Vcm)
}

/// The radius of vcm's pass `pass` (from 0): r_1 i^((alpha - 1) / 2) with i = pass + 1
/// (Georgiev et al. 2012, sec. 5.1; Knaus & Zwicker 2011), r_1 the scene's `radius` or SPPM's
/// automatic one.
pub fn vcm_radius(scene: &Scene, pass: u32) -> f32 {
    let r1 = scene.render.radius.unwrap_or_else(|| super::sppm::auto_radius(scene)) as f64;
    (r1 * ((pass as f64 + 1.0).powf(0.5 * (scene.render.alpha as f64 - 1.0)))) as f32
}

/// vcm's hashed grid of light vertices: SPPM's grid kernels over the light vertices' slots,
/// each vertex listed in the bucket of its own cell (`LISTS_OWN_CELL`), where a merge looks it
/// up from the cells its radius reaches (bidir_connect.wgsl).
struct MergeGrid {
    merge_setup: (Kernel, wgpu::BindGroup),
    setup: (Kernel, wgpu::BindGroup),
    count: (Kernel, wgpu::BindGroup),
    scan: (Kernel, wgpu::BindGroup),
    fill: (Kernel, wgpu::BindGroup),
    /// Each bucket's entries in a fixed order (bit-exact merging).
    order: (Kernel, wgpu::BindGroup),
}

/// A progressive light tracer: each pass traces one light subpath per pixel of the image and
/// adds the pass's splats to each pixel's sums. Driven through [`Integrator`].
pub struct LightTracer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    frame: Frame,
    pixel_count: u32,
    light_trace: Kernel,
    trace_group: wgpu::BindGroup,
    /// bpt's and vcm's camera pass and its bindings.
    bidir_camera: Option<(Kernel, wgpu::BindGroup)>,
    /// bpt and vcm under a wide filter ([`Frame::filter_reach`] > 0): the kernel that splats
    /// each pass's camera samples into the sums, and its bind group.
    filter_splat: Option<(Kernel, wgpu::BindGroup)>,
    /// Camera samples a pass: the renderer's pixels, and the filter's reach in rows beyond them.
    samples: u32,
    /// A pass's camera samples for `filter_splat` (16 bytes where none are splatted).
    camera_samples: wgpu::Buffer,
    /// vcm's grid of light vertices.
    merge_grid: Option<MergeGrid>,
    /// The scene, for vcm's radius of each pass.
    scene: Scene,
    splat_accumulate: Kernel,
    accumulate_group: wgpu::BindGroup,
    /// Passes done, the batch's first, the next part of the pass under way.
    progress: Progress,
    frame_buffer: wgpu::Buffer,
    splat: wgpu::Buffer,
    /// bpt's and vcm's light vertices (one for lt, which keeps none).
    store: Store,
    /// vcm's grid: its points (one a light-vertex slot), parameters and lists (a word each
    /// otherwise).
    grid_buffers: Vec<(&'static str, wgpu::Buffer)>,
    /// What the kernels did, counted in a pass of vcm's pilot ([`WORK_COUNTS`] words).
    work_counts: wgpu::Buffer,
    /// What vcm's pilot said of its choice for this render.
    pilot: super::PilotReport,
    /// The vertices a light subpath keeps on average, by the probe (bpt, vcm).
    vertices: Option<f64>,
    sums: PixelSums,
    /// [`Integrator::run_pass`]'s submissions in flight.
    submissions: crate::gpu::submissions::Submissions,
    // Kept alive for the bind groups.
    _scene: Arc<SceneBuffers>,
}

impl LightTracer {
    /// Rows of `scene`'s image whose splats, and under a splatting filter whose camera samples
    /// with the rows the filter reaches beyond them, fit in one of this device's storage buffers.
    pub fn max_rows(device: &wgpu::Device, scene: &Scene) -> u32 {
        let limit = device.limits().max_storage_buffer_binding_size;
        let width = (scene.render.width as u64).max(1);
        let rows = (limit / SPLAT_BYTES / width).min(u32::MAX as u64) as u32;
        match splat_reach_of(&scene.render) {
            0 => rows,
            reach => rows.min(((limit / PIXEL_BYTES / width).min(u32::MAX as u64) as u32).saturating_sub(2 * reach)),
        }
    }

    /// Bytes of the renderer's own buffers for a band of `rows` rows of `scene`'s image, as
    /// [`Integrator::gpu_memory`] reports them: the sums per pixel and their read-back copy, the
    /// splats, under a splatting filter the light sums and their copy and a pass's camera
    /// samples (the rows it reaches beyond the band counted as if inside the image), and the
    /// frame.
    pub fn renderer_bytes(scene: &Scene, rows: u32) -> u64 {
        let r = &scene.render;
        // The store as large as it may be: its slots are sized by a probe after this estimate
        // ([`store_slots`]), no more than every subpath at full depth or the budget hold.
        let store = match light_paths(r, u64::MAX, Some(0.0)) {
            Ok(n) if is_bidirectional(r.method) => {
                let slots = store_slots(n, r.max_depth, None).min(most_slots(u64::MAX));
                slots * (LIGHT_VERTEX_BYTES + merge_bytes(scene)) + 4 * n as u64 + 8
            }
            _ => 8,
        };
        let splatted = match splat_reach_of(r) {
            0 => 0,
            reach => (2 * rows as u64 + rows as u64 + 2 * reach as u64) * PIXEL_BYTES,
        };
        r.width as u64 * (rows as u64 * (2 * PIXEL_BYTES + SPLAT_BYTES) + splatted) + size_of::<Frame>() as u64 + store
    }

    /// What a light tracer (or bpt, vcm) cannot render of `scene`, as an error naming it:
    /// participating media, and for lt an environment light (seen directly only by camera
    /// paths, which bpt and vcm trace).
    pub fn check_scene(scene: &Scene) -> Result<(), Error> {
        let method = crate::scene::Named::name(scene.render.method);
        let refuse =
            |what: String| Err(Error::Setting(format!("{}: method {method} {what}; use pt-nee or sppm", scene.path.display())));
        if let Some(m) = scene.media.first() {
            return refuse(format!("does not render participating media yet (medium {:?})", m.name));
        }
        if scene.render.method == Method::Lt && scene.lights.iter().any(|l| l.kind.is_environment()) {
            return refuse("cannot show an environment light seen directly".into());
        }
        let r = &scene.render;
        if r.light_paths == Some(0) && is_bidirectional(r.method) {
            let file = scene.path.display();
            if r.method != Method::Vcm {
                return Err(Error::Setting(format!(
                    "{file}: render.light_paths = 0: method {method} needs light subpaths to connect to (vcm takes 0: camera \
                     subpaths alone)"
                )));
            }
            for (key, share) in [("connect_share", r.connect_share), ("merge_share", r.merge_share)] {
                if let Some(share) = share.filter(|&s| s > 0.0) {
                    return Err(Error::Setting(format!(
                        "{file}: render.light_paths = 0 leaves vcm no light subpath to join, but render.{key} is {share}: \
                         set it to 0, or light_paths above 0"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The light tracer for rows `rows` of the image, on scene buffers already uploaded; random
    /// numbers are keyed by the subpath's index, and every band traces all of them, so bands
    /// give the whole image bit for bit.
    pub(crate) fn with_scene_buffers(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        data: &SceneData,
        scene_buffers: Arc<SceneBuffers>,
        rows: Range<u32>,
    ) -> Result<Self, Error> {
        Self::build(device, queue, scene, data, scene_buffers, rows, merges(&scene.render))
    }

    /// The light tracer of a scene whose shares vcm's pilot chose (`integrators::shares`),
    /// reporting what the pilot says of its choice and the seconds it took, `pilot`
    /// ([`Integrator::notes`], [`Integrator::setup_seconds`]). Its kernels are the
    /// pilot's, which merge where the share says so: a merge share of 0 chosen leaves them
    /// (and the grid's buffers) as they are rather than compiling others within the render's time.
    pub(super) fn with_pilot(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        data: &SceneData,
        scene_buffers: Arc<SceneBuffers>,
        pilot: super::PilotReport,
    ) -> Result<Self, Error> {
        let mut tracer = Self::build(device, queue, scene, data, scene_buffers, 0..scene.render.height, true)?;
        tracer.pilot = pilot;
        Ok(tracer)
    }

    /// [`LightTracer::with_scene_buffers`], its kernels merging where `merge` (vcm).
    fn build(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        data: &SceneData,
        scene_buffers: Arc<SceneBuffers>,
        rows: Range<u32>,
        merge: bool,
    ) -> Result<Self, Error> {
        Self::check_scene(scene)?;
        let r = &scene.render;
        let mut frame = super::band_frame(scene, data, &rows)?;
        let pixel_count = r.width.checked_mul(frame.height).ok_or_else(|| Error::Setting("image too large".into()))?;
        if pixel_count as u64 * SPLAT_BYTES > device.limits().max_storage_buffer_binding_size {
            return Err(Error::Setting(format!(
                "{}x{} pixels need more memory than this device's buffers hold; render it in bands of at most {} rows",
                r.width,
                frame.height,
                Self::max_rows(device, scene)
            )));
        }
        let limit = device.limits().max_storage_buffer_binding_size;
        // The shares of camera vertices that connect and merge (shaders/shared/bidir.wgsl).
        let shares = Shares::of(r);
        (frame.connect_share, frame.merge_share) = (shares.connect, shares.merge);
        let bidir = is_bidirectional(r.method);
        // An environment's light subpaths aimed at what the camera sees, at SPPM's share
        // (`environment_light_aim` in shaders/shared/emitter/environment.wgsl).
        if bidir && scene.lights.iter().any(|l| l.kind.is_environment()) {
            frame.env_aim = super::sppm::ENV_AIM;
        }
        let merge = merge && r.method == Method::Vcm;
        // bpt's and vcm's camera samples splatted through a wide filter (lt has none).
        frame.filter_reach = splat_reach_of(r);
        let (samples, camera_samples) = super::pixel_sums::camera_samples(device, &frame);

        let mut spec = super::specialization(scene, data);
        spec.constants.push(("BIDIR", if bidir { 1.0 } else { 0.0 }));
        spec.constants.push(("VCM_MERGE", if merge { 1.0 } else { 0.0 }));
        // vcm weighs its strategies by the power heuristic, bpt by the balance heuristic
        // (shaders/shared/vcm.wgsl's `mis`).
        spec.constants.push(("MIS_POWER", if r.method == Method::Vcm { 1.0 } else { 0.0 }));
        let light_trace = spec.kernel(device, "light_trace")?;
        let splat_accumulate = Kernel::new(device, "splat_accumulate")?;
        let frame_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&frame),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let splat = storage_buffer(device, "splat", &vec![0u32; pixel_count as usize * (SPLAT_BYTES / 4) as usize]);
        let sums = PixelSums::new(device, queue, pixel_count, frame.filter_reach > 0);
        let work_counts = storage_buffer(device, "work_counts", &[0u32; WORK_COUNTS as usize]);
        let own = Own {
            frame: &frame_buffer,
            splat: &splat,
            radiance: &sums.radiance,
            light_sums: sums.light_sums(),
            camera_samples: &camera_samples,
            work_counts: &work_counts,
        };
        // bpt and vcm: as many light subpaths as their vertices fit the store, by the mean a
        // probe of the render's own subpaths keeps; lt one a pixel of the whole image.
        let vertices = if bidir {
            Some(probe_vertices(device, queue, &light_trace, &frame, scene, data, &scene_buffers, &own)?)
        } else {
            None
        };
        frame.photon_count = light_paths(r, limit, vertices)?;
        // Room for one subpath at least (vcm may trace none).
        let paths = frame.photon_count.max(1);
        let (slots, paths) = if bidir {
            (store_slots(paths, r.max_depth, vertices).min(most_slots(limit)), paths)
        } else {
            // One vertex: the smallest binding the kernel's declaration takes.
            (1, 1)
        };
        let store = Store::new(device, slots, paths);
        let merge_slots = if merge { slots as u32 } else { 1 };
        frame.vp_count = if merge { merge_slots } else { 0 };
        let grid_buffers = grid_buffers(device, scene, data, merge_slots, paths);
        let resources = own.resources(&scene_buffers, &store, &grid_buffers);
        let trace_group = light_trace.bind_group(device, &resources)?;
        let merge_grid = if merge {
            let stage = |name: &'static str| -> Result<(Kernel, wgpu::BindGroup), Error> {
                // Each light vertex listed in its own cell's bucket (shared/grid_build.wgsl).
                let kernel = spec.kernel_with(device, name, &[("LISTS_OWN_CELL", 1.0)])?;
                let group = kernel.bind_group(device, &resources)?;
                Ok((kernel, group))
            };
            Some(MergeGrid {
                merge_setup: stage("merge_setup")?,
                setup: stage("grid_setup")?,
                count: stage("grid_count")?,
                scan: stage("grid_scan")?,
                fill: stage("grid_fill")?,
                order: stage("merge_order")?,
            })
        } else {
            None
        };
        let bidir_camera = if bidir {
            let kernel = spec.kernel(device, "bidir_camera")?;
            let group = kernel.bind_group(device, &resources)?;
            Some((kernel, group))
        } else {
            None
        };
        let filter_splat = super::pixel_sums::filter_splat(device, &spec, &frame, &resources)?;
        let accumulate_group = splat_accumulate.bind_group(device, &resources)?;
        drop(resources);
        Ok(Self {
            device: device.clone(),
            queue: queue.clone(),
            frame,
            pixel_count,
            light_trace,
            trace_group,
            bidir_camera,
            filter_splat,
            samples,
            camera_samples,
            merge_grid,
            scene: scene.clone(),
            splat_accumulate,
            accumulate_group,
            progress: Progress::default(),
            frame_buffer,
            splat,
            store,
            grid_buffers,
            work_counts,
            pilot: Default::default(),
            vertices,
            sums,
            submissions: crate::gpu::submissions::Submissions::new(),
            _scene: scene_buffers,
        })
    }

    /// vcm's grid buffer `name`.
    fn grid_buffer(&self, name: &str) -> &wgpu::Buffer {
        &self.grid_buffers.iter().find(|(n, _)| *n == name).expect("a grid buffer").1
    }

    /// Light subpaths a pass.
    fn paths(&self) -> u32 {
        self.frame.photon_count
    }

    /// The vertices a light subpath keeps on average, by the probe that sized the store (bpt,
    /// vcm; `None` for lt).
    pub(super) fn vertices_per_subpath(&self) -> Option<f64> {
        self.vertices
    }

    /// Whether the camera's samples are splatted through a wide filter, the light subpaths'
    /// splats summed apart ([`LightTracer::counted_pass`]'s second sums).
    pub(super) fn splats_apart(&self) -> bool {
        self.filter_splat.is_some()
    }

    /// vcm's radius `radius` at the first pass (its pilot's, set once the probe has said how
    /// many light subpaths a pass takes).
    pub(super) fn set_radius(&mut self, radius: Option<f32>) {
        self.scene.render.radius = radius;
    }

    /// vcm's pilot: one pass at `shares` with `paths` light subpaths (at most as many as the
    /// tracer was built for), its kernels counting their work. Returns the pixel sums after it
    /// (and the light sums, where kept apart) and the counts ([`WORK_COUNTS`] words).
    pub(super) fn counted_pass(&mut self, shares: Shares, paths: u32) -> Result<(super::SplatSums, Vec<u32>), Error> {
        let capacity = (self.store.light_path_first.size() / 4) as u32;
        if paths > capacity {
            return Err(Error::Setting(format!("vcm's pilot: {paths} light subpaths a pass, room for {capacity}")));
        }
        (self.frame.connect_share, self.frame.merge_share, self.frame.count_work) = (shares.connect, shares.merge, 1);
        self.frame.photon_count = paths;
        self.queue.write_buffer(&self.work_counts, 0, bytemuck::cast_slice(&[0u32; WORK_COUNTS as usize]));
        self.run_pass()?;
        let sums = self.sums.all_sums()?;
        let counts = crate::gpu::readback::read_whole(&self.device, &self.queue, &self.work_counts)?;
        self.frame.count_work = 0;
        Ok((sums, counts))
    }
}

impl Integrator for LightTracer {
    fn run_pass(&mut self) -> Result<(), Error> {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("light_trace") });
        self.record_pass(&mut encoder);
        self.submissions.submit(&self.device, &self.queue, encoder.finish())
    }

    /// The pass's next subpaths, at most `size.photons` of them; after the last,
    /// the pass's splats become each pixel's estimate.
    fn record_pass_part(&mut self, encoder: &mut wgpu::CommandEncoder, size: PartSize) -> Part {
        let paths = self.paths();
        let (first, end, pass_done) = self.progress.next_part(&mut self.frame, size.photons, paths);
        if first == 0 {
            // The pass's vertices take the store's slots from the first.
            encoder.clear_buffer(&self.store.light_vertex_count, 0, Some(4));
        }
        if self.merge_grid.is_some() {
            self.frame.global_radius = vcm_radius(&self.scene, self.frame.pass_index);
            if first == 0 {
                // The pass's merge points are appended from the first.
                encoder.clear_buffer(self.grid_buffer("merge_count"), 0, None);
            }
        }
        super::record_upload(&self.device, &self.queue, encoder, &self.frame_buffer, bytemuck::bytes_of(&self.frame));
        self.light_trace.dispatch(encoder, &self.trace_group, end - first);
        // At a merge share of 0 (chosen by vcm's pilot) no camera vertex merges.
        let grid = self.merge_grid.as_ref().filter(|_| self.frame.merge_share > 0.0);
        if let (true, Some(grid)) = (pass_done, grid) {
            // The grid sized by the pass's radius (grid_setup reads it as the largest), then
            // the light vertices listed in its buckets (SPPM's record_point_grid).
            let r = self.frame.global_radius.to_bits();
            super::record_upload(&self.device, &self.queue, encoder, self.grid_buffer("grid_max_radius"), bytemuck::bytes_of(&r));
            grid.merge_setup.0.dispatch_groups(encoder, &grid.merge_setup.1, 1);
            grid.setup.0.dispatch_groups(encoder, &grid.setup.1, 1);
            encoder.clear_buffer(self.grid_buffer("grid_cell_count"), 0, None);
            let args = self.grid_buffer("merge_args");
            grid.count.0.dispatch_indirect(encoder, &grid.count.1, args, 0);
            grid.scan.0.dispatch_groups(encoder, &grid.scan.1, 1);
            grid.fill.0.dispatch_indirect(encoder, &grid.fill.1, args, 0);
            let buckets = (self.grid_buffer("grid_cell_start").size() / 4 - 1) as u32;
            grid.order.0.dispatch(encoder, &grid.order.1, buckets);
        }
        if pass_done {
            if let Some((kernel, group)) = &self.bidir_camera {
                kernel.dispatch(encoder, group, self.samples);
            }
            if let Some((kernel, group)) = &self.filter_splat {
                kernel.dispatch(encoder, group, self.pixel_count);
            }
            // Without light subpaths (vcm's light_paths = 0) no splat: the camera pass counted
            // the sample.
            if paths > 0 {
                self.splat_accumulate.dispatch(encoder, &self.accumulate_group, self.pixel_count);
            }
        }
        Part { work: Work::Photons, items: end - first, pass_done }
    }

    /// The mean of each pixel's estimates over the completed passes.
    fn record_resolve_to_texture(&mut self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) -> Result<(), Error> {
        self.sums.record_resolve_to_texture(encoder, texture, &self.frame, &self.frame_buffer)
    }

    /// Each pass's subpaths are keyed by the pass index, so a batch needs only its indices.
    fn start_at_pass(&mut self, first: u32) -> Result<(), Error> {
        self.progress.start_at_pass(first)
    }

    fn set_camera(&mut self, camera: &crate::scene::Camera) -> Result<(), Error> {
        super::set_frame_camera(&mut self.frame, camera)?;
        self.reset();
        Ok(())
    }

    /// Start over: no estimate in any pixel, and no splat of a pass under way.
    fn reset(&mut self) {
        self.sums.clear();
        self.queue.write_buffer(&self.store.light_vertex_count, 0, &[0u8; 8]);
        self.queue.write_buffer(&self.splat, 0, &vec![0u8; self.splat.size() as usize]);
        self.progress.reset();
    }

    fn passes(&self) -> u32 {
        self.progress.passes
    }

    fn pilot(&self) -> &super::PilotReport {
        &self.pilot
    }

    fn set_pilot(&mut self, report: super::PilotReport) {
        self.pilot = report;
    }

    /// Light vertices the store had no room for: their connections and merges are missing
    /// from the image, which is then darker than it should be where they would have added.
    fn warnings(&mut self) -> Result<Vec<String>, Error> {
        if self.vertices.is_none() {
            // lt keeps no light vertices.
            return Ok(Vec::new());
        }
        let counts: Vec<u32> = crate::gpu::readback::read_whole(&self.device, &self.queue, &self.store.light_vertex_count)?;
        Ok(match counts[1] {
            0 => Vec::new(),
            lost => vec![format!(
                "{lost} light vertices found no room in the light-vertex store ({} slots, sized by a probe of {PROBE_PATHS} \
                 light subpaths): the image misses their connections and merges; set render.light_paths lower",
                self.store.light_vertices.size() / LIGHT_VERTEX_BYTES
            )],
        })
    }

    /// Light subpaths, or without them (vcm's `light_paths = 0`) camera subpaths.
    fn work_per_pass(&self) -> u64 {
        match self.paths() {
            0 => self.pixel_count as u64,
            n => n as u64,
        }
    }

    fn work_unit(&self) -> &'static str {
        match self.paths() {
            0 => "samples",
            _ => "light paths",
        }
    }

    fn image(&mut self) -> Result<Rgb32Image, Error> {
        self.sums.image(self.frame.width, self.frame.height)
    }
    fn splat_sums(&mut self) -> Result<Option<super::SplatSums>, Error> {
        self.filter_splat.as_ref().map(|_| self.sums.all_sums()).transpose()
    }

    fn gpu_memory(&self) -> super::GpuMemory {
        let samples = self.filter_splat.as_ref().map(|_| ("camera_samples", &self.camera_samples));
        let own = [
            ("frame", &self.frame_buffer),
            ("splat", &self.splat),
            ("light_vertices", &self.store.light_vertices),
            ("light_path_first", &self.store.light_path_first),
            ("light_vertex_count", &self.store.light_vertex_count),
        ]
        .into_iter()
        .chain(samples)
        .chain(self.grid_buffers.iter().map(|(name, buffer)| (*name, buffer)))
        .chain(self.sums.buffers());
        super::GpuMemory {
            scene: super::sizes(self._scene.resources().iter().map(|r| (r.name, r.buffer))),
            renderer: super::sizes(own),
        }
    }

    fn state(&mut self) -> Result<Vec<u8>, Error> {
        self.sums.state(self.progress.passes, self.progress.passes as u64 * self.paths() as u64)
    }

    fn image_of_state(&self, state: &[u8]) -> Result<Rgb32Image, Error> {
        self.sums.image_of_state(state, self.frame.width, self.frame.height)
    }

    /// Refuses a state that no render could have left (see the path tracer's).
    fn restore(&mut self, state: &[u8]) -> Result<(), Error> {
        let (width, rows) = (self.frame.width, self.frame.row_offset);
        let weights = self.filter_splat.is_some().then(|| super::filter::splat_weight_bound(&self.frame));
        let light_counted = self.paths() > 0;
        let passes =
            self.sums.restore(state, self.progress.first_pass, self.paths() as u64, width, rows, weights, light_counted)?;
        self.progress.restored(passes);
        Ok(())
    }
}

/// How many pixels either way bpt's and vcm's camera samples are splatted under `r`'s filter
/// ([`crate::scene::PixelFilter::splat_reach`]); 0 for lt, which traces no camera subpaths.
fn splat_reach_of(r: &RenderSettings) -> u32 {
    if is_bidirectional(r.method) {
        r.filter.splat_reach()
    } else {
        0
    }
}

/// Whether the render `r` may merge: vcm with a share of camera vertices that merge above 0,
/// or one its pilot chooses (at 0 it stores no merge points and builds no grid).
fn merges(r: &RenderSettings) -> bool {
    r.method == Method::Vcm && Shares::of(r).merge > 0.0
}

/// The shares of camera vertices that connect to light vertices and that merge with them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shares {
    /// The share that connects, in [0, 1].
    pub connect: f32,
    /// The share that merges, in [0, 1] (vcm).
    pub merge: f32,
}

impl Shares {
    /// The render `r`'s shares as set, 1 where not (0 without light subpaths).
    pub fn of(r: &RenderSettings) -> Self {
        let default = if r.light_paths == Some(0) { 0.0 } else { 1.0 };
        Self { connect: r.connect_share.unwrap_or(default), merge: r.merge_share.unwrap_or(default) }
    }
}

/// Whether vcm's pilot chooses `scene`'s shares (`integrators::shares`): vcm with neither
/// share set, and light subpaths not set to none.
pub fn pilot_chooses_shares(scene: &Scene) -> bool {
    let r = &scene.render;
    r.method == Method::Vcm && r.connect_share.is_none() && r.merge_share.is_none() && r.light_paths != Some(0)
}

/// The light-vertex store (`shaders/shared/light_vertex.wgsl`): its slots, each subpath's
/// first vertex, and the slots taken this pass and the vertices not kept over the render.
struct Store {
    light_vertices: wgpu::Buffer,
    light_path_first: wgpu::Buffer,
    light_vertex_count: wgpu::Buffer,
}

impl Store {
    /// A store of `slots` vertices for `paths` subpaths.
    fn new(device: &wgpu::Device, slots: u64, paths: u32) -> Self {
        Self {
            light_vertices: zeroed_buffer(device, "light_vertices", slots.max(1) * LIGHT_VERTEX_BYTES, STORAGE_USAGE),
            light_path_first: zeroed_buffer(device, "light_path_first", 4 * paths as u64, STORAGE_USAGE),
            light_vertex_count: zeroed_buffer(device, "light_vertex_count", 8, STORAGE_USAGE),
        }
    }
}

/// The light tracer's buffers that a probe and the render share.
struct Own<'a> {
    frame: &'a wgpu::Buffer,
    splat: &'a wgpu::Buffer,
    radiance: &'a wgpu::Buffer,
    light_sums: &'a wgpu::Buffer,
    camera_samples: &'a wgpu::Buffer,
    work_counts: &'a wgpu::Buffer,
}

impl<'a> Own<'a> {
    /// Every buffer the light tracer's kernels bind, by name.
    fn resources(
        &self,
        scene_buffers: &'a SceneBuffers,
        store: &'a Store,
        grid_buffers: &'a [(&'static str, wgpu::Buffer)],
    ) -> Vec<Resource<'a>> {
        let mut resources = scene_buffers.resources();
        resources.push(Resource { name: "frame", buffer: self.frame });
        resources.push(Resource { name: "splat", buffer: self.splat });
        resources.push(Resource { name: "radiance", buffer: self.radiance });
        resources.push(Resource { name: "light_sums", buffer: self.light_sums });
        resources.push(Resource { name: "camera_samples", buffer: self.camera_samples });
        resources.push(Resource { name: "light_vertices", buffer: &store.light_vertices });
        resources.push(Resource { name: "light_path_first", buffer: &store.light_path_first });
        resources.push(Resource { name: "light_vertex_count", buffer: &store.light_vertex_count });
        resources.push(Resource { name: "work_counts", buffer: self.work_counts });
        for (name, buffer) in grid_buffers {
            resources.push(Resource { name, buffer });
        }
        resources
    }
}

/// The mean number of vertices a light subpath of the render keeps: the light pass alone
/// (`light_trace`, the render's kernel) over [`PROBE_PATHS`] subpaths into a store of one slot,
/// which counts the slots they ask for all the same. Its splats are cleared; its numbers are
/// those of the render's first pass, and nothing of it reaches the image.
#[allow(clippy::too_many_arguments)]
fn probe_vertices(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    light_trace: &Kernel,
    frame: &Frame,
    scene: &Scene,
    data: &SceneData,
    scene_buffers: &SceneBuffers,
    own: &Own,
) -> Result<f64, Error> {
    let paths = PROBE_PATHS;
    let probe = Frame { photon_count: paths, work_first: 0, work_end: paths, pass_index: 0, count_work: 0, ..*frame };
    let store = Store::new(device, 1, paths);
    let grid = grid_buffers(device, scene, data, 1, paths);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("light_trace") });
    queue.write_buffer(own.frame, 0, bytemuck::bytes_of(&probe));
    let group = light_trace.bind_group(device, &own.resources(scene_buffers, &store, &grid))?;
    light_trace.dispatch(&mut encoder, &group, paths);
    encoder.clear_buffer(own.splat, 0, None);
    queue.submit([encoder.finish()]);
    let counts: Vec<u32> = crate::gpu::readback::read_whole(device, queue, &store.light_vertex_count)?;
    queue.write_buffer(own.frame, 0, bytemuck::bytes_of(frame));
    Ok(counts[0] as f64 / paths as f64)
}

/// Bytes of vcm's grid a light-vertex slot (its point, its grid entry and its merge entry;
/// the buckets, 4 a subpath, are in the margin).
fn merge_bytes(scene: &Scene) -> u64 {
    if merges(&scene.render) {
        size_of::<VisiblePoint>() as u64 + 4 + MERGE_ENTRY_BYTES + 4
    } else {
        0
    }
}

/// vcm's grid over `slots` light-vertex slots of `paths` subpaths (a word each where `slots`
/// is 1): room for a point a slot and their count, the grid build's dispatch, the box of the
/// scene's surfaces, the pass's radius, the grid's parameters, a count and a start a bucket (4
/// buckets a subpath: a pass stores a few vertices a subpath), and room for each point in the
/// bucket of its own cell, as its index and as its merge entry (position and slot,
/// merge_order.wgsl).
fn grid_buffers(
    device: &wgpu::Device,
    scene: &Scene,
    data: &SceneData,
    slots: u32,
    paths: u32,
) -> Vec<(&'static str, wgpu::Buffer)> {
    let table_size = if slots > 1 { paths.saturating_mul(4).next_power_of_two() } else { 1 };
    let (lo, hi) = super::sppm::grid_bounds(scene, data);
    let grid_scene = GridScene { lo: lo.into(), table_size, hi: hi.into(), _pad: 0 };
    let words = |n: usize| vec![0u32; n.max(1)];
    vec![
        (
            "visible_points",
            zeroed_buffer(device, "visible_points", slots as u64 * size_of::<VisiblePoint>() as u64, STORAGE_USAGE),
        ),
        ("merge_count", storage_buffer(device, "merge_count", &words(1))),
        (
            "merge_args",
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("merge_args"),
                contents: bytemuck::cast_slice(&[0u32; 3]),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            }),
        ),
        ("grid_scene", storage_buffer(device, "grid_scene", bytemuck::bytes_of(&grid_scene))),
        ("grid_max_radius", storage_buffer(device, "grid_max_radius", &words(8))),
        ("grid_params", storage_buffer(device, "grid_params", &words(size_of::<GridParams>() / 4))),
        ("grid_cell_count", storage_buffer(device, "grid_cell_count", &words(table_size as usize))),
        ("grid_cell_start", storage_buffer(device, "grid_cell_start", &words(table_size as usize + 1))),
        ("grid_entries", zeroed_buffer(device, "grid_entries", 4 * slots as u64, STORAGE_USAGE)),
        ("merge_entries", zeroed_buffer(device, "merge_entries", slots as u64 * MERGE_ENTRY_BYTES, STORAGE_USAGE)),
    ]
}
