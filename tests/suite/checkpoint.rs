//! Checkpoints and resume through the command line: a render stopped (even by SIGKILL) and
//! resumed gives the image an uninterrupted render gives, bit for bit, for SPPM and pt-nee,
//! with either sampler and under a splatting filter; a checkpoint of another scene or other settings is refused.

use crate::common;

use sppm_gpu::scene::Named;
use std::path::Path;
use std::process::{Command, Output};

const SIZE: [&str; 8] = ["--width", "40", "--height", "32", "--photons", "4000", "--seed", "9"];

fn sppm_gpu(scene: &str, method: &str, out: &Path, args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"));
    command
        .arg(common::scene_path(scene))
        .arg("-o")
        .arg(out)
        .args(["--method", method])
        .args(SIZE)
        .args(args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir());
    command
}

fn run(mut command: Command) -> Output {
    let output = command.output().expect("the binary runs");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    output
}

fn bits(path: &Path) -> Vec<u32> {
    let image = sppm_gpu::image_io::read_exr(path).unwrap_or_else(|e| panic!("{e}"));
    image.pixels.iter().flatten().map(|v| v.to_bits()).collect()
}

/// The passes a resumed run starts from, as it reports them.
fn resumed_after(stderr: &[u8]) -> u32 {
    let text = String::from_utf8_lossy(stderr);
    let line = text.lines().find(|l| l.starts_with("resuming from ")).unwrap_or_else(|| panic!("{text}"));
    line.rsplit(" after ").next().and_then(|t| t.strip_suffix(" passes")).and_then(|n| n.parse().ok()).unwrap()
}

#[test]
fn stopped_and_resumed_equals_uninterrupted() {
    if common::gpu().is_none() {
        return;
    }
    // mitsuba/lights.xml: a gaussian filter, whose samples pt-nee splats (sums of weights), as
    // SPPM splats its passes' estimates (its default schedule there, the global one).
    for (scene, method, sampler) in [
        ("cornell-box.toml", "sppm", "independent"),
        ("cornell-box.toml", "pt-nee", "independent"),
        ("cornell-box.toml", "sppm", "sobol"),
        ("cornell-box.toml", "pt-nee", "sobol"),
        ("mitsuba/lights.xml", "pt-nee", "sobol"),
        ("mitsuba/lights.xml", "sppm", "sobol"),
    ] {
        let dir = common::scratch(&format!("checkpoint-resume-{method}-{sampler}-{}", scene.len()));
        let (full, part, resumed, checkpoint) =
            (dir.join("full.exr"), dir.join("part.exr"), dir.join("resumed.exr"), dir.join("ck"));
        let ck = checkpoint.to_str().unwrap();
        let s = ["--sampler", sampler];
        run(sppm_gpu(scene, method, &full, &[&["--iterations", "6"][..], &s].concat()));
        run(sppm_gpu(scene, method, &part, &[&["--iterations", "3", "--checkpoint", ck][..], &s].concat()));
        let output = run(sppm_gpu(scene, method, &resumed, &[&["--iterations", "6", "--resume", ck][..], &s].concat()));
        assert_eq!(resumed_after(&output.stderr), 3);
        assert_ne!(bits(&part), bits(&full), "{method} {sampler}: 3 passes differ from 6");
        assert!(bits(&resumed) == bits(&full), "{method} {sampler}: resumed after 3 passes differs from 6 passes in one run");
    }
}

/// The adaptive radius rule's per-point tests are part of the state: a render stopped after
/// 4 passes and resumed to 8 gives the image of 8 passes in one run, which differs from the
/// plain rule's.
#[test]
fn adaptive_radius_resumes_bit_for_bit() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("checkpoint-resume-adaptive");
    let (full, part, resumed, plain, checkpoint) =
        (dir.join("full.exr"), dir.join("part.exr"), dir.join("resumed.exr"), dir.join("plain.exr"), dir.join("ck"));
    let ck = checkpoint.to_str().unwrap();
    let rule = ["--radius-rule", "adaptive"];
    run(sppm_gpu("cornell-spheres.toml", "sppm", &full, &[&["--iterations", "8"][..], &rule].concat()));
    run(sppm_gpu("cornell-spheres.toml", "sppm", &plain, &["--iterations", "8"]));
    run(sppm_gpu("cornell-spheres.toml", "sppm", &part, &[&["--iterations", "4", "--checkpoint", ck][..], &rule].concat()));
    let output =
        run(sppm_gpu("cornell-spheres.toml", "sppm", &resumed, &[&["--iterations", "8", "--resume", ck][..], &rule].concat()));
    assert_eq!(resumed_after(&output.stderr), 4);
    assert_ne!(bits(&plain), bits(&full), "the adaptive rule changed nothing");
    assert!(bits(&resumed) == bits(&full), "resumed after 4 passes differs from 8 passes in one run");
    // The rule is in the fingerprint: the plain rule does not resume it.
    let refused = sppm_gpu("cornell-spheres.toml", "sppm", &dir.join("other.exr"), &["--iterations", "8", "--resume", ck])
        .output()
        .unwrap();
    assert!(!refused.status.success(), "a checkpoint of the adaptive rule resumed under the plain one");
}

/// Killed with SIGKILL at some pass (checkpoints after every pass), resumed to two passes
/// past its checkpoint: the image of as many passes in one run, bit for bit.
#[test]
fn sigkill_then_resume_is_bit_identical() {
    if common::gpu().is_none() {
        return;
    }
    for method in ["sppm", "pt-nee"] {
        let dir = common::scratch(&format!("checkpoint-sigkill-{method}"));
        let checkpoint = dir.join("ck");
        let ck = checkpoint.to_str().unwrap();
        let mut child = sppm_gpu(
            "cornell-box.toml",
            method,
            &dir.join("killed.exr"),
            &["--iterations", "1000000", "--checkpoint", ck, "--checkpoint-every", "0"],
        )
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
        let start = std::time::Instant::now();
        while !checkpoint.exists() {
            assert!(start.elapsed().as_secs() < 120, "{method}: no checkpoint written");
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        std::thread::sleep(std::time::Duration::from_millis(500));
        child.kill().unwrap();
        child.wait().unwrap();
        assert!(!dir.join("killed.exr").exists(), "killed before writing its image");

        let probe = run(sppm_gpu("cornell-box.toml", method, &dir.join("probe.exr"), &["--iterations", "1", "--resume", ck]));
        let passes = resumed_after(&probe.stderr);
        assert!(passes >= 1, "{method}: checkpoint after {passes} passes");
        let target = (passes + 2).to_string();
        let resumed = dir.join("resumed.exr");
        run(sppm_gpu("cornell-box.toml", method, &resumed, &["--iterations", &target, "--resume", ck]));
        let full = dir.join("full.exr");
        run(sppm_gpu("cornell-box.toml", method, &full, &["--iterations", &target]));
        assert!(bits(&resumed) == bits(&full), "{method}: killed after {passes} passes and resumed differs");
    }
}

#[test]
fn a_checkpoint_of_another_scene_or_settings_is_refused() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("checkpoint-refused");
    let checkpoint = dir.join("ck");
    let ck = checkpoint.to_str().unwrap();
    run(sppm_gpu("cornell-box.toml", "sppm", &dir.join("a.exr"), &["--iterations", "1", "--checkpoint", ck]));
    use sppm_gpu::sampler::Sampler;
    let other = if Sampler::DEFAULT == Sampler::Sobol { Sampler::Independent } else { Sampler::Sobol };
    let sampler_changed = format!("sampler {:?} (now {other:?})", Sampler::DEFAULT);
    for (scene, extra, expected) in [
        ("cornell-spheres.toml", &[][..], "the geometry"),
        ("cornell-box.toml", &["--alpha", "0.5"][..], "alpha 0.6667 (now 0.5)"),
        ("cornell-box.toml", &["--sampler", other.name()][..], sampler_changed.as_str()),
    ] {
        let output = sppm_gpu(scene, "sppm", &dir.join("b.exr"), &[&["--iterations", "2", "--resume", ck][..], extra].concat())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("cannot resume: it was made from another scene or other settings"), "{stderr}");
        assert!(stderr.contains(expected), "{stderr}");
        assert!(!dir.join("b.exr").exists());
    }
}

/// A device lost mid-render (a driver crash or GPU reset; `SPPM_GPU_LOSE_DEVICE_AFTER` makes
/// one) ends the run with a clear error and no panic, pointing to the last checkpoint, from
/// which the render goes on to the image an uninterrupted run gives, bit for bit.
#[test]
fn a_lost_device_leaves_a_checkpoint_to_resume_from() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("checkpoint-lost-device");
    let checkpoint = dir.join("ck");
    let ck = checkpoint.to_str().unwrap();
    let output = sppm_gpu(
        "cornell-box.toml",
        "sppm",
        &dir.join("lost.exr"),
        &["--iterations", "6", "--checkpoint", ck, "--checkpoint-every", "0"],
    )
    .env("SPPM_GPU_LOSE_DEVICE_AFTER", "3")
    .output()
    .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("the GPU device was lost"), "{stderr}");
    assert!(stderr.contains(&format!("--resume {ck} goes on from the last checkpoint")), "{stderr}");
    // The device cannot give its image back: the last checkpoint's, made on the host, is
    // written, and matches the device's image of those 3 passes.
    assert!(stderr.contains("the image of the 3 passes of the last checkpoint was written"), "{stderr}");
    let three = dir.join("three.exr");
    run(sppm_gpu("cornell-box.toml", "sppm", &three, &["--iterations", "3"]));
    let host = sppm_gpu::image_io::read_exr(&dir.join("lost.exr")).unwrap();
    let device = sppm_gpu::image_io::read_exr(&three).unwrap();
    for (a, b) in host.pixels.iter().flatten().zip(device.pixels.iter().flatten()) {
        assert!((a - b).abs() <= 1e-5 * b.abs().max(1e-3), "host resolve {a} vs device {b}");
    }
    let resumed = dir.join("resumed.exr");
    let output = run(sppm_gpu("cornell-box.toml", "sppm", &resumed, &["--iterations", "6", "--resume", ck]));
    assert_eq!(resumed_after(&output.stderr), 3);
    let full = dir.join("full.exr");
    run(sppm_gpu("cornell-box.toml", "sppm", &full, &["--iterations", "6"]));
    assert!(bits(&resumed) == bits(&full), "resumed after the lost device differs");
}

/// vcm's pilot's choice is kept by the checkpoint, and a resumed render renders it without a
/// pilot of its own (under a time limit the pilot's choice depends on the passes that fit, and
/// a resumed run has another limit): resumed after 3 of 6 passes, the image of 6 passes in one
/// run, bit for bit. A checkpoint whose choice is not one is refused, naming the file.
#[test]
fn vcm_resumes_with_its_pilots_choice() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("checkpoint-vcm-pilot");
    let checkpoint = dir.join("ck");
    let ck = checkpoint.to_str().unwrap();
    let six = ["--iterations", "6"];
    let output = sppm_gpu("cornell-box.toml", "vcm", &dir.join("lost.exr"), &[&six[..], &["--checkpoint", ck]].concat())
        .args(["--checkpoint-every", "0"])
        .env("SPPM_GPU_LOSE_DEVICE_AFTER", "3")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1), "{}", String::from_utf8_lossy(&output.stderr));
    let saved = sppm_gpu::checkpoint::read(&checkpoint).unwrap();
    let choice = saved.pilot.clone().expect("the pilot's choice is kept");
    let full = dir.join("full.exr");
    let stderr = String::from_utf8_lossy(&run(sppm_gpu("cornell-box.toml", "vcm", &full, &six)).stderr).into_owned();
    assert!(stderr.contains("vcm's pilot ("), "{stderr}");
    let resumed = dir.join("resumed.exr");
    let output = run(sppm_gpu("cornell-box.toml", "vcm", &resumed, &[&six[..], &["--resume", ck]].concat()));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains(&format!("vcm renders {choice} as its pilot chose when the render began")), "{stderr}");
    assert!(!stderr.contains("vcm's pilot ("), "a resumed render ran a pilot: {stderr}");
    assert_eq!(resumed_after(&output.stderr), 3);
    assert!(bits(&resumed) == bits(&full), "vcm resumed after 3 passes differs from 6 passes in one run");
    let altered = sppm_gpu::checkpoint::Checkpoint { pilot: Some("1/2".into()), ..saved };
    sppm_gpu::checkpoint::write(&checkpoint, &altered).unwrap();
    let output = sppm_gpu("cornell-box.toml", "vcm", &resumed, &[&six[..], &["--resume", ck]].concat()).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains(ck) && stderr.contains("`1/2` is not a choice of vcm's pilot"), "{stderr}");
}

/// Where vcm's first passes varied far more than its pilot read (a test hook scales what they
/// showed), the render starts over with the pilot's runner-up, which the checkpoint keeps and a
/// resumed render renders; the image is the new choice's.
#[test]
fn vcm_keeps_the_choice_its_first_passes_switched_to() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("checkpoint-vcm-switch");
    let checkpoint = dir.join("ck");
    let ck = checkpoint.to_str().unwrap();
    let out = dir.join("switched.exr");
    let mut command = sppm_gpu("cornell-box.toml", "vcm", &out, &["--time-limit", "3", "--checkpoint", ck]);
    command.env("SPPM_GPU_CHECK_RATIO", "1e6");
    let output = run(command);
    let stderr = String::from_utf8_lossy(&output.stderr);
    let saved = sppm_gpu::checkpoint::read(&checkpoint).unwrap();
    let choice: sppm_gpu::integrators::shares::Choice = saved.pilot.as_deref().expect("a choice kept").parse().unwrap();
    let said = format!("{} renders less error in the time left; the render starts over with it", choice.description());
    assert!(stderr.contains(&said), "{said}\n{stderr}");
    let chose = stderr.split("vcm's pilot (").nth(1).and_then(|rest| rest.split(") chose ").nth(1)).unwrap_or_default();
    assert!(!chose.starts_with(&choice.description()), "the pilot chose it already: {stderr}");
    let image = sppm_gpu::image_io::read_image(&out).unwrap();
    assert!(image.pixels.iter().flatten().all(|v| v.is_finite()) && image.pixels.iter().flatten().any(|&v| v > 0.0));
    let resumed = dir.join("resumed.exr");
    let output = run(sppm_gpu("cornell-box.toml", "vcm", &resumed, &["--time-limit", "1", "--resume", ck]));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains(&format!("vcm renders {choice} as its pilot chose when the render began")), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}
