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
    /// Shutter time of this pass in [0, 1): camera and photon paths both see the scene then.
    pub time: f32,
    /// 1 when some shape moves (has a velocity), so that traversal offsets rays by it.
    pub motion: u32,
    /// Path tracing: 1 for next-event estimation, 0 for naive.
    pub nee: u32,
    pub _pad0: u32,
    pub _pad1: u32,
    pub _pad2: u32,
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
    /// Where the triangle's vertex attributes start in the `attributes` buffer, with flags:
    /// [`HAS_NORMALS`] (three shading normals, xyz) and [`HAS_UVS`] (then two entries,
    /// `(u0, v0, u1, v1)` and `(u2, v2, -, -)`); 0 for none.
    pub attributes: u32,
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
    /// First texel in the `texels` buffer, or [`NO_TEXTURE`].
    pub texture: u32,
    /// Texture width in the low 16 bits, height in the high 16.
    pub texture_size: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuShape {
    pub emission: [f32; 3],
    pub emits: u32,
    /// Displacement over the shutter: the shape sits at its position + velocity * time.
    pub velocity: [f32; 3],
    pub _pad: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Emitter {
    /// [`EMITTER_AREA`], [`EMITTER_POINT`] or [`EMITTER_DIRECTIONAL`].
    pub kind: u32,
    /// The emitting primitive of an area emitter.
    pub prim_ref: u32,
    /// Inclusive running sum of `pmf`; the last is infinite so that every u < 1 falls in.
    pub cdf: f32,
    /// Probability of choosing this emitter, proportional to its power.
    pub pmf: f32,
    /// Point light: its position. Directional: the centre of the disk photons leave from.
    pub position: [f32; 3],
    /// Area of the primitive, or of the directional light's disk.
    pub area: f32,
    /// Point light: intensity (W/sr). Directional: irradiance.
    pub radiance: [f32; 3],
    /// Radius of the directional light's disk.
    pub radius: f32,
    /// Direction of travel of a directional light.
    pub direction: [f32; 3],
    pub _pad: u32,
}

/// What `grid_setup` needs from the host: the box holding every visible point and the hash
/// table's size (a power of two).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GridScene {
    pub lo: [f32; 3],
    pub table_size: u32,
    pub hi: [f32; 3],
    pub _pad: u32,
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

pub const HAS_NORMALS: u32 = 1 << 31;
pub const HAS_UVS: u32 = 1 << 30;
pub const ATTRIBUTE_INDEX_MASK: u32 = HAS_UVS - 1;
pub const EMITTER_AREA: u32 = 0;
pub const EMITTER_POINT: u32 = 1;
pub const EMITTER_DIRECTIONAL: u32 = 2;
pub const NO_TEXTURE: u32 = u32::MAX;
pub const MATERIAL_DIFFUSE: u32 = 0;
pub const MATERIAL_MIRROR: u32 = 1;
pub const MATERIAL_DIELECTRIC: u32 = 2;
pub const MATERIAL_GLOSSY: u32 = 3;
/// u32 words per visible point in the flux accumulator.
pub const ACCUM_STRIDE: u32 = 8;
/// Invocations per workgroup of every kernel.
pub const WORKGROUP_SIZE: u32 = 64;
