//! The per-pass constants every integrator uploads ([`Frame`]): the camera, a band's rows,
//! the shutter time, the kernels' specialization, and how a frame reaches the device.

use super::filter::{self, set_pixel_filter};
use super::sppm;
use crate::error::Error;
use crate::layout::Frame;
use crate::scene::{Camera, Scene};

/// Copy `bytes` into `dst` from within `encoder`, through a small buffer that wgpu keeps
/// alive until the commands have run: passes recorded into one encoder each see their own
/// constants. Written with `write_buffer`, not mapped at creation: on a lost device that
/// reports an error instead of panicking.
pub(super) fn record_upload(
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

/// The frame of an integrator over rows `rows` of `scene`'s image: the whole image's camera
/// and settings, the band's height and first row, and the light and ray constants of `data`.
pub(super) fn band_frame(
    scene: &Scene,
    data: &crate::gpu::scene_buffers::SceneData,
    rows: &std::ops::Range<u32>,
) -> Result<Frame, Error> {
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
pub(super) fn specialization(scene: &Scene, data: &crate::gpu::scene_buffers::SceneData) -> crate::gpu::Specialization {
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
        strategies: r.strategies,
        ..camera_frame_for(&scene.camera, r.width, r.height)
    }
}

/// The camera fields of [`Frame`] (and the image size) for `camera` on a `width` x `height`
/// image.
pub fn camera_frame_for(c: &Camera, width: u32, height: u32) -> Frame {
    let (forward, right, up) = c.basis();
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

/// Point `frame`'s camera fields at `camera` (validated), keeping its image size.
pub(super) fn set_frame_camera(frame: &mut Frame, camera: &Camera) -> Result<(), Error> {
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
