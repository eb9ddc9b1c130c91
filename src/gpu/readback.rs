//! Copying GPU buffers back to the host.

use super::GpuError;

/// Wait for the queue and read `size` bytes of `buffer` (which must allow COPY_SRC).
pub fn read_buffer<T: bytemuck::Pod>(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    staging: &wgpu::Buffer,
    size: u64,
) -> Result<Vec<T>, GpuError> {
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
    encoder.copy_buffer_to_buffer(buffer, 0, staging, 0, size);
    queue.submit([encoder.finish()]);
    let bytes = map_staging(device, staging, size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Wait for the queue and read all of `buffer` (which must allow COPY_SRC) through a staging
/// buffer made for this one read: for reads now and then, not every pass.
pub fn read_whole<T: bytemuck::Pod>(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
) -> Result<Vec<T>, GpuError> {
    let staging = staging_buffer(device, "readback", buffer.size());
    read_buffer(device, queue, buffer, &staging, buffer.size())
}

/// Wait for the queue and read the first `size` bytes of `staging`.
fn map_staging(device: &wgpu::Device, staging: &wgpu::Buffer, size: u64) -> Result<Vec<u8>, GpuError> {
    let slice = staging.slice(..size);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuError(format!("waiting for the GPU failed: {e}")))?;
    receiver
        .recv()
        .map_err(|_| GpuError("the GPU never answered a readback".into()))?
        .map_err(|e| GpuError(format!("reading back a buffer failed: {e}")))?;
    let data = slice.get_mapped_range().map_err(|e| GpuError(format!("mapping a buffer failed: {e}")))?.to_vec();
    staging.unmap();
    Ok(data)
}

/// Wait for the queue and read back an `Rgba32Float` or `Rgba16Float` texture (such as one
/// [`Integrator::record_resolve_to_texture`](crate::integrators::Integrator::record_resolve_to_texture)
/// wrote) as RGBA, row by row from the top. The copy pads rows to 256 bytes.
pub fn read_texture(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) -> Result<Vec<[f32; 4]>, GpuError> {
    let channel_bytes = match texture.format() {
        wgpu::TextureFormat::Rgba32Float => 4,
        wgpu::TextureFormat::Rgba16Float => 2,
        f => return Err(GpuError(format!("reading back a {f:?} texture is not supported"))),
    };
    let (width, height) = (texture.width(), texture.height());
    let texel = 4 * channel_bytes;
    let padded = (width * texel).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let size = padded as u64 * height as u64;
    let staging = staging_buffer(device, "texture readback", size);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("texture readback") });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded), rows_per_image: Some(height) },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    let bytes = map_staging(device, &staging, size)?;
    let channel = |at: usize| match channel_bytes {
        4 => f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]),
        _ => f16_to_f32(u16::from_le_bytes([bytes[at], bytes[at + 1]])),
    };
    Ok((0..height)
        .flat_map(|y| (0..width).map(move |x| (y * padded + x * texel) as usize))
        .map(|at| [0, 1, 2, 3].map(|c| channel(at + c * channel_bytes as usize)))
        .collect())
}

/// An IEEE 754 half-precision value as f32.
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = ((h >> 10) & 0x1f) as i32;
    let mantissa = (h & 0x3ff) as f32;
    sign * match exponent {
        0 => mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

/// A buffer to read back through, of `size` bytes.
pub fn staging_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
