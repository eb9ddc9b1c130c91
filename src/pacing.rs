//! Pacing: how a render's passes reach the device, and how the host knows which are done.
//!
//! `Queue::submit` returns at once on a GPU: a host that submits pass after pass queues
//! thousands ahead of the device, and every decision it takes by the passes *submitted* (a
//! time limit, progress, Ctrl-C, a checkpoint) is taken far too early, while the queue holds
//! commands and upload buffers without bound. (A CPU device such as lavapipe runs much of the
//! work inside the submit, which hides this.) A [`Pacer`] instead
//!
//! - keeps at most [`MAX_IN_FLIGHT`] submissions in flight: one running, one queued behind it,
//!   so the device never waits for the host while the host records the next;
//! - puts several passes into one submission where passes are short, about
//!   [`SUBMISSION_SECONDS`] of device time each (at most [`MAX_PASSES_PER_SUBMISSION`]), so
//!   the fixed cost of a submission and its wait is spread over many passes. Passes keep
//!   their indices and random numbers, so the image does not depend on the grouping, bit for
//!   bit;
//! - reports each submission's passes as they complete, with the time they completed: the
//!   caller judges progress, checkpoints and interrupts on those;
//! - keeps a time limit on completed passes: it starts no pass that would end more than half
//!   a pass past the limit (by the device time a pass took so far), so a render stops at the
//!   pass boundary nearest the limit; at least one pass is always run, so a single pass
//!   longer than the limit still gives an image. Once a limit is reached or [`Pacer::stop`]
//!   called, nothing more is submitted and the run ends when what is in flight completes.
//!
//! The scheduling is independent of wgpu ([`PassQueue`]): [`DeviceQueue`] submits an
//! integrator's passes to a device, and the tests drive a [`Pacer`] through a simulated
//! device and clock.

use std::collections::VecDeque;
use std::time::Instant;

use crate::error::Error;
use crate::integrators::Integrator;

pub use crate::gpu::submissions::{wait_for, MAX_IN_FLIGHT};

/// The device time one submission aims at: long beside the host's recording and a submit's
/// fixed cost (tens of microseconds), short enough that a stop waits for little.
pub const SUBMISSION_SECONDS: f64 = 0.02;

/// Passes one submission holds at most (each keeps a few small upload buffers alive until it
/// completes).
pub const MAX_PASSES_PER_SUBMISSION: u32 = 256;

/// Where a [`Pacer`] sends passes: records passes into one submission, and waits for one.
pub trait PassQueue {
    /// What identifies a submission to [`PassQueue::wait`] for.
    type Ticket;
    /// Record the next `count` passes into one submission and submit it.
    fn submit(&mut self, count: u32) -> Result<Self::Ticket, Error>;
    /// Block until the submission of `ticket` (and every one before it) has completed.
    fn wait(&mut self, ticket: Self::Ticket) -> Result<(), Error>;
    /// Seconds on the run's clock (a monotonic clock; the tests' is simulated).
    fn now(&self) -> f64;
}

/// Where a paced run stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Goal {
    /// The pass index to end before: passes up to `end_pass - 1` are run.
    pub end_pass: u32,
    /// Seconds of the run's clock, from the [`Pacer`]'s creation, after which no pass is
    /// started (see the module's rule).
    pub time_limit: Option<f64>,
}

/// Passes completed, as a [`Pacer`] reports them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Completed {
    /// Passes done (the integrator's count: a resumed render's earlier passes included).
    pub passes: u32,
    /// Passes this submission completed.
    pub new_passes: u32,
    /// When they completed, in seconds since the [`Pacer`] was made.
    pub seconds: f64,
}

/// Completions over which the device's seconds per pass are measured. A wait may return
/// later than its submission completed (a CPU device runs the next submission inside its
/// submit, before the host waits for the one before), which a span of several absorbs.
const WINDOW: usize = 8;

/// A submission in flight.
struct InFlight<T> {
    ticket: T,
    passes: u32,
}

/// Submits passes to a [`PassQueue`] under the rules of the module.
pub struct Pacer<Q: PassQueue> {
    queue: Q,
    goal: Goal,
    in_flight: VecDeque<InFlight<Q::Ticket>>,
    /// Passes submitted and completed, as pass indices (the integrator's count).
    submitted: u32,
    completed: u32,
    /// Passes this pacer has submitted.
    started: u32,
    /// Passes done before it.
    started_from: u32,
    /// When the last submission completed (0 before any).
    last_completion: f64,
    /// (time, passes completed) at the last completions, from when the device last started
    /// from idle: their span gives the device's seconds per pass.
    window: VecDeque<(f64, u32)>,
    /// The device's seconds per pass, measured over `window` (kept when it starts anew).
    seconds_per_pass: Option<f64>,
    stopping: bool,
    max_group: u32,
    most_passes_in_flight: u32,
    most_submissions_in_flight: usize,
    largest_group: u32,
}

impl<Q: PassQueue> Pacer<Q> {
    /// Pace `queue`'s passes towards `goal`; `passes_done` have been run before (a resumed
    /// render's, or a batch's first pass index).
    pub fn new(queue: Q, passes_done: u32, goal: Goal) -> Self {
        Self {
            queue,
            goal,
            in_flight: VecDeque::new(),
            submitted: passes_done,
            completed: passes_done,
            started: 0,
            started_from: passes_done,
            last_completion: 0.0,
            window: VecDeque::new(),
            seconds_per_pass: None,
            stopping: false,
            max_group: MAX_PASSES_PER_SUBMISSION,
            most_passes_in_flight: 0,
            most_submissions_in_flight: 0,
            largest_group: 0,
        }
    }

    /// At most `passes` passes a submission (at least 1): one a submission makes every pass
    /// a point where the caller can act (the lost-device test hook does).
    pub fn with_max_group(mut self, passes: u32) -> Self {
        self.max_group = passes.clamp(1, MAX_PASSES_PER_SUBMISSION);
        self
    }

    /// Submit nothing more: what is in flight completes, and [`Pacer::next_completion`] returns `None`
    /// after it.
    pub fn stop(&mut self) {
        self.stopping = true;
    }

    /// Whether no more passes will be submitted: the goal's passes are all submitted, the
    /// time is up or [`Pacer::stop`] was called.
    pub fn stopped(&self) -> bool {
        self.stopping || self.submitted >= self.goal.end_pass
    }

    /// Submit while there is room and passes to run, then wait for the oldest submission in
    /// flight: the passes done after it. `None` once nothing is in flight and nothing more
    /// will be submitted.
    pub fn next_completion(&mut self) -> Result<Option<Completed>, Error> {
        while self.in_flight.len() < MAX_IN_FLIGHT {
            let now = self.queue.now();
            let count = self.group(now);
            if count == 0 {
                break;
            }
            if self.in_flight.is_empty() {
                // The device starts from idle: time before now is not its work.
                self.window.clear();
                self.window.push_back((now, self.completed));
            }
            let ticket = self.queue.submit(count)?;
            self.in_flight.push_back(InFlight { ticket, passes: count });
            self.submitted += count;
            self.started += count;
            self.largest_group = self.largest_group.max(count);
            self.most_submissions_in_flight = self.most_submissions_in_flight.max(self.in_flight.len());
            self.most_passes_in_flight = self.most_passes_in_flight.max(self.passes_in_flight());
        }
        let Some(oldest) = self.in_flight.pop_front() else { return Ok(None) };
        self.queue.wait(oldest.ticket)?;
        let now = self.queue.now();
        self.last_completion = now;
        self.completed += oldest.passes;
        self.window.push_back((now, self.completed));
        if self.window.len() > WINDOW + 1 {
            self.window.pop_front();
        }
        let (&(t0, p0), &(t1, p1)) = (self.window.front().expect("a start"), self.window.back().expect("this"));
        if p1 > p0 {
            self.seconds_per_pass = Some((t1 - t0).max(0.0) / (p1 - p0) as f64);
        }
        if self.completed == self.started_from + oldest.passes {
            // The run's first submission also paid for the driver's compiling the kernels at
            // their first dispatch: later spans leave it out.
            self.window.clear();
            self.window.push_back((now, self.completed));
        }
        if self.goal.time_limit.is_some_and(|limit| now >= limit) {
            self.stopping = true;
        }
        Ok(Some(Completed { passes: self.completed, new_passes: oldest.passes, seconds: now }))
    }

    /// Wait for everything in flight, submitting nothing more for now (before reading the
    /// integrator's state): the last completion, if anything was in flight.
    pub fn drain(&mut self) -> Result<Option<Completed>, Error> {
        let stopping = std::mem::replace(&mut self.stopping, true);
        let mut last = None;
        while !self.in_flight.is_empty() {
            last = self.next_completion()?;
        }
        self.stopping = stopping || self.goal.time_limit.is_some_and(|limit| self.last_completion >= limit);
        Ok(last)
    }

    /// Passes in the submissions in flight.
    pub fn passes_in_flight(&self) -> u32 {
        self.in_flight.iter().map(|f| f.passes).sum()
    }

    /// The most passes that were in flight at once.
    pub fn most_passes_in_flight(&self) -> u32 {
        self.most_passes_in_flight
    }

    /// The most submissions that were in flight at once (at most [`MAX_IN_FLIGHT`]).
    pub fn most_submissions_in_flight(&self) -> usize {
        self.most_submissions_in_flight
    }

    /// The most passes one submission held.
    pub fn largest_group(&self) -> u32 {
        self.largest_group
    }

    /// Passes completed (the integrator's count).
    pub fn completed(&self) -> u32 {
        self.completed
    }

    /// The queue, to reach what it submits for (the integrator).
    pub fn queue(&mut self) -> &mut Q {
        &mut self.queue
    }

    /// The queue back.
    pub fn into_queue(self) -> Q {
        self.queue
    }

    /// Passes the next submission holds at `now`: 0 to submit nothing now.
    fn group(&mut self, now: f64) -> u32 {
        let left = self.goal.end_pass.saturating_sub(self.submitted);
        if left == 0 || self.stopping {
            return 0;
        }
        // Until a pass has completed its cost is unknown (and may exceed any limit): one at
        // a time.
        let Some(d) = self.seconds_per_pass else {
            return u32::from(self.in_flight.is_empty());
        };
        let d = d.max(1e-9);
        let mut count = ((SUBMISSION_SECONDS / d) as u32).clamp(1, self.max_group);
        if let Some(limit) = self.goal.time_limit {
            // The device is busy until the passes in flight are done, then runs these. Start
            // a pass only if it ends before the limit plus half a pass: the run then stops at
            // the pass boundary nearest the limit.
            let start = (self.last_completion + self.passes_in_flight() as f64 * d).max(now);
            let fit = ((limit - start) / d + 0.5).floor();
            if fit < 1.0 {
                if self.started == 0 {
                    return 1;
                }
                // With passes in flight, judge again when the next completes (the estimate
                // may have been high); with none, the run is over.
                if self.in_flight.is_empty() {
                    self.stopping = true;
                }
                return 0;
            }
            count = count.min(fit.min(u32::MAX as f64) as u32);
        }
        count.min(left)
    }
}

/// The [`PassQueue`] of an integrator on its device: each submission is one command buffer
/// holding `count` whole passes ([`Integrator::record_pass`]), and a wait polls the device
/// for that submission.
pub struct DeviceQueue<'a> {
    integrator: &'a mut dyn Integrator,
    device: wgpu::Device,
    queue: wgpu::Queue,
    start: Instant,
}

impl<'a> DeviceQueue<'a> {
    /// Submit `integrator`'s passes on `device`'s `queue` (the ones it was made on); the clock
    /// starts now.
    pub fn new(integrator: &'a mut dyn Integrator, device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        Self { integrator, device: device.clone(), queue: queue.clone(), start: Instant::now() }
    }

    /// The integrator.
    pub fn integrator(&mut self) -> &mut dyn Integrator {
        self.integrator
    }

    /// The device.
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }
}

impl PassQueue for DeviceQueue<'_> {
    type Ticket = wgpu::SubmissionIndex;

    fn submit(&mut self, count: u32) -> Result<wgpu::SubmissionIndex, Error> {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("passes") });
        for _ in 0..count {
            self.integrator.record_pass(&mut encoder);
        }
        Ok(self.queue.submit([encoder.finish()]))
    }

    fn wait(&mut self, ticket: wgpu::SubmissionIndex) -> Result<(), Error> {
        wait_for(&self.device, ticket)
    }

    fn now(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A simulated device: each pass takes `pass_seconds` of device time, recording one takes
    /// `record_seconds` of the host's. With `in_submit` the work runs inside the submit, as
    /// on a CPU device; else the device runs submissions one after another in the background.
    struct Sim {
        pass_seconds: Vec<f64>,
        record_seconds: f64,
        in_submit: bool,
        clock: f64,
        /// When the device is done with everything submitted.
        device_free: f64,
        passes: u32,
        /// Passes submitted and not waited for, and the most there ever were.
        outstanding: VecDeque<(u32, f64)>,
        most_outstanding: u32,
        submissions: Vec<u32>,
    }

    impl Sim {
        fn new(pass_seconds: f64, in_submit: bool) -> Self {
            Self::varying(vec![pass_seconds], in_submit)
        }
        /// Pass `i` takes `pass_seconds[min(i, len - 1)]`.
        fn varying(pass_seconds: Vec<f64>, in_submit: bool) -> Self {
            Self {
                pass_seconds,
                record_seconds: 20e-6,
                in_submit,
                clock: 0.0,
                device_free: 0.0,
                passes: 0,
                outstanding: VecDeque::new(),
                most_outstanding: 0,
                submissions: Vec::new(),
            }
        }
        fn cost(&self, pass: u32) -> f64 {
            self.pass_seconds[(pass as usize).min(self.pass_seconds.len() - 1)]
        }
    }

    impl PassQueue for Sim {
        /// When the submission completes.
        type Ticket = f64;
        fn submit(&mut self, count: u32) -> Result<f64, Error> {
            self.clock += self.record_seconds * count as f64;
            let work: f64 = (self.passes..self.passes + count).map(|p| self.cost(p)).sum();
            self.passes += count;
            self.device_free = self.device_free.max(self.clock) + work;
            if self.in_submit {
                self.clock = self.device_free;
            }
            self.outstanding.push_back((count, self.device_free));
            let n: u32 = self.outstanding.iter().map(|o| o.0).sum();
            self.most_outstanding = self.most_outstanding.max(n);
            self.submissions.push(count);
            Ok(self.device_free)
        }
        fn wait(&mut self, done: f64) -> Result<(), Error> {
            self.clock = self.clock.max(done);
            self.outstanding.retain(|o| o.1 > done);
            Ok(())
        }
        fn now(&self) -> f64 {
            self.clock
        }
    }

    /// Run to the end; (passes completed, the clock at the end, completions seen).
    fn run(pacer: &mut Pacer<Sim>) -> (u32, f64, Vec<Completed>) {
        let mut seen = Vec::new();
        while let Some(c) = pacer.next_completion().unwrap() {
            seen.push(c);
        }
        (pacer.completed(), pacer.queue().clock, seen)
    }

    #[test]
    fn no_more_than_two_submissions_are_ever_in_flight() {
        // 1 ms passes on a device that runs them behind the host's back: without the wait
        // the host would queue all 10,000 at once.
        let mut pacer = Pacer::new(Sim::new(1e-3, false), 0, Goal { end_pass: 10_000, time_limit: None });
        let (done, _, seen) = run(&mut pacer);
        assert_eq!(done, 10_000);
        assert_eq!(pacer.queue().passes, 10_000);
        assert!(pacer.most_submissions_in_flight() <= MAX_IN_FLIGHT);
        let most = pacer.queue().most_outstanding;
        assert_eq!(most, pacer.most_passes_in_flight());
        // Two submissions of about SUBMISSION_SECONDS each.
        assert!(most <= 2 * (SUBMISSION_SECONDS / 1e-3) as u32, "{most} passes were in flight");
        // Completions count up to the goal, each at a later time.
        assert!(seen.windows(2).all(|w| w[1].passes == w[0].passes + w[1].new_passes && w[1].seconds >= w[0].seconds));
    }

    #[test]
    fn short_passes_share_a_submission_and_keep_the_device_busy() {
        let mut pacer = Pacer::new(Sim::new(1e-3, false), 0, Goal { end_pass: 2_000, time_limit: None });
        let (_, clock, _) = run(&mut pacer);
        let largest = pacer.largest_group();
        let groups = &pacer.queue().submissions;
        assert_eq!(groups[0], 1, "the first pass goes alone: its cost is unknown");
        assert!((19..=20).contains(&largest), "{groups:?}");
        // The device never waited for the host: 2,000 passes of 1 ms, plus the first
        // pass's recording.
        assert!(clock < 2.0 + 1e-3, "{clock}");
        // Long passes go one a submission.
        let mut pacer = Pacer::new(Sim::new(0.5, false), 0, Goal { end_pass: 8, time_limit: None });
        run(&mut pacer);
        assert_eq!(pacer.queue().submissions, vec![1; 8]);
    }

    #[test]
    fn the_time_limit_is_kept_on_a_device_that_runs_behind_the_host() {
        for pass_seconds in [1e-4, 3.8e-3, 0.05, 0.3] {
            for in_submit in [false, true] {
                let mut pacer =
                    Pacer::new(Sim::new(pass_seconds, in_submit), 0, Goal { end_pass: u32::MAX, time_limit: Some(5.0) });
                let (done, clock, seen) = run(&mut pacer);
                // Ended at the pass boundary nearest the limit, within half a pass and the
                // passes' recording; where the work runs inside the submit, the passes in
                // flight are done before the host waits for them, and the run may end a pass
                // early.
                let slack = if in_submit { pass_seconds } else { pass_seconds / 2.0 };
                assert!(
                    (clock - 5.0).abs() <= slack + 1e-3,
                    "{pass_seconds} s passes (in submit: {in_submit}): ended at {clock}"
                );
                assert_eq!(seen.last().unwrap().seconds, clock);
                assert_eq!(done, pacer.queue().passes, "every pass submitted completed");
            }
        }
    }

    #[test]
    fn a_pass_longer_than_the_limit_runs_once() {
        // 100 s passes under a 60 s limit (a Mitsuba 0.5 file's 5M photons on a CPU device):
        // one pass, not two.
        for in_submit in [false, true] {
            let mut pacer = Pacer::new(Sim::new(100.0, in_submit), 0, Goal { end_pass: 1_000, time_limit: Some(60.0) });
            let (done, clock, _) = run(&mut pacer);
            assert_eq!((done, clock), (1, 100.0 + 20e-6));
        }
        // 40 s passes: the second would end at 80 s, 20 s past the limit and more than half
        // a pass; it is not started.
        let mut pacer = Pacer::new(Sim::new(40.0, false), 0, Goal { end_pass: 1_000, time_limit: Some(60.0) });
        assert_eq!(run(&mut pacer).0, 1);
        // 30 s passes: the second ends at 60 s.
        let mut pacer = Pacer::new(Sim::new(30.0, false), 0, Goal { end_pass: 1_000, time_limit: Some(60.0) });
        assert_eq!(run(&mut pacer).0, 2);
    }

    #[test]
    fn a_stop_ends_the_run_after_what_is_in_flight() {
        let mut pacer = Pacer::new(Sim::new(1e-3, false), 0, Goal { end_pass: u32::MAX, time_limit: None });
        let mut last = 0.0;
        while let Some(c) = pacer.next_completion().unwrap() {
            last = c.seconds;
            if c.seconds >= 1.0 && !pacer.stopped() {
                pacer.stop();
                last = c.seconds;
                // What is in flight is at most two submissions' worth of device time.
                let left = pacer.passes_in_flight() as f64 * 1e-3;
                assert!(left <= 2.0 * SUBMISSION_SECONDS + 1e-9, "{left} s in flight");
            }
        }
        assert!(last < 1.0 + 2.0 * SUBMISSION_SECONDS + 2e-3, "ended at {last}");
        assert_eq!(pacer.completed(), pacer.queue().passes);
    }

    #[test]
    fn batches_and_resumed_runs_end_exactly_at_their_pass() {
        let mut pacer = Pacer::new(Sim::new(2e-4, false), 37, Goal { end_pass: 1_000, time_limit: None });
        let (done, _, seen) = run(&mut pacer);
        assert_eq!((done, pacer.queue().passes), (1_000, 963));
        assert_eq!(seen.first().unwrap().passes, 38);
    }

    #[test]
    fn a_drain_waits_for_everything_and_the_run_goes_on() {
        let mut pacer = Pacer::new(Sim::new(1e-3, false), 0, Goal { end_pass: 500, time_limit: None });
        pacer.next_completion().unwrap();
        pacer.next_completion().unwrap();
        pacer.drain().unwrap();
        assert_eq!(pacer.passes_in_flight(), 0);
        assert_eq!(pacer.completed(), pacer.queue().passes);
        assert!(!pacer.stopped());
        assert_eq!(run(&mut pacer).0, 500);
    }

    #[test]
    fn passes_that_grow_slower_do_not_overrun_the_limit_by_more_than_in_flight() {
        // The first passes are fast, the later ones 50x slower (a camera moving into a
        // complex part of the scene): the estimate lags by one submission at most.
        let costs: Vec<f64> = (0..2_000).map(|i| if i < 1_000 { 1e-3 } else { 5e-2 }).collect();
        let mut pacer = Pacer::new(Sim::varying(costs, false), 0, Goal { end_pass: u32::MAX, time_limit: Some(3.0) });
        let (_, clock, _) = run(&mut pacer);
        assert!(clock <= 3.0 + 2.0 * 20.0 * 5e-2, "{clock}");
    }
}
