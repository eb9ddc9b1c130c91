//! Integrators: SPPM and the path tracers (naive, and with next-event estimation) share the
//! scene, its GPU buffers, the camera, the shutter and the kernels' shared WGSL; each one is
//! driven through [`Integrator`].

pub mod bands;
pub mod filter;
pub mod path;
pub mod sppm;

pub use bands::Bands;
pub use filter::set_pixel_filter;
pub use path::PathTracer;
pub use sppm::{Deposits, Sppm};

use crate::error::Error;
use crate::gpu::scene_buffers::{SceneBuffers, SceneData};
use crate::image_io::Rgb32Image;
use crate::scene::Method;
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
    /// SPPM's gather radii over the visible points (read back); `None` for the path tracers.
    fn radius_stats(&self) -> Result<Option<sppm::RadiusStats>, Error> {
        Ok(None)
    }
}

/// Copy `bytes` into `dst` from within `encoder`, through a small buffer that wgpu keeps
/// alive until the commands have run: passes recorded into one encoder each see their own
/// constants. Written with `write_buffer`, not mapped at creation: on a lost device that
/// reports an error instead of panicking.
fn record_upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    encoder: &mut wgpu::CommandEncoder,
    dst: &wgpu::Buffer,
    bytes: &[u8],
) {
    let upload = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("upload"),
        size: bytes.len() as u64,
        usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    queue.write_buffer(&upload, 0, bytes);
    encoder.copy_buffer_to_buffer(&upload, 0, dst, 0, bytes.len() as u64);
}

/// The bytes of an integrator's state: its pass count and work so far, then one buffer.
fn encode_state(passes: u32, work: u64, buffer: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(12 + buffer.len());
    out.extend_from_slice(&passes.to_le_bytes());
    out.extend_from_slice(&work.to_le_bytes());
    out.extend_from_slice(buffer);
    out
}

/// (passes, work, buffer) of [`encode_state`]'s bytes, the buffer `expected` bytes long.
fn decode_state(state: &[u8], expected: u64) -> Result<(u32, u64, &[u8]), Error> {
    if state.len() as u64 != 12 + expected {
        return Err(Error::Setting(format!(
            "the saved state holds {} bytes where this render needs {}: made for another image size",
            state.len(),
            12 + expected
        )));
    }
    let passes = u32::from_le_bytes(state[0..4].try_into().expect("4 bytes"));
    let work = u64::from_le_bytes(state[4..12].try_into().expect("8 bytes"));
    // The next pass would count past the largest pass count.
    if passes == u32::MAX {
        return Err(Error::Setting(format!("the saved state is corrupt: its pass count {passes} leaves no pass to run")));
    }
    Ok((passes, work, &state[12..]))
}

/// GPU buffers by name and size, split into the scene's (geometry, BVH, materials, lights:
/// proportional to the scene) and the renderer's (per pixel or per visible point).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuMemory {
    /// The scene's buffers, bytes each.
    pub scene: Vec<(String, u64)>,
    /// The renderer's buffers (summed over bands), bytes each.
    pub renderer: Vec<(String, u64)>,
}

impl GpuMemory {
    /// Bytes of the scene's buffers.
    pub fn scene_bytes(&self) -> u64 {
        self.scene.iter().map(|(_, b)| b).sum()
    }
    /// Bytes of the renderer's buffers.
    pub fn renderer_bytes(&self) -> u64 {
        self.renderer.iter().map(|(_, b)| b).sum()
    }
    /// All bytes.
    pub fn total(&self) -> u64 {
        self.scene_bytes() + self.renderer_bytes()
    }
}

/// Names and sizes of `buffers`.
fn sizes<'a>(buffers: impl IntoIterator<Item = (&'a str, &'a wgpu::Buffer)>) -> Vec<(String, u64)> {
    buffers.into_iter().map(|(name, b)| (name.to_string(), b.size())).collect()
}

/// The integrator for `scene.render.method`, on the caller's device.
pub fn create(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<Box<dyn Integrator>, Error> {
    check_device_for(device, scene)?;
    let data = SceneData::new(scene)?;
    let buffers = Arc::new(SceneBuffers::new(device, &data));
    create_on(device, queue, scene, &data, buffers)
}

/// SPPM, and any method in bands, need the device's storage buffers and workgroups
/// ([`crate::gpu::check_device`]): refused before the scene is built.
fn check_device_for(device: &wgpu::Device, scene: &Scene) -> Result<(), Error> {
    if scene.render.method == Method::Sppm || max_rows(device, scene) < scene.render.height {
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
) -> Result<Box<dyn Integrator>, Error> {
    let (rows, height) = (max_rows(device, scene), scene.render.height);
    Ok(match scene.render.method {
        // An image whose per-pixel buffers do not fit in one storage buffer goes in bands.
        _ if rows < height => Box::new(Bands::with_scene_buffers(device, queue, scene, data, buffers, rows)?),
        Method::Sppm => Box::new(Sppm::with_scene_buffers(device, queue, scene, data, buffers, 0..height, Deposits::Auto)?),
        Method::Pt | Method::PtNee => Box::new(PathTracer::with_scene_buffers(device, queue, scene, data, buffers, 0..height)?),
    })
}

/// What a render will take, computed before anything is allocated (see [`memory_need`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryNeed {
    /// The scene's buffers, an upper bound from its primitive, attribute and texel counts.
    pub scene: u64,
    /// The renderer's buffers over all bands, as [`Integrator::gpu_memory`] will report them.
    pub renderer: u64,
    /// Host memory for the image: the estimate read back (16 bytes a pixel), the image
    /// (12) and its encoding for the file (up to 12), 40 bytes a pixel.
    pub host: u64,
}

impl MemoryNeed {
    /// Device memory: the scene's and the renderer's buffers.
    pub fn gpu(&self) -> u64 {
        self.scene + self.renderer
    }
}

/// The memory a render of `scene` on `device` takes, before allocating any of it, so that a
/// render that cannot fit is refused at once rather than killed by the system later.
pub fn memory_need(device: &wgpu::Device, scene: &Scene) -> MemoryNeed {
    let r = &scene.render;
    let rows = max_rows(device, scene).clamp(1, r.height.max(1));
    let bands = (0..r.height).step_by(rows as usize).map(|y0| (y0 + rows).min(r.height) - y0);
    let renderer = bands
        .map(|band| match r.method {
            Method::Sppm => Sppm::renderer_bytes(scene, band, device.limits().max_storage_buffer_binding_size),
            Method::Pt | Method::PtNee => PathTracer::renderer_bytes(scene, band),
        })
        .sum();
    // Per triangle: itself (48), its reference (4), a BVH node at most (32), shading normals
    // (48) and texture coordinates (32); per sphere: itself, a reference and a node. A scene
    // traced through the CWBVH has a node of 80 bytes at most per primitive (every interior
    // node has two children or more) and a copy of each primitive in leaf order (48).
    let attributes: u64 = scene.triangles.iter().map(|t| 48 * t.n.is_some() as u64 + 32 * t.uv.is_some() as u64).sum();
    let primitives = scene.triangles.len() + scene.spheres.len();
    let cwbvh = if crate::gpu::scene_buffers::uses_cwbvh(primitives) { primitives as u64 * (48 + 80 - 32) } else { 0 };
    let texels: u64 = scene.textures.iter().map(|t| 16 * t.width as u64 * t.height as u64).sum();
    let fixed = 64 * (scene.materials.len() + scene.shapes.len() + scene.lights.len() + 64) as u64;
    let scene_bytes = scene.triangles.len() as u64 * 84 + attributes + scene.spheres.len() as u64 * 68 + texels + fixed + cwbvh;
    MemoryNeed { scene: scene_bytes, renderer, host: r.width as u64 * r.height as u64 * 40 }
}

use crate::scene::files::available_memory;

/// Refuse at once a render of `scene` on `device` (of `adapter`) that needs more memory than
/// it can have: `limit` when given (device buffers and host image together), else on a CPU
/// device (whose buffers are host memory) the host's available memory. A render that does not fit would otherwise grow
/// until the system kills it, with nothing written.
pub fn check_memory(device: &wgpu::Device, adapter: &wgpu::AdapterInfo, scene: &Scene, limit: Option<u64>) -> Result<(), Error> {
    let need = memory_need(device, scene);
    let cpu_device = adapter.device_type == wgpu::DeviceType::Cpu;
    let (total, have, source) = match limit {
        Some(limit) => (need.gpu() + need.host, limit, "the --memory-limit"),
        None if cpu_device => match available_memory() {
            Some(available) => {
                (need.gpu() + need.host, available, "the host's available memory (a CPU device's buffers are host memory)")
            }
            None => return Ok(()),
        },
        None => match available_memory() {
            Some(available) => (need.host, available, "the host's available memory"),
            None => return Ok(()),
        },
    };
    if total <= have {
        return Ok(());
    }
    let r = &scene.render;
    let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
    let pixels = (r.width as u64 * r.height as u64).max(1);
    Err(Error::Setting(format!(
        "{}: a {}x{} image (spp {}) needs about {:.1} GiB: {:.1} GiB of device buffers ({} bytes a pixel, the scene's {:.2} GiB \
         included) and {:.1} GiB for the image on the host; that is more than {} ({:.1} GiB). Render it smaller, or raise \
         --memory-limit",
        scene.path.display(),
        r.width,
        r.height,
        r.spp,
        gib(total),
        gib(need.gpu()),
        need.renderer / pixels,
        gib(need.scene),
        gib(need.host),
        source,
        gib(have)
    )))
}

/// Rows of `scene`'s image that one integrator of `scene.render.method` holds on `device`;
/// [`create`] splits taller images into [`Bands`] of this many rows.
pub fn max_rows(device: &wgpu::Device, scene: &Scene) -> u32 {
    match scene.render.method {
        Method::Sppm => Sppm::max_rows(device, scene),
        Method::Pt | Method::PtNee => PathTracer::max_rows(device, scene),
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

use crate::layout::Frame;
use crate::scene::{Camera, Scene};

/// The frame of an integrator over rows `rows` of `scene`'s image: the whole image's camera
/// and settings, the band's height and first row, and the light and ray constants of `data`.
fn band_frame(scene: &Scene, data: &crate::gpu::scene_buffers::SceneData, rows: &std::ops::Range<u32>) -> Result<Frame, Error> {
    let height = scene.render.height;
    if rows.is_empty() || rows.end > height {
        return Err(Error::Setting(format!("rows {rows:?} are not within the image's {height} rows")));
    }
    let mut frame = Frame {
        height: rows.end - rows.start,
        row_offset: rows.start,
        emitter_count: data.emitters.len() as u32,
        ray_epsilon: data.ray_epsilon(),
        power_total: data.power_total,
        direct: (scene.render.direct == crate::scene::DirectLight::Sampled) as u32,
        direct_samples: sppm::direct_samples(&scene.render),
        work_end: u32::MAX,
        ..camera_frame(scene)
    };
    set_pixel_filter(&mut frame, scene.render.filter)?;
    Ok(frame)
}

/// What the tracing kernels of `scene` are compiled for: the features of its `data`, its
/// pixel filter, its sampler and its radius rule.
fn specialization(scene: &Scene, data: &crate::gpu::scene_buffers::SceneData) -> crate::gpu::Specialization {
    let mut spec = crate::gpu::Specialization::of(data);
    spec.constants.extend(filter::pixel_filter_constants(scene.render.filter));
    spec.constants.extend(scene.render.sampler.constants());
    spec.constants.extend(scene.render.radius_rule.constants());
    spec
}

/// The camera part of [`Frame`]: position and the image-plane basis at distance 1
/// (`cam_right` spans half the image width, `cam_up` half its height).
pub fn camera_frame(scene: &Scene) -> Frame {
    let r = &scene.render;
    Frame {
        spp: r.spp,
        seed: r.seed,
        max_depth: r.max_depth,
        alpha: r.alpha,
        ..camera_frame_for(&scene.camera, r.width, r.height)
    }
}

/// The camera fields of [`Frame`] (and the image size) for `camera` on a `width` x `height`
/// image.
pub fn camera_frame_for(c: &Camera, width: u32, height: u32) -> Frame {
    let forward = (c.look_at - c.position).normalize();
    let right = forward.cross(c.up).normalize();
    let up = right.cross(forward);
    let tan_half = (c.fov.to_radians() * 0.5).tan();
    let (min, max) = c.crop.map_or((glam::Vec2::ZERO, glam::Vec2::ONE), |w| (w.min, w.max));
    // The whole film's aspect ratio, of which the image is the window [min, max].
    let extent = max - min;
    let aspect = (width as f32 / extent.x) / (height as f32 / extent.y);
    let (right, up) = (right * tan_half * aspect, up * tan_half);
    // The window's image plane: the film's coordinates sx' = sx (max - min).x + (min + max).x
    // - 1 and sy' = sy (max - min).y + 1 - (min + max).y, in the kernels' sx, sy in [-1, 1]
    // (shared/camera.wgsl), folded into the basis. The forward part stays 1, so a thin lens
    // still focuses on the plane at focus_distance.
    let centre = forward + right * (min.x + max.x - 1.0) + up * (1.0 - min.y - max.y);
    Frame {
        cam_position: c.position.into(),
        lens_radius: c.aperture_radius,
        cam_right: (right * extent.x).into(),
        focus_distance: c.focus_distance,
        cam_up: (up * extent.y).into(),
        width,
        cam_forward: centre.into(),
        height,
        image_height: height,
        ..Frame::default()
    }
}

/// Texel formats the resolve kernels write, by slot: the token replaced in their WGSL.
const RESOLVE_FORMATS: [&str; 2] = ["rgba32float", "rgba16float"];

/// The resolve kernel `name` (a `*_resolve_texture` kernel) for `texture`'s format, from
/// `kernels` (one a format, made when first needed), after checking `texture` as a target for
/// a `width` x `height` image ([`check_resolve_target`]).
fn resolve_kernel<'a>(
    device: &wgpu::Device,
    kernels: &'a mut [Option<crate::gpu::Kernel>; 2],
    name: &'static str,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Result<&'a crate::gpu::Kernel, Error> {
    let slot = check_resolve_target(texture, width, height)?;
    Ok(match &mut kernels[slot] {
        Some(kernel) => kernel,
        empty => empty.insert(crate::gpu::Kernel::specialized(device, name, &[("rgba32float", RESOLVE_FORMATS[slot])], &[])?),
    })
}

/// The slot in [`RESOLVE_FORMATS`] of `texture`, a resolve target for a `width` x `height`
/// image: it must be that size, `Rgba32Float` or `Rgba16Float`, with `STORAGE_BINDING`.
fn check_resolve_target(texture: &wgpu::Texture, width: u32, height: u32) -> Result<usize, Error> {
    let slot = match texture.format() {
        wgpu::TextureFormat::Rgba32Float => 0,
        wgpu::TextureFormat::Rgba16Float => 1,
        f => return Err(Error::Setting(format!("the target texture is {f:?}; use Rgba16Float or Rgba32Float"))),
    };
    let size = texture.size();
    if size.width != width || size.height != height || !texture.usage().contains(wgpu::TextureUsages::STORAGE_BINDING) {
        return Err(Error::Setting(format!(
            "the target texture is {}x{} with usage {:?}; it must be {width}x{height} with STORAGE_BINDING",
            size.width,
            size.height,
            texture.usage(),
        )));
    }
    Ok(slot)
}

/// Point `frame`'s camera fields at `camera` (validated), keeping its image size.
fn set_frame_camera(frame: &mut Frame, camera: &Camera) -> Result<(), Error> {
    crate::scene::validate_camera(camera).map_err(Error::Setting)?;
    let f = camera_frame_for(camera, frame.width, frame.image_height);
    frame.cam_position = f.cam_position;
    frame.lens_radius = f.lens_radius;
    frame.cam_right = f.cam_right;
    frame.focus_distance = f.focus_distance;
    frame.cam_up = f.cam_up;
    frame.cam_forward = f.cam_forward;
    Ok(())
}

/// The shutter time of pass `pass` in [0, 1): the base-2 radical inverse of the pass index
/// (van der Corput), rotated by an offset drawn from the seed (Cranley-Patterson rotation).
/// Any run of passes from the first covers the shutter evenly, so a render stopped early by
/// a time limit still averages over the whole shutter.
pub fn shutter_time(seed: u32, pass: u32) -> f32 {
    let radical_inverse = pass.reverse_bits() as f64 / 4294967296.0;
    // SplitMix-style hash of the seed to an offset in [0, 1).
    let mut z = (seed as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    let offset = (z >> 11) as f64 / (1u64 << 53) as f64;
    let t = (radical_inverse + offset).fract() as f32;
    // Rounding to f32 can give exactly 1.
    t.min(1.0 - f32::EPSILON / 2.0)
}

/// [`create`], with its kernels compiled first by one pass of a tiny copy of `scene` (8x8
/// pixels, at most a thousand photons) sharing its pipelines ([`crate::gpu::share_kernels`]);
/// also the seconds that took. Drivers compile a kernel when it is made (NVIDIA) or first
/// dispatched (lavapipe), so the renderer's own first pass, a time limit and a rate then
/// measure rendering alone.
pub fn create_compiled(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<(Box<dyn Integrator>, f64), Error> {
    crate::gpu::share_kernels(|| {
        let start = std::time::Instant::now();
        check_device_for(device, scene)?;
        // The scene's records depend on its shapes, materials, lights and camera medium, not
        // on the image: one BVH and one upload serve both renderers.
        let data = SceneData::new(scene)?;
        let buffers = Arc::new(SceneBuffers::new(device, &data));
        let mut tiny = scene.clone();
        let r = &mut tiny.render;
        (r.width, r.height, r.photons, r.iterations, r.time_limit) = (8, 8, r.photons.min(1024), 1, None);
        let mut warm_up = create_on(device, queue, &tiny, &data, buffers.clone())?;
        warm_up.run_pass()?;
        warm_up.image()?;
        let seconds = start.elapsed().as_secs_f64();
        Ok((create_on(device, queue, scene, &data, buffers)?, seconds))
    })
}
