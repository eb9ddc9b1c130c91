//! What a render takes: the GPU buffers an integrator holds ([`GpuMemory`]), and the memory
//! a render will need, computed before anything is allocated ([`memory_need`],
//! [`check_memory`]).

use super::{LightTracer, PathTracer, Renderer, Sppm};
use crate::error::Error;
use crate::layout::{GpuBvhNode, GpuSphere, GpuTriangle};
use crate::scene::files::available_memory;
use crate::scene::Scene;

/// Bytes of one `vec4f` of `attributes` or `texels` (a texel, or a third of a triangle's
/// shading normals).
const ATTRIBUTE_BYTES: u64 = 16;

/// GPU buffers by name and size, split into the scene's (geometry, BVH, materials, lights:
/// proportional to the scene) and the renderer's (per pixel or per visible point).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuMemory {
    /// The scene's buffers, bytes each.
    pub scene: Vec<(String, u64)>,
    /// The renderer's buffers (summed over bands), bytes each.
    pub renderer: Vec<(String, u64)>,
}

impl GpuMemory {
    /// Bytes of the scene's buffers.
    pub fn scene_bytes(&self) -> u64 {
        self.scene.iter().map(|(_, b)| b).sum()
    }
    /// Bytes of the renderer's buffers.
    pub fn renderer_bytes(&self) -> u64 {
        self.renderer.iter().map(|(_, b)| b).sum()
    }
    /// All bytes.
    pub fn total(&self) -> u64 {
        self.scene_bytes() + self.renderer_bytes()
    }
}

/// Names and sizes of `buffers`.
pub(super) fn sizes<'a>(buffers: impl IntoIterator<Item = (&'a str, &'a wgpu::Buffer)>) -> Vec<(String, u64)> {
    buffers.into_iter().map(|(name, b)| (name.to_string(), b.size())).collect()
}

/// What a render will take, computed before anything is allocated (see [`memory_need`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryNeed {
    /// The scene's buffers, an upper bound from its primitive, attribute and texel counts.
    pub scene: u64,
    /// The renderer's buffers over all bands, as [`Integrator::gpu_memory`](super::Integrator::gpu_memory) will report them.
    pub renderer: u64,
    /// Host memory for the image: the estimate read back (16 bytes a pixel), the image
    /// (12) and its encoding for the file (up to 12), 40 bytes a pixel.
    pub host: u64,
}

impl MemoryNeed {
    /// Device memory: the scene's and the renderer's buffers.
    pub fn gpu(&self) -> u64 {
        self.scene + self.renderer
    }
}

/// The memory a render of `scene` on `device` takes, before allocating any of it, so that a
/// render that cannot fit is refused at once rather than killed by the system later.
pub fn memory_need(device: &wgpu::Device, scene: &Scene) -> MemoryNeed {
    let r = &scene.render;
    let rows = max_rows(device, scene).clamp(1, r.height.max(1));
    let renderer = (0..r.height)
        .step_by(rows as usize)
        .map(|y0| y0..(y0 + rows).min(r.height))
        .map(|band| match Renderer::of(r) {
            Renderer::Sppm => Sppm::renderer_bytes(scene, band, device.limits().max_storage_buffer_binding_size),
            Renderer::Path => PathTracer::renderer_bytes(scene, band.len() as u32),
            Renderer::Light => LightTracer::renderer_bytes(scene, band.len() as u32),
        })
        .sum();
    // Per triangle: itself, its reference in `prim_refs` and a BVH node at most, shading
    // normals (three attribute words) and texture coordinates (two); per sphere: itself, a
    // reference and a node. A scene traced through the CWBVH has a wide node at most per
    // primitive (every interior node has two children or more) and a copy of each primitive
    // in leaf order (three words, `leaf_prims`), in place of the binary tree's nodes.
    let (node, reference, word) = (size_of::<GpuBvhNode>() as u64, size_of::<u32>() as u64, ATTRIBUTE_BYTES);
    let triangle = size_of::<GpuTriangle>() as u64 + reference + node;
    let sphere = size_of::<GpuSphere>() as u64 + reference + node;
    let attributes: u64 = scene.triangles.iter().map(|t| word * (3 * t.n.is_some() as u64 + 2 * t.uv.is_some() as u64)).sum();
    let primitives = scene.triangles.len() + scene.spheres.len();
    let cwbvh = if crate::gpu::scene_buffers::uses_cwbvh(primitives) {
        primitives as u64 * (size_of::<crate::accel::CwNode>() as u64 + 3 * word - node)
    } else {
        0
    };
    let texels: u64 = scene.textures.iter().map(|t| word * t.width as u64 * t.height as u64).sum();
    // Materials, shapes and lights, 64 bytes each at most, and 64 more for the uniforms.
    let fixed = 64 * (scene.materials.len() + scene.shapes.len() + scene.lights.len() + 64) as u64;
    let scene_bytes =
        scene.triangles.len() as u64 * triangle + attributes + scene.spheres.len() as u64 * sphere + texels + fixed + cwbvh;
    MemoryNeed { scene: scene_bytes, renderer, host: r.width as u64 * r.height as u64 * 40 }
}

/// Refuse at once a render of `scene` on `device` (of `adapter`) that needs more memory than
/// it can have: `limit` when given (device buffers and host image together), else on a CPU
/// device (whose buffers are host memory) the host's available memory. A render that does not fit would otherwise grow
/// until the system kills it, with nothing written.
pub fn check_memory(device: &wgpu::Device, adapter: &wgpu::AdapterInfo, scene: &Scene, limit: Option<u64>) -> Result<(), Error> {
    let need = memory_need(device, scene);
    let cpu_device = adapter.device_type == wgpu::DeviceType::Cpu;
    let (total, have, source) = match limit {
        Some(limit) => (need.gpu() + need.host, limit, "the --memory-limit"),
        None if cpu_device => match available_memory() {
            Some(available) => {
                (need.gpu() + need.host, available, "the host's available memory (a CPU device's buffers are host memory)")
            }
            None => return Ok(()),
        },
        None => match available_memory() {
            Some(available) => (need.host, available, "the host's available memory"),
            None => return Ok(()),
        },
    };
    if total <= have {
        return Ok(());
    }
    let r = &scene.render;
    let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
    let pixels = (r.width as u64 * r.height as u64).max(1);
    Err(Error::Setting(format!(
        "{}: a {}x{} image (spp {}) needs about {:.1} GiB: {:.1} GiB of device buffers ({} bytes a pixel, the scene's {:.2} GiB \
         included) and {:.1} GiB for the image on the host; that is more than {} ({:.1} GiB). Render it smaller, or raise \
         --memory-limit",
        scene.path.display(),
        r.width,
        r.height,
        r.spp,
        gib(total),
        gib(need.gpu()),
        need.renderer / pixels,
        gib(need.scene),
        gib(need.host),
        source,
        gib(have)
    )))
}

/// Rows of `scene`'s image that one integrator of `scene.render.method` holds on `device`;
/// [`create`](super::create) splits taller images into [`Bands`](super::Bands) of this many rows.
pub fn max_rows(device: &wgpu::Device, scene: &Scene) -> u32 {
    match Renderer::of(&scene.render) {
        Renderer::Sppm => Sppm::max_rows(device, scene),
        Renderer::Path => PathTracer::max_rows(device, scene),
        Renderer::Light => LightTracer::max_rows(device, scene),
    }
}
