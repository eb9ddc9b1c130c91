//! A render split into batches of passes (`src/batch.rs`): SPPM's global radius schedule
//! (Knaus & Zwicker 2011) against the references and its own formula, and batches merged
//! against one process rendering every pass, through the library and the command line.

use crate::common;

use sppm_gpu::batch::{merge, read_partial, write_partial, Partial};
use sppm_gpu::checkpoint::Fingerprint;
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators::sppm::global_radius_sq;
use sppm_gpu::integrators::{self, Integrator, Sppm};
use sppm_gpu::metrics::{compare, count_negative, count_non_finite, downsample_box};
use sppm_gpu::scene::{Method, RadiusSchedule, Scene};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A merged pixel may differ from one process's by this much, relative, plus `ABSOLUTE`: the
/// bound `src/batch.rs` states (f32 rounding of the batch sums and of the GPU's sums taken in
/// another order).
const RELATIVE: f32 = 1e-5;
const ABSOLUTE: f32 = 1e-6;

fn global(name: &str, size: u32, photons: u32) -> Scene {
    let mut scene = common::load_scene(name);
    scene.render.width = size;
    scene.render.height = size;
    scene.render.photons = photons;
    scene.render.radius_schedule = RadiusSchedule::Global;
    scene
}

/// Passes `first..end` of `scene` by one integrator, as the command line's `--passes` does.
fn batch(gpu: &sppm_gpu::gpu::GpuContext, scene: &Scene, first: u32, end: u32) -> Rgb32Image {
    batch_with_splats(gpu, scene, first, end).0
}

/// [`batch`], and the sums its image is made of under a splatting filter.
fn batch_with_splats(
    gpu: &sppm_gpu::gpu::GpuContext,
    scene: &Scene,
    first: u32,
    end: u32,
) -> (Rgb32Image, Option<sppm_gpu::integrators::SplatSums>) {
    let mut r = integrators::create(&gpu.device, &gpu.queue, scene).unwrap_or_else(|e| panic!("{e}"));
    r.start_at_pass(first).unwrap_or_else(|e| panic!("{e}"));
    while r.passes() < end {
        r.run_pass().unwrap_or_else(|e| panic!("{e}"));
    }
    let image = r.image().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(count_non_finite(&image), 0);
    assert_eq!(count_negative(&image), 0);
    (image, r.splat_sums().unwrap_or_else(|e| panic!("{e}")))
}

/// The largest difference between `a` and `b` in units of the stated bound (at most 1 passes).
fn worst_against_bound(a: &Rgb32Image, b: &Rgb32Image) -> f32 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let mut worst = 0.0f32;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            worst = worst.max((p[c] - q[c]).abs() / (RELATIVE * q[c].abs() + ABSOLUTE));
        }
    }
    worst
}

/// The global schedule converges where the per-point one does: the furnace's 2.0, and the
/// Cornell scenes against their references with the tolerances of `tests/suite/sppm.rs`, at
/// 12 passes of 100,000 photons. At 24 passes of 200,000 (2026-11-30) the relMSE read 8.8e-5
/// (cornell-box) and 4.3e-4 (cornell-spheres), the channel means within 0.08%; at a quarter of
/// the photons 1.8e-4 and 6.0e-4, within 0.12%: under the bounds (3e-3, 1e-2; 2 and 3%) by
/// 16x or more, where a schedule that converges elsewhere shows as it did at 24 passes.
#[test]
fn global_schedule_matches_references() {
    let Some(gpu) = common::gpu() else { return };
    let mut furnace = common::load_scene("furnace.toml");
    furnace.render.radius_schedule = RadiusSchedule::Global;
    let mean = batch(&gpu, &furnace, 0, furnace.render.iterations).mean();
    for c in mean {
        assert!((c - 2.0).abs() < 0.02, "furnace mean {mean:?}");
    }
    for (name, max_rel_mse, max_ratio) in [("cornell-box", 0.003, 0.02), ("cornell-spheres", 0.01, 0.03)] {
        let mut scene = global(&format!("{name}.toml"), 128, 100_000);
        scene.render.iterations = 12;
        let image = batch(&gpu, &scene, 0, 12);
        let reference = downsample_box(&common::reference(&format!("{name}.exr")), 2).unwrap();
        let c = compare(&image, &reference, 4).unwrap();
        eprintln!("{name}, global schedule: {c:?}");
        assert!(c.rel_mse < max_rel_mse, "{name}: relMSE {}", c.rel_mse);
        for r in c.mean_ratio {
            assert!((r - 1.0).abs() < max_ratio, "{name}: channel mean ratios {:?}", c.mean_ratio);
        }
    }
}

/// Every visible point of pass i takes r_i, r_i^2 = r_1^2 prod_{k<i} (k + alpha) / (k + 1),
/// whatever pass the renderer started at.
#[test]
fn global_radius_follows_the_schedule() {
    let Some(gpu) = common::gpu() else { return };
    let scene = global("cornell-box.toml", 32, 10_000);
    let alpha = scene.render.alpha;
    // The schedule itself, against the product written out for the third pass.
    let r1 = 0.05f32;
    let expected = (r1 as f64).powi(2) * ((1.0 + alpha as f64) / 2.0) * ((2.0 + alpha as f64) / 3.0);
    assert!((global_radius_sq(r1, alpha, 2) - expected).abs() < 1e-15);
    assert_eq!(global_radius_sq(r1, alpha, 0), (r1 as f64).powi(2));
    // It shrinks as Knaus & Zwicker's r_i^2 ~ i^(alpha - 1).
    let ratio = global_radius_sq(r1, alpha, 9999) / global_radius_sq(r1, alpha, 999);
    assert!((ratio / 10f64.powf(alpha as f64 - 1.0) - 1.0).abs() < 1e-3, "{ratio}");

    for first in [0, 5] {
        let mut sppm = Sppm::new(&gpu.device, &gpu.queue, &scene).unwrap();
        sppm.start_at_pass(first).unwrap();
        for pass in first..first + 3 {
            sppm.trace_camera_paths();
            let points = sppm.visible_point_positions().unwrap();
            let r = global_radius_sq(sppm.initial_radius(), alpha, pass).sqrt() as f32;
            let found: Vec<f32> = points.iter().map(|p| p[3]).filter(|&w| w > 0.0).collect();
            assert!(found.len() > points.len() / 2);
            assert!(found.iter().all(|&w| w == r), "pass {pass}: radii {:?} where {r}", &found[..4]);
            sppm.build_grid().unwrap();
            sppm.trace_photons();
            sppm.update_statistics();
        }
    }
    // A radius per point cannot start anywhere but at the beginning.
    let mut per_point = scene.clone();
    per_point.render.radius_schedule = RadiusSchedule::PerPoint;
    let mut sppm = Sppm::new(&gpu.device, &gpu.queue, &per_point).unwrap();
    let e = sppm.start_at_pass(4).unwrap_err().to_string();
    assert!(e.contains("radius_schedule") && e.contains("global"), "{e}");
}

/// Four batches written as partials, read back and merged, against one integrator running
/// every pass: within the stated bound, for SPPM with the global schedule and for pt-nee, with
/// either sampler (the Sobol sampler's photons are numbered across passes), and for pt-nee,
/// bpt and SPPM under a gaussian filter, whose partials carry the splat sums (without them,
/// merged by passes, the merge is off by more than the bound).
#[test]
fn batches_merge_to_the_whole_render() {
    let Some(gpu) = common::gpu() else { return };
    let dir = common::scratch("gpu-batch-merge");
    // Every integrator of one scene, method and sampler makes the same kernels: made once.
    sppm_gpu::gpu::share_kernels(|| merges(&gpu, &dir));
}

/// [`batches_merge_to_the_whole_render`]'s renders and checks, in `dir`.
fn merges(gpu: &sppm_gpu::gpu::GpuContext, dir: &std::path::Path) {
    use sppm_gpu::sampler::Sampler;
    use sppm_gpu::scene::PixelFilter;
    let gaussian = PixelFilter::Gaussian { stddev: 0.5 };
    for (method, sampler, filter) in [
        (Method::Sppm, Sampler::Independent, PixelFilter::Box),
        (Method::PtNee, Sampler::Independent, PixelFilter::Box),
        (Method::Sppm, Sampler::Sobol, PixelFilter::Box),
        (Method::PtNee, Sampler::Sobol, PixelFilter::Box),
        (Method::PtNee, Sampler::Sobol, gaussian),
        (Method::Bpt, Sampler::Sobol, gaussian),
        (Method::Sppm, Sampler::Sobol, gaussian),
    ] {
        let mut scene = global("cornell-spheres.toml", 48, 20_000);
        (scene.render.method, scene.render.sampler, scene.render.filter) = (method, sampler, filter);
        let whole = batch(gpu, &scene, 0, 12);
        let fingerprint = Fingerprint::of(&scene);
        let ranges = [(0, 3), (3, 4), (4, 9), (9, 12)];
        let mut unsplatted = Vec::new();
        let mut parts: Vec<Partial> = ranges
            .iter()
            .map(|&(a, b)| {
                let path = dir.join(format!("{method:?}-{sampler:?}-{filter:?}-{a}-{b}.exr"));
                let (image, splat) = batch_with_splats(gpu, &scene, a, b);
                assert_eq!(splat.is_some(), filter != PixelFilter::Box, "{method:?} {filter:?}: splat sums");
                write_partial(&path, &image, splat.as_ref(), a, b, &fingerprint).unwrap();
                let plain = dir.join(format!("plain-{a}-{b}.exr"));
                write_partial(&plain, &image, None, a, b, &fingerprint).unwrap();
                unsplatted.push(read_partial(&plain).unwrap_or_else(|e| panic!("{e}")));
                read_partial(&path).unwrap_or_else(|e| panic!("{e}"))
            })
            .collect();
        if filter != PixelFilter::Box {
            let (merged, _) = merge(&unsplatted).unwrap();
            let worst = worst_against_bound(&merged, &whole);
            assert!(worst > 1.0, "{method:?} {filter:?}: merged by passes, {worst} times the bound");
        }
        // Any order.
        parts.reverse();
        let (merged, warnings) = merge(&parts).unwrap_or_else(|e| panic!("{e}"));
        assert!(warnings.is_empty(), "{warnings:?}");
        let worst = worst_against_bound(&merged, &whole);
        eprintln!("{method:?} {sampler:?} {filter:?}: the merge differs from one process by at most {worst:.3} of the bound");
        assert!(worst <= 1.0, "{method:?} {sampler:?} {filter:?}: {worst} times the bound");
        // Not the same as a batch alone: the merge averages every pass.
        assert!(worst_against_bound(&parts[0].sum, &whole) > 1.0);

        // Passes missing: a warning, and the mean of the passes present.
        let (partial, warnings) = merge(&parts[..2]).unwrap();
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("passes 0..4"), "{warnings:?}");
        assert_eq!((partial.width, partial.height), (48, 48));
        // The same pass twice: refused.
        let e = merge(&[parts[1].clone(), parts[1].clone()]).unwrap_err().to_string();
        assert!(e.contains("share passes"), "{e}");
    }
    // Another render's part: refused, naming the difference.
    let mut scene = global("cornell-spheres.toml", 48, 20_000);
    let a = dir.join("seed0.exr");
    let b = dir.join("seed1.exr");
    write_partial(&a, &batch(gpu, &scene, 0, 1), None, 0, 1, &Fingerprint::of(&scene)).unwrap();
    scene.render.seed = 1;
    write_partial(&b, &batch(gpu, &scene, 1, 2), None, 1, 2, &Fingerprint::of(&scene)).unwrap();
    let e = merge(&[read_partial(&a).unwrap(), read_partial(&b).unwrap()]).unwrap_err().to_string();
    assert!(e.contains("seed 0 (now 1)"), "{e}");
    // Another sampler's part: refused too.
    scene.render.seed = 0;
    scene.render.sampler = if scene.render.sampler == Sampler::Sobol { Sampler::Independent } else { Sampler::Sobol };
    write_partial(&b, &batch(gpu, &scene, 1, 2), None, 1, 2, &Fingerprint::of(&scene)).unwrap();
    let e = merge(&[read_partial(&a).unwrap(), read_partial(&b).unwrap()]).unwrap_err().to_string();
    assert!(e.contains("sampler"), "{e}");
    // An image that is not a partial.
    let plain = dir.join("plain.exr");
    sppm_gpu::image_io::write_exr(&plain, &Rgb32Image::new(4, 4)).unwrap();
    assert!(read_partial(&plain).unwrap_err().to_string().contains("not a partial image"));
}

fn binary() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"));
    command.env("XDG_RUNTIME_DIR", std::env::temp_dir());
    command
}

fn run(command: &mut Command) -> (Option<i32>, String) {
    let out = command.output().expect("the binary runs");
    (out.status.code(), String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr))
}

/// The command line: `--passes A..B --partial`, `merge`, and the refusals.
#[test]
fn command_line_batches_and_merge() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("gpu-batch-cli");
    let scene = common::scene_path("cornell-box.toml");
    let settings = ["--width", "40", "--height", "30", "--photons", "20000", "--radius-schedule", "global"];
    let part = |range: &str| dir.join(format!("part-{range}.exr"));
    for range in ["0..2", "2..5", "5..6"] {
        let (code, text) = run(binary().arg(&scene).args(settings).args(["--passes", range, "--partial"]).arg(part(range)));
        assert_eq!(code, Some(0), "{text}");
    }
    let merged = dir.join("merged.exr");
    let parts: Vec<PathBuf> = ["5..6", "0..2", "2..5"].iter().map(|r| part(r)).collect();
    let (code, text) = run(binary().arg("merge").args(&parts).arg("-o").arg(&merged));
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("merged 3 parts: 6 passes"), "{text}");
    let whole = dir.join("whole.exr");
    let (code, text) = run(binary().arg(&scene).args(settings).args(["--iterations", "6", "-o"]).arg(&whole));
    assert_eq!(code, Some(0), "{text}");
    let read = |p: &Path| sppm_gpu::image_io::read_exr(p).unwrap();
    let worst = worst_against_bound(&read(&merged), &read(&whole));
    assert!(worst <= 1.0, "{worst} times the bound");

    // Missing passes: a warning, exit 0.
    let (code, text) = run(binary().arg("merge").arg(part("0..2")).arg(part("5..6")).arg("-o").arg(dir.join("gap.png")));
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("warning: passes 2..5 are in no part"), "{text}");
    // Overlap: an error naming both files, exit 1, nothing written.
    let twice = dir.join("twice.exr");
    let (code, text) = run(binary().arg("merge").arg(part("2..5")).arg(part("2..5")).arg("-o").arg(&twice));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("share passes") && text.contains("part-2..5.exr"), "{text}");
    assert!(!twice.exists());
    // A merge onto one of its parts, and a part that is not there: refused before anything.
    let (code, text) = run(binary().arg("merge").arg(part("0..2")).arg(part("2..5")).arg("-o").arg(part("0..2")));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("it will not write over its own input"), "{text}");
    assert!(read_partial(&part("0..2")).is_ok(), "the part is intact");
    let (code, text) = run(binary().arg("merge").arg(dir.join("missing.exr")).arg("-o").arg(dir.join("m.exr")));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("missing.exr"), "{text}");
    // A radius per point cannot be split, and a partial must be EXR.
    let (code, text) =
        run(binary().arg(&scene).args(["--width", "8", "--height", "8", "--passes", "2..4", "--partial"]).arg(part("x")));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("radius_schedule"), "{text}");
    let (code, text) = run(binary().arg(&scene).args(settings).args(["--passes", "0..1", "--partial"]).arg(dir.join("p.png")));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains(".exr"), "{text}");
    let (code, text) = run(binary().arg(&scene).args(["--passes", "4..2", "-o"]).arg(dir.join("q.png")));
    assert_eq!(code, Some(2), "{text}");
    // Adapters: the list, and a choice by index or name.
    let (code, text) = run(binary().arg("--list-adapters"));
    assert_eq!(code, Some(0), "{text}");
    assert!(text.starts_with("0: "), "{text}");
    let name = text.lines().next().unwrap()[3..].split(' ').next().unwrap().to_string();
    for adapter in ["0", name.as_str()] {
        let out = dir.join("adapter.png");
        let (code, text) = run(binary()
            .arg(&scene)
            .args(["--width", "8", "--height", "8", "--iterations", "1", "--adapter", adapter, "-o"])
            .arg(&out));
        assert_eq!(code, Some(0), "--adapter {adapter}: {text}");
    }
    let (code, text) = run(binary().arg(&scene).args(["--adapter", "99", "-o"]).arg(dir.join("none.png")));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("no adapter 99"), "{text}");
}
