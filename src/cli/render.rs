//! `sppm-gpu SCENE -o OUT`: the render, paced by the device's completed passes
//! (`sppm_gpu::pacing`), with its progress bar, signals, checkpoints and lost-device recovery.

use super::args::load_scene;
use super::output::{self, Inputs, Kind};
use super::Cli;
use indicatif::{ProgressBar, ProgressStyle};
use sppm_gpu::checkpoint::Checkpoint;
use sppm_gpu::gpu::GpuContext;
use sppm_gpu::integrators::{self, light, shares::Choice, FirstPasses};
use sppm_gpu::pacing::{DeviceQueue, Goal, Pacer, PassQueue};
use sppm_gpu::scene::{self, Method, Named};
use sppm_gpu::{image_io, say, Error};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
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

/// SIGINT and SIGTERM. Before the first pass is submitted (loading the scene, compiling the
/// kernels) there is nothing to keep: a signal ends the process at once, saying where it was.
/// Once passes run, the first signal ends the render after the passes in flight (nothing more
/// is submitted) and the image of the passes done is written; a second exits at once. The
/// exit code is 130 or 143, as a shell reports a process killed by the signal.
struct Interrupt {
    /// Set by the first signal while rendering.
    pending: Arc<AtomicBool>,
    /// The number of the last signal received.
    signal: Arc<AtomicUsize>,
    /// What the run is doing before its passes, for the message; `None` once they run.
    stage: Arc<Mutex<Option<&'static str>>>,
}

/// The name of `signal` and the exit code that reports it.
fn signal_name(signal: i32) -> (&'static str, u8) {
    match signal {
        signal_hook::consts::SIGTERM => ("SIGTERM", 143),
        _ => ("SIGINT", 130),
    }
}

impl Interrupt {
    fn watch() -> Result<Self, Error> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let failed = |e: std::io::Error| Error::Setting(format!("cannot watch for Ctrl-C: {e}"));
        let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]).map_err(failed)?;
        let interrupt = Self {
            pending: Arc::new(AtomicBool::new(false)),
            signal: Arc::new(AtomicUsize::new(0)),
            stage: Arc::new(Mutex::new(Some("starting"))),
        };
        let (pending, signal, stage) = (interrupt.pending.clone(), interrupt.signal.clone(), interrupt.stage.clone());
        std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                for received in signals.forever() {
                    let (name, code) = signal_name(received);
                    let before_passes = *stage.lock().unwrap_or_else(|e| e.into_inner());
                    if let Some(doing) = before_passes {
                        eprintln!("interrupted by {name} while {doing}: nothing was rendered or written");
                    }
                    if before_passes.is_some() || pending.swap(true, Ordering::SeqCst) {
                        // _exit: no atexit handler runs under the driver's feet.
                        signal_hook::low_level::exit(code as i32);
                    }
                    // Said at once: a pass of billions of photons may take long to finish.
                    eprintln!(
                        "{name}: stopping after the passes in flight, then writing their image; another {name} exits at once"
                    );
                    signal.store(received as usize, Ordering::SeqCst);
                }
            })
            .map_err(failed)?;
        Ok(interrupt)
    }

    /// Says what the run is doing before its first pass.
    fn stage(&self, doing: &'static str) {
        *self.stage.lock().unwrap_or_else(|e| e.into_inner()) = Some(doing);
        Self::hold_for_a_test(doing);
    }

    /// Test hook: with `SPPM_GPU_HOLD` set to `doing` (a stage, or `after N passes`), say so
    /// on stderr and wait for a signal, so that a test signals the run at a stage it has
    /// seen rather than after a guessed sleep (tests/suite/outputs.rs).
    fn hold_for_a_test(doing: &str) {
        if std::env::var("SPPM_GPU_HOLD").is_ok_and(|hold| hold == doing) {
            eprintln!("held {doing} (SPPM_GPU_HOLD)");
            loop {
                std::thread::park();
            }
        }
    }

    /// From here passes run: the first signal ends the render gracefully.
    fn rendering(&self) {
        *self.stage.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }

    /// The signal's name and the exit code that reports it, once one has arrived.
    fn received(&self) -> Option<(&'static str, u8)> {
        if !self.pending.load(Ordering::SeqCst) {
            return None;
        }
        Some(signal_name(self.signal.load(Ordering::SeqCst) as i32))
    }
}

/// Render `scene_path` to `-o` and or `--partial`; `Some(code)` when a signal ended the
/// render early (its image is written all the same).
pub(crate) fn render(cli: &Cli, scene_path: &Path) -> Result<Option<u8>, Error> {
    let interrupt = Interrupt::watch()?;
    let default_output = (cli.output.is_none() && cli.partial.is_none()).then(|| free_name(scene_path));
    if let Some(path) = &default_output {
        eprintln!("note: no -o given: writing {}", path.display());
    }
    let output = cli.output.as_deref().or(default_output.as_deref());
    if cli.partial.is_some() && (cli.checkpoint.is_some() || cli.resume.is_some()) {
        return Err(Error::Setting("--partial renders a batch: it takes no --checkpoint or --resume".into()));
    }
    if cli.passes.is_some() && (cli.checkpoint.is_some() || cli.resume.is_some()) {
        return Err(Error::Setting("--passes renders a batch: it takes no --checkpoint or --resume".into()));
    }
    if cli.strategy_images && (cli.partial.is_some() || cli.passes.is_some() || cli.checkpoint.is_some() || cli.resume.is_some())
    {
        return Err(Error::Setting(
            "--strategy-images renders a whole image again per strategy: it takes no --passes, --partial, --checkpoint or --resume"
                .into(),
        ));
    }
    if !(cli.checkpoint_every >= 0.0 && cli.checkpoint_every.is_finite()) {
        return Err(Error::Setting(format!(
            "--checkpoint-every must be a number of seconds, 0 or more, got {}",
            cli.checkpoint_every
        )));
    }
    // What the run writes, checked before any work (src/cli/output.rs) and again once the
    // scene has named its files; a checkpoint resumed is an input unless it is the one written.
    let writes: Vec<(&Path, Kind)> =
        [(output, Kind::Image), (cli.partial.as_deref(), Kind::Partial), (cli.checkpoint.as_deref(), Kind::Checkpoint)]
            .into_iter()
            .filter_map(|(path, kind)| path.map(|p| (p, kind)))
            .collect();
    for (i, (a, _)) in writes.iter().enumerate() {
        if writes[..i].iter().any(|(b, _)| same_file(a, b)) {
            return Err(Error::Setting(format!("{}: named as two outputs of one run", a.display())));
        }
    }
    let resumed = cli.resume.as_deref().filter(|r| cli.checkpoint.as_deref().is_none_or(|c| !same_file(r, c)));
    let mut inputs = Inputs::of(std::iter::once(scene_path).chain(resumed));
    for &(path, kind) in &writes {
        output::check(path, kind, &inputs)?;
    }
    interrupt.stage("loading the scene");
    // Seconds of each phase before the passes, for --stats.
    let mut phases: Vec<(&str, f64)> = Vec::new();
    let mut clock = Instant::now();
    let mut lap = |phases: &mut Vec<(&str, f64)>, name| {
        phases.push((name, clock.elapsed().as_secs_f64()));
        clock = Instant::now();
    };
    let (mut scene, _) = load_scene(scene_path, &cli.overrides)?;
    lap(&mut phases, "load");
    if cli.overrides.time_limit.is_some() && cli.overrides.iterations.is_none() && cli.passes.is_none() {
        // --time-limit alone: as many passes as fit.
        scene.render.iterations = u32::MAX;
    }
    inputs.extend(scene.inputs.iter().cloned());
    let why = match (cli.overrides.method.is_some(), scene::is_mitsuba_xml(scene_path), scene::is_pbrt(scene_path)) {
        (true, _, _) => "--method",
        (false, true, _) => "the file's <integrator>; --method picks another",
        (false, _, true) => "the file's Integrator; --method picks another",
        (false, false, false) => "the scene's `method`; --method picks another",
    };
    eprintln!("rendering {} with {} ({why})", scene_path.display(), scene.render.method.name());
    let strategy_outputs = match (cli.strategy_images, output) {
        (true, Some(output)) => strategy_outputs(output, scene.render.method)?,
        _ => Vec::new(),
    };
    let mut checks = writes.clone();
    checks.extend(strategy_outputs.iter().map(|(_, p)| (p.as_path(), Kind::Image)));
    for &(path, kind) in &checks {
        output::check(path, kind, &inputs)?;
    }
    interrupt.stage("starting the GPU");
    let gpu = match &cli.adapter {
        Some(selector) => GpuContext::with_adapter(selector)?,
        None => GpuContext::new()?,
    };
    lap(&mut phases, "GPU start");
    scene.render.fit_pass_work(gpu.pass_work());
    integrators::check_memory(&gpu.device, &gpu.adapter_info, &scene, cli.memory_limit)?;
    for warning in integrators::limitations(&scene) {
        eprintln!("warning: {}: {warning}", scene.path.display());
    }
    // A resumed render is checked against its checkpoint before the kernels, and renders the
    // strategies vcm's pilot chose when it began, which the checkpoint keeps (under a time limit
    // the pilot's choice depends on the passes that fit, and a resumed run has its own limit).
    let fingerprint = sppm_gpu::checkpoint::Fingerprint::of(&scene);
    let resumed = match &cli.resume {
        Some(path) => {
            let cannot = |e| cannot_resume(path, e);
            let saved = sppm_gpu::checkpoint::read(path)?;
            saved.fingerprint.check(&fingerprint).map_err(cannot)?;
            let kept = saved.pilot.as_deref().map(str::parse::<Choice>).transpose().map_err(cannot)?;
            Some((path, saved.state, kept))
        }
        None => None,
    };
    let kept = resumed.as_ref().and_then(|(_, _, kept)| *kept).filter(|_| light::pilot_chooses_shares(&scene));
    if let Some(choice) = kept {
        choice.apply(&mut scene.render);
        eprintln!("note: vcm renders {choice} as its pilot chose when the render began (kept by the checkpoint)");
    }
    interrupt.stage("compiling the kernels");
    // Under a time limit the kernels are compiled first, so that the limit is spent on
    // passes (a first run on lavapipe compiles for seconds); otherwise the first pass does it.
    let (mut integrator, compile) = match scene.render.time_limit {
        Some(_) => {
            // A batch starts at its first pass: no pass before it.
            let first = if cli.passes.is_some() { FirstPasses::NotRun } else { FirstPasses::Checked };
            integrators::create_compiled(&gpu.device, &gpu.queue, &scene, first).map(|(i, s)| (i, Some(s)))?
        }
        None => (integrators::create(&gpu.device, &gpu.queue, &scene)?, None),
    };
    lap(&mut phases, if compile.is_some() { "scene, BVH, renderer and kernels" } else { "scene, BVH and renderer" });
    if let Some(seconds) = compile.filter(|&s| s >= 1.0) {
        eprintln!("note: compiled the kernels in {seconds:.1} s (cached for the next run); the time limit starts now");
    }
    for note in integrator.notes() {
        eprintln!("note: {note}");
    }
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
    let pilot = kept.or_else(|| integrator.pilot_choice());
    if let Some((path, state, _)) = &resumed {
        integrator.restore(state).map_err(|e| cannot_resume(path, e))?;
        eprintln!("resuming from {} after {} passes", path.display(), integrator.passes());
    }
    // The last checkpoint's state is also kept here: a lost device's render writes its image.
    let mut saved: Option<(u32, Vec<u8>)> = None;
    let mut save = |integrator: &mut dyn integrators::Integrator| -> Result<(), Error> {
        if let Some(path) = &cli.checkpoint {
            let state = integrator.state()?;
            let checkpoint = Checkpoint { fingerprint: fingerprint.clone(), state, pilot: pilot.map(|c| c.to_string()) };
            sppm_gpu::checkpoint::write(path, &checkpoint)?;
            let state = checkpoint.state;
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
    // Under a time limit the bar runs in milliseconds against it (or against the passes,
    // when they end the render first); otherwise in passes.
    let limit_ms = r.time_limit.map(|t| (t * 1e3) as u64);
    let progress = match limit_ms {
        Some(ms) => ProgressBar::new(ms)
            .with_style(ProgressStyle::with_template("{bar:40} {msg}  {elapsed_precise} (ETA {eta})").expect("valid template")),
        None => ProgressBar::new(end_pass as u64).with_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} passes  {msg}  {elapsed_precise} (ETA {eta})")
                .expect("valid template"),
        ),
    };
    let start = Instant::now();
    // Test hook: lose the device after this many passes of this run, as a driver crash or a
    // GPU reset would (tests/suite/checkpoint.rs).
    let lose_device_after: Option<u32> = std::env::var("SPPM_GPU_LOSE_DEVICE_AFTER").ok().and_then(|v| v.parse().ok());
    if limit_ms.is_none() {
        progress.set_position(first_pass as u64);
    }
    // Passes are submitted through a pacer and everything is judged on completed passes and
    // the time they completed (src/pacing.rs): the time limit, progress, Ctrl-C, checkpoints.
    // What the render spent before its first pass (vcm's pilot) counts against the limit.
    let setup = integrator.setup_seconds();
    let goal = Goal { end_pass, time_limit: r.time_limit.map(|t| (t - setup).max(0.0)) };
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
    interrupt.rendering();
    let hold_after: Option<u32> =
        std::env::var("SPPM_GPU_HOLD").ok().and_then(|hold| hold.strip_prefix("after ")?.strip_suffix(" passes")?.parse().ok());
    let paced = (|| -> Result<(), Error> {
        loop {
            if interrupt.received().is_some() {
                pacer.stop();
            }
            let Some(done) = pacer.next_completion()? else { break };
            gpu.check()?;
            if hold_after.is_some_and(|n| done.passes >= n) && interrupt.received().is_none() {
                // The test hook of `hold_for_a_test`, here until the first signal.
                eprintln!("held after {} passes (SPPM_GPU_HOLD)", done.passes);
                while interrupt.received().is_none() {
                    std::thread::park_timeout(std::time::Duration::from_millis(5));
                }
            }
            let work = (done.passes - first_pass) as u64 * work_per_pass;
            let rate = format!("{:.2} M {unit}/s", work as f64 / done.seconds / 1e6);
            match (limit_ms, r.time_limit) {
                (Some(ms), Some(limit)) => {
                    let by_passes = (done.passes - first_pass) as f64 / (end_pass - first_pass).max(1) as f64;
                    let fraction = (done.seconds / limit).max(by_passes).min(1.0);
                    progress.set_position((fraction * ms as f64) as u64);
                    progress.set_message(format!("{:.1}/{limit} s, {} passes, {rate}", done.seconds, done.passes));
                }
                _ => {
                    progress.set_position(done.passes as u64);
                    progress.set_message(rate);
                }
            }
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
    if let Some((name, code)) = interrupt.received() {
        // Stopped before a pass of this run completed: a batch has nothing of its own, a new
        // render nothing at all (a resumed one has the passes it resumed).
        if integrator.passes() == first_pass && (first_pass == 0 || cli.partial.is_some()) {
            progress.finish_and_clear();
            eprintln!("interrupted by {name} before the first pass completed: nothing was written");
            return Ok(Some(code));
        }
    }
    save(integrator.as_mut())?;
    let image = integrator.image()?;
    gpu.check()?;
    let seconds = start.elapsed().as_secs_f64();
    progress.finish_and_clear();

    let write_start = Instant::now();
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
        let splat = integrator.splat_sums()?;
        sppm_gpu::batch::write_partial(partial, &image, splat.as_ref(), first_pass, integrator.passes(), &fingerprint)?;
        written.push(format!("{} (passes {first_pass}..{})", partial.display(), integrator.passes()));
    }
    if !strategy_outputs.is_empty() && !integrator.splits_strategies() {
        eprintln!(
            "warning: --strategy-images: vcm's pilot chose photon mapping, sppm's estimator, whose image is not split by \
             strategy: no strategy images written (set --connect-share and --merge-share to render vcm's strategies)"
        );
    } else if !strategy_outputs.is_empty() && interrupt.received().is_none() {
        // One strategy's renderer after another, the same kernels: made once.
        sppm_gpu::gpu::share_kernels(|| -> Result<(), Error> {
            for (strategy, path) in &strategy_outputs {
                let share = strategy_image(&gpu, &scene, *strategy, integrator.passes(), pilot)?;
                if path.exists() {
                    eprintln!("note: replacing {}", path.display());
                }
                image_io::write_image(path, &share)?;
                written.push(path.display().to_string());
            }
            Ok(())
        })?;
    }
    for warning in integrator.warnings()? {
        eprintln!("warning: {warning}");
    }
    let work = (integrator.passes() - first_pass) as u64 * integrator.work_per_pass();
    let ended = match (interrupt.received(), r.time_limit) {
        (Some((name, _)), _) => format!("ended by {name}"),
        _ if integrator.passes() >= end_pass => format!("all {} passes done", end_pass - first_pass),
        (None, Some(limit)) => format!("ended by the time limit of {limit} s"),
        (None, None) => "ended early".to_string(),
    };
    say!(
        "{}: {} passes, {work} {unit} in {:.2} s ({:.2} M {unit}/s, {:.2} passes/s) -> {}; {ended}",
        r.method.name(),
        integrator.passes() - first_pass,
        seconds,
        work as f64 / seconds / 1e6,
        (integrator.passes() - first_pass) as f64 / seconds,
        written.join(" and ")
    );
    if cli.stats {
        phases.extend([("passes", seconds), ("image written", write_start.elapsed().as_secs_f64())]);
        let list: Vec<String> = phases.iter().map(|(name, s)| format!("{name} {s:.2} s")).collect();
        say!("time: {}", list.join(", "));
        match compile {
            Some(compile) => say!("kernels compiled in {compile:.2} s, before the time limit's clock started"),
            None => say!("kernels: compiled by the driver during the first pass (a --time-limit compiles them first)"),
        }
        say!(
            "in flight: at most {most_in_flight} passes (at most {most_submissions} submissions of up to {largest_group} passes)"
        );
        if let Some(radius) = integrator.radius_stats()? {
            say!("radius after the last pass: min {:.3e}, mean {:.3e}, max {:.3e}", radius.min, radius.mean, radius.max);
        }
        let memory = integrator.gpu_memory();
        if r.method == Method::Sppm && rows >= r.height && interrupt.received().is_none() {
            // Where a pass's time goes, each stage waited for: two more passes on a renderer
            // of their own, after the image is written.
            let mut sppm = sppm_gpu::integrators::Sppm::new(&gpu.device, &gpu.queue, &scene)?;
            sppm.run_pass()?;
            sppm.wait()?;
            let stage = super::bench::stage_times(&mut sppm, 2)?;
            let list: Vec<String> =
                super::bench::STAGES.iter().zip(stage).map(|(name, s)| format!("{name} {:.1} ms", 1e3 * s / 2.0)).collect();
            say!("a pass's stages (two passes timed after the render, each stage waited for): {}", list.join(", "));
        }
        print_memory(&memory);
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

/// The strategies of `method` and the file each one's share of `output` goes to
/// (`--strategy-images`): `OUT-emission.exr` beside `OUT.exr`, and so on.
fn strategy_outputs(output: &Path, method: Method) -> Result<Vec<(u32, std::path::PathBuf)>, Error> {
    use sppm_gpu::layout::{STRATEGY_CONNECT, STRATEGY_EMISSION, STRATEGY_LIGHT_TRACE, STRATEGY_MERGE, STRATEGY_NEE};
    let names: &[(u32, &str)] = match method {
        Method::Bpt => {
            &[(STRATEGY_EMISSION, "emission"), (STRATEGY_NEE, "nee"), (STRATEGY_CONNECT, "connect"), (STRATEGY_LIGHT_TRACE, "lt")]
        }
        Method::Vcm => &[
            (STRATEGY_EMISSION, "emission"),
            (STRATEGY_NEE, "nee"),
            (STRATEGY_CONNECT, "connect"),
            (STRATEGY_MERGE, "merge"),
            (STRATEGY_LIGHT_TRACE, "lt"),
        ],
        other => {
            return Err(Error::Setting(format!(
                "--strategy-images: method {} has no strategies to weigh against each other; use bpt or vcm",
                other.name()
            )))
        }
    };
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = output.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
    Ok(names.iter().map(|&(bit, name)| (bit, output.with_file_name(format!("{stem}-{name}.{ext}")))).collect())
}

/// The error of a render that cannot resume from the checkpoint at `path`, for `why`.
fn cannot_resume(path: &Path, why: impl std::fmt::Display) -> Error {
    Error::Setting(format!("{}: cannot resume: {why}", path.display()))
}

/// `passes` passes of `scene` keeping only `strategy`'s weighted contributions: its share of
/// the image the same passes and seed give.
fn strategy_image(
    gpu: &GpuContext,
    scene: &sppm_gpu::scene::Scene,
    strategy: u32,
    passes: u32,
    pilot: Option<Choice>,
) -> Result<image_io::Rgb32Image, Error> {
    let mut scene = scene.clone();
    // vcm's pilot's choice for the whole image (no pilot of its own for each strategy).
    if let Some(choice) = pilot.filter(|_| light::pilot_chooses_shares(&scene)) {
        choice.apply(&mut scene.render);
    }
    scene.render.strategies = strategy;
    scene.render.iterations = passes;
    scene.render.time_limit = None;
    let mut integrator = integrators::create(&gpu.device, &gpu.queue, &scene)?;
    for _ in 0..passes {
        integrator.run_pass()?;
    }
    let image = integrator.image()?;
    gpu.check()?;
    Ok(image)
}

/// The default output of `scene`: its name with `.exr` in the current directory, or the first
/// `NAME-N.exr` that does not exist.
fn free_name(scene: &Path) -> std::path::PathBuf {
    let stem = scene.file_stem().map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    std::iter::once(format!("{stem}.exr"))
        .chain((1..).map(|n| format!("{stem}-{n}.exr")))
        .map(std::path::PathBuf::from)
        .find(|p| p.symlink_metadata().is_err())
        .expect("a free name")
}

/// Whether `a` and `b` name one file (the same path, or the same file once resolved).
fn same_file(a: &Path, b: &Path) -> bool {
    a == b || a.canonicalize().is_ok_and(|a| b.canonicalize().is_ok_and(|b| a == b))
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
            say!("    {name:24} {:>10}", mib(b));
        }
    }
}
