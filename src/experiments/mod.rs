//! Experiments behind `docs/experiments.md`: equal-time comparisons of the integrators
//! (`compare`), parameter sweeps of SPPM (`sweep`), and images and timings over passes
//! (`passes`). Each writes a CSV table and its figures (PNG) into one folder.
//!
//! Time is the wall time of the passes alone: passes run through a [`Pacer`], which keeps the
//! device busy (several passes a submission where they are short, the next submission queued
//! while one runs), and the clock runs from a run's first submission until its last
//! completion; it stops while a snapshot is read back and measured. Setting up an integrator
//! (scene upload, kernel creation) is not counted.

pub mod plot;

use crate::error::Error;
use crate::gpu::GpuContext;
use crate::image_io::{self, Rgb32Image};
use crate::integrators::{self, Integrator};
use crate::metrics;
use crate::pacing::{DeviceQueue, Goal, Pacer};
use crate::scene::{DirectLight, Method, Named, RadiusRule, RadiusSchedule, RenderSettings, Scene};
use indicatif::{ProgressBar, ProgressStyle};
use plot::{Chart, Series, Tile};
use std::path::{Path, PathBuf};

/// A method as [`compare`] runs it: the integrator, for SPPM where its direct light comes
/// from, and the sampler. Named like the method, with `sppm-photons` for SPPM with direct
/// light from photons alone (`direct = "photons"`), and `/independent` or `/sobol` after the
/// name for a sampler other than the scene's (`pt-nee/sobol`), so that one run can set the
/// samplers side by side; `sppm-shrink` and `sppm-adaptive` are SPPM with that
/// [`RadiusRule`] rather than the scene's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    /// The integrator.
    pub method: Method,
    /// SPPM's source of direct light (ignored by the path tracers).
    pub direct: DirectLight,
    /// The sampler, or `None` for the scene's.
    pub sampler: Option<crate::sampler::Sampler>,
    /// SPPM's radius rule, or `None` for the scene's.
    pub radius_rule: Option<crate::scene::RadiusRule>,
}

/// [`Variant::name`]s: a row per variant of [`Variant::ALL`], a column per sampler (the
/// scene's, independent, sobol).
const VARIANT_NAMES: [[&str; 3]; 9] = [
    ["sppm", "sppm/independent", "sppm/sobol"],
    ["sppm-photons", "sppm-photons/independent", "sppm-photons/sobol"],
    ["pt", "pt/independent", "pt/sobol"],
    ["pt-nee", "pt-nee/independent", "pt-nee/sobol"],
    ["sppm-shrink", "sppm-shrink/independent", "sppm-shrink/sobol"],
    ["sppm-adaptive", "sppm-adaptive/independent", "sppm-adaptive/sobol"],
    ["lt", "lt/independent", "lt/sobol"],
    ["bpt", "bpt/independent", "bpt/sobol"],
    ["vcm", "vcm/independent", "vcm/sobol"],
];

impl Variant {
    /// Every variant, in the order of [`Variant::name`]'s list.
    pub const ALL: [Variant; 9] = [
        Variant { method: Method::Sppm, direct: DirectLight::Sampled, sampler: None, radius_rule: None },
        Variant { method: Method::Sppm, direct: DirectLight::Photons, sampler: None, radius_rule: None },
        Variant { method: Method::Pt, direct: DirectLight::Sampled, sampler: None, radius_rule: None },
        Variant { method: Method::PtNee, direct: DirectLight::Sampled, sampler: None, radius_rule: None },
        Variant { method: Method::Sppm, direct: DirectLight::Sampled, sampler: None, radius_rule: Some(RadiusRule::Shrink) },
        Variant { method: Method::Sppm, direct: DirectLight::Sampled, sampler: None, radius_rule: Some(RadiusRule::Adaptive) },
        Variant { method: Method::Lt, direct: DirectLight::Sampled, sampler: None, radius_rule: None },
        Variant { method: Method::Bpt, direct: DirectLight::Sampled, sampler: None, radius_rule: None },
        Variant { method: Method::Vcm, direct: DirectLight::Sampled, sampler: None, radius_rule: None },
    ];

    /// From its name: `sppm`, `sppm-photons`, `pt`, `pt-nee`, `sppm-shrink`, `sppm-adaptive`
    /// `lt`, `bpt` or `vcm`, optionally followed by `/independent` or `/sobol`.
    pub fn parse(name: &str) -> Result<Self, Error> {
        use crate::sampler::Sampler;
        [None, Some(Sampler::Independent), Some(Sampler::Sobol)]
            .into_iter()
            .flat_map(|sampler| Self::ALL.into_iter().map(move |v| Variant { sampler, ..v }))
            .find(|v| v.name() == name)
            .ok_or_else(|| {
                Error::Setting(format!(
                    "unknown method `{name}`: expected sppm, sppm-photons, pt, pt-nee, sppm-shrink or sppm-adaptive, \
                     optionally with /independent or /sobol"
                ))
            })
    }

    /// Every name [`Variant::parse`] reads: each variant with the scene's sampler, then
    /// with `/independent`, then with `/sobol`.
    pub fn names() -> Vec<&'static str> {
        (0..3).flat_map(|column| VARIANT_NAMES.iter().map(move |row| row[column])).collect()
    }

    /// Its name, as [`Variant::parse`] reads it.
    pub fn name(self) -> &'static str {
        use crate::sampler::Sampler;
        let row = Self::ALL.iter().position(|v| {
            v.method == self.method
                && (v.method != Method::Sppm || (v.direct == self.direct && v.radius_rule == self.radius_rule))
        });
        let column = match self.sampler {
            None => 0,
            Some(Sampler::Independent) => 1,
            Some(Sampler::Sobol) => 2,
        };
        VARIANT_NAMES[row.expect("every method has a variant")][column]
    }

    /// `render` set to this variant.
    pub fn apply(self, render: &mut RenderSettings) {
        render.method = self.method;
        render.direct = self.direct;
        if let Some(sampler) = self.sampler {
            render.sampler = sampler;
        }
        if let Some(rule) = self.radius_rule {
            render.radius_rule = rule;
        }
    }
}

/// Snapshot times for a run of `limit` seconds: `first`, then doubling (`2 first`,
/// `4 first`, ...) while below the limit, and the limit itself last.
pub fn snapshot_times(first: f64, limit: f64) -> Vec<f64> {
    let mut times = Vec::new();
    let mut t = first;
    while t < limit * (1.0 - 1e-9) {
        times.push(t);
        t *= 2.0;
    }
    times.push(limit);
    times
}

/// Seconds of passes a method runs before [`compare`] turns to the method furthest behind
/// (a slice ends early at a snapshot's time).
const SLICE: f64 = 0.25;

/// An integrator with a clock that counts only its passes.
struct Timed {
    integrator: Box<dyn Integrator>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    seconds: f64,
}

/// Passes done, and the [`Timed`] clock when they completed.
#[derive(Clone, Copy, Debug)]
struct Done {
    passes: u32,
    /// Passes the completion added.
    new_passes: u32,
    seconds: f64,
}

impl Timed {
    /// A renderer of `scene`, its kernels compiled before its clock starts
    /// ([`integrators::create_compiled`]); the clock starts at what it spent on the render
    /// before its first pass (vcm's pilot).
    fn compiled(gpu: &GpuContext, scene: &Scene) -> Result<Self, Error> {
        let (integrator, _) = integrators::create_compiled(&gpu.device, &gpu.queue, scene, integrators::FirstPasses::Checked)?;
        let seconds = integrator.setup_seconds();
        Ok(Self { integrator, device: gpu.device.clone(), queue: gpu.queue.clone(), seconds })
    }

    /// Run passes through a [`Pacer`] (the device kept busy, several passes a submission
    /// where they are short) until pass `end_pass`, or for about `budget` seconds (at least
    /// one pass); the clock advances by the run's wall time, from its first submission to
    /// its last completion. Each completion, on the clock.
    fn run(&mut self, end_pass: u32, budget: Option<f64>) -> Result<Vec<Done>, Error> {
        let passes = self.integrator.passes();
        let queue = DeviceQueue::new(self.integrator.as_mut(), &self.device, &self.queue);
        let mut pacer = Pacer::new(queue, passes, Goal { end_pass, time_limit: budget });
        let mut done = Vec::new();
        while let Some(c) = pacer.next_completion()? {
            done.push(Done { passes: c.passes, new_passes: c.new_passes, seconds: self.seconds + c.seconds });
        }
        if let Some(last) = done.last() {
            self.seconds = last.seconds;
        }
        Ok(done)
    }

    fn passes(&self) -> u32 {
        self.integrator.passes()
    }

    /// The current image (not timed).
    fn image(&mut self) -> Result<Rgb32Image, Error> {
        self.integrator.image()
    }
}

/// Read a reference image and check that it suits the scene's image size and `downsample`.
fn load_reference(path: &Path, scene: &Scene, downsample: u32) -> Result<Rgb32Image, Error> {
    let reference = image_io::read_image(path)?;
    let r = &scene.render;
    if (reference.width, reference.height) != (r.width, r.height) {
        return Err(Error::Setting(format!(
            "{}: the reference is {}x{} but the scene renders {}x{}",
            path.display(),
            reference.width,
            reference.height,
            r.width,
            r.height
        )));
    }
    metrics::downsample_box(&reference, downsample).map_err(Error::Setting)?;
    Ok(reference)
}

fn create_dir(dir: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::Setting(format!("{}: cannot create the folder: {e}", dir.display())))
}

fn progress_bar(len: u64, template: &str) -> ProgressBar {
    let bar = ProgressBar::new(len);
    bar.set_style(ProgressStyle::with_template(template).expect("valid template"));
    bar
}

/// A line for the log: above the progress bar on a terminal, else on stderr.
fn note(bar: &ProgressBar, line: String) {
    if bar.is_hidden() {
        eprintln!("{line}");
    } else {
        bar.println(line);
    }
}

/// The note under a chart: image size, settings (`varied` is the one a sweep changes) and
/// device.
fn device_note(gpu: &GpuContext, scene: &Scene, varied: Option<SweepParam>) -> String {
    let r = &scene.render;
    let show = |p: SweepParam, v: String| if varied == Some(p) { "varied".to_string() } else { v };
    let photons = show(SweepParam::Photons, r.photons.to_string());
    let radius = show(SweepParam::Radius, r.radius.map_or("automatic".to_string(), |v| v.to_string()));
    let alpha = show(SweepParam::Alpha, r.alpha.to_string());
    format!(
        "{}x{}; sppm: photons/pass {photons}, initial radius {radius}, alpha {alpha}; {} ({:?}), {} CPU threads",
        r.width,
        r.height,
        gpu.adapter_info.name,
        gpu.adapter_info.backend,
        std::thread::available_parallelism().map_or(0, |n| n.get())
    )
}

/// Short form of an error figure for captions and logs.
fn sci(v: f64) -> String {
    format!("{v:.2e}")
}

/// One measurement of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// The method, or the swept parameter's value.
    pub label: String,
    /// Seconds of passes so far.
    pub seconds: f64,
    /// Passes completed.
    pub passes: u32,
    /// relMSE against the reference, after the run's box-downsampling.
    pub rel_mse: f64,
    /// RMSE against the reference, after the run's box-downsampling.
    pub rmse: f64,
}

/// The CSV of an equal-time comparison: `method,seconds,passes,relMSE,RMSE`.
pub fn write_compare_csv(path: &Path, snapshots: &[Snapshot]) -> Result<(), Error> {
    let rows: Vec<Vec<String>> = snapshots
        .iter()
        .map(|s| {
            vec![
                s.label.clone(),
                format!("{:.3}", s.seconds),
                s.passes.to_string(),
                format!("{:.6e}", s.rel_mse),
                format!("{:.6e}", s.rmse),
            ]
        })
        .collect();
    plot::write_csv(path, &["method", "seconds", "passes", "relMSE", "RMSE"], &rows)
}

/// The log-log chart of relMSE against seconds, one line per label, in order of first
/// appearance.
pub fn write_time_chart(path: &Path, title: &str, y_desc: &str, note: &str, snapshots: &[Snapshot]) -> Result<(), Error> {
    let series = group(snapshots, |s| (s.seconds, s.rel_mse));
    plot::write_chart(
        path,
        &Chart { title, x_desc: "seconds (wall time of passes)", y_desc, log_x: true, log_y: true, note },
        &series,
    )
}

/// Snapshots as one series per label, in order of first appearance.
fn group(snapshots: &[Snapshot], point: impl Fn(&Snapshot) -> (f64, f64)) -> Vec<Series> {
    let mut series: Vec<Series> = Vec::new();
    for s in snapshots {
        match series.iter_mut().find(|x| x.name == s.label) {
            Some(x) => x.points.push(point(s)),
            None => series.push(Series { name: s.label.clone(), points: vec![point(s)] }),
        }
    }
    series
}

/// Settings of [`compare`].
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// The reference image (EXR or PNG), of the scene's size.
    pub reference: PathBuf,
    /// The methods to run, in the order of the CSV and the figures.
    pub methods: Vec<Variant>,
    /// Seconds of passes for each method.
    pub time_limit: f64,
    /// The first snapshot time; later ones double it (see [`snapshot_times`]).
    pub first_snapshot: f64,
    /// Box-downsampling factor before the metrics.
    pub downsample: u32,
    /// Stop a method after this many passes even if time is left.
    pub max_passes: Option<u32>,
    /// The folder for the CSV and figures (created if missing).
    pub out: PathBuf,
}

/// Render `scene` with each method for `time_limit` seconds of passes, measuring the error
/// against the reference at doubling times. Writes `compare.csv`, `relmse-vs-time.png` and
/// `equal-time.png` (the final images side by side, with their error maps) into `out`, and
/// returns the snapshots.
pub fn compare(scene: &Scene, name: &str, opts: &CompareOptions) -> Result<Vec<Snapshot>, Error> {
    compare_on(&GpuContext::new()?, scene, name, opts)
}

/// [`compare`] on the device `gpu` (the Python package's, which picks the adapter and keeps
/// the device for later renders).
pub fn compare_on(gpu: &GpuContext, scene: &Scene, name: &str, opts: &CompareOptions) -> Result<Vec<Snapshot>, Error> {
    if opts.methods.is_empty() {
        return Err(Error::Setting("--methods names no method".into()));
    }
    if !(opts.time_limit > 0.0 && opts.time_limit.is_finite()) {
        return Err(Error::Setting(format!("the time limit must be a positive number of seconds, got {}", opts.time_limit)));
    }
    if !(opts.first_snapshot > 0.0 && opts.first_snapshot.is_finite()) {
        return Err(Error::Setting(format!(
            "--first-snapshot must be a positive number of seconds, got {}",
            opts.first_snapshot
        )));
    }
    let reference = load_reference(&opts.reference, scene, opts.downsample)?;
    create_dir(&opts.out)?;
    let mut fitted = scene.clone();
    fitted.render.fit_pass_work(gpu.pass_work());
    let scene = &fitted;
    let times = snapshot_times(opts.first_snapshot, opts.time_limit);
    let limit_ms = (opts.time_limit * 1e3) as u64;
    let bar = progress_bar(opts.methods.len() as u64 * limit_ms, "{bar:40} {msg}  {elapsed_precise}");

    // Every method's integrator lives for the whole run, and the next slice of passes always
    // goes to the method whose clock is furthest behind: a change in the machine's load (it
    // may be shared) then falls on all methods alike instead of on whichever runs at that
    // moment.
    struct Run {
        label: &'static str,
        timed: Timed,
        max_passes: u32,
        next: usize,
        last: Option<(Rgb32Image, Snapshot)>,
    }
    let mut runs = Vec::new();
    let max_passes = opts.max_passes.unwrap_or(u32::MAX);
    for &variant in &opts.methods {
        let mut s = scene.clone();
        variant.apply(&mut s.render);
        // As a render under --time-limit alone: as many passes as fit, which vcm's pilot
        // counts on (its merges stand for the render's passes, `shares::render_passes`), not
        // the file's own.
        s.render.iterations = max_passes;
        bar.set_message(format!("{}: compiling", variant.name()));
        let timed = Timed::compiled(gpu, &s)?;
        for line in timed.integrator.notes() {
            note(&bar, format!("{}: note: {line}", variant.name()));
        }
        runs.push(Run { label: variant.name(), timed, max_passes, next: 0, last: None });
    }
    let mut snapshots = Vec::new();
    while let Some(run) =
        runs.iter_mut().filter(|r| r.next < times.len()).min_by(|a, b| a.timed.seconds.total_cmp(&b.timed.seconds))
    {
        // Up to the next snapshot, in slices of at most SLICE seconds.
        let budget = (times[run.next] - run.timed.seconds).min(SLICE);
        run.timed.run(run.max_passes, Some(budget))?;
        let capped = run.timed.passes() >= run.max_passes;
        let seconds = run.timed.seconds;
        if seconds >= times[run.next] || capped {
            let img = run.timed.image()?;
            let c = metrics::compare(&img, &reference, opts.downsample).map_err(Error::Setting)?;
            let snap =
                Snapshot { label: run.label.into(), seconds, passes: run.timed.passes(), rel_mse: c.rel_mse, rmse: c.rmse };
            bar.set_message(format!("{}: {} passes, {seconds:.1} s, relMSE {}", run.label, snap.passes, sci(c.rel_mse)));
            note(&bar, format!("{:8} {seconds:8.2} s {:6} passes  relMSE {}", run.label, snap.passes, sci(c.rel_mse)));
            snapshots.push(snap.clone());
            run.last = Some((img, snap));
            while run.next < times.len() && times[run.next] <= seconds {
                run.next += 1;
            }
            if capped {
                run.next = times.len();
            }
        }
        bar.set_position(runs.iter().map(|r| ((r.timed.seconds * 1e3) as u64).min(limit_ms)).sum());
    }
    // Snapshots grouped by method, in the order of --methods.
    snapshots.sort_by_key(|s: &Snapshot| opts.methods.iter().position(|&m| m.name() == s.label));
    let finals: Vec<_> = runs.into_iter().map(|r| (r.label, r.last.expect("at least one snapshot"))).collect();
    bar.finish_and_clear();

    write_compare_csv(&opts.out.join("compare.csv"), &snapshots)?;
    let y_desc = format!("relMSE ({0}x{0} box-downsampled)", opts.downsample);
    let title = format!("{name}: relMSE against time");
    let note = device_note(gpu, scene, None);
    write_time_chart(&opts.out.join("relmse-vs-time.png"), &title, &y_desc, &note, &snapshots)?;

    let mut images = vec![Tile::render(&reference, vec!["reference".into()])];
    let mut errors = vec![Tile::blank(reference.width, reference.height)];
    for (label, (img, snap)) in &finals {
        images.push(Tile::render(
            img,
            vec![format!("{label}: {:.1} s, {} passes", snap.seconds, snap.passes), format!("relMSE {}", sci(snap.rel_mse))],
        ));
        errors.push(Tile::colours(&plot::error_map(img, &reference, opts.downsample)?, Vec::new()));
    }
    let legend =
        format!("per-pixel relative error after {0}x{0} box-downsampling, sqrt((x - ref)^2 / (ref^2 + 0.01)):", opts.downsample);
    let title = format!("{name} at equal time ({} s of passes each)", opts.time_limit);
    plot::write_montage(&opts.out.join("equal-time.png"), &title, &[images, errors], Some(&legend))?;

    crate::say!(
        "{name}, {}x{}, {} ({}), {} s per method",
        scene.render.width,
        scene.render.height,
        gpu.adapter_info.name,
        gpu.adapter_info.backend,
        opts.time_limit
    );
    crate::say!("{:8} {:>8} {:>7} {:>12} {:>10}", "method", "seconds", "passes", "relMSE", "RMSE");
    for s in &snapshots {
        crate::say!("{:8} {:8.2} {:7} {:12.4e} {:10.4e}", s.label, s.seconds, s.passes, s.rel_mse, s.rmse);
    }
    crate::say!("wrote compare.csv, relmse-vs-time.png, equal-time.png in {}", opts.out.display());
    Ok(snapshots)
}

/// The render setting a [`sweep`] varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepParam {
    /// The initial radius (scene units).
    Radius,
    /// The radius reduction parameter.
    Alpha,
    /// Photons per pass.
    Photons,
    /// SPPM's radius schedule: 0 per point (Hachisuka & Jensen 2009), 1 global (Knaus &
    /// Zwicker 2011).
    RadiusSchedule,
}

impl SweepParam {
    /// From its command-line name.
    pub fn parse(name: &str) -> Result<Self, Error> {
        match name {
            "radius" => Ok(Self::Radius),
            "alpha" => Ok(Self::Alpha),
            "photons" => Ok(Self::Photons),
            "radius-schedule" => Ok(Self::RadiusSchedule),
            _ => Err(Error::Setting(format!("unknown parameter `{name}`: expected radius, alpha, photons or radius-schedule"))),
        }
    }

    /// Its command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Radius => "radius",
            Self::Alpha => "alpha",
            Self::Photons => "photons",
            Self::RadiusSchedule => "radius-schedule",
        }
    }

    /// A caption for one value.
    fn label(self, value: f64) -> String {
        match self {
            Self::Radius => format!("radius {value}"),
            Self::Alpha => format!("alpha {value}"),
            Self::Photons => format!("{value} photons"),
            Self::RadiusSchedule if value == 0.0 => "radius per point".into(),
            Self::RadiusSchedule => "global radius".into(),
        }
    }

    /// Set `value` in `render`, checking its range as the command line does.
    pub fn apply(self, render: &mut RenderSettings, value: f64) -> Result<(), Error> {
        match self {
            Self::Radius if value > 0.0 && value.is_finite() => render.radius = Some(value as f32),
            Self::Alpha if value > 0.0 && value < 1.0 => render.alpha = value as f32,
            Self::Photons if value >= 1.0 && value <= u32::MAX as f64 && value.fract() == 0.0 => {
                render.photons = value as u32;
                render.work_given.photons = true;
            }
            Self::RadiusSchedule if value == 0.0 || value == 1.0 => {
                render.radius_schedule = if value == 1.0 { RadiusSchedule::Global } else { RadiusSchedule::PerPoint };
                render.radius_schedule_given = true;
            }
            _ => return Err(Error::Setting(format!("{value} is not a valid {}", self.name()))),
        }
        Ok(())
    }
}

/// Settings of [`sweep`].
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// The setting varied.
    pub param: SweepParam,
    /// Its values, one render each.
    pub values: Vec<f64>,
    /// The reference image (EXR or PNG), of the scene's size.
    pub reference: PathBuf,
    /// Box-downsampling factor before the metrics.
    pub downsample: u32,
    /// The folder for the CSV and figures (created if missing).
    pub out: PathBuf,
}

/// Render `scene` (its own passes, `render.iterations`) once per value of the parameter,
/// measuring the error after every pass. Writes `sweep.csv`
/// (`parameter,value,pass,seconds,relMSE,RMSE`), `relmse-vs-passes.png` (log-log),
/// `relmse-vs-PARAM.png` (after the last pass) and `images.png` (the last images side by
/// side with their error maps) into `out`, and returns the snapshots (labelled by value).
pub fn sweep(scene: &Scene, name: &str, opts: &SweepOptions) -> Result<Vec<Snapshot>, Error> {
    if opts.values.is_empty() {
        return Err(Error::Setting("--values names no value".into()));
    }
    let mut settings = Vec::new();
    for &v in &opts.values {
        let mut s = scene.clone();
        opts.param.apply(&mut s.render, v)?;
        settings.push(s);
    }
    let reference = load_reference(&opts.reference, scene, opts.downsample)?;
    create_dir(&opts.out)?;
    let gpu = GpuContext::new()?;
    for s in &mut settings {
        s.render.fit_pass_work(gpu.pass_work());
    }
    let passes = scene.render.iterations;
    let bar = progress_bar(opts.values.len() as u64 * passes as u64, "{bar:40} {pos}/{len} passes  {msg}  {elapsed_precise}");

    let mut snapshots = Vec::new();
    let mut images = Vec::new();
    let mut errors = Vec::new();
    let mut rows = Vec::new();
    for (&value, s) in opts.values.iter().zip(&settings) {
        let label = value.to_string();
        let mut run = Timed::compiled(&gpu, s)?;
        let mut img = None;
        // Snapshots after 1, 2, 4, ... passes and the last; the passes between run paced.
        while run.passes() < passes {
            let end = (2 * run.passes()).clamp(1, passes);
            let before = run.passes();
            run.run(end, None)?;
            let i = run.image()?;
            let c = metrics::compare(&i, &reference, opts.downsample).map_err(Error::Setting)?;
            let snap =
                Snapshot { label: label.clone(), seconds: run.seconds, passes: run.passes(), rel_mse: c.rel_mse, rmse: c.rmse };
            rows.push(vec![
                opts.param.name().to_string(),
                label.clone(),
                snap.passes.to_string(),
                format!("{:.3}", snap.seconds),
                format!("{:.6e}", snap.rel_mse),
                format!("{:.6e}", snap.rmse),
            ]);
            bar.inc((run.passes() - before) as u64);
            bar.set_message(format!("{}: relMSE {}", opts.param.label(value), sci(c.rel_mse)));
            snapshots.push(snap);
            img = Some(i);
        }
        let img = img.expect("at least one pass");
        let last = snapshots.last().expect("a snapshot");
        note(
            &bar,
            format!(
                "{}: relMSE {} after {} passes, {:.2} s",
                opts.param.label(value),
                sci(last.rel_mse),
                last.passes,
                last.seconds
            ),
        );
        images.push(Tile::render(&img, vec![opts.param.label(value), format!("relMSE {}", sci(last.rel_mse))]));
        errors.push(Tile::colours(&plot::error_map(&img, &reference, opts.downsample)?, Vec::new()));
    }
    bar.finish_and_clear();

    let p = opts.param.name();
    plot::write_csv(&opts.out.join("sweep.csv"), &["parameter", "value", "pass", "seconds", "relMSE", "RMSE"], &rows)?;
    let y_desc = format!("relMSE ({0}x{0} box-downsampled)", opts.downsample);
    let mut series = group(&snapshots, |s| (s.passes as f64, s.rel_mse));
    for s in &mut series {
        s.name = opts.param.label(s.name.parse().expect("a number"));
    }
    let title = format!("{name}: relMSE over passes, by {p}");
    let note = device_note(&gpu, scene, Some(opts.param));
    plot::write_chart(
        &opts.out.join("relmse-vs-passes.png"),
        &Chart { title: &title, x_desc: "passes", y_desc: &y_desc, log_x: true, log_y: true, note: &note },
        &series,
    )?;
    let finals: Vec<(f64, f64)> =
        opts.values.iter().zip(&series).map(|(&v, s)| (v, s.points.last().expect("a point").1)).collect();
    let (lo, hi) = finals.iter().fold((f64::INFINITY, 0.0f64), |(l, h), p| (l.min(p.0), h.max(p.0)));
    let title = format!("{name}: relMSE after {passes} passes, by {p}");
    let chart = Chart { title: &title, x_desc: p, y_desc: &y_desc, log_x: lo > 0.0 && hi >= 10.0 * lo, log_y: true, note: &note };
    plot::write_chart(
        &opts.out.join(format!("relmse-vs-{p}.png")),
        &chart,
        &[Series { name: format!("after {passes} passes"), points: finals.clone() }],
    )?;
    let r = &scene.render;
    let title = format!("{name}: {passes} passes of {} photons, by {p}", r.photons);
    let legend =
        format!("per-pixel relative error after {0}x{0} box-downsampling, sqrt((x - ref)^2 / (ref^2 + 0.01)):", opts.downsample);
    plot::write_montage(&opts.out.join("images.png"), &title, &[images, errors], Some(&legend))?;

    crate::say!("{name}, {}x{}, {passes} passes x {} photons, {}", r.width, r.height, r.photons, gpu.adapter_info.name);
    crate::say!("{:>10} {:>12} {:>10} {:>9}", p, "relMSE", "RMSE", "seconds");
    for v in &opts.values {
        let last = snapshots.iter().rev().find(|x| x.label == v.to_string()).expect("a snapshot");
        crate::say!("{:>10} {:12.4e} {:10.4e} {:9.2}", v, last.rel_mse, last.rmse, last.seconds);
    }
    crate::say!("wrote sweep.csv, relmse-vs-passes.png, relmse-vs-{p}.png, images.png in {}", opts.out.display());
    Ok(snapshots)
}

/// Settings of [`passes`].
#[derive(Clone, Debug)]
pub struct PassesOptions {
    /// Pass counts after which the image is kept; the run lasts until the largest.
    pub snapshots: Vec<u32>,
    /// A reference image, for relMSE in the captions.
    pub reference: Option<PathBuf>,
    /// Box-downsampling factor before the metrics.
    pub downsample: u32,
    /// The folder for the CSV and figures (created if missing).
    pub out: PathBuf,
}

/// Time of one pass, for [`passes`].
#[derive(Clone, Debug, PartialEq)]
pub struct PassTime {
    /// The pass's number, from 1.
    pub pass: u32,
    /// Its wall time (submission to completion).
    pub seconds: f64,
}

/// Render `scene` for the largest of `snapshots` passes, timing each pass. Writes
/// `passes.csv` (`pass,seconds,total_seconds`), `time-per-pass.png` and `images.png` (the
/// image after each snapshot's passes, with relMSE when there is a reference) into `out`.
pub fn passes(scene: &Scene, name: &str, opts: &PassesOptions) -> Result<Vec<PassTime>, Error> {
    let mut snaps = opts.snapshots.clone();
    snaps.sort_unstable();
    snaps.dedup();
    let Some(&last) = snaps.last() else {
        return Err(Error::Setting("--snapshots names no pass count".into()));
    };
    if snaps[0] == 0 {
        return Err(Error::Setting("--snapshots: pass counts start at 1".into()));
    }
    let reference = opts.reference.as_deref().map(|p| load_reference(p, scene, opts.downsample)).transpose()?;
    create_dir(&opts.out)?;
    let gpu = GpuContext::new()?;
    let mut s = scene.clone();
    s.render.fit_pass_work(gpu.pass_work());
    s.render.iterations = last;
    let bar = progress_bar(last as u64, "{bar:40} {pos}/{len} passes  {msg}  {elapsed_precise}");
    let mut run = Timed::compiled(&gpu, &s)?;
    let mut times = Vec::new();
    let mut tiles = Vec::new();
    let mut rows = Vec::new();
    // The passes up to each snapshot run paced; a pass's time is its submission's wall time
    // (from the completion before it) shared among the submission's passes.
    for &snap in &snaps {
        let mut since = run.seconds;
        for done in run.run(snap, None)? {
            let t = (done.seconds - since) / done.new_passes as f64;
            since = done.seconds;
            for pass in done.passes - done.new_passes + 1..=done.passes {
                times.push(PassTime { pass, seconds: t });
                rows.push(vec![pass.to_string(), format!("{t:.4}"), format!("{:.3}", since - t * (done.passes - pass) as f64)]);
            }
            bar.inc(done.new_passes as u64);
            bar.set_message(format!("{:.1} ms/pass", t * 1e3));
        }
        let img = run.image()?;
        let n = run.passes();
        let mut caption = vec![format!("{n} pass{}, {:.1} s", if n == 1 { "" } else { "es" }, run.seconds)];
        if let Some(r) = &reference {
            let c = metrics::compare(&img, r, opts.downsample).map_err(Error::Setting)?;
            caption.push(format!("relMSE {}", sci(c.rel_mse)));
        }
        note(&bar, caption.join(", "));
        tiles.push(Tile::render(&img, caption));
    }
    bar.finish_and_clear();

    plot::write_csv(&opts.out.join("passes.csv"), &["pass", "seconds", "total_seconds"], &rows)?;
    let r = &s.render;
    let what = match r.method {
        Method::Sppm => format!("{} photons", r.photons),
        _ => format!("{} spp", r.spp),
    };
    let title = format!("{name}: time per pass ({}, {what})", r.method.name());
    let note = device_note(&gpu, &s, None);
    let series =
        Series { name: r.method.name().into(), points: times.iter().map(|t| (t.pass as f64, t.seconds * 1e3)).collect() };
    plot::write_chart(
        &opts.out.join("time-per-pass.png"),
        &Chart { title: &title, x_desc: "pass", y_desc: "milliseconds", log_x: false, log_y: false, note: &note },
        &[series],
    )?;
    let title = format!("{name}: {} over passes", r.method.name());
    plot::write_montage(&opts.out.join("images.png"), &title, &[tiles], None)?;

    let total: f64 = times.iter().map(|t| t.seconds).sum();
    let rest = &times[1.min(times.len() - 1)..];
    crate::say!(
        "{name}: {last} passes in {total:.2} s; first pass {:.0} ms, then {:.0} ms per pass on average ({})",
        times[0].seconds * 1e3,
        rest.iter().map(|t| t.seconds).sum::<f64>() / rest.len() as f64 * 1e3,
        gpu.adapter_info.name
    );
    crate::say!("wrote passes.csv, time-per-pass.png, images.png in {}", opts.out.display());
    Ok(times)
}
