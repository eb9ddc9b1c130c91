//! Path tracing on the same scene, camera, lights and BSDF code as SPPM, for comparison:
//! naive (`method = "pt"`) or with next-event estimation and MIS (`"pt-nee"`). Each pass adds
//! one sample per pixel (`path_trace`); the image is the running mean, or under a filter wider
//! than the box the ratio of each pixel's filter-weighted sum of its neighbours' samples to
//! their weights' (`filter_splat`; [`super::filter`]).

use super::pixel_sums::{PixelSums, Progress, PIXEL_BYTES};
use super::{Integrator, Part, PartSize, Work};
use crate::error::Error;
use crate::gpu::scene_buffers::{SceneBuffers, SceneData};
use crate::gpu::{Kernel, Resource};
use crate::image_io::Rgb32Image;
use crate::layout::Frame;
use crate::scene::{Method, Scene};
use std::ops::Range;
use std::sync::Arc;
use wgpu::util::DeviceExt;

/// A progressive path tracer, naive or with next-event estimation (`Method::Pt` or
/// `Method::PtNee`): each pass adds one sample per pixel, up to `max_depth` bounces, and the
/// image is the mean of the samples so far. Driven through [`Integrator`].
pub struct PathTracer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    frame: Frame,
    pixel_count: u32,
    path_trace: Kernel,
    group: wgpu::BindGroup,
    /// Under a wide filter ([`Frame::filter_reach`] > 0): the kernel that splats each pass's
    /// samples into the sums, and its bind group.
    filter_splat: Option<(Kernel, wgpu::BindGroup)>,
    /// Camera samples a pass: the renderer's pixels, and the filter's reach in rows beyond them.
    samples: u32,
    /// A pass's camera samples for `filter_splat` (16 bytes where none are splatted).
    camera_samples: wgpu::Buffer,
    /// Passes done, the batch's first, the next part of the pass under way.
    progress: Progress,
    frame_buffer: wgpu::Buffer,
    /// Each pixel's samples summed.
    sums: PixelSums,
    /// [`Integrator::run_pass`]'s submissions in flight.
    submissions: crate::gpu::submissions::Submissions,
    /// What vcm's pilot said, where it chose no light subpaths.
    pilot: super::PilotReport,
    // Kept alive for the bind group.
    _scene: Arc<SceneBuffers>,
}

impl PathTracer {
    /// Set up `scene.render.method` (`Pt` or `PtNee`) for `scene` on the caller's device.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<Self, Error> {
        let data = SceneData::new(scene)?;
        let scene_buffers = Arc::new(SceneBuffers::upload(device, scene, &data)?);
        Self::with_scene_buffers(device, queue, scene, &data, scene_buffers, 0..scene.render.height)
    }

    /// Rows of `scene`'s image whose sums, and whose camera samples with the rows a splatting
    /// filter reaches beyond them, fit in one of this device's storage buffers.
    pub fn max_rows(device: &wgpu::Device, scene: &Scene) -> u32 {
        let pixels = device.limits().max_storage_buffer_binding_size / 16;
        let rows = (pixels / (scene.render.width as u64).max(1)).min(u32::MAX as u64) as u32;
        rows.saturating_sub(2 * scene.render.filter.splat_reach())
    }

    /// Bytes of the renderer's own buffers for a band of `rows` rows of `scene`'s image, as
    /// [`Integrator::gpu_memory`] reports them: the sums per pixel and their read-back copy,
    /// a pass's camera samples under a wide filter (the rows it reaches beyond the band
    /// counted as if inside the image), and the frame.
    pub fn renderer_bytes(scene: &Scene, rows: u32) -> u64 {
        let reach = scene.render.filter.splat_reach();
        let sample_rows = if reach > 0 { rows as u64 + 2 * reach as u64 } else { 0 };
        scene.render.width as u64 * (rows as u64 * 2 + sample_rows) * PIXEL_BYTES + std::mem::size_of::<Frame>() as u64
    }

    /// The path tracer for rows `rows` of the image only, on scene buffers already uploaded
    /// (a band of [`Bands`](super::Bands)); random numbers are keyed by the pixel's place in
    /// the whole image, so the bands give the whole image bit for bit.
    pub(crate) fn with_scene_buffers(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        data: &SceneData,
        scene_buffers: Arc<SceneBuffers>,
        rows: Range<u32>,
    ) -> Result<Self, Error> {
        let r = &scene.render;
        let mut frame = super::band_frame(scene, data, &rows)?;
        frame.filter_reach = r.filter.splat_reach();
        let band_height = frame.height;
        let pixel_count = r.width.checked_mul(band_height).ok_or_else(|| Error::Setting("image too large".into()))?;
        let bytes = pixel_count as u64 * PIXEL_BYTES;
        if bytes > device.limits().max_storage_buffer_binding_size {
            return Err(Error::Setting(format!(
                "{}x{} pixels need more memory than this device's buffers hold; render it in bands of at most {} rows",
                r.width,
                band_height,
                Self::max_rows(device, scene)
            )));
        }
        // vcm here is vcm without light subpaths (light::camera_subpaths_alone): pt-nee on
        // vcm's scene, refused where vcm refuses it.
        if r.method == Method::Vcm {
            super::LightTracer::check_scene(scene)?;
        }
        let nee = matches!(r.method, Method::PtNee | Method::Vcm);

        let mut spec = super::specialization(scene, data);
        spec.constants.push(("PATH_NEE", if nee { 1.0 } else { 0.0 }));
        let path_trace = spec.kernel(device, "path_trace")?;
        // The rows a pass traces: the band's, and under a wide filter those it reaches beyond.
        let (samples, camera_samples) = super::pixel_sums::camera_samples(device, &frame);
        let frame_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&frame),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let sums = PixelSums::new(device, queue, pixel_count, false);
        let mut resources = scene_buffers.resources();
        resources.push(Resource { name: "frame", buffer: &frame_buffer });
        resources.push(Resource { name: "radiance", buffer: &sums.radiance });
        resources.push(Resource { name: "camera_samples", buffer: &camera_samples });
        let group = path_trace.bind_group(device, &resources)?;
        let filter_splat = super::pixel_sums::filter_splat(device, &spec, &frame, &resources)?;
        drop(resources);
        Ok(Self {
            device: device.clone(),
            queue: queue.clone(),
            frame,
            pixel_count,
            path_trace,
            group,
            filter_splat,
            samples,
            camera_samples,
            progress: Progress::default(),
            frame_buffer,
            sums,
            submissions: crate::gpu::submissions::Submissions::new(),
            pilot: Default::default(),
            _scene: scene_buffers,
        })
    }

    /// The path tracer reporting what vcm's pilot said of its choice of no light subpaths and
    /// the seconds it took ([`Integrator::notes`], [`Integrator::setup_seconds`]).
    pub(super) fn reporting(mut self, pilot: super::PilotReport) -> Self {
        self.pilot = pilot;
        self
    }
}

impl Integrator for PathTracer {
    fn run_pass(&mut self) -> Result<(), Error> {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("path_trace") });
        self.record_pass(&mut encoder);
        self.submissions.submit(&self.device, &self.queue, encoder.finish())
    }

    /// The pass's next pixels, at most `size.points` of them; after the last, under a wide
    /// filter, the pass's samples splatted into the sums.
    fn record_pass_part(&mut self, encoder: &mut wgpu::CommandEncoder, size: PartSize) -> Part {
        let (first, end, pass_done) = self.progress.next_part(&mut self.frame, size.points, self.samples);
        super::record_upload(&self.device, &self.queue, encoder, &self.frame_buffer, bytemuck::bytes_of(&self.frame));
        self.path_trace.dispatch(encoder, &self.group, end - first);
        if let (true, Some((kernel, group))) = (pass_done, &self.filter_splat) {
            kernel.dispatch(encoder, group, self.pixel_count);
        }
        Part { work: Work::CameraPaths, items: end - first, pass_done }
    }

    /// The mean of each pixel's samples, as [`Integrator::image`] computes it. Between the
    /// parts of a pass, pixels hold one sample more than others (under a wide filter, the
    /// passes splatted so far).
    fn record_resolve_to_texture(&mut self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) -> Result<(), Error> {
        self.sums.record_resolve_to_texture(encoder, texture, &self.frame, &self.frame_buffer)
    }

    /// Each pixel's sum counts its own samples, so a batch needs only its pass indices.
    fn start_at_pass(&mut self, first: u32) -> Result<(), Error> {
        self.progress.start_at_pass(first)
    }

    fn set_camera(&mut self, camera: &crate::scene::Camera) -> Result<(), Error> {
        super::set_frame_camera(&mut self.frame, camera)?;
        self.reset();
        Ok(())
    }

    /// Start over: no sample in any pixel. The buffer is cleared at the next submission.
    fn reset(&mut self) {
        self.sums.clear();
        self.progress.reset();
    }

    fn passes(&self) -> u32 {
        self.progress.passes
    }

    fn work_per_pass(&self) -> u64 {
        self.pixel_count as u64
    }

    fn work_unit(&self) -> &'static str {
        "samples"
    }

    fn pilot(&self) -> &super::PilotReport {
        &self.pilot
    }

    fn set_pilot(&mut self, report: super::PilotReport) {
        self.pilot = report;
    }

    fn image(&mut self) -> Result<Rgb32Image, Error> {
        self.sums.image(self.frame.width, self.frame.height)
    }
    fn splat_sums(&mut self) -> Result<Option<super::SplatSums>, Error> {
        self.filter_splat.as_ref().map(|_| self.sums.all_sums()).transpose()
    }
    fn gpu_memory(&self) -> super::GpuMemory {
        let samples = self.filter_splat.as_ref().map(|_| ("camera_samples", &self.camera_samples));
        let own = [("frame", &self.frame_buffer)].into_iter().chain(samples).chain(self.sums.buffers());
        super::GpuMemory {
            scene: super::sizes(self._scene.resources().iter().map(|r| (r.name, r.buffer))),
            renderer: super::sizes(own),
        }
    }
    fn state(&mut self) -> Result<Vec<u8>, Error> {
        self.sums.state(self.progress.passes, self.progress.passes as u64 * self.pixel_count as u64)
    }
    fn image_of_state(&self, state: &[u8]) -> Result<Rgb32Image, Error> {
        self.sums.image_of_state(state, self.frame.width, self.frame.height)
    }
    /// Refuses a state that no render could have left: work other than a sample a pixel a pass,
    /// sample counts other than its passes' (or weights out of their range under a wide
    /// filter), or sums not finite or negative.
    fn restore(&mut self, state: &[u8]) -> Result<(), Error> {
        let (width, rows) = (self.frame.width, self.frame.row_offset);
        let weights = self.filter_splat.is_some().then(|| super::filter::splat_weight_bound(&self.frame));
        let passes = self.sums.restore(state, self.progress.first_pass, self.pixel_count as u64, width, rows, weights, false)?;
        self.progress.restored(passes);
        Ok(())
    }
}
