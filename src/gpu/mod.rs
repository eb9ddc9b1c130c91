//! wgpu plumbing: the device, the kernels and the structs they share with the host.

pub mod baked_bvh;
mod context;
mod features;
mod kernel;
pub mod readback;
pub mod scene_buffers;
pub mod submissions;

pub use context::{adapters, check_device, required_limits, GpuContext, GpuError, STORAGE_BUFFERS_NEEDED};
pub use features::Specialization;
pub use kernel::{
    assemble, join_sharing_kernels, keep_kernels_in_process, shader_source, shader_source_for, share_kernels, validate,
    DeviceCaps, Kernel, Resource, KERNELS,
};
