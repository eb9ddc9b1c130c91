//! Creating the renderer's device: headless, or for a window's surface.

use std::fmt;

use super::DeviceCaps;

/// Errors from the GPU side: no adapter, a device the renderer cannot use, a lost device.
#[derive(Debug, Clone)]
pub struct GpuError(pub String);

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for GpuError {}

/// A device and queue owned by the renderer (the embedding API takes the caller's instead).
/// A clone shares the device, its queue and its first error.
#[derive(Clone)]
pub struct GpuContext {
    /// The device, created with [`required_limits`] and, where the adapter has them, the
    /// optional features of [`DeviceCaps::wanted`].
    pub device: wgpu::Device,
    /// The device's queue; every pass and readback is submitted here.
    pub queue: wgpu::Queue,
    /// Name, backend and driver of the adapter the device was made on (for logs and reports).
    pub adapter_info: wgpu::AdapterInfo,
    /// The adapter the device was made on (a window configures its surface with it).
    pub adapter: wgpu::Adapter,
    /// The first error the device reported outside any error scope (out of memory, a
    /// validation failure, a lost device), kept for [`GpuContext::check`] instead of wgpu's
    /// default handler, which panics.
    errors: std::sync::Arc<std::sync::Mutex<Option<String>>>,
}

/// The Vulkan, Metal and DX12 adapters of this machine, in the order
/// [`GpuContext::with_adapter`] numbers them.
pub fn adapters() -> Vec<wgpu::AdapterInfo> {
    let instance = GpuContext::instance();
    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::PRIMARY)).iter().map(|a| a.get_info()).collect()
}

/// Storage buffers the largest kernel binds in one stage.
pub const STORAGE_BUFFERS_NEEDED: u32 = 17;

/// What the renderer needs from a device, within what `adapter` offers.
pub fn required_limits(adapter: &wgpu::Limits) -> Result<wgpu::Limits, GpuError> {
    if adapter.max_storage_buffers_per_shader_stage < STORAGE_BUFFERS_NEEDED {
        return Err(GpuError(format!(
            "the GPU allows {} storage buffers per shader stage; sppm-gpu needs {}",
            adapter.max_storage_buffers_per_shader_stage, STORAGE_BUFFERS_NEEDED
        )));
    }
    Ok(wgpu::Limits {
        max_storage_buffers_per_shader_stage: STORAGE_BUFFERS_NEEDED,
        max_storage_buffer_binding_size: adapter.max_storage_buffer_binding_size,
        max_buffer_size: adapter.max_buffer_size,
        ..wgpu::Limits::default()
    })
}

/// Check that a caller's device has what the renderer needs (see [`required_limits`]): a
/// clear error instead of a validation panic later.
pub fn check_device(device: &wgpu::Device) -> Result<(), GpuError> {
    let have = device.limits();
    if have.max_storage_buffers_per_shader_stage < STORAGE_BUFFERS_NEEDED {
        return Err(GpuError(format!(
            "the device was created with max_storage_buffers_per_shader_stage = {}; sppm-gpu needs {} \
             (create it with sppm_gpu::gpu::required_limits(&adapter.limits()))",
            have.max_storage_buffers_per_shader_stage, STORAGE_BUFFERS_NEEDED
        )));
    }
    if have.max_compute_invocations_per_workgroup < 256 || have.max_compute_workgroup_size_x < 256 {
        return Err(GpuError("sppm-gpu needs compute workgroups of 256 invocations".into()));
    }
    Ok(())
}

impl GpuContext {
    /// The first Vulkan, Metal or DX12 adapter. GL is left out on purpose: `WGPU_BACKEND=gl`
    /// must not silently switch to a slower, different implementation.
    pub fn new() -> Result<Self, GpuError> {
        Self::with_limits(|limits| limits)
    }

    /// [`GpuContext::new`] with the device's limits passed through `adjust` first: lower
    /// ones make a device that behaves like a smaller GPU (tests use this to make large
    /// images go in bands).
    /// Where the environment variable `SPPM_GPU_ADAPTER` is set, its adapter
    /// ([`GpuContext::with_adapter`]'s selector): a machine with both lavapipe and a GPU runs
    /// its tests on the one it names.
    pub fn with_limits(adjust: impl FnOnce(wgpu::Limits) -> wgpu::Limits) -> Result<Self, GpuError> {
        let instance = Self::instance();
        match std::env::var(ADAPTER_VARIABLE) {
            Ok(selector) if !selector.trim().is_empty() => {
                let adapter = select_adapter(&instance, &selector)
                    .map_err(|GpuError(e)| GpuError(format!("{ADAPTER_VARIABLE}={selector}: {e}")))?;
                Self::on_adapter(adapter, adjust)
            }
            _ => Self::on_instance(&instance, None, adjust),
        }
    }

    /// [`GpuContext::new`] on the adapter `selector` names: its index in [`adapters`], or a
    /// part of its name (case-insensitive) that no other adapter's name has. One process per
    /// GPU of a machine picks its GPU this way (Vulkan does not see `CUDA_VISIBLE_DEVICES`).
    pub fn with_adapter(selector: &str) -> Result<Self, GpuError> {
        Self::on_adapter(select_adapter(&Self::instance(), selector)?, |limits| limits)
    }

    /// The instance [`GpuContext::new`] makes its device on: Vulkan, Metal or DX12. An
    /// application with a window makes its surface on it, then calls
    /// [`GpuContext::for_surface`].
    pub fn instance() -> wgpu::Instance {
        wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::PRIMARY,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        })
    }

    /// [`GpuContext::new`] on an adapter of `instance` that can present to `surface`: a
    /// preview window renders and draws on one device.
    pub fn for_surface(instance: &wgpu::Instance, surface: &wgpu::Surface<'_>) -> Result<Self, GpuError> {
        Self::on_instance(instance, Some(surface), |limits| limits)
    }

    fn on_instance(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
        adjust: impl FnOnce(wgpu::Limits) -> wgpu::Limits,
    ) -> Result<Self, GpuError> {
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            compatible_surface: surface,
            ..Default::default()
        }))
        .map_err(|e| {
            GpuError(format!(
                "no GPU adapter found ({e}). On Debian or Ubuntu without a GPU, install the \
                 software Vulkan driver: apt-get install -y mesa-vulkan-drivers"
            ))
        })?;
        Self::on_adapter(adapter, adjust)
    }

    fn on_adapter(adapter: wgpu::Adapter, adjust: impl FnOnce(wgpu::Limits) -> wgpu::Limits) -> Result<Self, GpuError> {
        let limits = adjust(required_limits(&adapter.limits())?);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("sppm-gpu"),
            // Subgroups and 64-bit atomics where there are: the photon pass shares deposits
            // between lanes and adds each fixed-point sum with one atomic (DeviceCaps).
            required_features: adapter.features() & DeviceCaps::wanted(),
            required_limits: limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| GpuError(format!("could not create a device on {}: {e}", adapter.get_info().name)))?;
        let errors = std::sync::Arc::new(std::sync::Mutex::new(None));
        let sink = errors.clone();
        device.on_uncaptured_error(std::sync::Arc::new(move |e: wgpu::Error| {
            let mut first = sink.lock().unwrap_or_else(|p| p.into_inner());
            first.get_or_insert_with(|| match e {
                wgpu::Error::OutOfMemory { .. } => "the GPU ran out of memory".to_string(),
                other => format!("the GPU reported an error: {other}"),
            });
        }));
        let lost = errors.clone();
        device.set_device_lost_callback(move |reason, message| {
            // The loss is the cause of whatever failed around it: it is the error to report.
            let mut first = lost.lock().unwrap_or_else(|p| p.into_inner());
            let detail = if message.is_empty() { String::new() } else { format!(": {message}") };
            *first = Some(format!("the GPU device was lost ({reason:?}){detail}"));
        });
        Ok(Self { device, queue, adapter_info: adapter.get_info(), adapter, errors })
    }

    /// The work of an SPPM pass where the scene does not set it, by kind of device: a CPU
    /// device (lavapipe) or a GPU ([`crate::scene::PassWork::DEFAULT`],
    /// [`crate::scene::PassWork::GPU`]). Chosen from the adapter, never from timings, so that
    /// one scene and seed give one image on one machine.
    pub fn pass_work(&self) -> crate::scene::PassWork {
        match self.adapter_info.device_type {
            wgpu::DeviceType::Cpu => crate::scene::PassWork::DEFAULT,
            _ => crate::scene::PassWork::GPU,
        }
    }

    /// The first error the device has reported since it was made, as an `Err`: callers check
    /// after submitting work, so a lost device or an exhausted GPU ends the run with a message
    /// rather than a panic or a hang.
    pub fn check(&self) -> Result<(), GpuError> {
        match self.errors.lock().unwrap_or_else(|p| p.into_inner()).as_ref() {
            Some(e) => Err(GpuError(e.clone())),
            None => Ok(()),
        }
    }
}

/// The environment variable that picks the adapter of [`GpuContext::new`] (an index or a
/// part of a name, as `--adapter`).
pub const ADAPTER_VARIABLE: &str = "SPPM_GPU_ADAPTER";

/// The adapter of `instance` that `selector` names: its index in [`adapters`], or a part of
/// its name (case-insensitive) that no other adapter's name has.
pub fn select_adapter(instance: &wgpu::Instance, selector: &str) -> Result<wgpu::Adapter, GpuError> {
    let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::PRIMARY));
    let list = || adapters.iter().enumerate().map(|(i, a)| format!("{i}: {}", a.get_info().name)).collect::<Vec<_>>().join(", ");
    let chosen = match selector.trim().parse::<usize>() {
        Ok(i) => adapters.get(i).ok_or_else(|| GpuError(format!("no adapter {i}; the adapters are {}", list())))?,
        Err(_) => {
            let want = selector.to_lowercase();
            let mut found = adapters.iter().filter(|a| a.get_info().name.to_lowercase().contains(&want));
            match (found.next(), found.next()) {
                (Some(a), None) => a,
                (None, _) => {
                    return Err(GpuError(format!("no adapter's name contains `{selector}`; the adapters are {}", list())))
                }
                (Some(_), Some(_)) => {
                    return Err(GpuError(format!("several adapters' names contain `{selector}`: {}; give an index", list())))
                }
            }
        }
    };
    Ok(chosen.clone())
}
