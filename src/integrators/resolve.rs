//! The resolve kernels' target textures: which formats they write and what a target must be.

use crate::error::Error;

/// Texel formats the resolve kernels write, by slot: the token replaced in their WGSL.
pub(super) const RESOLVE_FORMATS: [&str; 2] = ["rgba32float", "rgba16float"];

/// The resolve kernel `name` (a `*_resolve_texture` kernel) for `texture`'s format, from
/// `kernels` (one a format, made when first needed), after checking `texture` as a target for
/// a `width` x `height` image ([`check_resolve_target`]).
pub(super) fn resolve_kernel<'a>(
    device: &wgpu::Device,
    kernels: &'a mut [Option<crate::gpu::Kernel>; 2],
    name: &'static str,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Result<&'a crate::gpu::Kernel, Error> {
    let slot = check_resolve_target(texture, width, height)?;
    Ok(match &mut kernels[slot] {
        Some(kernel) => kernel,
        empty => empty.insert(crate::gpu::Kernel::specialized(device, name, &[("rgba32float", RESOLVE_FORMATS[slot])], &[])?),
    })
}

/// The slot in [`RESOLVE_FORMATS`] of `texture`, a resolve target for a `width` x `height`
/// image: it must be that size, `Rgba32Float` or `Rgba16Float`, with `STORAGE_BINDING`.
pub(super) fn check_resolve_target(texture: &wgpu::Texture, width: u32, height: u32) -> Result<usize, Error> {
    let slot = match texture.format() {
        wgpu::TextureFormat::Rgba32Float => 0,
        wgpu::TextureFormat::Rgba16Float => 1,
        f => return Err(Error::Setting(format!("the target texture is {f:?}; use Rgba16Float or Rgba32Float"))),
    };
    let size = texture.size();
    if size.width != width || size.height != height || !texture.usage().contains(wgpu::TextureUsages::STORAGE_BINDING) {
        return Err(Error::Setting(format!(
            "the target texture is {}x{} with usage {:?}; it must be {width}x{height} with STORAGE_BINDING",
            size.width,
            size.height,
            texture.usage(),
        )));
    }
    Ok(slot)
}
