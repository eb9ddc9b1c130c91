//! What crosses to the GPU, without the GPU API: the `#[repr(C)]` records the kernels read and write,
//! their constants, and the feature flags the kernels are specialized on.
//!
//! The scene model packs itself into these records ([`crate::scene`]) and the GPU code
//! uploads and binds them ([`crate::gpu`]); both stand on this module, which depends on
//! neither. Each record is declared once here and once in `shaders/shared/types.wgsl`;
//! `tests/suite/gpu_layout.rs` checks every offset and size with naga.

mod features;
mod records;

pub use features::Features;
pub use records::*;
