//! Shared by the GPU tests: a device, or a clear reason there is none.
#![allow(dead_code)]

mod rng;
pub mod scene_text;
pub mod serialized_writer;
#[allow(unused_imports)]
pub use rng::Rng;

use sppm_gpu::gpu::GpuContext;
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators::{Integrator, Sppm};
use sppm_gpu::metrics::{count_negative, count_non_finite};
use sppm_gpu::scene::Scene;
use std::path::{Path, PathBuf};

/// The device of the GPU tests: one for the whole test process, its kernels kept for it
/// (`keep_kernels_in_process`), so that a kernel an earlier test made is not compiled again
/// (a third of a test's time was making kernels, much of it the same ones: BENCHMARKS.md
/// "Tests and CI"). Without an adapter the test is skipped with a message, except under CI
/// (`CI=true`), where a missing adapter fails the test. A test whose device must fail, or
/// must be alone, takes [`own_gpu`].
pub fn gpu() -> Option<GpuContext> {
    static SHARED: std::sync::OnceLock<Option<GpuContext>> = std::sync::OnceLock::new();
    SHARED
        .get_or_init(|| {
            let gpu = own_gpu()?;
            sppm_gpu::gpu::keep_kernels_in_process(&gpu.device);
            Some(gpu)
        })
        .clone()
}

/// A device of the test's own (see [`gpu`]).
pub fn own_gpu() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("CI=true and no GPU adapter: {e}");
            }
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}

/// A test's scratch folder, `sppm-NAME-PID` under the system's temporary folder, made by
/// [`scratch`]: read it as the [`Path`] it derefs to (or [`Scratch::path`]). Dropping it
/// removes the folder and everything in it, except while the thread is panicking
/// (`std::thread::panicking()`): a failing test's files stay there for inspection, and
/// nothing is printed. Keep it alive while anything still reads or writes the folder
/// (`let dir = common::scratch("x");` at the top of the test): the test scratch folders were
/// never removed, and thousands of them piled up in /tmp.
pub struct Scratch(PathBuf);

/// A fresh, empty scratch folder `sppm-NAME-PID` under the system's temporary folder (one an
/// earlier run of the same process id left is removed first), removed again when the
/// returned [`Scratch`] is dropped.
pub fn scratch(name: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("sppm-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    Scratch(dir)
}

impl Scratch {
    /// The folder.
    pub fn path(&self) -> &Path {
        &self.0
    }

    /// The folder, left in place: for a failure that returns rather than panics (a
    /// proptest case's `prop_assert!`), whose files stay as a panicking test's do.
    pub fn keep(self) -> PathBuf {
        let mut this = std::mem::ManuallyDrop::new(self);
        std::mem::take(&mut this.0)
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<std::ffi::OsStr> for Scratch {
    fn as_ref(&self) -> &std::ffi::OsStr {
        self.0.as_os_str()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

pub fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name)
}

pub fn load_scene(name: &str) -> Scene {
    sppm_gpu::scene::load(&scene_path(name)).unwrap_or_else(|e| panic!("{e}"))
}

pub fn reference(name: &str) -> sppm_gpu::image_io::Rgb32Image {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/references").join(name);
    sppm_gpu::image_io::read_exr(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Closest hits of `rays` (origin and t_max, then direction, per ray) through `data` with the
/// `trace_rays` kernel compiled for `constants`: per ray (t, prim_ref as bits, b1, b2).
pub fn trace_rays(
    gpu: &GpuContext,
    data: &sppm_gpu::gpu::scene_buffers::SceneData,
    rays: &[[f32; 4]],
    constants: &[(&str, f64)],
) -> Vec<[f32; 4]> {
    trace_rays_with(gpu, data, rays, constants, &[])
}

/// Kernels only tests run, by name (`tests/shaders/<name>.wgsl`, its entry point named like
/// the file): kept out of the library's kernel table, assembled with the library's shared WGSL.
pub const TEST_KERNELS: &[(&str, &str)] = &[
    ("env_aim_test", include_str!("../../shaders/env_aim_test.wgsl")),
    ("mis_test", include_str!("../../shaders/mis_test.wgsl")),
    ("sampler_test", include_str!("../../shaders/sampler_test.wgsl")),
    ("sobol_test", include_str!("../../shaders/sobol_test.wgsl")),
    ("trace_rays", include_str!("../../shaders/trace_rays.wgsl")),
];

/// The WGSL of test kernel `name`, its imports expanded.
pub fn test_kernel_source(name: &str) -> String {
    let text = TEST_KERNELS.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("no test kernel {name}")).1;
    sppm_gpu::gpu::assemble(text, sppm_gpu::gpu::DeviceCaps::ALL).unwrap()
}

/// Test kernel `name` made on `gpu`'s device, `replace` made in its source and its
/// `constants` set (as `Kernel::specialized` does for the library's kernels).
pub fn test_kernel(
    gpu: &GpuContext,
    name: &'static str,
    replace: &[(&str, &str)],
    constants: &[(&str, f64)],
) -> sppm_gpu::gpu::Kernel {
    let text = TEST_KERNELS.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("no test kernel {name}")).1;
    sppm_gpu::gpu::Kernel::from_wgsl(&gpu.device, name, text, replace, constants).unwrap_or_else(|e| panic!("{e}"))
}

/// [`trace_rays`] with source replacements (the baked traversal of `gpu::baked_bvh`).
pub fn trace_rays_with(
    gpu: &GpuContext,
    data: &sppm_gpu::gpu::scene_buffers::SceneData,
    rays: &[[f32; 4]],
    constants: &[(&str, f64)],
    replace: &[(&str, &str)],
) -> Vec<[f32; 4]> {
    use sppm_gpu::gpu::readback::{read_buffer, staging_buffer};
    use sppm_gpu::gpu::scene_buffers::{storage_buffer, SceneBuffers};
    use sppm_gpu::gpu::Resource;
    use wgpu::util::DeviceExt;
    let kernel = test_kernel(gpu, "trace_rays", replace, constants);
    let buffers = SceneBuffers::new(&gpu.device, data);
    let n = rays.len() / 2;
    let ray_buffer = storage_buffer(&gpu.device, "rays", rays);
    let hits = storage_buffer(&gpu.device, "hits", &vec![[0f32; 4]; n]);
    // The traversal reads the ray offset and shutter time from the frame: a still scene at time 0.
    let frame = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("frame"),
        contents: bytemuck::bytes_of(&sppm_gpu::layout::Frame::default()),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let mut resources = buffers.resources();
    resources.push(Resource { name: "frame", buffer: &frame });
    resources.push(Resource { name: "rays", buffer: &ray_buffer });
    resources.push(Resource { name: "hits", buffer: &hits });
    let group = kernel.bind_group(&gpu.device, &resources).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    kernel.dispatch(&mut encoder, &group, n as u32);
    gpu.queue.submit([encoder.finish()]);
    let staging = staging_buffer(&gpu.device, "hits_staging", hits.size());
    read_buffer(&gpu.device, &gpu.queue, &hits, &staging, hits.size()).unwrap()
}

/// Run `passes` passes of `integrator` and read its image, every pixel finite and not
/// negative.
pub fn run_passes(integrator: &mut dyn Integrator, passes: u32) -> Rgb32Image {
    for _ in 0..passes {
        integrator.run_pass().unwrap();
    }
    let img = integrator.image().unwrap();
    assert_eq!(count_non_finite(&img), 0, "NaN or infinite pixels");
    assert_eq!(count_negative(&img), 0, "negative pixels");
    img
}

/// `scene` rendered by `method` at `size` x `size` for `passes` passes ([`run_passes`]).
pub fn render_at(scene: &Scene, method: sppm_gpu::scene::Method, size: u32, passes: u32) -> Rgb32Image {
    let gpu = gpu().expect("checked by the caller");
    let mut scene = scene.clone();
    scene.render.method = method;
    scene.render.width = size;
    scene.render.height = size;
    let mut integrator = sppm_gpu::integrators::create(&gpu.device, &gpu.queue, &scene).unwrap();
    run_passes(&mut *integrator, passes)
}

/// Mitsuba's test scene `mitsuba/NAME.xml` rendered by `method` for `passes` passes at its own
/// size, against Mitsuba 3's render of it (`tests/references/mitsuba/NAME.exr`), both reduced
/// to 8x8: relMSE below `max_rel_mse` and every channel mean within 1%.
pub fn check_mitsuba_reference(gpu: &GpuContext, name: &str, method: sppm_gpu::scene::Method, passes: u32, max_rel_mse: f64) {
    let mut scene = load_scene(&format!("mitsuba/{name}.xml"));
    scene.render.method = method;
    let mut integrator = sppm_gpu::integrators::create(&gpu.device, &gpu.queue, &scene).unwrap();
    let img = run_passes(&mut *integrator, passes);
    let c = sppm_gpu::metrics::compare(&img, &reference(&format!("mitsuba/{name}.exr")), 8).unwrap();
    eprintln!("{name} {method:?} {passes} passes: {c:?}");
    assert!(c.rel_mse < max_rel_mse, "{name} {method:?}: relMSE {}", c.rel_mse);
    for r in c.mean_ratio {
        assert!((r - 1.0).abs() < 0.01, "{name} {method:?}: channel mean ratios {:?}", c.mean_ratio);
    }
}

/// SPPM on `scene` for its `iterations` passes ([`run_passes`]).
pub fn render_sppm(gpu: &GpuContext, scene: &Scene) -> Rgb32Image {
    let mut sppm = Sppm::new(&gpu.device, &gpu.queue, scene).unwrap_or_else(|e| panic!("{e}"));
    run_passes(&mut sppm, scene.render.iterations)
}
