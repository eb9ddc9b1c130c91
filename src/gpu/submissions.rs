//! How an integrator's own passes reach the device: at most [`MAX_IN_FLIGHT`] submissions in
//! flight (the render loop's pacing over them is `crate::pacing`).

use std::collections::VecDeque;

use super::GpuError;
use crate::error::Error;

/// Submissions in flight at most: one running on the device and one queued behind it.
pub const MAX_IN_FLIGHT: usize = 2;

/// Block until `device` has completed the submission `ticket`.
pub fn wait_for(device: &wgpu::Device, ticket: wgpu::SubmissionIndex) -> Result<(), Error> {
    device
        .poll(wgpu::PollType::Wait { submission_index: Some(ticket), timeout: None })
        .map_err(|e| Error::Gpu(GpuError(format!("waiting for the GPU failed: {e}"))))?;
    Ok(())
}

/// The submissions of an integrator's own `Integrator::run_pass`, at most
/// [`MAX_IN_FLIGHT`] in flight: a loop of `run_pass` waits for the oldest before it submits
/// more, so an application that calls it cannot queue work without bound.
pub(crate) struct Submissions {
    in_flight: VecDeque<wgpu::SubmissionIndex>,
}

impl Submissions {
    pub(crate) fn new() -> Self {
        Self { in_flight: VecDeque::new() }
    }

    /// Submit `commands`, after waiting for the oldest submission if [`MAX_IN_FLIGHT`] are in
    /// flight.
    pub(crate) fn submit(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        commands: wgpu::CommandBuffer,
    ) -> Result<(), Error> {
        while self.in_flight.len() >= MAX_IN_FLIGHT {
            let oldest = self.in_flight.pop_front().expect("in flight");
            wait_for(device, oldest)?;
        }
        self.in_flight.push_back(queue.submit([commands]));
        Ok(())
    }
}
