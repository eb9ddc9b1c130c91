//! The `sppm-gpu` command line, laid out as cargo's: the arguments here with one `match`
//! over the subcommands, the options they share in [`args`], and one file a subcommand.

pub mod args;
mod bench;
pub mod convert;
mod diff;
mod experiments;
pub mod info;
mod merge;
mod output;
mod render;

use crate::view;
use args::{load_scene, parse_bytes, parse_pass_range, Overrides};
use clap::Parser;
use sppm_gpu::{say, Error};
use std::path::PathBuf;
use std::process::ExitCode;

/// Render a scene with stochastic progressive photon mapping on the GPU.
#[derive(Parser, Debug)]
#[command(version, about, args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(crate) struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Scene file: TOML (format version 1), Mitsuba scene XML (`.xml`, versions 0.5/0.6
    /// and 2/3), or pbrt-v4 (`.pbrt`).
    #[arg(required_unless_present = "list_adapters")]
    scene: Option<PathBuf>,
    /// Output image: .png (sRGB, clamped) or .exr (linear float RGB). Without it (and without
    /// --partial), SCENE's name with .exr in the current directory, or the first of NAME-1.exr,
    /// NAME-2.exr, ... that does not exist: nothing is replaced unasked.
    #[arg(short, long)]
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
    /// bpt and vcm: also write each strategy's weighted share of the image beside it
    /// (OUT-emission, -nee, -connect, -merge for vcm, -lt), each rendered again for the same
    /// passes and seed; the shares add up to the image.
    #[arg(long)]
    strategy_images: bool,
    #[command(flatten)]
    overrides: Overrides,
}

#[derive(clap::Subcommand, Debug)]
pub(crate) enum Command {
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
        #[arg(long, value_delimiter = ',', default_value = "sppm,pt,pt-nee", value_parser = variant())]
        methods: Vec<sppm_gpu::experiments::Variant>,
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
    /// What a scene holds as loaded (TOML, Mitsuba XML or pbrt-v4): image and settings, camera,
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

/// `compare --methods`: the names of [`sppm_gpu::experiments::Variant`], listed in `--help`.
fn variant() -> impl clap::builder::TypedValueParser<Value = sppm_gpu::experiments::Variant> {
    use clap::builder::TypedValueParser;
    use sppm_gpu::experiments::Variant;
    clap::builder::PossibleValuesParser::new(Variant::names()).map(|name| Variant::parse(&name).expect("a variant's name"))
}

/// Run the parsed command line: one arm a subcommand, the render without one.
fn run(cli: &Cli) -> Result<ExitCode, Error> {
    let done = |result: Result<(), Error>| result.map(|()| ExitCode::SUCCESS);
    match &cli.command {
        Some(Command::Diff { image, reference, downsample, error_image }) => {
            done(diff::diff(image, reference, *downsample, error_image.as_deref()))
        }
        Some(Command::Bench { scene, overrides }) => done(bench::bench(scene, overrides)),
        Some(Command::Convert { scene, output: toml, overrides }) => {
            output::check(toml, output::Kind::New, &output::Inputs::of([scene.as_path()]))?;
            let (loaded, _) = load_scene(scene, overrides)?;
            convert::convert(&loaded, toml)?;
            say!("wrote {}", toml.display());
            Ok(ExitCode::SUCCESS)
        }
        Some(Command::Info { scene, overrides }) => {
            let (loaded, _) = load_scene(scene, overrides)?;
            print!("{}", info::report(&loaded)?);
            Ok(ExitCode::SUCCESS)
        }
        Some(Command::View { scene, reference, passes_then_pause, exposure, overrides }) => {
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
            done(view::run(options))
        }
        Some(Command::Merge { parts, output }) => done(merge::merge(parts, output)),
        Some(command @ (Command::Compare { .. } | Command::Sweep { .. } | Command::Passes { .. })) => {
            done(experiments::experiment(command))
        }
        None if cli.list_adapters => {
            for (i, a) in sppm_gpu::gpu::adapters().iter().enumerate() {
                say!("{i}: {} ({:?}, {:?}, {} {})", a.name, a.device_type, a.backend, a.driver, a.driver_info);
            }
            Ok(ExitCode::SUCCESS)
        }
        None => {
            let Some(scene_path) = &cli.scene else {
                return Err(Error::Setting("a scene file is required".into()));
            };
            render::render(cli, scene_path).map(|code| code.map_or(ExitCode::SUCCESS, ExitCode::from))
        }
    }
}

/// Parse the command line and run it: the exit code, with errors printed.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
