//! Kernels: one WGSL file per compute kernel in `shaders/`, with one entry point of the same
//! name. Shared code lives in `shaders/shared/` and is pulled in with `#import NAME` lines.
//!
//! Bindings are matched by the name of the WGSL global: naga's reflection of the assembled
//! module gives each kernel's bind group layout, and the host hands over a table of named
//! buffers, of which each kernel takes the ones it declares.

use super::types::WORKGROUP_SIZE;
use super::GpuError;

/// Every kernel, by name (its file `shaders/<name>.wgsl`, its entry point and its label).
pub const KERNELS: &[&str] = &[
    "camera_pass",
    "grid_setup",
    "grid_count",
    "grid_scan",
    "grid_fill",
    "photon_pass",
    "photon_gather",
    "photon_resume_setup",
    "update_stats",
    "resolve",
    "resolve_texture",
    "path_trace",
    "path_resolve_texture",
    "trace_rays",
    "sampler_test",
    "sobol_test",
];

/// Shader files, embedded at build time so the binary stands alone.
const FILES: &[(&str, &str)] = &[
    ("camera_pass", include_str!("../../shaders/camera_pass.wgsl")),
    ("grid_setup", include_str!("../../shaders/grid_setup.wgsl")),
    ("grid_count", include_str!("../../shaders/grid_count.wgsl")),
    ("grid_scan", include_str!("../../shaders/grid_scan.wgsl")),
    ("grid_fill", include_str!("../../shaders/grid_fill.wgsl")),
    ("photon_pass", include_str!("../../shaders/photon_pass.wgsl")),
    ("photon_gather", include_str!("../../shaders/photon_gather.wgsl")),
    ("photon_resume_setup", include_str!("../../shaders/photon_resume_setup.wgsl")),
    ("update_stats", include_str!("../../shaders/update_stats.wgsl")),
    ("resolve", include_str!("../../shaders/resolve.wgsl")),
    ("resolve_texture", include_str!("../../shaders/resolve_texture.wgsl")),
    ("estimate", include_str!("../../shaders/shared/estimate.wgsl")),
    ("trace_rays", include_str!("../../shaders/trace_rays.wgsl")),
    ("types", include_str!("../../shaders/shared/types.wgsl")),
    ("rng", include_str!("../../shaders/shared/rng.wgsl")),
    ("sobol", include_str!("../../shaders/shared/sobol.wgsl")),
    ("sampling", include_str!("../../shaders/shared/sampling.wgsl")),
    ("scene", include_str!("../../shaders/shared/scene.wgsl")),
    ("cwbvh", include_str!("../../shaders/shared/cwbvh.wgsl")),
    ("bsdf", include_str!("../../shaders/shared/bsdf.wgsl")),
    ("coating", include_str!("../../shaders/shared/coating.wgsl")),
    ("camera", include_str!("../../shaders/shared/camera.wgsl")),
    ("grid", include_str!("../../shaders/shared/grid.wgsl")),
    ("lights", include_str!("../../shaders/shared/lights.wgsl")),
    ("envmap", include_str!("../../shaders/shared/envmap.wgsl")),
    ("direct", include_str!("../../shaders/shared/direct.wgsl")),
    ("lanes", include_str!("../../shaders/shared/lanes.wgsl")),
    ("lanes_single", include_str!("../../shaders/shared/lanes_single.wgsl")),
    ("flux", include_str!("../../shaders/shared/flux.wgsl")),
    ("flux_u32", include_str!("../../shaders/shared/flux_u32.wgsl")),
    ("path_trace", include_str!("../../shaders/path_trace.wgsl")),
    ("path_resolve_texture", include_str!("../../shaders/path_resolve_texture.wgsl")),
    ("sampler_test", include_str!("../../shaders/sampler_test.wgsl")),
    ("sobol_test", include_str!("../../shaders/sobol_test.wgsl")),
];

fn file(name: &str) -> Result<&'static str, GpuError> {
    FILES.iter().find(|(n, _)| *n == name).map(|(_, src)| *src).ok_or_else(|| GpuError(format!("no shader file named `{name}`")))
}

/// What a device offers that the kernels use where it is there, each with a fallback that
/// computes the same bits: the shared file to import in its place.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceCaps {
    /// Subgroup operations ([`wgpu::Features::SUBGROUP`]): the photon pass's lanes share
    /// deposits (`lanes`); without, `lanes_single`.
    pub subgroups: bool,
    /// 64-bit integer atomics ([`wgpu::Features::SHADER_INT64_ATOMIC_ALL_OPS`]): one atomic
    /// per fixed-point sum (`flux`); without, two u32 atomics and a carry (`flux_u32`).
    pub atomic64: bool,
}

impl DeviceCaps {
    /// Everything the kernels can use.
    pub const ALL: Self = Self { subgroups: true, atomic64: true };
    /// Nothing beyond core WebGPU.
    pub const NONE: Self = Self { subgroups: false, atomic64: false };

    /// The wgpu features behind them, to ask a device for where the adapter has them.
    pub fn wanted() -> wgpu::Features {
        wgpu::Features::SUBGROUP | wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_ALL_OPS
    }

    /// What `features` (a device's) allow.
    pub fn of(features: wgpu::Features) -> Self {
        let int64 = wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_ALL_OPS;
        Self { subgroups: features.contains(wgpu::Features::SUBGROUP), atomic64: features.contains(int64) }
    }

    /// The shared file imported in place of `name` on such a device.
    fn file_for<'a>(&self, name: &'a str) -> &'a str {
        match name {
            "lanes" if !self.subgroups => "lanes_single",
            "flux" if !self.atomic64 => "flux_u32",
            _ => name,
        }
    }
}

/// The WGSL of kernel `name` with its imports expanded, each shared file once, in order, for a
/// device with everything the kernels can use ([`DeviceCaps::ALL`]).
pub fn shader_source(name: &str) -> Result<String, GpuError> {
    shader_source_for(name, DeviceCaps::ALL)
}

/// [`shader_source`] for a device with `caps`: the fallback files of what it lacks imported
/// instead.
pub fn shader_source_for(name: &str, caps: DeviceCaps) -> Result<String, GpuError> {
    fn expand(name: &str, caps: DeviceCaps, seen: &mut Vec<String>, out: &mut String) -> Result<(), GpuError> {
        let name = caps.file_for(name);
        if seen.iter().any(|s| s == name) {
            return Ok(());
        }
        seen.push(name.to_string());
        for line in file(name)?.lines() {
            match line.trim().strip_prefix("#import ") {
                Some(import) => expand(import.trim(), caps, seen, out)?,
                None => {
                    out.push_str(line);
                    out.push('\n');
                }
            }
        }
        Ok(())
    }
    let mut out = String::new();
    expand(name, caps, &mut Vec::new(), &mut out)?;
    Ok(out)
}

/// Parse and validate WGSL with naga, as wgpu will (subgroup operations and 64-bit atomics
/// allowed: wgpu checks them against the device's features).
pub fn validate(name: &str, source: &str) -> Result<(naga::Module, naga::valid::ModuleInfo), GpuError> {
    let module =
        naga::front::wgsl::parse_str(source).map_err(|e| GpuError(format!("{name}.wgsl: {}", e.emit_to_string(source))))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::SUBGROUP
            | naga::valid::Capabilities::SHADER_INT64
            | naga::valid::Capabilities::SHADER_INT64_ATOMIC_ALL_OPS,
    )
    .subgroup_stages(naga::valid::ShaderStages::COMPUTE)
    .subgroup_operations(naga::valid::SubgroupOperationSet::all())
    .validate(&module)
    .map_err(|e| GpuError(format!("{name}.wgsl: {}", e.emit_to_string(source))))?;
    Ok((module, info))
}

/// A buffer handed to kernels under the name of its WGSL global.
pub struct Resource<'a> {
    /// The name of the WGSL global (`var<storage>` or `var<uniform>`) it binds to.
    pub name: &'a str,
    /// The buffer, bound whole.
    pub buffer: &'a wgpu::Buffer,
}

/// One compute pipeline and what it binds.
pub struct Kernel {
    /// The kernel's name: its file `shaders/<name>.wgsl`, its entry point and its label.
    pub name: &'static str,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// (binding, WGSL global name) of every resource the kernel uses.
    bindings: Vec<(u32, String)>,
}

impl Kernel {
    /// Assemble, validate and compile kernel `name` (one of [`KERNELS`]), with its bind group
    /// layout reflected from the globals its entry point uses.
    pub fn new(device: &wgpu::Device, name: &'static str) -> Result<Self, GpuError> {
        Self::specialized(device, name, &[], &[])
    }

    /// The kernel with each `(token, text)` replaced in its source first, for variants that
    /// WGSL cannot parameterize (the texel format of a storage texture), and its `override`
    /// constants set from `constants` (those the kernel does not declare are ignored, so one
    /// list such as [`Features::constants`](super::Features::constants) serves every kernel).
    pub fn specialized(
        device: &wgpu::Device,
        name: &'static str,
        replace: &[(&str, &str)],
        constants: &[(&str, f64)],
    ) -> Result<Self, GpuError> {
        let mut source = shader_source_for(name, DeviceCaps::of(device.features()))?;
        for (token, text) in replace {
            source = source.replace(token, text);
        }
        let (module, info) = validate(name, &source)?;
        let entry = module
            .entry_points
            .iter()
            .position(|e| e.name == name)
            .ok_or_else(|| GpuError(format!("{name}.wgsl has no entry point `{name}`")))?;
        let uses = info.get_entry_point(entry);
        let declared = |c: &&(&str, f64)| module.overrides.iter().any(|(_, o)| o.name.as_deref() == Some(c.0));
        let constants: Vec<(&str, f64)> = constants.iter().filter(declared).copied().collect();

        // Only the globals this entry point touches: imported files may declare more.
        let mut entries = Vec::new();
        let mut bindings = Vec::new();
        for (handle, var) in module.global_variables.iter() {
            let Some(binding) = &var.binding else { continue };
            if uses[handle].is_empty() {
                continue;
            }
            let ty = match var.space {
                naga::AddressSpace::Uniform => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                naga::AddressSpace::Storage { access } => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: !access.contains(naga::StorageAccess::STORE) },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                // A write-only 2D storage texture (the caller's image).
                naga::AddressSpace::Handle => match module.types[var.ty].inner {
                    naga::TypeInner::Image { class: naga::ImageClass::Storage { format, .. }, .. } => {
                        wgpu::BindingType::StorageTexture {
                            access: wgpu::StorageTextureAccess::WriteOnly,
                            format: match format {
                                naga::StorageFormat::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
                                naga::StorageFormat::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
                                f => return Err(GpuError(format!("{name}.wgsl: storage format {f:?} is not supported"))),
                            },
                            view_dimension: wgpu::TextureViewDimension::D2,
                        }
                    }
                    _ => continue,
                },
                _ => continue,
            };
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: binding.binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty,
                count: None,
            });
            bindings.push((binding.binding, var.name.clone().unwrap_or_default()));
        }
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(name), entries: &entries });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(name),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(name),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(name),
            layout: Some(&pipeline_layout),
            module: &shader,
            entry_point: Some(name),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
            cache: None,
        });
        Ok(Self { name, pipeline, layout, bindings })
    }

    /// A bind group taking, for each of the kernel's bindings, the resource of the same name.
    pub fn bind_group(&self, device: &wgpu::Device, resources: &[Resource]) -> Result<wgpu::BindGroup, GpuError> {
        self.bind_group_with_views(device, resources, &[])
    }

    /// [`Kernel::bind_group`] with texture views as well, each under its WGSL global's name.
    pub fn bind_group_with_views(
        &self,
        device: &wgpu::Device,
        resources: &[Resource],
        views: &[(&str, &wgpu::TextureView)],
    ) -> Result<wgpu::BindGroup, GpuError> {
        let mut entries = Vec::with_capacity(self.bindings.len());
        for (binding, name) in &self.bindings {
            let resource = if let Some(r) = resources.iter().find(|r| r.name == name) {
                r.buffer.as_entire_binding()
            } else if let Some((_, view)) = views.iter().find(|(n, _)| n == name) {
                wgpu::BindingResource::TextureView(view)
            } else {
                return Err(GpuError(format!("kernel {} binds `{name}`, which the host did not provide", self.name)));
            };
            entries.push(wgpu::BindGroupEntry { binding: *binding, resource });
        }
        Ok(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.name),
            layout: &self.layout,
            entries: &entries,
        }))
    }

    /// Record a dispatch of exactly `groups` workgroups (for the single-workgroup kernels).
    pub fn dispatch_groups(&self, encoder: &mut wgpu::CommandEncoder, bind_group: &wgpu::BindGroup, groups: u32) {
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.name), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(groups, 1, 1);
    }

    /// Record a dispatch whose workgroup counts a kernel wrote: three u32 at byte `offset`
    /// of `args` (a buffer with `INDIRECT` usage), laid out as [`Kernel::dispatch`] would.
    pub fn dispatch_indirect(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bind_group: &wgpu::BindGroup,
        args: &wgpu::Buffer,
        offset: u64,
    ) {
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.name), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups_indirect(args, offset);
    }

    /// Record a dispatch of `threads` invocations. More than 65535 workgroups spill into y;
    /// the kernels rebuild the linear index from `num_workgroups`.
    pub fn dispatch(&self, encoder: &mut wgpu::CommandEncoder, bind_group: &wgpu::BindGroup, threads: u32) {
        if threads == 0 {
            return;
        }
        let groups = threads.div_ceil(WORKGROUP_SIZE);
        let x = groups.min(65535);
        let y = groups.div_ceil(x);
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.name), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}
