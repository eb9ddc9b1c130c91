//! What a newcomer meets in the first hour, through the binary: the first line names the method
//! and why, the file's integrator is honoured, `--spp` is a path tracer's samples a pixel,
//! `--time-limit` alone renders as many passes as fit after the kernels are compiled, `-o` may
//! be left out, and no option is accepted and then ignored.

use crate::common;
use std::path::Path;
use std::process::Command;

/// Runs the binary with `args` in `dir`: exit code, stdout and stderr.
fn run_in(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
        .args(args)
        .current_dir(dir)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("the binary runs");
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (output.status.code(), text(&output.stdout), text(&output.stderr))
}

fn scene(name: &str) -> String {
    common::scene_path(name).display().to_string()
}

/// `N passes, W samples` of the summary line: the passes and the work they did.
fn passes_and_work(stdout: &str) -> (u64, u64) {
    let line = stdout.lines().find(|l| l.contains(" passes, ")).unwrap_or_else(|| panic!("no summary: {stdout}"));
    let words: Vec<&str> = line.split_whitespace().collect();
    let passes = words[1].parse().unwrap_or_else(|_| panic!("{line}"));
    let work = words[3].parse().unwrap_or_else(|_| panic!("{line}"));
    (passes, work)
}

/// The first line names the method and where it came from: a TOML scene's `method`, a
/// Mitsuba file's `<integrator type="path">` (pt-nee, its sample_count the passes), `--method`
/// with Mitsuba's and pbrt's name `path`.
#[test]
fn the_first_line_names_the_method_and_why() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("first-hour-method");
    let small = ["--width", "8", "--height", "8", "-o", "out.exr"];
    let cases: [(&str, &[&str], &str); 3] = [
        ("cornell-box.toml", &["--iterations", "1"], "with sppm (the scene's `method`"),
        ("mitsuba/box.xml", &["-D", "spp=2"], "with pt-nee (the file's <integrator>"),
        ("cornell-box.toml", &["--method", "path", "--iterations", "1"], "with pt-nee (--method)"),
    ];
    for (name, args, said) in cases {
        let path = scene(name);
        let mut all = vec![path.as_str()];
        all.extend_from_slice(&small);
        all.extend_from_slice(args);
        let (code, stdout, stderr) = run_in(&dir, &all);
        assert_eq!(code, Some(0), "{name}: {stderr}");
        let first = stderr.lines().next().unwrap_or_default();
        assert!(first.starts_with(&format!("rendering {path} {said}")), "{name}: {stderr}");
        if name.ends_with(".xml") {
            // sample_count 2: two passes of one sample a pixel.
            assert_eq!(passes_and_work(&stdout), (2, 2 * 64), "{stdout}");
        }
    }
}

/// `--spp N` is a path tracer's samples a pixel in all (its passes), as pbrt reads it; SPPM's
/// camera samples a pixel a pass, as before.
#[test]
fn spp_sets_a_path_tracers_samples_a_pixel() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("first-hour-spp");
    let path = scene("cornell-box.toml");
    let base = [path.as_str(), "--width", "8", "--height", "8", "-o", "out.exr", "--method", "pt-nee"];
    let (code, stdout, stderr) = run_in(&dir, &[&base[..], &["--spp", "4"]].concat());
    assert_eq!(code, Some(0), "{stderr}");
    assert_eq!(passes_and_work(&stdout), (4, 4 * 64), "{stdout}");
    let (code, _, stderr) = run_in(&dir, &[&base[..], &["--spp", "4", "--iterations", "8"]].concat());
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("a path tracer's samples a pixel are its passes"), "{stderr}");
}

/// `--time-limit` alone renders as many passes as fit (not the scene's 64), its clock started
/// after the kernels are compiled, and the summary says the limit ended it; `--stats` gives
/// the compile time.
#[test]
fn a_time_limit_alone_renders_until_the_limit() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("first-hour-time");
    let path = scene("cornell-box.toml");
    let args = [path.as_str(), "--width", "8", "--height", "8", "--photons", "1000", "-o", "out.exr", "--time-limit", "1.5"];
    let (code, stdout, stderr) = run_in(&dir, &[&args[..], &["--stats"]].concat());
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("; ended by the time limit of 1.5 s"), "{stdout}");
    let (passes, _) = passes_and_work(&stdout);
    assert!(passes > 64, "more passes than the scene's iterations: {stdout}");
    let seconds: f64 = stdout.split(" in ").nth(1).and_then(|s| s.split(' ').next()).unwrap().parse().unwrap();
    assert!((1.4..3.0).contains(&seconds), "the render's clock: {seconds} s: {stdout}");
    assert!(stdout.contains("kernels compiled in "), "{stdout}");
}

/// Without `-o` the image goes to the scene's name with `.exr` in the current directory, and a
/// second run takes the next free name rather than replacing the first.
#[test]
fn the_output_defaults_to_a_free_name() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("first-hour-default-output");
    let path = scene("cornell-box.toml");
    let args = [path.as_str(), "--width", "8", "--height", "8", "--iterations", "1", "--photons", "1000"];
    for expected in ["cornell-box.exr", "cornell-box-1.exr"] {
        let (code, _, stderr) = run_in(&dir, &args);
        assert_eq!(code, Some(0), "{stderr}");
        assert!(stderr.contains(&format!("note: no -o given: writing {expected}")), "{stderr}");
        assert!(dir.join(expected).exists(), "{expected}");
    }
}

/// Options a command does not read are refused, never ignored: `compare --method` (its methods
/// are `--methods`), `compare --direct` (they set it), `sweep --time-limit`, `bench --method`.
#[test]
fn options_a_command_does_not_read_are_refused() {
    let dir = common::scratch("first-hour-unused");
    let path = scene("cornell-box.toml");
    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/references/cornell-box.exr");
    let reference = reference.display().to_string();
    let cases: [(&[&str], &str); 4] = [
        (&["compare", &path, "--reference", &reference, "--time-limit", "1", "--method", "pt"], "compare does not take --method"),
        (
            &["compare", &path, "--reference", &reference, "--time-limit", "1", "--direct", "photons"],
            "compare does not take --direct",
        ),
        (
            &["sweep", &path, "--reference", &reference, "--param", "radius", "--values", "0.1", "--time-limit", "1"],
            "sweep does not take --time-limit",
        ),
        (&["bench", &path, "--method", "pt"], "bench does not take --method"),
    ];
    for (args, said) in cases {
        let (code, _, stderr) = run_in(&dir, args);
        assert_eq!(code, Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(said), "{args:?}: {stderr}");
    }
}
