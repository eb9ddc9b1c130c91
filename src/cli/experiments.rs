//! `sppm-gpu compare`, `sweep` and `passes`: the experiments of `sppm_gpu::experiments`.

use super::args::load_scene;
use super::output::{self, Inputs, Kind};
use super::{Command, Overrides};
use sppm_gpu::{experiments, Error};
use std::path::Path;

/// Loads `scene` for an experiment writing `files` into `out`, after checking them by the
/// output rule (src/cli/output.rs) before and after the scene names its files; `out` is made
/// where it does not exist.
fn load_for(
    scene: &Path,
    overrides: &Overrides,
    reference: Option<&Path>,
    out: &Path,
    files: &[(String, Kind)],
) -> Result<(sppm_gpu::scene::Scene, String), Error> {
    std::fs::create_dir_all(out).map_err(|e| Error::Setting(format!("{}: cannot create the folder: {e}", out.display())))?;
    let mut inputs = Inputs::of(std::iter::once(scene).chain(reference));
    let check =
        |inputs: &Inputs| files.iter().try_for_each(|(name, kind)| output::check(&out.join(name), *kind, inputs).map(drop));
    check(&inputs)?;
    let loaded = load_scene(scene, overrides)?;
    inputs.extend(loaded.0.inputs.iter().cloned());
    check(&inputs)?;
    Ok(loaded)
}

/// The `compare`, `sweep` and `passes` subcommands (in `experiments`).
pub(crate) fn experiment(command: &Command) -> Result<(), Error> {
    match command {
        Command::Compare { scene, reference, methods, downsample, first_snapshot, out, overrides } => {
            overrides.refuse("compare", &["method"], "it runs the methods of --methods (a comma-separated list)")?;
            // Each method of --methods sets SPPM's direct light (sppm, sppm-photons).
            overrides.refuse(
                "compare",
                &["direct"],
                "the methods of --methods set it (sppm samples it, sppm-photons takes it from photons)",
            )?;
            let files = [
                ("compare.csv".to_string(), Kind::Csv("method,seconds,passes,relMSE,RMSE")),
                ("relmse-vs-time.png".to_string(), Kind::Image),
                ("equal-time.png".to_string(), Kind::Image),
            ];
            let (scene, name) = load_for(scene, overrides, Some(reference), out, &files)?;
            let Some(time_limit) = scene.render.time_limit else {
                return Err(Error::Setting("compare needs --time-limit SECS".into()));
            };
            let methods = methods.clone();
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
            overrides.refuse("sweep", &["time-limit"], "it runs --iterations passes for each value")?;
            let param = experiments::SweepParam::parse(param)?;
            let files = [
                ("sweep.csv".to_string(), Kind::Csv("parameter,value,pass,seconds,relMSE,RMSE")),
                ("relmse-vs-passes.png".to_string(), Kind::Image),
                (format!("relmse-vs-{}.png", param.name()), Kind::Image),
                ("images.png".to_string(), Kind::Image),
            ];
            let (scene, name) = load_for(scene, overrides, Some(reference), out, &files)?;
            let opts = experiments::SweepOptions {
                param,
                values: values.clone(),
                reference: reference.clone(),
                downsample: *downsample,
                out: out.clone(),
            };
            experiments::sweep(&scene, &name, &opts).map(drop)
        }
        Command::Passes { scene, snapshots, reference, downsample, out, overrides } => {
            overrides.refuse("passes", &["time-limit", "iterations"], "it runs until the largest of --snapshots")?;
            let files = [
                ("passes.csv".to_string(), Kind::Csv("pass,seconds,total_seconds")),
                ("time-per-pass.png".to_string(), Kind::Image),
                ("images.png".to_string(), Kind::Image),
            ];
            let (scene, name) = load_for(scene, overrides, reference.as_deref(), out, &files)?;
            let opts = experiments::PassesOptions {
                snapshots: snapshots.clone(),
                reference: reference.clone(),
                downsample: *downsample,
                out: out.clone(),
            };
            experiments::passes(&scene, &name, &opts).map(drop)
        }
        _ => Err(Error::Setting("not an experiment: compare, sweep or passes".into())),
    }
}
