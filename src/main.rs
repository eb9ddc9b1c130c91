//! The `sppm-gpu` command line: render a scene file to PNG or EXR.

mod cli;
mod view;

use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use sppm_gpu::gpu::GpuContext;
use sppm_gpu::integrators::{self, Sppm};
use sppm_gpu::pacing::{self, DeviceQueue, Goal, Pacer, PassQueue};
use sppm_gpu::say;
use sppm_gpu::scene::{self, DirectLight, Method, RadiusSchedule};
use sppm_gpu::{experiments, image_io, Error};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Render a scene with stochastic progressive photon mapping on the GPU.
#[derive(Parser, Debug)]
#[command(version, about, args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Scene file: TOML (format version 1), or Mitsuba scene XML (`.xml`, versions 0.5/0.6
    /// and 2/3).
    #[arg(required_unless_present = "list_adapters")]
    scene: Option<PathBuf>,
    /// Output image: .png (sRGB, clamped) or .exr (linear float RGB).
    #[arg(short, long, required_unless_present_any = ["partial", "list_adapters"])]
    output: Option<PathBuf>,
    /// Render passes A to B-1 of the render only (`A..B`): a batch of a render split into
    /// batches, each drawing the random numbers the whole render draws for it. SPPM needs
    /// radius_schedule = "global" for this; the path tracers need nothing.
    #[arg(long, value_parser = parse_pass_range, value_name = "A..B")]
    passes: Option<(u32, u32)>,
    /// Write the batch's partial image (.exr): the sum of its passes' estimates, with the pass
    /// range and the render's fingerprint in the header, for `sppm-gpu merge`.
    #[arg(long, value_name = "OUT.exr")]
    partial: Option<PathBuf>,
    /// The GPU to render on: its index in --list-adapters, or a part of its name.
    #[arg(long)]
    adapter: Option<String>,
    /// List the GPUs (Vulkan, Metal, DX12 adapters) with the indices --adapter takes, and exit.
    #[arg(long)]
    list_adapters: bool,
    /// After rendering, print the GPU memory each buffer takes.
    #[arg(long)]
    stats: bool,
    /// Refuse a render that needs more memory than this, device buffers and host image
    /// together: bytes, or with a K, M or G suffix (powers of 1024). Without it, a render on a
    /// CPU device is checked against the host's available memory.
    #[arg(long, value_parser = parse_bytes)]
    memory_limit: Option<u64>,
    /// Write the render's state to this file every --checkpoint-every seconds, at the end and
    /// when interrupted, for --resume.
    #[arg(long)]
    checkpoint: Option<PathBuf>,
    /// Seconds between checkpoints (0: after every pass).
    #[arg(long, default_value_t = 300.0)]
    checkpoint_every: f64,
    /// Go on from a checkpoint of the same scene and settings, up to --iterations passes in all.
    #[arg(long)]
    resume: Option<PathBuf>,
    #[command(flatten)]
    overrides: Overrides,
}

/// Settings that override the scene's `[render]` table.
#[derive(clap::Args, Debug, Default)]
struct Overrides {
    /// SPPM passes (overrides render.iterations).
    #[arg(long)]
    iterations: Option<u32>,
    /// Photons per pass (overrides render.photons).
    #[arg(long)]
    photons: Option<u32>,
    /// Initial gather radius in scene units (overrides render.radius).
    #[arg(long)]
    radius: Option<f32>,
    /// Radius reduction parameter, 0 < alpha < 1 (overrides render.alpha).
    #[arg(long)]
    alpha: Option<f32>,
    /// Random seed (overrides render.seed).
    #[arg(long)]
    seed: Option<u32>,
    /// Stop at the pass boundary nearest this many seconds of completed passes (overrides render.time_limit).
    #[arg(long)]
    time_limit: Option<f64>,
    /// Image width in pixels (overrides render.width).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (overrides render.height).
    #[arg(long)]
    height: Option<u32>,
    /// Rendering method: sppm, pt (naive path tracing) or pt-nee (next-event estimation with
    /// MIS) (overrides render.method).
    #[arg(long, value_parser = ["sppm", "pt", "pt-nee"])]
    method: Option<String>,
    /// Camera samples per pixel in each pass (overrides render.spp).
    #[arg(long)]
    spp: Option<u32>,
    /// Most scattering events on a path (overrides render.max_depth).
    #[arg(long)]
    max_depth: Option<u32>,
    /// SPPM's direct light: sampled in the camera pass (default) or from photons alone, as
    /// in the original algorithm (overrides render.direct).
    #[arg(long, value_parser = ["sampled", "photons"])]
    direct: Option<String>,
    /// SPPM with sampled direct light: camera paths per visible point per pass that gather
    /// direct light (overrides render.direct_samples; default automatic).
    #[arg(long)]
    direct_samples: Option<u32>,
    /// SPPM's radius schedule: per-point (each visible point's radius shrinks with its
    /// photons; default) or global (the radius of pass i depends on i alone, so passes can
    /// run in batches; Knaus & Zwicker 2011) (overrides render.radius_schedule).
    #[arg(long, value_parser = ["per-point", "global"])]
    radius_schedule: Option<String>,
    /// How each SPPM visible point's radius shrinks (per-point schedule): shrink (by alpha of
    /// each pass's photons; default) or adaptive (by alpha only where its photons stop looking
    /// uniform over its disc, by a chi-square test) (overrides render.radius_rule).
    #[arg(long, value_parser = ["shrink", "adaptive"])]
    radius_rule: Option<String>,
    /// Where the kernels' random numbers come from: independent (PCG streams) or sobol
    /// (Owen-scrambled Sobol points) (overrides render.sampler).
    #[arg(long, value_parser = ["independent", "sobol"])]
    sampler: Option<String>,
    /// Set a Mitsuba XML scene's parameter `$name`, as Mitsuba's own `-D name=value` (over the
    /// file's `<default>`); repeatable.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
    defines: Vec<(String, String)>,
}

/// `NAME=VALUE` of `-D`.
fn parse_define(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.is_empty() => Ok((name.to_owned(), value.to_owned())),
        _ => Err(format!("\"{text}\" is not NAME=VALUE")),
    }
}

#[derive(clap::Subcommand, Debug)]
enum Command {
    /// Merge the partial images of batches of one render (`--passes A..B --partial`) into its
    /// image: the sum of their passes' estimates over the passes they hold.
    Merge {
        /// The partial images (.exr), in any order.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// Output image: .png or .exr.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Error metrics between an image and a reference (EXR or PNG).
    Diff {
        image: PathBuf,
        reference: PathBuf,
        /// Box-downsample both images by this factor first.
        #[arg(long, default_value_t = 1)]
        downsample: u32,
        /// Also write the false-colour map of the per-pixel relative error (after the
        /// downsampling, enlarged back) to this PNG.
        #[arg(long)]
        error_image: Option<PathBuf>,
    },
    /// Equal-time comparison of methods against a reference: a CSV of relMSE at doubling
    /// times, a log-log chart and the final images side by side.
    Compare {
        scene: PathBuf,
        /// Reference image (EXR or PNG) of the scene's size.
        #[arg(long)]
        reference: PathBuf,
        /// Methods to run, in order (each for --time-limit seconds of passes); sppm-photons is
        /// SPPM with direct light from photons alone; `/independent` or `/sobol` after a
        /// method sets its sampler (`pt-nee/sobol`); sppm-adaptive is SPPM with
        /// radius_rule = "adaptive", sppm-shrink with "shrink".
        #[arg(long, value_delimiter = ',', default_value = "sppm,pt,pt-nee", value_parser = [
            "sppm", "sppm-photons", "pt", "pt-nee",
            "sppm/independent", "sppm-photons/independent", "pt/independent", "pt-nee/independent",
            "sppm/sobol", "sppm-photons/sobol", "pt/sobol", "pt-nee/sobol",
            "sppm-shrink", "sppm-adaptive", "sppm-shrink/independent", "sppm-adaptive/independent",
            "sppm-shrink/sobol", "sppm-adaptive/sobol",
        ])]
        methods: Vec<String>,
        /// Box-downsample before measuring the error.
        #[arg(long, default_value_t = 1)]
        downsample: u32,
        /// Time of the first snapshot in seconds; later ones double it.
        #[arg(long, default_value_t = 0.5)]
        first_snapshot: f64,
        /// Folder for compare.csv, relmse-vs-time.png and equal-time.png.
        #[arg(long, default_value = "out/compare")]
        out: PathBuf,
        /// Render overrides; --time-limit (required here, unless the scene sets one) is the
        /// time of each method, --iterations caps its passes.
        #[command(flatten)]
        overrides: Overrides,
    },
    /// Render once per value of one setting, measuring relMSE after every pass: a CSV,
    /// charts and the final images side by side.
    Sweep {
        scene: PathBuf,
        /// The setting to vary (radius-schedule: 0 per point, 1 global).
        #[arg(long, value_parser = ["radius", "alpha", "photons", "radius-schedule"])]
        param: String,
        /// Its values, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        values: Vec<f64>,
        /// Reference image (EXR or PNG) of the scene's size.
        #[arg(long)]
        reference: PathBuf,
        /// Box-downsample before measuring the error.
        #[arg(long, default_value_t = 1)]
        downsample: u32,
        /// Folder for sweep.csv, the charts and images.png.
        #[arg(long, default_value = "out/sweep")]
        out: PathBuf,
        #[command(flatten)]
        overrides: Overrides,
    },
    /// Time every pass and keep the image after chosen pass counts: a CSV, a chart of time
    /// per pass and the images side by side.
    Passes {
        scene: PathBuf,
        /// Pass counts whose images to keep, comma-separated; the run ends at the largest.
        #[arg(long, value_delimiter = ',', required = true)]
        snapshots: Vec<u32>,
        /// Reference image, for relMSE in the captions.
        #[arg(long)]
        reference: Option<PathBuf>,
        /// Box-downsample before measuring the error.
        #[arg(long, default_value_t = 1)]
        downsample: u32,
        /// Folder for passes.csv, time-per-pass.png and images.png.
        #[arg(long, default_value = "out/passes")]
        out: PathBuf,
        #[command(flatten)]
        overrides: Overrides,
    },
    /// A window that shows the estimate refining pass by pass; the camera, method and
    /// exposure change under the mouse and keys.
    #[command(after_help = view::KEYS)]
    View {
        scene: PathBuf,
        /// Reference image (EXR or PNG) of the render's size: relMSE in the title, and the
        /// error map (key e).
        #[arg(long)]
        reference: Option<PathBuf>,
        /// Pause after this many passes, and again after each camera move or method switch
        /// (a fixed pass count makes a save reproducible bit for bit).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
        passes_then_pause: Option<u32>,
        /// Exposure in stops (keys + and - change it).
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        exposure: f32,
        #[command(flatten)]
        overrides: Overrides,
    },
    /// What a scene holds as loaded (TOML or Mitsuba XML): image and settings, camera,
    /// shapes, triangles, materials and lights by kind, and the kernel features it turns on.
    Info {
        scene: PathBuf,
        #[command(flatten)]
        overrides: Overrides,
    },
    /// Write a scene as read (Mitsuba XML, say) in our TOML format, which renders the same:
    /// OUT.toml and its meshes as PLY files in OUT.meshes/ (new files only).
    Convert {
        scene: PathBuf,
        /// The TOML file to write.
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        overrides: Overrides,
    },
    /// Time each stage of an SPPM pass (waiting for the GPU after each) and report
    /// throughput.
    Bench {
        scene: PathBuf,
        #[command(flatten)]
        overrides: Overrides,
    },
}

/// Print relMSE = mean((x - ref)^2 / (ref^2 + 0.01)), RMSE and the channel mean ratios.
fn diff(image: &Path, reference: &Path, downsample: u32, error_image: Option<&Path>) -> Result<(), Error> {
    let a = image_io::read_image(image)?;
    let b = image_io::read_image(reference)?;
    let c = sppm_gpu::metrics::compare(&a, &b, downsample).map_err(Error::Setting)?;
    say!(
        "relMSE {:.6}  RMSE {:.6}  mean ratio {:.4} {:.4} {:.4}  (downsample {downsample})",
        c.rel_mse,
        c.rmse,
        c.mean_ratio[0],
        c.mean_ratio[1],
        c.mean_ratio[2]
    );
    if let Some(path) = error_image {
        experiments::plot::write_error_image(path, &a, &b, downsample)?;
    }
    Ok(())
}

/// Load a scene and apply the command line's overrides; also its name (the file stem).
fn load_scene(path: &Path, overrides: &Overrides) -> Result<(scene::Scene, String), Error> {
    let mut scene = scene::load_with(path, &overrides.defines)?;
    // A Mitsuba film's size sets its field of view along one axis: one of --width and
    // --height alone keeps the file's aspect ratio, and so the framing.
    if scene::is_mitsuba_xml(path) {
        let (w, h) = (scene.render.width as f64, scene.render.height as f64);
        match (overrides.width, overrides.height) {
            (Some(width), None) => scene.render.height = ((width as f64 * h / w).round() as u32).max(1),
            (None, Some(height)) => scene.render.width = ((height as f64 * w / h).round() as u32).max(1),
            _ => {}
        }
    }
    apply_overrides(overrides, &mut scene.render)?;
    let name = path.file_stem().map_or_else(|| path.display().to_string(), |s| s.to_string_lossy().into_owned());
    Ok((scene, name))
}

/// The `compare`, `sweep` and `passes` subcommands (in `experiments`).
fn experiment(command: &Command) -> Result<(), Error> {
    match command {
        Command::Compare { scene, reference, methods, downsample, first_snapshot, out, overrides } => {
            let (scene, name) = load_scene(scene, overrides)?;
            let Some(time_limit) = scene.render.time_limit else {
                return Err(Error::Setting("compare needs --time-limit SECS".into()));
            };
            let methods = methods.iter().map(|m| experiments::Variant::parse(m)).collect::<Result<_, _>>()?;
            let opts = experiments::CompareOptions {
                reference: reference.clone(),
                methods,
                time_limit,
                first_snapshot: *first_snapshot,
                downsample: *downsample,
                max_passes: overrides.iterations,
                out: out.clone(),
            };
            experiments::compare(&scene, &name, &opts).map(drop)
        }
        Command::Sweep { scene, param, values, reference, downsample, out, overrides } => {
            let (scene, name) = load_scene(scene, overrides)?;
            let opts = experiments::SweepOptions {
                param: experiments::SweepParam::parse(param)?,
                values: values.clone(),
                reference: reference.clone(),
                downsample: *downsample,
                out: out.clone(),
            };
            experiments::sweep(&scene, &name, &opts).map(drop)
        }
        Command::Passes { scene, snapshots, reference, downsample, out, overrides } => {
            let (scene, name) = load_scene(scene, overrides)?;
            let opts = experiments::PassesOptions {
                snapshots: snapshots.clone(),
                reference: reference.clone(),
                downsample: *downsample,
                out: out.clone(),
            };
            experiments::passes(&scene, &name, &opts).map(drop)
        }
        Command::Diff { .. }
        | Command::Bench { .. }
        | Command::View { .. }
        | Command::Merge { .. }
        | Command::Info { .. }
        | Command::Convert { .. } => {
            unreachable!("not an experiment")
        }
    }
}

/// Apply the command line's overrides to the scene's `[render]` table, checking each.
fn apply_overrides(cli: &Overrides, render: &mut scene::RenderSettings) -> Result<(), Error> {
    fn positive(flag: &str, v: Option<u32>, max: u32, dst: &mut u32) -> Result<(), Error> {
        if let Some(v) = v {
            if v == 0 || v > max {
                return Err(Error::Setting(format!("--{flag} must be between 1 and {max}, got {v}")));
            }
            *dst = v;
        }
        Ok(())
    }
    positive("iterations", cli.iterations, u32::MAX, &mut render.iterations)?;
    positive("photons", cli.photons, u32::MAX, &mut render.photons)?;
    render.work_given.photons |= cli.photons.is_some();
    positive("width", cli.width, 16384, &mut render.width)?;
    positive("height", cli.height, 16384, &mut render.height)?;
    positive("spp", cli.spp, 1024, &mut render.spp)?;
    render.work_given.spp |= cli.spp.is_some();
    positive("max-depth", cli.max_depth, 1024, &mut render.max_depth)?;
    if cli.direct_samples.is_some() {
        let mut n = 1;
        positive("direct-samples", cli.direct_samples, scene::MAX_DIRECT_SAMPLES, &mut n)?;
        render.direct_samples = Some(n);
    }
    if let Some(r) = cli.radius {
        if !(r > 0.0 && r.is_finite()) {
            return Err(Error::Setting(format!("--radius must be a positive number, got {r}")));
        }
        render.radius = Some(r);
    }
    if let Some(a) = cli.alpha {
        if !(a > 0.0 && a < 1.0) {
            return Err(Error::Setting(format!("--alpha must be between 0 and 1 (exclusive), got {a}")));
        }
        render.alpha = a;
    }
    if let Some(t) = cli.time_limit {
        if !(t > 0.0 && t.is_finite()) {
            return Err(Error::Setting(format!("--time-limit must be a positive number of seconds, got {t}")));
        }
        render.time_limit = Some(t);
    }
    if let Some(s) = cli.seed {
        render.seed = s;
    }
    if let Some(m) = &cli.method {
        render.method = match m.as_str() {
            "pt" => Method::Pt,
            "pt-nee" => Method::PtNee,
            _ => Method::Sppm,
        };
    }
    if let Some(d) = &cli.direct {
        render.direct = if d == "photons" { DirectLight::Photons } else { DirectLight::Sampled };
    }
    if let Some(s) = &cli.radius_schedule {
        render.radius_schedule = if s == "global" { RadiusSchedule::Global } else { RadiusSchedule::PerPoint };
    }
    if let Some(s) = &cli.radius_rule {
        render.radius_rule = if s == "adaptive" { scene::RadiusRule::Adaptive } else { scene::RadiusRule::Shrink };
    }
    if let Some(s) = &cli.sampler {
        render.sampler = if s == "sobol" { sppm_gpu::sampler::Sampler::Sobol } else { sppm_gpu::sampler::Sampler::Independent };
    }
    Ok(())
}

/// Refuse, before anything is loaded or rendered, outputs that would replace their input (the
/// scene, or a part to merge) or cannot be written as an image: a wrong extension, a
/// directory that does not exist, a directory or file that cannot be written.
fn check_output(output: &Path, input: &Path) -> Result<(), Error> {
    let ext = output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("png") | Some("exr")) {
        return Err(Error::Setting(format!("{}: the output must end in .png or .exr", output.display())));
    }
    let dir = match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(Error::Setting(format!("{}: the output's directory {} does not exist", output.display(), dir.display())));
    }
    if output.is_dir() {
        return Err(Error::Setting(format!("{}: the output is a directory", output.display())));
    }
    let cannot = |e: std::io::Error| Error::Setting(format!("{}: the output cannot be written: {e}", output.display()));
    if output.exists() {
        // Opened for writing without truncating: the file is left as it is.
        std::fs::OpenOptions::new().write(true).open(output).map_err(cannot)?;
    } else {
        // A file made and removed beside it: the directory takes new files.
        let name = output.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let probe = dir.join(format!(".{name}.{}.sppm-gpu-probe", std::process::id()));
        std::fs::File::create_new(&probe).map_err(cannot)?;
        let _ = std::fs::remove_file(&probe);
    }
    if let (Ok(a), Ok(b)) = (output.canonicalize(), input.canonicalize()) {
        if a == b {
            return Err(Error::Setting(format!(
                "{}: the output would overwrite its input {}",
                output.display(),
                input.display()
            )));
        }
    }
    Ok(())
}

fn run(cli: &Cli) -> Result<ExitCode, Error> {
    if let Some(Command::Diff { image, reference, downsample, error_image }) = &cli.command {
        return diff(image, reference, *downsample, error_image.as_deref()).map(|()| ExitCode::SUCCESS);
    }
    if let Some(Command::Bench { scene, overrides }) = &cli.command {
        return bench(scene, overrides).map(|()| ExitCode::SUCCESS);
    }
    if let Some(Command::Convert { scene, output, overrides }) = &cli.command {
        let (loaded, _) = load_scene(scene, overrides)?;
        cli::convert::convert(&loaded, output)?;
        say!("wrote {}", output.display());
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(Command::Info { scene, overrides }) = &cli.command {
        let (loaded, _) = load_scene(scene, overrides)?;
        print!("{}", cli::info::report(&loaded)?);
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(Command::View { scene, reference, passes_then_pause, exposure, overrides }) = &cli.command {
        if let Some(line) = view::no_display() {
            return Err(Error::Setting(line));
        }
        let (loaded, _) = load_scene(scene, overrides)?;
        let options = view::Options {
            scene_path: scene.clone(),
            scene: loaded,
            reference: reference.clone(),
            passes_then_pause: *passes_then_pause,
            exposure: *exposure,
        };
        return view::run(options).map(|()| ExitCode::SUCCESS);
    }
    if let Some(Command::Merge { parts, output }) = &cli.command {
        return merge(parts, output).map(|()| ExitCode::SUCCESS);
    }
    if let Some(command) = &cli.command {
        return experiment(command).map(|()| ExitCode::SUCCESS);
    }
    if cli.list_adapters {
        for (i, a) in sppm_gpu::gpu::adapters().iter().enumerate() {
            say!("{i}: {} ({:?}, {:?}, {} {})", a.name, a.device_type, a.backend, a.driver, a.driver_info);
        }
        return Ok(ExitCode::SUCCESS);
    }
    let Some(scene_path) = &cli.scene else {
        return Err(Error::Setting("a scene file is required".into()));
    };
    if cli.output.is_none() && cli.partial.is_none() {
        return Err(Error::Setting("-o OUTPUT or --partial OUT.exr is required".into()));
    }
    render(cli, scene_path).map(|code| code.map_or(ExitCode::SUCCESS, ExitCode::from))
}

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

/// `A..B` (passes A to B-1, B > A) as `(A, B)`.
fn parse_pass_range(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`{text}`: a range of passes A..B (A from 0, B > A), such as 0..16");
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let (a, b): (u32, u32) = (a.trim().parse().map_err(|_| bad())?, b.trim().parse().map_err(|_| bad())?);
    if b <= a {
        return Err(bad());
    }
    Ok((a, b))
}

/// `sppm-gpu merge PART... -o OUT`.
fn merge(parts: &[PathBuf], output: &Path) -> Result<(), Error> {
    for part in parts {
        check_output(output, part)?;
    }
    let partials = parts.iter().map(|p| sppm_gpu::batch::read_partial(p)).collect::<Result<Vec<_>, _>>()?;
    let (image, warnings) = sppm_gpu::batch::merge(&partials)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    if output.exists() {
        eprintln!("note: replacing {}", output.display());
    }
    image_io::write_image(output, &image)?;
    let passes: u32 = partials.iter().map(|p| p.end - p.first).sum();
    let end = partials.iter().map(|p| p.end).max().unwrap_or(0);
    say!("merged {} parts: {passes} passes of 0..{end} -> {}", partials.len(), output.display());
    Ok(())
}

/// `1000000`, `512K`, `64M`, `8G` (powers of 1024) as bytes.
fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let (digits, unit) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&t[..i], c.to_ascii_uppercase()),
        _ => (t, 'B'),
    };
    let shift = match unit {
        'B' => 0,
        'K' => 10,
        'M' => 20,
        'G' => 30,
        _ => return Err(format!("`{text}`: a number of bytes, with K, M or G for powers of 1024")),
    };
    let n: u64 = digits.trim().parse().map_err(|_| format!("`{text}`: a number of bytes, with K, M or G for powers of 1024"))?;
    n.checked_mul(1 << shift).filter(|&b| b > 0).ok_or_else(|| format!("`{text}`: out of range"))
}

/// Bytes of memory the host can still give: `MemAvailable` in /proc/meminfo (Linux).
fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Refuse at once a render that needs more memory than it can have: `limit` when given
/// (device buffers and host image together), else on a CPU device (whose buffers are host
/// memory) the host's available memory. A render that does not fit would otherwise grow
/// until the system kills it, with nothing written.
fn check_memory(gpu: &GpuContext, scene: &scene::Scene, limit: Option<u64>) -> Result<(), Error> {
    let need = integrators::memory_need(&gpu.device, scene);
    let cpu_device = gpu.adapter_info.device_type == wgpu::DeviceType::Cpu;
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
fn render(cli: &Cli, scene_path: &Path) -> Result<Option<u8>, Error> {
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
    check_memory(&gpu, &scene, cli.memory_limit)?;
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
    // GPU reset would (tests/checkpoint.rs).
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
    let (most_in_flight, largest_group) = (pacer.most_passes_in_flight(), pacer.largest_group());
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
            "in flight: at most {most_in_flight} passes (at most {} submissions of up to {largest_group} passes)",
            pacing::MAX_IN_FLIGHT
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

/// Run the scene's passes with a wait after each stage and print where the time goes.
fn bench(scene_path: &Path, overrides: &Overrides) -> Result<(), Error> {
    let (mut scene, _) = load_scene(scene_path, overrides)?;
    let gpu = GpuContext::new()?;
    scene.render.fit_pass_work(gpu.pass_work());
    let mut sppm = Sppm::new(&gpu.device, &gpu.queue, &scene)?;
    let r = &scene.render;
    // One untimed pass first: the driver may compile kernels at their first dispatch.
    sppm.run_pass()?;
    sppm.wait()?;
    // Stage totals: camera paths, grid build, photons, statistics.
    let mut stage = [0.0f64; 4];
    let start = Instant::now();
    while sppm.passes() <= r.iterations {
        let mut t = Instant::now();
        let mut lap = |i: usize, sppm: &Sppm| -> Result<(), Error> {
            sppm.wait()?;
            stage[i] += t.elapsed().as_secs_f64();
            t = Instant::now();
            Ok(())
        };
        sppm.trace_camera_paths();
        lap(0, &sppm)?;
        sppm.build_grid()?;
        lap(1, &sppm)?;
        sppm.trace_photons();
        lap(2, &sppm)?;
        sppm.update_statistics();
        lap(3, &sppm)?;
    }
    let seconds = start.elapsed().as_secs_f64();
    let passes = r.iterations as f64;
    let paths = sppm_gpu::integrators::sppm::direct_samples(r);
    let direct = match r.direct {
        DirectLight::Photons => "from photons".to_string(),
        DirectLight::Sampled => format!("sampled by {paths} camera paths per visible point"),
    };
    say!(
        "{}: {}x{}, {} passes (after one untimed) x {} photons, max_depth {}, direct light {}, {}",
        scene_path.display(),
        r.width,
        r.height,
        r.iterations,
        r.photons,
        r.max_depth,
        direct,
        gpu.adapter_info.name
    );
    for (name, s) in ["camera paths", "grid build", "photons", "statistics"].iter().zip(stage) {
        say!("  {name:32} {:8.1} ms/pass  {:5.1}%", 1e3 * s / passes, 100.0 * s / seconds);
    }
    say!(
        "  total {seconds:.2} s: {:.2} passes/s, {:.3} M photons/s, {:.2} M camera paths/s",
        passes / seconds,
        passes * r.photons as f64 / seconds / 1e6,
        passes * (r.width * r.height * r.spp * paths) as f64 / stage[0] / 1e6
    );
    let radius = sppm.radius_stats()?;
    say!(
        "  radius after the last pass: min {:.3e}, mean {:.3e}, max {:.3e} (initial {:.3e})",
        radius.min,
        radius.mean,
        radius.max,
        sppm.initial_radius()
    );
    if sppm.deposits_at_once() {
        say!(
            "  photon hits added at once to the visible points around them (at least {} photons a visible point)",
            sppm_gpu::integrators::sppm::AT_ONCE_PHOTONS_PER_POINT
        );
    } else {
        let (gathered, resumed) = sppm.photon_hits_gathered()?;
        say!(
            "  photon hits of the last pass gathered: {gathered} (room for {} at a time); photon threads resumed to deposit at once: {resumed}",
            sppm.photon_hit_capacity()
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
