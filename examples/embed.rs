//! Photon mapping inside an application that owns its wgpu device.
//!
//! ```text
//! cargo run --release --example embed -- scenes/cornell-box.toml 8 embed.png
//! ```
//!
//! Arguments: the scene (default `scenes/cornell-box.toml`), the number of frames (default
//! 8; one SPPM pass per frame) and the output PNG (default `embed.png`; the second view goes
//! to `embed-view2.png` beside it).
//!
//! The application creates its own instance, adapter and device (asking for the limits
//! `sppm_gpu::gpu::required_limits` names), has a compute kernel of its own, and each frame
//! records into one command encoder: its own dispatch, one SPPM pass of each of two renderers
//! (the scene from the file's camera, and from a second camera), and each renderer's current
//! estimate into a texture the application owns (Rgba32Float and Rgba16Float). Nothing is
//! submitted but by the application. At the end it copies the textures back, checks its own
//! kernel's result, and saves the images.

use sppm_gpu::gpu::readback;
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators::{Integrator, Sppm};
use sppm_gpu::scene::Camera;
use std::path::PathBuf;
use std::process::ExitCode;

/// The application's own kernel: every frame adds `i + 1` to element `i`.
const APP_KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read_write> data: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if id.x < arrayLength(&data) {
        data[id.x] += id.x + 1u;
    }
}
"#;

const APP_ELEMENTS: u32 = 4096;

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene_path = PathBuf::from(args.next().unwrap_or_else(|| "scenes/cornell-box.toml".into()));
    let frames: u32 = match args.next() {
        Some(n) => n.parse().ok().filter(|&n| n > 0).ok_or(format!("FRAMES must be a positive integer, got {n:?}"))?,
        None => 8,
    };
    let output = PathBuf::from(args.next().unwrap_or_else(|| "embed.png".into()));

    // The application's device. The renderer needs more storage buffers per shader stage than
    // wgpu's defaults; `required_limits` says how many, within what the adapter offers.
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::VULKAN | wgpu::Backends::METAL | wgpu::Backends::DX12,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .map_err(|e| format!("no GPU adapter ({e}); on Debian or Ubuntu: apt-get install -y mesa-vulkan-drivers"))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("application"),
        required_features: wgpu::Features::empty(),
        required_limits: sppm_gpu::gpu::required_limits(&adapter.limits())?,
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))?;

    // The application's own compute work.
    let app_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("app kernel"),
        source: wgpu::ShaderSource::Wgsl(APP_KERNEL.into()),
    });
    let app_pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("app kernel"),
        layout: None,
        module: &app_module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let app_data = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("app data"),
        size: APP_ELEMENTS as u64 * 4,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false, // zeroed
    });
    let app_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("app data"),
        layout: &app_pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: app_data.as_entire_binding() }],
    });

    // Two renderers on the application's device: the file's view, and one from the left.
    let scene = sppm_gpu::scene::load(&scene_path)?;
    let mut view1 = Sppm::new(&device, &queue, &scene)?;
    let mut view2 = Sppm::new(&device, &queue, &scene)?;
    let c = &scene.camera;
    let turned = glam::Quat::from_rotation_y(0.35) * (c.position - c.look_at);
    view2.set_camera(&Camera { position: c.look_at + turned, ..c.clone() })?;

    // The textures the estimates go to, owned by the application.
    let (width, height) = (scene.render.width, scene.render.height);
    let texture = |label, format| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
    };
    let target1 = texture("view 1", wgpu::TextureFormat::Rgba32Float);
    let target2 = texture("view 2", wgpu::TextureFormat::Rgba16Float);

    let start = std::time::Instant::now();
    for _ in 0..frames {
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        {
            let mut pass =
                encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("app"), timestamp_writes: None });
            pass.set_pipeline(&app_pipeline);
            pass.set_bind_group(0, &app_group, &[]);
            pass.dispatch_workgroups(APP_ELEMENTS.div_ceil(64), 1, 1);
        }
        view1.record_pass(&mut encoder);
        view1.record_resolve_to_texture(&mut encoder, &target1)?;
        view2.record_pass(&mut encoder);
        view2.record_resolve_to_texture(&mut encoder, &target2)?;
        queue.submit([encoder.finish()]);
    }

    // Read everything back: the application's buffer and both textures.
    let data: Vec<u32> = readback::read_whole(&device, &queue, &app_data)?;
    let seconds = start.elapsed().as_secs_f64();
    for (i, &x) in data.iter().enumerate() {
        if x != frames * (i as u32 + 1) {
            return Err(format!("the application's kernel gave {x} at {i}, expected {}", frames * (i as u32 + 1)).into());
        }
    }
    let image1 = read_image(&device, &queue, &target1)?;
    let image2 = read_image(&device, &queue, &target2)?;
    let output2 =
        output.with_file_name(format!("{}-view2.png", output.file_stem().map_or("embed".into(), |s| s.to_string_lossy())));
    sppm_gpu::image_io::write_png(&output, &image1)?;
    sppm_gpu::image_io::write_png(&output2, &image2)?;

    for (name, sppm, path) in [("view 1", &view1, &output), ("view 2", &view2, &output2)] {
        let r = sppm.radius_stats()?;
        println!(
            "{name}: {} passes, {} photons, radius {:.4}..{:.4} (mean {:.4}) -> {}",
            sppm.passes(),
            sppm.photons_traced(),
            r.min,
            r.max,
            r.mean,
            path.display()
        );
    }
    println!(
        "{frames} frames in {seconds:.2} s on {}; the application's kernel checked ({APP_ELEMENTS} elements)",
        adapter.get_info().name
    );
    Ok(())
}

/// An RGBA texture read back, as the linear RGB image it holds.
fn read_image(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Rgb32Image, Box<dyn std::error::Error>> {
    let texels = readback::read_texture(device, queue, texture)?;
    Ok(Rgb32Image::from_rgba(texture.width(), texture.height(), &texels))
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
