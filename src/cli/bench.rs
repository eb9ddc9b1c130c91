//! `sppm-gpu bench SCENE`: the time of each stage of an SPPM pass.

use super::args::{load_scene, Overrides};
use sppm_gpu::gpu::GpuContext;
use sppm_gpu::integrators::Sppm;
use sppm_gpu::scene::DirectLight;
use sppm_gpu::{say, Error};
use std::path::Path;
use std::time::Instant;

/// The stages of an SPPM pass, in order.
pub(crate) const STAGES: [&str; 4] = ["camera paths", "grid build", "photons", "statistics"];

/// Runs `passes` passes of `sppm`, waiting for the device after each stage: the seconds of
/// each of [`STAGES`], summed.
pub(crate) fn stage_times(sppm: &mut Sppm, passes: u32) -> Result<[f64; 4], Error> {
    let mut stage = [0.0f64; 4];
    for _ in 0..passes {
        let mut t = Instant::now();
        let mut lap = |i: usize, sppm: &Sppm| -> Result<(), Error> {
            sppm.wait()?;
            stage[i] += t.elapsed().as_secs_f64();
            t = Instant::now();
            Ok(())
        };
        sppm.trace_camera_paths();
        lap(0, sppm)?;
        sppm.build_grid()?;
        lap(1, sppm)?;
        sppm.trace_photons();
        lap(2, sppm)?;
        sppm.update_statistics();
        lap(3, sppm)?;
    }
    Ok(stage)
}

/// Run the scene's passes with a wait after each stage and print where the time goes.
pub(crate) fn bench(scene_path: &Path, overrides: &Overrides) -> Result<(), Error> {
    overrides.refuse("bench", &["method", "time-limit"], "it times the stages of SPPM passes, --iterations of them")?;
    let (mut scene, _) = load_scene(scene_path, overrides)?;
    let gpu = GpuContext::new()?;
    scene.render.fit_pass_work(gpu.pass_work());
    let mut sppm = Sppm::new(&gpu.device, &gpu.queue, &scene)?;
    let r = &scene.render;
    // One untimed pass first: the driver may compile kernels at their first dispatch.
    sppm.run_pass()?;
    sppm.wait()?;
    let start = Instant::now();
    let stage = stage_times(&mut sppm, r.iterations)?;
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
    for (name, s) in STAGES.iter().zip(stage) {
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
