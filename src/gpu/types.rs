//! Structs that cross to the GPU. Each is declared once here and once in
//! `shaders/shared/types.wgsl`; `tests/gpu_layout.rs` checks every offset and size with naga.

use bytemuck::{Pod, Zeroable};

pub use crate::accel::{BvhNode, GridParams};

/// Per-pass constants (uniform `frame`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Frame {
    pub cam_position: [f32; 3],
    pub lens_radius: f32,
    pub cam_right: [f32; 3],
    pub focus_distance: f32,
    pub cam_up: [f32; 3],
    pub width: u32,
    pub cam_forward: [f32; 3],
    pub height: u32,
    pub spp: u32,
    pub pass_index: u32,
    pub seed: u32,
    pub max_depth: u32,
    pub photon_count: u32,
    pub emitter_count: u32,
    pub ray_epsilon: f32,
    pub power_total: f32,
    pub alpha: f32,
    pub vp_count: u32,
    pub _pad: [u32; 2],
}

/// A triangle as a corner and two edges.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTriangle {
    pub p0: [f32; 3],
    pub material: u32,
    pub e1: [f32; 3],
    pub shape: u32,
    pub e2: [f32; 3],
    /// First of three entries in the normals buffer, or [`NO_NORMALS`].
    pub normals: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuSphere {
    pub center: [f32; 3],
    pub radius: f32,
    pub material: u32,
    pub shape: u32,
    pub _pad: [u32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuMaterial {
    pub albedo: [f32; 3],
    pub kind: u32,
    pub ior: f32,
    pub roughness: f32,
    pub texture: u32,
    pub _pad: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuShape {
    pub emission: [f32; 3],
    pub emits: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Emitter {
    pub prim_ref: u32,
    pub cdf: f32,
    pub pmf: f32,
    pub area: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct VisiblePoint {
    pub normal: [f32; 3],
    pub _pad0: u32,
    pub weight: [f32; 3],
    pub _pad1: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct VpStats {
    pub tau: [f32; 3],
    pub n: f32,
    pub ld: [f32; 3],
    pub radius: f32,
}

pub const NO_NORMALS: u32 = u32::MAX;
pub const NO_TEXTURE: u32 = u32::MAX;
pub const MATERIAL_DIFFUSE: u32 = 0;
pub const MATERIAL_MIRROR: u32 = 1;
pub const MATERIAL_DIELECTRIC: u32 = 2;
/// u32 words per visible point in the flux accumulator.
pub const ACCUM_STRIDE: u32 = 8;
/// Invocations per workgroup of every kernel.
pub const WORKGROUP_SIZE: u32 = 64;
