//! The embedding API as `examples/embed.rs` uses it, small: an application with its own
//! device interleaves its own compute work with SPPM passes in its own encoders and reads the
//! estimate from its own textures and buffers. Checked against the same renderer driven by
//! `run_pass` and read with `image()`, bit for bit.
//!
//! Like every GPU test, these are skipped without an adapter, except under `CI=true`.

use crate::common;

use sppm_gpu::gpu::readback;
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators::sppm::auto_radius;
use sppm_gpu::integrators::{Integrator, Sppm};
use sppm_gpu::scene::{Camera, Scene};

/// Odd sizes on purpose: texture rows of 40 texels need padding to 256 bytes in a copy.
const WIDTH: u32 = 40;
const HEIGHT: u32 = 30;
const PHOTONS: u32 = 20_000;
const PASSES: u32 = 3;

/// A scene from `scenes/`, reduced.
fn small(name: &str, seed: u32) -> Scene {
    let mut scene = common::load_scene(name);
    scene.render.width = WIDTH;
    scene.render.height = HEIGHT;
    scene.render.photons = PHOTONS;
    scene.render.seed = seed;
    scene
}

/// Skip the test without an adapter, except under CI (the rule of `common::gpu`).
fn no_adapter(e: impl std::fmt::Display) -> Option<(wgpu::Adapter, wgpu::Device, wgpu::Queue)> {
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("CI=true and no GPU adapter: {e}");
    }
    eprintln!("skipping GPU test: {e}");
    None
}

/// The application's own device, as `examples/embed.rs` makes it, with `limits` chosen from
/// the adapter's.
fn app_device(limits: impl FnOnce(&wgpu::Adapter) -> wgpu::Limits) -> Option<(wgpu::Adapter, wgpu::Device, wgpu::Queue)> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::VULKAN | wgpu::Backends::METAL | wgpu::Backends::DX12,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = match pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())) {
        Ok(adapter) => adapter,
        Err(e) => return no_adapter(e),
    };
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("application"),
        required_features: wgpu::Features::empty(),
        required_limits: limits(&adapter),
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .expect("the adapter gives a device with limits within its own");
    Some((adapter, device, queue))
}

fn sppm_device() -> Option<(wgpu::Adapter, wgpu::Device, wgpu::Queue)> {
    app_device(|a| sppm_gpu::gpu::required_limits(&a.limits()).unwrap_or_else(|e| panic!("{e}")))
}

/// The application's own kernel (as in `examples/embed.rs`): adds `i + 1` to element `i`.
struct AppKernel {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    data: wgpu::Buffer,
}

const APP_ELEMENTS: u32 = 1000;

impl AppKernel {
    fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("app kernel"),
            source: wgpu::ShaderSource::Wgsl(
                "@group(0) @binding(0) var<storage, read_write> data: array<u32>;
                 @compute @workgroup_size(64)
                 fn main(@builtin(global_invocation_id) id: vec3u) {
                     if id.x < arrayLength(&data) { data[id.x] += id.x + 1u; }
                 }"
                .into(),
            ),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("app kernel"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let data = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("app data"),
            size: APP_ELEMENTS as u64 * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("app data"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: data.as_entire_binding() }],
        });
        AppKernel { pipeline, group, data }
    }

    fn record(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("app"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(APP_ELEMENTS.div_ceil(64), 1, 1);
    }
}

pub(crate) fn target(device: &wgpu::Device, format: wgpu::TextureFormat, width: u32, height: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("app target"),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

fn read_buffer(device: &wgpu::Device, queue: &wgpu::Queue, buffer: &wgpu::Buffer) -> Vec<u8> {
    readback::read_whole(device, queue, buffer).expect("readback")
}

/// An Rgba32Float or Rgba16Float texture as RGB, and its alpha channel.
fn read_texture(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) -> (Rgb32Image, Vec<f32>) {
    let texels = readback::read_texture(device, queue, texture).expect("texture readback");
    let rgb = Rgb32Image::from_rgba(texture.width(), texture.height(), &texels);
    (rgb, texels.iter().map(|t| t[3]).collect())
}

#[test]
fn f16_decoding() {
    use readback::f16_to_f32;
    assert_eq!(f16_to_f32(0x3c00), 1.0);
    assert_eq!(f16_to_f32(0xc000), -2.0);
    assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
    assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
    assert_eq!(f16_to_f32(0x7bff), 65504.0);
}

fn bits(img: &Rgb32Image) -> Vec<[u32; 3]> {
    img.pixels.iter().map(|p| p.map(f32::to_bits)).collect()
}

fn assert_bit_equal(a: &Rgb32Image, b: &Rgb32Image, what: &str) {
    assert_eq!((a.width, a.height), (b.width, b.height), "{what}: size");
    let first = bits(a).iter().zip(bits(b)).position(|(x, y)| *x != y);
    if let Some(i) = first {
        panic!("{what}: pixel {i} differs: {:?} vs {:?}", a.pixels[i], b.pixels[i]);
    }
}

fn mean(img: &Rgb32Image) -> f64 {
    img.mean().iter().sum::<f64>() / 3.0
}

/// One frame as the example records it: the application's dispatch, then a pass and a
/// resolve of each renderer into its texture, in one encoder, submitted once.
fn frame(device: &wgpu::Device, queue: &wgpu::Queue, app: Option<&AppKernel>, renderers: &mut [(&mut Sppm, &wgpu::Texture)]) {
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
    if let Some(app) = app {
        app.record(&mut encoder);
    }
    for (sppm, texture) in renderers.iter_mut() {
        sppm.record_pass(&mut encoder);
        sppm.record_resolve_to_texture(&mut encoder, texture).unwrap_or_else(|e| panic!("{e}"));
    }
    queue.submit([encoder.finish()]);
}

/// The same renderer driven the simple way: `run_pass` and `image()`.
fn reference(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, passes: u32) -> (Sppm, Rgb32Image) {
    let mut sppm = Sppm::new(device, queue, scene).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..passes {
        sppm.run_pass().unwrap_or_else(|e| panic!("{e}"));
    }
    let image = sppm.image().unwrap_or_else(|e| panic!("{e}"));
    (sppm, image)
}

/// What `examples/embed.rs` does: the application's kernel and two renderers interleaved
/// in the application's encoders, read from its own textures and buffer.
#[test]
fn interleaved_with_the_application_matches_run_pass() {
    let Some((_adapter, device, queue)) = sppm_device() else { return };
    let box_scene = small("cornell-box.toml", 7);
    let spheres_scene = small("cornell-spheres.toml", 3);
    let app = AppKernel::new(&device);
    let mut a = Sppm::new(&device, &queue, &box_scene).unwrap_or_else(|e| panic!("{e}"));
    let mut b = Sppm::new(&device, &queue, &spheres_scene).unwrap_or_else(|e| panic!("{e}"));
    let target_a = target(&device, wgpu::TextureFormat::Rgba32Float, WIDTH, HEIGHT);
    let target_b = target(&device, wgpu::TextureFormat::Rgba32Float, WIDTH, HEIGHT);

    // Before any pass there is nothing to resolve: an error, not a panic.
    let mut encoder = device.create_command_encoder(&Default::default());
    assert!(a.record_resolve_to_texture(&mut encoder, &target_a).is_err());
    drop(encoder);

    for _ in 0..PASSES {
        frame(&device, &queue, Some(&app), &mut [(&mut a, &target_a), (&mut b, &target_b)]);
    }

    // The application's own kernel ran once per frame, in order with ours.
    let data: Vec<u32> = bytemuck::cast_slice(&read_buffer(&device, &queue, &app.data)).to_vec();
    for (i, &x) in data.iter().enumerate() {
        assert_eq!(x, PASSES * (i as u32 + 1), "application data at {i}");
    }

    // Each texture holds exactly what the same renderer gives through run_pass and image().
    let (ref_a, image_a) = reference(&device, &queue, &box_scene, PASSES);
    let (ref_b, image_b) = reference(&device, &queue, &spheres_scene, PASSES);
    let (tex_a, alpha_a) = read_texture(&device, &queue, &target_a);
    let (tex_b, _) = read_texture(&device, &queue, &target_b);
    assert_bit_equal(&tex_a, &image_a, "cornell-box texture vs run_pass");
    assert_bit_equal(&tex_b, &image_b, "cornell-spheres texture vs run_pass");
    assert!(alpha_a.iter().all(|&x| x == 1.0), "alpha is 1");
    // Two renderers on one device do not disturb each other, and really render.
    assert_ne!(bits(&tex_a), bits(&tex_b));
    for img in [&tex_a, &tex_b] {
        assert!(img.pixels.iter().flatten().all(|x| x.is_finite() && *x >= 0.0));
        assert!(mean(img) > 0.05, "mean {}", mean(img));
    }

    // Counters and radius statistics, as the caller reads them.
    assert_eq!((a.passes(), a.photons_traced()), (PASSES, PASSES as u64 * PHOTONS as u64));
    assert_eq!((b.passes(), b.photons_traced()), (ref_b.passes(), ref_b.photons_traced()));
    let stats = a.radius_stats().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(stats, ref_a.radius_stats().unwrap_or_else(|e| panic!("{e}")));
    assert!(0.0 < stats.min && stats.min <= stats.mean && stats.mean <= stats.max, "{stats:?}");
    assert!(stats.max <= a.initial_radius() && stats.min < a.initial_radius(), "{stats:?}: radii shrink");

    // The same estimate into an Rgba16Float texture: half precision of the same values.
    let half = target(&device, wgpu::TextureFormat::Rgba16Float, WIDTH, HEIGHT);
    // And into the application's buffer at an offset.
    let offset = 256;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("app image"),
        size: offset + WIDTH as u64 * HEIGHT as u64 * 16,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    a.record_resolve_to_texture(&mut encoder, &half).unwrap_or_else(|e| panic!("{e}"));
    a.record_resolve_to_buffer(&mut encoder, &buffer, offset).unwrap_or_else(|e| panic!("{e}"));
    queue.submit([encoder.finish()]);
    let (tex_half, alpha_half) = read_texture(&device, &queue, &half);
    for (i, (h, f)) in tex_half.pixels.iter().zip(&image_a.pixels).enumerate() {
        for c in 0..3 {
            let tolerance = 1e-3 * f[c].abs() + 1e-7;
            assert!((h[c] - f[c]).abs() <= tolerance, "rgba16float pixel {i} channel {c}: {} vs {}", h[c], f[c]);
        }
    }
    assert!(alpha_half.iter().all(|&x| x == 1.0));
    let rgba: Vec<[f32; 4]> = bytemuck::cast_slice(&read_buffer(&device, &queue, &buffer)[offset as usize..]).to_vec();
    let from_buffer = Rgb32Image::from_fn(WIDTH, HEIGHT, |x, y| {
        let p = rgba[(y * WIDTH + x) as usize];
        [p[0], p[1], p[2]]
    });
    assert_bit_equal(&from_buffer, &image_a, "buffer resolve vs run_pass");

    // Targets the renderer cannot write are errors, not panics.
    let mut encoder = device.create_command_encoder(&Default::default());
    let wrong_format = target(&device, wgpu::TextureFormat::Rgba8Unorm, WIDTH, HEIGHT);
    let err = a.record_resolve_to_texture(&mut encoder, &wrong_format).expect_err("Rgba8Unorm");
    assert!(err.to_string().contains("Rgba32Float"), "{err}");
    let wrong_size = target(&device, wgpu::TextureFormat::Rgba32Float, WIDTH + 1, HEIGHT);
    assert!(a.record_resolve_to_texture(&mut encoder, &wrong_size).is_err());
    let small_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 16,
        usage: wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    assert!(a.record_resolve_to_buffer(&mut encoder, &small_buffer, 0).is_err());
    queue.submit([encoder.finish()]);
}

/// `reset` starts over with the same random numbers; `set_camera` moves the view and gives
/// what a renderer made for that camera gives.
#[test]
fn reset_and_set_camera_between_passes() {
    let Some((_adapter, device, queue)) = sppm_device() else { return };
    let mut scene = small("cornell-box.toml", 7);
    // The initial radius stays what it was made with when the camera moves; fix it so that
    // a renderer made for the moved camera starts from the same one.
    scene.render.radius = Some(auto_radius(&scene));
    let app = AppKernel::new(&device);
    let mut sppm = Sppm::new(&device, &queue, &scene).unwrap_or_else(|e| panic!("{e}"));
    let texture = target(&device, wgpu::TextureFormat::Rgba32Float, WIDTH, HEIGHT);
    let render = |sppm: &mut Sppm| {
        for _ in 0..PASSES {
            frame(&device, &queue, Some(&app), &mut [(&mut *sppm, &texture)]);
        }
        read_texture(&device, &queue, &texture).0
    };

    let first = render(&mut sppm);
    sppm.reset();
    assert_eq!((sppm.passes(), sppm.photons_traced()), (0, 0));
    let again = render(&mut sppm);
    assert_bit_equal(&again, &first, "after reset");
    assert_eq!(sppm.passes(), PASSES);

    // A reset between passes recorded into one encoder and submitted later works too:
    // passes recorded after it start over.
    sppm.reset();
    let mut encoder = device.create_command_encoder(&Default::default());
    for _ in 0..PASSES {
        sppm.record_pass(&mut encoder);
    }
    sppm.record_resolve_to_texture(&mut encoder, &texture).unwrap_or_else(|e| panic!("{e}"));
    queue.submit([encoder.finish()]);
    assert_bit_equal(&read_texture(&device, &queue, &texture).0, &first, "passes in one encoder");

    let c = &scene.camera;
    let moved = Camera { position: c.position + glam::Vec3::new(0.6, -0.2, 0.0), ..c.clone() };
    sppm.set_camera(&moved).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sppm.passes(), 0);
    let turned = render(&mut sppm);
    assert_ne!(bits(&turned), bits(&first), "the camera moved");
    let (_, expected) = reference(&device, &queue, &Scene { camera: moved, ..scene.clone() }, PASSES);
    assert_bit_equal(&turned, &expected, "set_camera vs a renderer made for that camera");

    // A camera the loader would refuse is an error, and the renderer is left as it was.
    let bad = Camera { look_at: c.position, ..c.clone() };
    assert!(sppm.set_camera(&bad).is_err());
    assert_eq!(sppm.passes(), PASSES);
}

/// A device made with wgpu's default limits (8 storage buffers per stage) is refused with
/// an error that says what to do, not a validation panic.
#[test]
fn a_device_with_default_limits_is_refused() {
    let Some((adapter, device, queue)) = app_device(|_| wgpu::Limits::default()) else { return };
    assert_eq!(device.limits().max_storage_buffers_per_shader_stage, 8);
    let scene = small("cornell-box.toml", 7);
    let err = match Sppm::new(&device, &queue, &scene) {
        Ok(_) => panic!("Sppm::new accepted a device with 8 storage buffers per stage"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("max_storage_buffers_per_shader_stage = 8"), "{err}");
    assert!(err.contains("required_limits"), "{err}");
    // And `required_limits` asks for what the renderer says it needs.
    let limits = sppm_gpu::gpu::required_limits(&adapter.limits()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(limits.max_storage_buffers_per_shader_stage, sppm_gpu::gpu::STORAGE_BUFFERS_NEEDED);
}

/// Where the device has subgroups, the photon pass's lanes share the deposits they make at
/// once (`shaders/shared/lanes.wgsl`), and with 64-bit atomics each fixed-point sum takes one
/// atomic (`flux.wgsl`); an application's device without them gets kernels where each lane
/// deposits alone (`lanes_single.wgsl`) with pairs of u32 atomics (`flux_u32.wgsl`). Flux is
/// summed in fixed point, so the two give the same image bit for bit. With no room for photon
/// hits, so that every deposit takes that way (the gather uses neither feature).
#[test]
fn with_and_without_device_features_the_same_image() {
    use sppm_gpu::gpu::DeviceCaps;
    let Some((_adapter, device, queue)) = sppm_device() else { return };
    assert_eq!(DeviceCaps::of(device.features()), DeviceCaps::NONE, "the application asked for no features");
    let Some(gpu) = common::gpu() else { return };
    let caps = DeviceCaps::of(gpu.device.features());
    assert_eq!(caps, DeviceCaps::of(gpu.adapter.features()), "GpuContext asks for subgroups and 64-bit atomics where there are");
    if caps == DeviceCaps::NONE {
        eprintln!("this adapter has neither subgroups nor 64-bit atomics: nothing to compare");
        return;
    }
    let scene = small("cornell-spheres.toml", 11);
    let direct_deposits = |device: &wgpu::Device, queue: &wgpu::Queue| {
        let mut sppm = Sppm::new(device, queue, &scene).unwrap_or_else(|e| panic!("{e}"));
        sppm.set_photon_hit_capacity(0);
        for _ in 0..PASSES {
            sppm.run_pass().unwrap_or_else(|e| panic!("{e}"));
        }
        let resumed = sppm.photon_hits_gathered().unwrap_or_else(|e| panic!("{e}")).1;
        assert!(resumed > 0, "no photon thread deposited at once");
        sppm.image().unwrap_or_else(|e| panic!("{e}"))
    };
    let without = direct_deposits(&device, &queue);
    let with = direct_deposits(&gpu.device, &gpu.queue);
    assert_bit_equal(&with, &without, &format!("with {caps:?} vs without"));
    // And the gather, the way deposits take where there is room, gives the same image.
    let (_, gathered) = reference(&gpu.device, &gpu.queue, &scene, PASSES);
    assert_bit_equal(&gathered, &with, "gathered vs deposited at once");
    assert!(mean(&with) > 0.05, "mean {}", mean(&with));
}

/// SPPM passes recorded in parts of any size gather their photons once a pass, as whole
/// passes do: parts end on a photon thread's block of 16 photons, so a pass's parts take no
/// more threads than the room to save their states holds (with parts that split blocks, the
/// last part of a pass found that room full and the pass gathered twice).
#[test]
fn sppm_parts_gather_once_a_pass() {
    use sppm_gpu::integrators::PartSize;
    let Some(gpu) = common::gpu() else { return };
    let scene = small("cornell-spheres.toml", 3);
    let mut whole = Sppm::new(&gpu.device, &gpu.queue, &scene).unwrap_or_else(|e| panic!("{e}"));
    let mut parts = Sppm::new(&gpu.device, &gpu.queue, &scene).unwrap_or_else(|e| panic!("{e}"));
    assert!(!parts.deposits_at_once(), "this scene gathers");
    for _ in 0..PASSES {
        whole.run_pass().unwrap_or_else(|e| panic!("{e}"));
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        while !parts.record_pass_part(&mut encoder, PartSize { points: 187, photons: 5_333 }).pass_done {}
        gpu.queue.submit([encoder.finish()]);
    }
    assert_eq!(whole.gathers(), PASSES as u64, "whole passes");
    assert_eq!(parts.gathers(), PASSES as u64, "passes in parts");
    assert_bit_equal(&parts.image().unwrap_or_else(|e| panic!("{e}")), &whole.image().unwrap_or_else(|e| panic!("{e}")), "parts");
}

/// Passes recorded in bounded parts (`record_pass_part`, as `sppm-gpu view` records them)
/// give the image of whole passes bit for bit, for SPPM, the path tracers and a banded image;
/// a pass dropped half way by `reset` leaves nothing behind; SPPM refuses to resolve in the
/// middle of a pass, and the path tracers' texture holds what `image()` reads.
#[test]
fn passes_in_parts_match_whole_passes() {
    use sppm_gpu::integrators::{self, Bands, PartSize, Work};
    use sppm_gpu::scene::Method;
    let Some((_adapter, device, queue)) = sppm_device() else { return };
    let texture = target(&device, wgpu::TextureFormat::Rgba32Float, WIDTH, HEIGHT);
    // Sizes that divide nothing evenly: 7 parts of camera paths, 4 of photons.
    let size = PartSize { points: 187, photons: 5_333 };
    for method in [Method::Sppm, Method::PtNee, Method::Pt] {
        let mut scene = small("cornell-spheres.toml", 5);
        scene.render.method = method;
        let whole = {
            let mut r = integrators::create(&device, &queue, &scene).unwrap_or_else(|e| panic!("{e}"));
            for _ in 0..PASSES {
                r.run_pass().unwrap_or_else(|e| panic!("{e}"));
            }
            r.image().unwrap_or_else(|e| panic!("{e}"))
        };
        let mut r = integrators::create(&device, &queue, &scene).unwrap_or_else(|e| panic!("{e}"));
        // Most of a pass (for SPPM into its photons), dropped by a reset: its light and
        // photons must not show.
        let mut encoder = device.create_command_encoder(&Default::default());
        for _ in 0..if method == Method::Sppm { 9 } else { 5 } {
            assert!(!r.record_pass_part(&mut encoder, size).pass_done, "{method:?}: these parts do not finish a pass");
        }
        if method == Method::Sppm {
            assert!(r.record_resolve_to_texture(&mut encoder, &texture).is_err(), "SPPM resolved mid-pass");
        }
        queue.submit([encoder.finish()]);
        r.reset();
        let mut parts = 0;
        for pass in 0..PASSES {
            // A frame per part, each submitted on its own.
            loop {
                let mut encoder = device.create_command_encoder(&Default::default());
                let part = r.record_pass_part(&mut encoder, size);
                let limit = if part.work == Work::Photons { size.photons } else { size.points };
                assert!(part.items > 0 && part.items <= limit, "{method:?}: {part:?}");
                queue.submit([encoder.finish()]);
                parts += 1;
                if part.pass_done {
                    break;
                }
                assert_eq!(r.passes(), pass, "{method:?}: a pass counted before its last part");
            }
        }
        assert_eq!(r.passes(), PASSES);
        let expected_parts = match method {
            // Photon parts end on blocks of 16 photons (a photon thread's).
            Method::Sppm => (WIDTH * HEIGHT).div_ceil(size.points) + PHOTONS.div_ceil(size.photons / 16 * 16),
            _ => (WIDTH * HEIGHT).div_ceil(size.points),
        };
        assert_eq!(parts, PASSES * expected_parts, "{method:?}: parts");
        let mut encoder = device.create_command_encoder(&Default::default());
        r.record_resolve_to_texture(&mut encoder, &texture).unwrap_or_else(|e| panic!("{e}"));
        queue.submit([encoder.finish()]);
        assert_bit_equal(&r.image().unwrap_or_else(|e| panic!("{e}")), &whole, &format!("{method:?} in parts"));
        assert_bit_equal(&read_texture(&device, &queue, &texture).0, &whole, &format!("{method:?} texture"));

        // Bands of 11 rows, in parts that cross from one band to the next.
        let mut bands = Bands::new(&device, &queue, &scene, 11).unwrap_or_else(|e| panic!("{e}"));
        for _ in 0..PASSES {
            let mut encoder = device.create_command_encoder(&Default::default());
            while !bands.record_pass_part(&mut encoder, size).pass_done {}
            queue.submit([encoder.finish()]);
        }
        assert_eq!(bands.passes(), PASSES);
        assert_bit_equal(&bands.image().unwrap_or_else(|e| panic!("{e}")), &whole, &format!("{method:?} bands in parts"));
    }
}

/// Several passes in one submission, as the pacer groups short passes
/// (`sppm_gpu::pacing::DeviceQueue`), give the image of one pass a submission bit for bit,
/// for SPPM, the path tracers and a banded image; and `run_pass`, which waits once two of its
/// submissions are in flight, gives it too.
#[test]
fn passes_grouped_in_submissions_match_one_a_submission() {
    use sppm_gpu::integrators::{self, Bands, Integrator};
    use sppm_gpu::pacing::{DeviceQueue, PassQueue};
    use sppm_gpu::scene::Method;
    let Some((_adapter, device, queue)) = sppm_device() else { return };
    const N: u32 = 6;
    for method in [Method::Sppm, Method::PtNee, Method::Pt] {
        let mut scene = small("cornell-spheres.toml", 9);
        scene.render.method = method;
        let render = |groups: &[u32], bands: bool| {
            let mut r: Box<dyn Integrator> = if bands {
                Box::new(Bands::new(&device, &queue, &scene, 11).unwrap_or_else(|e| panic!("{e}")))
            } else {
                integrators::create(&device, &queue, &scene).unwrap_or_else(|e| panic!("{e}"))
            };
            let mut q = DeviceQueue::new(r.as_mut(), &device, &queue);
            let tickets: Vec<_> = groups.iter().map(|&n| q.submit(n).unwrap_or_else(|e| panic!("{e}"))).collect();
            for t in tickets {
                q.wait(t).unwrap_or_else(|e| panic!("{e}"));
            }
            assert_eq!(r.passes(), N);
            r.image().unwrap_or_else(|e| panic!("{e}"))
        };
        let single = render(&[1; N as usize], false);
        assert_bit_equal(&render(&[4, 2], false), &single, &format!("{method:?} in groups of 4 and 2"));
        assert_bit_equal(&render(&[N], true), &single, &format!("{method:?} banded, one submission"));
        let mut r = integrators::create(&device, &queue, &scene).unwrap_or_else(|e| panic!("{e}"));
        for _ in 0..N {
            r.run_pass().unwrap_or_else(|e| panic!("{e}"));
        }
        assert_bit_equal(&r.image().unwrap_or_else(|e| panic!("{e}")), &single, &format!("{method:?} run_pass"));
    }
}
