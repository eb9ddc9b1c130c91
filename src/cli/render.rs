//! `sppm-gpu SCENE -o OUT`: the render, paced by the device's completed passes
//! (`sppm_gpu::pacing`), with its progress bar, signals, checkpoints and lost-device recovery.

use super::args::{check_output, load_scene};
use super::Cli;
use indicatif::{ProgressBar, ProgressStyle};
use sppm_gpu::gpu::GpuContext;
use sppm_gpu::integrators;
use sppm_gpu::pacing::{DeviceQueue, Goal, Pacer, PassQueue};
use sppm_gpu::scene::Method;
use sppm_gpu::{experiments, image_io, say, Error};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// A render stopped by a device error (a lost device, an exhausted GPU): the image of the
/// passes done is written if the device can still give it back, else the image of the last
/// checkpoint (`(path, (passes, state))`), computed on the host; the error says what was kept
/// and that `--resume` goes on from the checkpoint.
fn after_a_device_error(
    error: Error,
    integrator: &mut dyn integrators::Integrator,
    gpu: &GpuContext,
    output: Option<&Path>,
    checkpoint: Option<(&Path, &(u32, Vec<u8>))>,
) -> Error {
    // A lost device reports the loss when polled; it is then the error to give.
    let _ = gpu.device.poll(wgpu::PollType::Poll);
    let error = gpu.check().err().map(Error::from).unwrap_or(error);
    let Some(output) = output else {
        return Error::Setting(format!("{error}; the batch's passes are lost: render the batch again"));
    };
    let passes = integrator.passes();
    let write = |image: &sppm_gpu::image_io::Rgb32Image, passes: u32, whose: &str| match image_io::write_image(output, image) {
        Ok(()) => format!("the image of the {passes} passes {whose} was written to {}", output.display()),
        Err(e) => format!("the image of the passes {whose} could not be written: {e}"),
    };
    let kept = match (integrator.image().and_then(|image| Ok(gpu.check().map(|()| image)?)), checkpoint) {
        (Ok(image), _) if passes > 0 => write(&image, passes, "before it"),
        (_, Some((_, (passes, state)))) => match integrator.image_of_state(state) {
            Ok(image) => write(&image, *passes, "of the last checkpoint"),
            Err(e) => format!("the last checkpoint's image could not be made: {e}"),
        },
        _ => "the device could not give back the image of the passes before it (--checkpoint keeps them)".to_string(),
    };
    let resume = match checkpoint {
        Some((path, _)) => format!("; --resume {} goes on from the last checkpoint", path.display()),
        None => String::new(),
    };
    Error::Setting(format!("{error}; {kept}{resume}"))
}

/// SIGINT and SIGTERM during a render: the first ends it after the passes in flight (nothing
/// more is submitted), and the image of the passes done is written; a second exits at once (130 or 143, as a shell
/// reports a process killed by the signal).
struct Interrupt {
    /// Set by the first signal.
    pending: Arc<AtomicBool>,
    /// The number of the last signal received.
    signal: Arc<AtomicUsize>,
}

impl Interrupt {
    fn watch() -> Result<Self, Error> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let pending = Arc::new(AtomicBool::new(false));
        let signal = Arc::new(AtomicUsize::new(0));
        let failed = |e: std::io::Error| Error::Setting(format!("cannot watch for Ctrl-C: {e}"));
        for (sig, code) in [(SIGINT, 130), (SIGTERM, 143)] {
            // In this order: a signal that finds `pending` set exits; the first sets it.
            signal_hook::flag::register_conditional_shutdown(sig, code, Arc::clone(&pending)).map_err(failed)?;
            signal_hook::flag::register(sig, Arc::clone(&pending)).map_err(failed)?;
            signal_hook::flag::register_usize(sig, Arc::clone(&signal), sig as usize).map_err(failed)?;
        }
        Ok(Self { pending, signal })
    }

    /// The signal's name and the exit code that reports it, once one has arrived.
    fn received(&self) -> Option<(&'static str, u8)> {
        if !self.pending.load(Ordering::SeqCst) {
            return None;
        }
        Some(match self.signal.load(Ordering::SeqCst) as i32 {
            signal_hook::consts::SIGTERM => ("SIGTERM", 143),
            _ => ("SIGINT", 130),
        })
    }
}

/// Render `scene_path` to `-o` and or `--partial`; `Some(code)` when a signal ended the
/// render early (its image is written all the same).
pub(crate) fn render(cli: &Cli, scene_path: &Path) -> Result<Option<u8>, Error> {
    let interrupt = Interrupt::watch()?;
    let output = cli.output.as_deref();
    for path in output.into_iter().chain(cli.partial.as_deref()) {
        check_output(path, scene_path)?;
    }
    if let Some(partial) = &cli.partial {
        if !partial.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")) {
            return Err(Error::Setting(format!("{}: a partial image is an .exr file", partial.display())));
        }
        if cli.checkpoint.is_some() || cli.resume.is_some() {
            return Err(Error::Setting("--partial renders a batch: it takes no --checkpoint or --resume".into()));
        }
    }
    if cli.passes.is_some() && (cli.checkpoint.is_some() || cli.resume.is_some()) {
        return Err(Error::Setting("--passes renders a batch: it takes no --checkpoint or --resume".into()));
    }
    let (mut scene, _) = load_scene(scene_path, &cli.overrides)?;
    let gpu = match &cli.adapter {
        Some(selector) => GpuContext::with_adapter(selector)?,
        None => GpuContext::new()?,
    };
    scene.render.fit_pass_work(gpu.pass_work());
    integrators::check_memory(&gpu.device, &gpu.adapter_info, &scene, cli.memory_limit)?;
    for warning in integrators::limitations(&scene) {
        eprintln!("warning: {}: {warning}", scene.path.display());
    }
    let mut integrator = integrators::create(&gpu.device, &gpu.queue, &scene)?;
    let r = &scene.render;
    let rows = integrators::max_rows(&gpu.device, &scene);
    if rows < r.height {
        eprintln!(
            "note: a {}x{} image (spp {}) exceeds one storage buffer on this device: rendering in bands of {rows} rows{}",
            r.width,
            r.height,
            r.spp,
            if r.method == Method::Sppm { ", each tracing every pass's photons" } else { "" }
        );
    }
    let fingerprint = sppm_gpu::checkpoint::Fingerprint::of(&scene);
    if let Some(path) = &cli.resume {
        let (saved, state) = sppm_gpu::checkpoint::read(path)?;
        saved.check(&fingerprint).map_err(|e| Error::Setting(format!("{}: cannot resume: {e}", path.display())))?;
        integrator.restore(&state).map_err(|e| Error::Setting(format!("{}: cannot resume: {e}", path.display())))?;
        eprintln!("resuming from {} after {} passes", path.display(), integrator.passes());
    }
    // The last checkpoint's state is also kept here: a lost device's render writes its image.
    let mut saved: Option<(u32, Vec<u8>)> = None;
    let mut save = |integrator: &mut dyn integrators::Integrator| -> Result<(), Error> {
        if let Some(path) = &cli.checkpoint {
            let state = integrator.state()?;
            sppm_gpu::checkpoint::write(path, &fingerprint, &state)?;
            saved = Some((integrator.passes(), state));
        }
        Ok(())
    };
    let mut last_checkpoint = Instant::now();
    let unit = integrator.work_unit();
    // A batch runs passes first..end of the render; a whole render 0..iterations.
    let end_pass = match cli.passes {
        Some((first, end)) => {
            integrator.start_at_pass(first)?;
            end
        }
        None => r.iterations,
    };

    // Passes of this run: a resumed render's rates count only these.
    let first_pass = integrator.passes();
    let progress = ProgressBar::new(end_pass as u64);
    progress.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} passes  {msg}  {elapsed_precise} (ETA {eta})")
            .expect("valid template"),
    );
    let start = Instant::now();
    // Test hook: lose the device after this many passes of this run, as a driver crash or a
    // GPU reset would (tests/suite/checkpoint.rs).
    let lose_device_after: Option<u32> = std::env::var("SPPM_GPU_LOSE_DEVICE_AFTER").ok().and_then(|v| v.parse().ok());
    progress.set_position(first_pass as u64);
    // Passes are submitted through a pacer and everything is judged on completed passes and
    // the time they completed (src/pacing.rs): the time limit, progress, Ctrl-C, checkpoints.
    let goal = Goal { end_pass, time_limit: r.time_limit };
    let mut pacer = Pacer::new(
        Losing {
            inner: DeviceQueue::new(integrator.as_mut(), &gpu.device, &gpu.queue),
            at: lose_device_after.map(|n| first_pass + n),
        },
        first_pass,
        goal,
    );
    if lose_device_after.is_some() {
        pacer = pacer.with_max_group(1);
    }
    let work_per_pass = pacer.queue().inner.integrator().work_per_pass();
    let paced = (|| -> Result<(), Error> {
        loop {
            if interrupt.received().is_some() {
                pacer.stop();
            }
            let Some(done) = pacer.next_completion()? else { break };
            gpu.check()?;
            let work = (done.passes - first_pass) as u64 * work_per_pass;
            progress.set_position(done.passes as u64);
            progress.set_message(format!("{:.2} M {unit}/s", work as f64 / done.seconds / 1e6));
            if cli.checkpoint.is_some() && last_checkpoint.elapsed().as_secs_f64() >= cli.checkpoint_every {
                pacer.drain()?;
                gpu.check()?;
                save(pacer.queue().inner.integrator())?;
                last_checkpoint = Instant::now();
            }
        }
        Ok(())
    })();
    let (most_in_flight, most_submissions, largest_group) =
        (pacer.most_passes_in_flight(), pacer.most_submissions_in_flight(), pacer.largest_group());
    drop(pacer);
    if let Err(e) = paced {
        progress.finish_and_clear();
        let last = cli.checkpoint.as_deref().zip(saved.as_ref());
        return Err(after_a_device_error(e, integrator.as_mut(), &gpu, output, last));
    }
    save(integrator.as_mut())?;
    let image = integrator.image()?;
    gpu.check()?;
    let seconds = start.elapsed().as_secs_f64();
    progress.finish_and_clear();

    let mut written: Vec<String> = Vec::new();
    if let Some(output) = output {
        if output.exists() {
            eprintln!("note: replacing {}", output.display());
        }
        image_io::write_image(output, &image)?;
        written.push(output.display().to_string());
    }
    if let Some(partial) = &cli.partial {
        if partial.exists() {
            eprintln!("note: replacing {}", partial.display());
        }
        sppm_gpu::batch::write_partial(partial, &image, first_pass, integrator.passes(), &fingerprint)?;
        written.push(format!("{} (passes {first_pass}..{})", partial.display(), integrator.passes()));
    }
    let work = (integrator.passes() - first_pass) as u64 * integrator.work_per_pass();
    say!(
        "{}: {} passes, {work} {unit} in {:.2} s ({:.2} M {unit}/s, {:.2} passes/s) -> {}",
        experiments::method_name(r.method),
        integrator.passes() - first_pass,
        seconds,
        work as f64 / seconds / 1e6,
        (integrator.passes() - first_pass) as f64 / seconds,
        written.join(" and ")
    );
    if cli.stats {
        say!(
            "in flight: at most {most_in_flight} passes (at most {most_submissions} submissions of up to {largest_group} passes)"
        );
        print_memory(&integrator.gpu_memory());
    }
    let interrupted = interrupt.received();
    if let Some((name, _)) = interrupted {
        eprintln!(
            "interrupted by {name} after {} of {} passes: wrote the image of those to {}",
            integrator.passes(),
            end_pass,
            written.join(" and ")
        );
    }
    Ok(interrupted.map(|(_, code)| code))
}

/// The render's queue, which loses the device before submitting pass `at` (a test hook).
struct Losing<'a> {
    inner: DeviceQueue<'a>,
    at: Option<u32>,
}

impl PassQueue for Losing<'_> {
    type Ticket = wgpu::SubmissionIndex;
    fn submit(&mut self, count: u32) -> Result<wgpu::SubmissionIndex, Error> {
        if self.at == Some(self.inner.integrator().passes()) {
            self.inner.device().destroy();
        }
        self.inner.submit(count)
    }
    fn wait(&mut self, ticket: wgpu::SubmissionIndex) -> Result<(), Error> {
        self.inner.wait(ticket)
    }
    fn now(&self) -> f64 {
        self.inner.now()
    }
}

/// The `--stats` table: every buffer, largest first, under its part.
fn print_memory(memory: &integrators::GpuMemory) {
    let mib = |b: u64| match b {
        0..0x10_0000 => format!("{:.1} KiB", b as f64 / 1024.0),
        _ => format!("{:.1} MiB", b as f64 / (1u64 << 20) as f64),
    };
    say!("GPU memory: {}", mib(memory.total()));
    for (part, buffers, bytes) in
        [("scene", &memory.scene, memory.scene_bytes()), ("renderer", &memory.renderer, memory.renderer_bytes())]
    {
        say!("  {part}: {}", mib(bytes));
        let mut sorted = buffers.clone();
        sorted.sort_by_key(|(_, bytes)| std::cmp::Reverse(*bytes));
        for (name, b) in sorted {
            say!("    {name:24} {:>12} bytes", b);
        }
    }
}
