//! sppm-gpu: stochastic progressive photon mapping as WGSL compute kernels on wgpu.
//!
//! A physically based renderer: stochastic progressive photon mapping (SPPM, Hachisuka &
//! Jensen 2009) and two path tracers for comparison, all running as compute kernels on any
//! Vulkan, Metal or DX12 device, including a software one (lavapipe). Scenes are TOML files
//! (format version 1, see docs/guide/scene-format.md); the output is linear RGB radiance, written as OpenEXR
//! or sRGB PNG. The same scene, settings and seed give the same image bit for bit on the same
//! machine: photon flux is summed in fixed point, so the order in which photons arrive does
//! not matter.
//!
//! Each SPPM pass traces one camera path per pixel sample to its first diffuse surface (the
//! visible point), sampling direct light on the way and there (next-event estimation with
//! MIS, the code the path tracer runs), builds a hashed grid over the visible points, traces
//! `photons` photons from the lights and adds the flux of those that have bounced at least
//! once to the visible points within radius, then updates each point's statistics:
//! N' = N + alpha M, r' = r sqrt(N' / (N + M)), tau' = (tau + phi) r'^2 / r^2. After k
//! passes of P photons a pixel's radiance is L = ld / k + tau / (k P pi r^2), ld summing the
//! emitted and direct light the camera paths found. `direct = "photons"` is the original
//! algorithm, photons carrying direct light too.
//!
//! # Modules
//!
//! - [`layout`]: what crosses to the GPU, without wgpu: the `#[repr(C)]` records shared with
//!   the kernels and the feature flags they are specialized on. The scene model and the GPU
//!   code both stand on it.
//! - [`scene`]: the scene format, parsed and validated into world-space triangles and
//!   spheres, materials, textures and lights ([`scene::load`]). No wgpu.
//! - [`accel`]: the BVH over the primitives and the hashed grid over visible points, built on
//!   the host, with host traversal and lookup functions that the kernels mirror.
//! - [`gpu`]: the device ([`gpu::GpuContext`], [`gpu::required_limits`]), the WGSL kernels
//!   and the scene's storage buffers.
//! - [`integrators`]: [`integrators::Sppm`] and [`integrators::PathTracer`], both behind the
//!   progressive [`integrators::Integrator`] trait.
//! - [`image_io`]: [`image_io::Rgb32Image`] and reading and writing it as EXR or PNG.
//! - [`metrics`]: relMSE, RMSE and other comparisons against a reference image.
//! - [`error`]: [`Error`], everything the library can return.
//! - [`pacing`]: how passes reach the device: at most two submissions in flight, short
//!   passes grouped, time judged on completed passes.
//! - [`experiments`]: equal-time comparisons and parameter sweeps behind the project's
//!   reports.
//!
//! # Rendering a scene file
//!
//! Load a scene, make a device, run passes, and write the estimate:
//!
//! ```no_run
//! use std::path::Path;
//! use sppm_gpu::gpu::GpuContext;
//! use sppm_gpu::integrators::Sppm;
//!
//! fn main() -> Result<(), sppm_gpu::Error> {
//!     let scene = sppm_gpu::scene::load(Path::new("scenes/cornell-box.toml"))?;
//!     let gpu = GpuContext::new()?;
//!     let mut sppm = Sppm::new(&gpu.device, &gpu.queue, &scene)?;
//!     for _ in 0..scene.render.iterations {
//!         sppm.run_pass()?;
//!     }
//!     // Linear radiance; reading it back waits for the submitted passes.
//!     let image = sppm.image()?;
//!     sppm_gpu::image_io::write_image(Path::new("cornell-box.png"), &image)?;
//!     Ok(())
//! }
//! ```
//!
//! [`integrators::create`] gives the integrator the scene's `method` asks for, as a
//! `Box<dyn Integrator>`. `run_pass` never has more than [`pacing::MAX_IN_FLIGHT`] of its
//! passes queued on the device: it waits for the oldest first.
//!
//! # Rendering for a time, paced by the device
//!
//! A render loop that keeps a fast GPU busy, puts several short passes into one submission
//! and judges a time limit (or progress, or an interrupt) on the passes the device has
//! *completed* drives the integrator through a [`pacing::Pacer`], as the command line does:
//!
//! ```no_run
//! # fn main() -> Result<(), sppm_gpu::Error> {
//! use sppm_gpu::pacing::{DeviceQueue, Goal, Pacer};
//! # let scene = sppm_gpu::scene::load(std::path::Path::new("scenes/cornell-box.toml"))?;
//! let gpu = sppm_gpu::gpu::GpuContext::new()?;
//! let mut integrator = sppm_gpu::integrators::create(&gpu.device, &gpu.queue, &scene)?;
//! let queue = DeviceQueue::new(integrator.as_mut(), &gpu.device, &gpu.queue);
//! // At most 10,000 passes, none started that would end past 5 s.
//! let mut pacer = Pacer::new(queue, 0, Goal { end_pass: 10_000, time_limit: Some(5.0) });
//! while let Some(done) = pacer.next_completion()? {
//!     println!("{} passes done at {:.2} s", done.passes, done.seconds);
//! }
//! drop(pacer);
//! let image = integrator.image()?;
//! # Ok(())
//! # }
//! ```
//!
//! # Embedding in an application
//!
//! The command line's crates (clap, indicatif, plotters, signal-hook, winit) and the
//! `experiments` module come with the default cargo feature `cli`; an application depends on
//! `sppm-gpu = { ..., default-features = false }` and builds only what the kernels need
//! (wgpu, naga, the scene readers).
//!
//! Every integrator ([`integrators::Sppm`], [`integrators::PathTracer`]) works on the
//! caller's device and records into the caller's command encoder through
//! [`Integrator`](integrators::Integrator):
//! [`record_pass`](integrators::Integrator::record_pass) records a whole pass with no trip to
//! the host, [`record_pass_part`](integrators::Integrator::record_pass_part) a bounded part of
//! one (for an application that must draw a frame every few tens of milliseconds, such as
//! `sppm-gpu view`), and
//! [`record_resolve_to_texture`](integrators::Integrator::record_resolve_to_texture) writes
//! the current estimate into a `width` x `height` `Rgba16Float` or `Rgba32Float` texture with
//! `STORAGE_BINDING` usage (alpha 1), ready to sample or copy in the same submission.
//! [`Sppm::record_resolve_to_buffer`](integrators::Sppm::record_resolve_to_buffer) does the
//! same into a buffer.
//!
//! Device requirements: no features (subgroups and 64-bit atomics are used where the device
//! has them, [`gpu::DeviceCaps`]), and the limits of
//! [`gpu::required_limits`]`(&adapter.limits())` ([`gpu::STORAGE_BUFFERS_NEEDED`] storage buffers per shader stage, the
//! adapter's largest storage buffer binding and buffer size, wgpu's defaults otherwise).
//! [`Sppm::new`](integrators::Sppm::new) checks the device ([`gpu::check_device`]) and returns
//! an error rather than failing validation later.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! # let adapter: wgpu::Adapter = unimplemented!();
//! # let scene = sppm_gpu::scene::load(std::path::Path::new("scenes/cornell-box.toml"))?;
//! // `adapter` is the application's own.
//! let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
//!     required_features: wgpu::Features::empty(),
//!     required_limits: sppm_gpu::gpu::required_limits(&adapter.limits())?,
//!     ..Default::default()
//! }))?;
//! use sppm_gpu::integrators::Integrator;
//! let mut sppm = sppm_gpu::integrators::Sppm::new(&device, &queue, &scene)?;
//! let texture = device.create_texture(&wgpu::TextureDescriptor {
//!     label: Some("sppm estimate"),
//!     size: wgpu::Extent3d { width: scene.render.width, height: scene.render.height, depth_or_array_layers: 1 },
//!     mip_level_count: 1,
//!     sample_count: 1,
//!     dimension: wgpu::TextureDimension::D2,
//!     format: wgpu::TextureFormat::Rgba16Float,
//!     usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
//!     view_formats: &[],
//! });
//!
//! // Each frame: one more pass, then the estimate so far into the texture, in the
//! // application's own encoder alongside its other work.
//! let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
//! sppm.record_pass(&mut encoder);
//! sppm.record_resolve_to_texture(&mut encoder, &texture)?;
//! queue.submit([encoder.finish()]);
//! # Ok(())
//! # }
//! ```
//!
//! [`set_camera`](integrators::Integrator::set_camera) moves the camera and starts over;
//! [`reset`](integrators::Integrator::reset) starts over in place.

#![deny(missing_docs)]

pub mod accel;
pub mod batch;
pub mod checkpoint;
pub mod error;
#[cfg(feature = "cli")]
pub mod experiments;
pub mod gpu;
pub mod image_io;
pub mod integrators;
pub mod layout;
pub mod metrics;
pub mod pacing;
pub mod sampler;
pub mod scene;

pub use error::Error;

/// `println!` for command-line output: where stdout is a pipe whose reader has gone
/// (`sppm-gpu bench | head -1`), the line is dropped instead of the process panicking, so the
/// render and the files it writes still complete.
#[doc(hidden)]
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}
