//! `sppm-gpu compare`, `sweep` and `passes`: the experiments of `sppm_gpu::experiments`.

use super::args::load_scene;
use super::Command;
use sppm_gpu::{experiments, Error};

/// The `compare`, `sweep` and `passes` subcommands (in `experiments`).
pub(crate) fn experiment(command: &Command) -> Result<(), Error> {
    match command {
        Command::Compare { scene, reference, methods, downsample, first_snapshot, out, overrides } => {
            let (scene, name) = load_scene(scene, overrides)?;
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
        _ => Err(Error::Setting("not an experiment: compare, sweep or passes".into())),
    }
}
