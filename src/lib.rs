//! sppm-gpu: stochastic progressive photon mapping as WGSL compute kernels on wgpu.

pub mod accel;
pub mod error;
pub mod experiments;
pub mod gpu;
pub mod image_io;
pub mod integrators;
pub mod metrics;
pub mod scene;

pub use error::Error;
