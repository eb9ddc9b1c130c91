//! Done means: a separate crate that depends on sppm-gpu by path, creates its own device,
//! renders scenes/cornell-box.toml through the public API into its own texture, and matches
//! the command line's image for the same seed and settings, bit for bit.
//!
//! The command line is built (`cargo build --release --bin sppm-gpu`, a no-op when it is
//! up to date) and run on the same scene with the same overrides; its EXR is read with
//! `sppm_gpu::image_io::read_exr`. Without a GPU adapter the test is skipped with a message,
//! except under `CI=true`, where it fails.

use embed_check::{App, AppError};
use std::path::{Path, PathBuf};
use std::process::Command;

const WIDTH: u32 = 64;
const HEIGHT: u32 = 64;
const PASSES: u32 = 4;
const PHOTONS: u32 = 50_000;
const SEED: u32 = 7;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("the workspace root")
}

/// The target directory this test was built into (`<target>/<profile>/deps/<test>`).
fn target_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test's path");
    exe.ancestors().nth(3).expect("<target>/<profile>/deps/<test>").to_path_buf()
}

/// Build the command line in release mode and give its path.
fn cli() -> PathBuf {
    let build = Command::new(env!("CARGO"))
        .args(["build", "--release", "-p", "sppm-gpu", "--bin", "sppm-gpu"])
        .current_dir(workspace())
        .output()
        .expect("cargo runs");
    assert!(build.status.success(), "cargo build --release --bin sppm-gpu failed:\n{}", String::from_utf8_lossy(&build.stderr));
    let path = target_dir().join("release").join(format!("sppm-gpu{}", std::env::consts::EXE_SUFFIX));
    assert!(path.is_file(), "no command line at {}", path.display());
    path
}

#[test]
fn embedded_render_matches_the_command_line() {
    let app = match App::new() {
        Ok(app) => app,
        Err(AppError::NoAdapter(e)) if std::env::var("CI").map_or(true, |v| v != "true") => {
            eprintln!("skipping GPU test: no GPU adapter: {e}");
            return;
        }
        Err(e) => panic!("{e}"),
    };
    let scene_path = workspace().join("scenes/cornell-box.toml");

    // The command line's image.
    let exr = std::env::temp_dir().join(format!("embed-check-{}.exr", std::process::id()));
    let output = Command::new(cli())
        .arg(&scene_path)
        .args(["--width", &WIDTH.to_string(), "--height", &HEIGHT.to_string()])
        .args(["--iterations", &PASSES.to_string(), "--photons", &PHOTONS.to_string(), "--seed", &SEED.to_string()])
        .arg("-o")
        .arg(&exr)
        .output()
        .expect("the command line runs");
    assert!(
        output.status.success(),
        "sppm-gpu failed: {}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let expected = sppm_gpu::image_io::read_exr(&exr).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_file(&exr);

    // The same scene and settings through the public API, on the application's device.
    let mut scene = sppm_gpu::scene::load(&scene_path).unwrap_or_else(|e| panic!("{e}"));
    scene.render.width = WIDTH;
    scene.render.height = HEIGHT;
    scene.render.iterations = PASSES;
    scene.render.photons = PHOTONS;
    scene.render.seed = SEED;
    let texels = app.render(&scene, PASSES).unwrap_or_else(|e| panic!("{e}"));

    assert_eq!((expected.width, expected.height), (WIDTH, HEIGHT));
    assert_eq!(texels.len(), expected.pixels.len());
    let mut differing = 0;
    for (i, (t, e)) in texels.iter().zip(&expected.pixels).enumerate() {
        let same = (0..3).all(|c| t[c].to_bits() == e[c].to_bits());
        if !same {
            if differing < 5 {
                eprintln!("pixel ({}, {}): texture {:?}, command line {:?}", i as u32 % WIDTH, i as u32 / WIDTH, &t[..3], e);
            }
            differing += 1;
        }
        assert_eq!(t[3], 1.0, "alpha at {i}");
    }
    assert_eq!(differing, 0, "{differing} of {} pixels differ from the command line's image", texels.len());
    let mean: f32 = texels.iter().map(|t| t[0] + t[1] + t[2]).sum::<f32>() / (3 * texels.len()) as f32;
    assert!(mean > 0.05, "the image is lit (mean {mean})");
    eprintln!(
        "{}x{}, {PASSES} passes of {PHOTONS} photons on {}: bit for bit equal to the command line",
        WIDTH, HEIGHT, app.adapter_name
    );
}
