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
    let slice = staging.slice(..size);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError(format!("waiting for the GPU failed: {e}")))?;
    receiver
        .recv()
        .map_err(|_| GpuError("the GPU never answered a readback".into()))?
        .map_err(|e| GpuError(format!("reading back a buffer failed: {e}")))?;
    let data = {
        let view = slice.get_mapped_range().map_err(|e| GpuError(format!("mapping a buffer failed: {e}")))?;
        bytemuck::cast_slice(&view).to_vec()
    };
    staging.unmap();
    Ok(data)
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
