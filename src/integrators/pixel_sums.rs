//! The per-pixel sums of the integrators whose passes each add one estimate of every pixel
//! (the path tracers and the light tracer): `radiance`, the sum of the estimates (rgb) and
//! their count (w), or under a splatting filter the filter-weighted sum of the camera's
//! samples and their weights' sum ([`super::filter`]) with bpt's and vcm's light subpaths'
//! splats summed apart (`light_sums`), their read-back, their state for checkpoints and
//! batches, and their resolve.

use super::{decode_state, encode_state, resolve_kernel, shutter_time};
use crate::error::Error;
use crate::gpu::readback::{read_buffer, staging_buffer};
use crate::gpu::{Kernel, Resource};
use crate::image_io::Rgb32Image;
use crate::layout::Frame;

/// Bytes of a pixel's sums: a `vec4f`.
pub(super) const PIXEL_BYTES: u64 = 16;

/// A `vec4f` a pixel and its read-back copy.
struct Sums {
    buffer: wgpu::Buffer,
    staging: wgpu::Buffer,
}

impl Sums {
    fn new(device: &wgpu::Device, name: &'static str, staging_name: &'static str, bytes: u64) -> Self {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(name),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { buffer, staging: staging_buffer(device, staging_name, bytes) }
    }
}

/// What an image splatted through a wide filter is made of, per pixel, row-major: the camera
/// samples' filter-weighted sum (rgb) and their weights' sum (w), and for bpt and vcm their
/// light subpaths' splats summed apart (rgb, and the passes in w). The image is the first's
/// ratio plus the second's; batches of one render add both and merge to its image exactly.
/// (Read back where nothing splats, `camera` holds the passes' estimates and their count.)
#[derive(Clone, Debug, PartialEq)]
pub struct SplatSums {
    /// The camera samples' weighted sums and weights.
    pub camera: Vec<[f32; 4]>,
    /// The light subpaths' splats and passes (bpt, vcm), or SPPM's direct light of the camera
    /// paths after a point's first and passes: what is averaged by passes.
    pub light: Option<Vec<[f32; 4]>>,
}

impl SplatSums {
    /// Zeroed sums of `pixels` pixels, light sums too where `light`.
    pub(super) fn zero(pixels: usize, light: bool) -> Self {
        SplatSums { camera: vec![[0.0; 4]; pixels], light: light.then(|| vec![[0.0; 4]; pixels]) }
    }

    /// The state after `passes` passes that did `work`: the camera's sums, then the light's.
    pub(super) fn encode_state(&self, passes: u32, work: u64) -> Vec<u8> {
        let mut bytes: Vec<u8> = bytemuck::cast_slice(&self.camera).to_vec();
        if let Some(light) = &self.light {
            bytes.extend_from_slice(bytemuck::cast_slice(light));
        }
        encode_state(passes, work, &bytes)
    }
}

/// The ratio of a pixel's sums, rgb over w; black where w is 0.
fn ratio(s: &[f32; 4]) -> [f32; 3] {
    let n = s[3];
    if n > 0.0 {
        [s[0] / n, s[1] / n, s[2] / n]
    } else {
        [0.0; 3]
    }
}

/// The sums of `pixel_count` pixels, one estimate a pixel a pass.
pub(super) struct PixelSums {
    device: wgpu::Device,
    queue: wgpu::Queue,
    pixel_count: u32,
    /// `radiance`: `array<vec4f>`, bound by the kernels that add to it.
    pub(super) radiance: wgpu::Buffer,
    staging: wgpu::Buffer,
    /// bpt and vcm under a splatting filter: `light_sums`, the light subpaths' splats a pass
    /// summed apart from the camera's weighted samples (rgb, and the passes in w), for they
    /// are averaged by passes, the camera's by weights. A placeholder of one pixel otherwise.
    light: Sums,
    /// Whether `light` holds light sums.
    has_light: bool,
    /// `path_resolve_texture` for Rgba32Float and Rgba16Float targets, made when first used.
    resolve_texture: [Option<Kernel>; 2],
}

impl PixelSums {
    /// Zeroed sums for `pixel_count` pixels, and light sums apart where `light`.
    pub(super) fn new(device: &wgpu::Device, queue: &wgpu::Queue, pixel_count: u32, light: bool) -> Self {
        let bytes = pixel_count as u64 * PIXEL_BYTES;
        let radiance = Sums::new(device, "radiance", "radiance_staging", bytes);
        let light_bytes = if light { bytes } else { PIXEL_BYTES };
        Self {
            device: device.clone(),
            queue: queue.clone(),
            pixel_count,
            radiance: radiance.buffer,
            staging: radiance.staging,
            light: Sums::new(device, "light_sums", "light_sums_staging", light_bytes),
            has_light: light,
            resolve_texture: [None, None],
        }
    }

    /// The buffers, by name, for [`super::Integrator::gpu_memory`].
    pub(super) fn buffers(&self) -> Vec<(&'static str, &wgpu::Buffer)> {
        let mut buffers = vec![("radiance", &self.radiance), ("radiance_staging", &self.staging)];
        if self.has_light {
            buffers.extend([("light_sums", &self.light.buffer), ("light_sums_staging", &self.light.staging)]);
        }
        buffers
    }

    /// The light sums (a placeholder where there are none), for the kernel that adds to them.
    pub(super) fn light_sums(&self) -> &wgpu::Buffer {
        &self.light.buffer
    }

    fn bytes(&self) -> u64 {
        self.pixel_count as u64 * PIXEL_BYTES
    }

    /// Bytes of a state's sums: the camera's, and the light's where kept apart.
    fn state_bytes(&self) -> u64 {
        self.bytes() * if self.has_light { 2 } else { 1 }
    }

    /// The mean of each pixel's estimates (their weighted mean under a splatting filter, plus
    /// the light sums' mean), `width` x `height`; black where none has weight yet.
    pub(super) fn mean(sums: &[[f32; 4]], light: Option<&[[f32; 4]]>, width: u32, height: u32) -> Rgb32Image {
        let mut img = Rgb32Image::new(width, height);
        for (i, (dst, s)) in img.pixels.iter_mut().zip(sums).enumerate() {
            *dst = ratio(s);
            if let Some(light) = light {
                let l = ratio(&light[i]);
                *dst = [dst[0] + l[0], dst[1] + l[1], dst[2] + l[2]];
            }
        }
        img
    }

    /// The image so far, read back (waits for the submitted passes).
    pub(super) fn image(&self, width: u32, height: u32) -> Result<Rgb32Image, Error> {
        let SplatSums { camera, light } = self.all_sums()?;
        Ok(Self::mean(&camera, light.as_deref(), width, height))
    }

    /// Each pixel's sums so far (rgb and the estimates' count, or their weights'), read back
    /// (waits for the submitted passes).
    pub(super) fn sums(&self) -> Result<Vec<[f32; 4]>, Error> {
        Ok(read_buffer(&self.device, &self.queue, &self.radiance, &self.staging, self.bytes())?)
    }

    /// [`PixelSums::sums`] and the light sums where kept apart: the camera's sums and the
    /// light's, as [`SplatSums`] holds them (the camera's then counts where nothing splats).
    pub(super) fn all_sums(&self) -> Result<SplatSums, Error> {
        let light = match self.has_light {
            true => Some(read_buffer(&self.device, &self.queue, &self.light.buffer, &self.light.staging, self.bytes())?),
            false => None,
        };
        Ok(SplatSums { camera: self.sums()?, light })
    }

    /// Record the mean of each pixel's estimates into `texture` (see
    /// [`super::Integrator::record_resolve_to_texture`]); `frame_buffer` holds the image's size.
    pub(super) fn record_resolve_to_texture(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        frame: &Frame,
        frame_buffer: &wgpu::Buffer,
    ) -> Result<(), Error> {
        let kernel =
            resolve_kernel(&self.device, &mut self.resolve_texture, "path_resolve_texture", texture, frame.width, frame.height)?;
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let resources = [
            Resource { name: "frame", buffer: frame_buffer },
            Resource { name: "radiance", buffer: &self.radiance },
            Resource { name: "light_sums", buffer: &self.light.buffer },
        ];
        let group = kernel.bind_group_with_views(&self.device, &resources, &[("out_image", &view)])?;
        kernel.dispatch(encoder, &group, self.pixel_count);
        Ok(())
    }

    /// No estimate in any pixel; the buffers are cleared at the next submission.
    pub(super) fn clear(&self) {
        for buffer in [&self.radiance, &self.light.buffer] {
            self.queue.write_buffer(buffer, 0, &vec![0u8; buffer.size() as usize]);
        }
    }

    /// The state after `passes` passes that did `work` (waits for them).
    pub(super) fn state(&self, passes: u32, work: u64) -> Result<Vec<u8>, Error> {
        Ok(self.all_sums()?.encode_state(passes, work))
    }

    /// The image of a state, on the host.
    pub(super) fn image_of_state(&self, state: &[u8], width: u32, height: u32) -> Result<Rgb32Image, Error> {
        let (_, _, bytes) = decode_state(state, self.state_bytes())?;
        let (sums, light) = bytes.split_at(self.bytes() as usize);
        let light: Option<Vec<[f32; 4]>> = self.has_light.then(|| bytemuck::pod_collect_to_vec(light));
        Ok(Self::mean(&bytemuck::pod_collect_to_vec(sums), light.as_deref(), width, height))
    }

    /// Load a state whose passes from `first_pass` each did `work_per_pass`, after checking
    /// that a render could have left it: work other than that a pass, estimate counts other
    /// than its passes' (under a splatting filter, `weights` a pass's most weight in a pixel:
    /// weights not above 0 and beyond that a pass; light sums whose count is not the passes',
    /// or 0 where `light_counted` is false), or sums not finite or negative are refused.
    /// `width` and `row_offset` name pixels in the message. Returns the state's pass count.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn restore(
        &self,
        state: &[u8],
        first_pass: u32,
        work_per_pass: u64,
        width: u32,
        row_offset: u32,
        weights: Option<f32>,
        light_counted: bool,
    ) -> Result<u32, Error> {
        let (passes, work, bytes) = decode_state(state, self.state_bytes())?;
        let corrupt = |what: String| Err(Error::Setting(format!("the saved state is corrupt: {what}")));
        let Some(k) = passes.checked_sub(first_pass).filter(|_| work == passes as u64 * work_per_pass) else {
            return corrupt(format!(
                "it holds {passes} passes (from pass {first_pass}) and {work} samples of {} pixels",
                self.pixel_count
            ));
        };
        // Each pass adds 1 to every pixel's count, in f32: exact up to 2^24, where it stays.
        let count = k.min(1 << 24) as f32;
        let (sums, light) = bytes.split_at(self.bytes() as usize);
        let parts = [(sums, weights), (light, None)];
        for (part, (sums, weights)) in parts.into_iter().enumerate().take(if self.has_light { 2 } else { 1 }) {
            let count = if part == 1 && !light_counted { 0.0 } else { count };
            let what = if part == 1 { "light subpaths' sum" } else { "sum" };
            check_sums(sums, k, count, weights, (width, row_offset), what)?;
        }
        self.queue.write_buffer(&self.radiance, 0, sums);
        if self.has_light {
            self.queue.write_buffer(&self.light.buffer, 0, light);
        }
        Ok(passes)
    }
}

/// Check the sums of a state after `k` passes, a `vec4f` a pixel (`what` in the message): each
/// counts `count` estimates, or under a splatting filter (`weights`, a pass's most weight in a
/// pixel) weights above 0 and at most that a pass (0 before any); radiance finite and not
/// negative. `(width, row_offset)` name the pixels in the message.
pub(super) fn check_sums(
    sums: &[u8],
    k: u32,
    count: f32,
    weights: Option<f32>,
    (width, row_offset): (u32, u32),
    what: &str,
) -> Result<(), Error> {
    for (i, s) in sums.chunks_exact(PIXEL_BYTES as usize).enumerate() {
        let s: [f32; 4] = bytemuck::pod_read_unaligned(s);
        let weight_ok = match weights {
            None => s[3] == count,
            Some(most) => (k == 0 && s[3] == 0.0) || (s[3] > 0.0 && s[3] <= most * k as f32),
        };
        if !weight_ok || s[..3].iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            let (x, y) = (i % width as usize, row_offset as usize + i / width as usize);
            let expected = match weights {
                None => format!("{count} samples"),
                Some(most) => format!("samples of weight above 0 and at most {}", most * k as f32),
            };
            return Err(Error::Setting(format!(
                "the saved state is corrupt: pixel ({x}, {y}) holds the {what} {:?} of {} samples, where {k} passes give \
                 {expected} of finite, non-negative radiance",
                &s[..3],
                s[3]
            )));
        }
    }
    Ok(())
}

/// A pass's camera samples under a splatting filter (`camera_samples`, which `filter_splat`
/// reads): one a pixel of `frame`'s rows and of the rows its filter reaches beyond them
/// within the image (`splat_rows` in `shaders/shared/camera.wgsl`). Returns the samples a
/// pass, `frame`'s pixels where the filter splats nothing, and the buffer, then 16 bytes.
pub(super) fn camera_samples(device: &wgpu::Device, frame: &Frame) -> (u32, wgpu::Buffer) {
    let reach = frame.filter_reach;
    let first = frame.row_offset.saturating_sub(reach);
    let end = (frame.row_offset + frame.height + reach).min(frame.image_height);
    let samples = frame.width * (end - first);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("camera_samples"),
        size: if reach > 0 { samples as u64 * PIXEL_BYTES } else { PIXEL_BYTES },
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    (samples, buffer)
}

/// `filter_splat` and its bind group over `resources` (the frame, the sums and the camera
/// samples) where `frame`'s camera samples are splatted through a wide filter; `None` else.
pub(super) fn filter_splat(
    device: &wgpu::Device,
    spec: &crate::gpu::Specialization,
    frame: &Frame,
    resources: &[Resource],
) -> Result<Option<(Kernel, wgpu::BindGroup)>, Error> {
    if frame.filter_reach == 0 {
        return Ok(None);
    }
    let kernel = spec.kernel(device, "filter_splat")?;
    let group = kernel.bind_group(device, resources)?;
    Ok(Some((kernel, group)))
}

/// Where an integrator of one estimate a pixel a pass stands: the passes recorded, the first
/// pass of its batch ([`super::Integrator::start_at_pass`]) and the first item (pixel or light
/// subpath) of the next part of the pass under way (0: a new pass).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Progress {
    pub(super) passes: u32,
    pub(super) first_pass: u32,
    next: u32,
}

impl Progress {
    /// The next part of the pass, at most `size` of its `total` items: sets `frame`'s pass
    /// index, shutter time and work range, and returns the items and whether they end the pass
    /// (which then counts).
    pub(super) fn next_part(&mut self, frame: &mut Frame, size: u32, total: u32) -> (u32, u32, bool) {
        let first = self.next;
        let end = first.saturating_add(size.max(1)).min(total);
        frame.pass_index = self.passes;
        frame.time = shutter_time(frame.seed, self.passes);
        frame.work_first = first;
        frame.work_end = end;
        self.next = end;
        let pass_done = end == total;
        if pass_done {
            self.next = 0;
            self.passes += 1;
        }
        (first, end, pass_done)
    }

    /// Run passes `first`, `first + 1`, ...: only before any pass.
    pub(super) fn start_at_pass(&mut self, first: u32) -> Result<(), Error> {
        if self.passes != self.first_pass || self.next != 0 {
            return Err(Error::Setting("start_at_pass: passes have run already".into()));
        }
        self.first_pass = first;
        self.passes = first;
        Ok(())
    }

    /// Start over: no pass done, none under way.
    pub(super) fn reset(&mut self) {
        self.next = 0;
        self.passes = self.first_pass;
    }

    /// `passes` done, as a restored state says, none under way.
    pub(super) fn restored(&mut self, passes: u32) {
        self.next = 0;
        self.passes = passes;
    }
}
