//! A device that fails (out of memory, lost, invalid use) gives a clear error through
//! `GpuContext::check`, which the command line calls after every pass, not a panic or a hang.
//! The test provokes the one failure it can on any device, an allocation over the device's
//! limit (a validation error); out-of-memory and device loss take the same path.

use crate::common;

#[test]
fn an_allocation_over_the_limit_is_reported_not_panicked() {
    // Its own device: the error stays with the device (the suite's others share one).
    let Some(gpu) = common::own_gpu() else { return };
    gpu.check().unwrap();
    // Larger than the device allows: wgpu reports it to the context's error sink.
    let too_large = gpu.device.limits().max_buffer_size + 4;
    let _buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("too large"),
        size: too_large,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
    let error = gpu.check().expect_err("the failed allocation is reported");
    assert!(error.0.contains("GPU"), "{}", error.0);
    // The first error stays: later checks keep failing rather than going on quietly.
    assert!(gpu.check().is_err());
}
