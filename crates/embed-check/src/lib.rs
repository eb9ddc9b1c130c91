//! A stand-in for a user's own wgpu application that wants photon-mapped images without
//! handing its device over: it makes its own instance, adapter and device, and uses only
//! sppm-gpu's public API to render into a texture it owns. `tests/matches_cli.rs` checks the
//! result against the `sppm-gpu` command line's image for the same settings.

use sppm_gpu::integrators::{Integrator, Sppm};
use sppm_gpu::scene::Scene;

/// The application's GPU: its own device and queue.
pub struct App {
    /// The application's device, created with `sppm_gpu::gpu::required_limits`.
    pub device: wgpu::Device,
    /// The device's queue, shared by the application's work and the renderer's.
    pub queue: wgpu::Queue,
    /// The adapter's name, for messages.
    pub adapter_name: String,
}

/// Why an [`App`] could not start.
#[derive(Debug)]
pub enum AppError {
    /// No Vulkan, Metal or DX12 adapter on this machine.
    NoAdapter(String),
    /// An adapter, but not a device the renderer can use.
    Device(String),
}

impl std::fmt::Display for AppError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AppError::NoAdapter(e) => write!(f, "no GPU adapter: {e}"),
            AppError::Device(e) => write!(f, "no usable device: {e}"),
        }
    }
}

impl App {
    /// The first Vulkan, Metal or DX12 adapter, with a device that has the limits the
    /// renderer asks for.
    pub fn new() -> Result<Self, AppError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN | wgpu::Backends::METAL | wgpu::Backends::DX12,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
            .map_err(|e| AppError::NoAdapter(e.to_string()))?;
        let limits = sppm_gpu::gpu::required_limits(&adapter.limits()).map_err(|e| AppError::Device(e.to_string()))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("embed-check"),
            required_features: wgpu::Features::empty(),
            required_limits: limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| AppError::Device(e.to_string()))?;
        Ok(App { device, queue, adapter_name: adapter.get_info().name })
    }

    /// Render `passes` SPPM passes of `scene` (one encoder each, recorded by the renderer and
    /// submitted here), resolve the estimate into an Rgba32Float texture of the
    /// application's, and read it back: `width * height` RGBA texels, row-major.
    pub fn render(&self, scene: &Scene, passes: u32) -> Result<Vec<[f32; 4]>, String> {
        let (width, height) = (scene.render.width, scene.render.height);
        let mut sppm = Sppm::new(&self.device, &self.queue, scene).map_err(|e| e.to_string())?;
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("embed-check target"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        for _ in 0..passes {
            let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
            sppm.record_pass(&mut encoder);
            self.queue.submit([encoder.finish()]);
        }
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("resolve") });
        sppm.record_resolve_to_texture(&mut encoder, &texture).map_err(|e| e.to_string())?;
        self.queue.submit([encoder.finish()]);
        if sppm.passes() != passes {
            return Err(format!("the renderer counted {} passes, expected {passes}", sppm.passes()));
        }
        sppm_gpu::gpu::readback::read_texture(&self.device, &self.queue, &texture).map_err(|e| e.to_string())
    }
}
