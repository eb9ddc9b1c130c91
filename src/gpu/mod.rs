//! wgpu plumbing: the device, the kernels and the structs they share with the host.

mod context;
mod kernel;
pub mod readback;
pub mod scene_buffers;
pub mod types;

pub use context::{GpuContext, GpuError};
pub use kernel::{shader_source, validate, Kernel, Resource, KERNELS};
