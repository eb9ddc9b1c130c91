//! The rule for every path the program writes (src/cli/output.rs), through the binary: never
//! a file the run reads, an existing file replaced only by one of its own kind, and every
//! output checked before any work. Each case runs without a GPU: it is refused before one is
//! asked for.

use crate::common;

use std::path::Path;
use std::process::Command;

/// A fresh directory holding a copy of `scenes/textured.toml` and its texture (removed when
/// dropped).
fn scene_dir(name: &str) -> common::Scratch {
    let dir = common::scratch(&format!("outputs-{name}"));
    std::fs::create_dir_all(dir.join("textures")).unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    std::fs::copy(scenes.join("textured.toml"), dir.join("scene.toml")).unwrap();
    std::fs::copy(scenes.join("textures/checker.png"), dir.join("textures/checker.png")).unwrap();
    dir
}

/// Runs the binary with `args`: its exit code and stderr.
fn run(args: &[&std::ffi::OsStr]) -> (Option<i32>, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
        .args(args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("the binary runs");
    (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned())
}

fn os<P: AsRef<std::ffi::OsStr> + ?Sized>(p: &P) -> &std::ffi::OsStr {
    p.as_ref()
}

/// `--checkpoint` naming the scene file, `-o` naming its texture and `--partial` naming its
/// environment map would replace them: each is refused, and the file is left as it was.
#[test]
fn a_run_never_writes_over_its_inputs() {
    let dir = scene_dir("inputs");
    let scene = dir.join("scene.toml");
    let texture = dir.join("textures/checker.png");
    let (scene_text, texture_bytes) = (std::fs::read(&scene).unwrap(), std::fs::read(&texture).unwrap());
    let out = dir.join("out.png");

    let (code, stderr) = run(&[os(&scene), os("-o"), os(&out), os("--iterations"), os("2"), os("--checkpoint"), os(&scene)]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("scene.toml: the run reads this file"), "{stderr}");

    let (code, stderr) = run(&[os(&scene), os("-o"), os(&texture), os("--iterations"), os("2")]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("checker.png: the run reads this file"), "{stderr}");

    let env = dir.join("sky.exr");
    sppm_gpu::image_io::write_exr(&env, &sppm_gpu::image_io::Rgb32Image::from_fn(8, 4, |_, _| [0.5; 3])).unwrap();
    let text = String::from_utf8(scene_text.clone()).unwrap() + "\n[[lights]]\ntype = \"envmap\"\nfile = \"sky.exr\"\n";
    let lit = dir.join("lit.toml");
    std::fs::write(&lit, text).unwrap();
    let env_bytes = std::fs::read(&env).unwrap();
    let (code, stderr) =
        run(&[os(&lit), os("--partial"), os(&env), os("--passes"), os("0..2"), os("--radius-schedule"), os("global")]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("sky.exr: the run reads this file"), "{stderr}");

    // diff's error map over the reference it reads.
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    std::fs::copy(&texture, &a).unwrap();
    std::fs::copy(&texture, &b).unwrap();
    let (code, stderr) = run(&[os("diff"), os(&a), os(&b), os("--error-image"), os(&b)]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("b.png: the run reads this file"), "{stderr}");

    assert_eq!(std::fs::read(&scene).unwrap(), scene_text);
    assert_eq!(std::fs::read(&texture).unwrap(), texture_bytes);
    assert_eq!(std::fs::read(&env).unwrap(), env_bytes);
    assert_eq!(std::fs::read(&b).unwrap(), texture_bytes);
    assert!(!out.exists());
}

/// An existing file is replaced only by one of its kind: a text named `notes.png`, a PNG named
/// as the checkpoint, a scene named as `convert`'s output are refused.
#[test]
fn an_existing_file_of_another_kind_is_refused() {
    let dir = scene_dir("kinds");
    let scene = dir.join("scene.toml");
    let notes = dir.join("notes.png");
    std::fs::write(&notes, "my notes\n").unwrap();
    let (code, stderr) = run(&[os(&scene), os("-o"), os(&notes), os("--iterations"), os("2")]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("notes.png: exists and is another kind of file") && stderr.contains("remove it first"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "my notes\n");

    let picture = dir.join("picture.png");
    std::fs::copy(dir.join("textures/checker.png"), &picture).unwrap();
    let out = dir.join("out.exr");
    let (code, stderr) = run(&[os(&scene), os("-o"), os(&out), os("--checkpoint"), os(&picture)]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("exists and is a PNG image, not of the kind of the checkpoint"), "{stderr}");

    let existing = dir.join("existing.toml");
    std::fs::write(&existing, "# mine\n").unwrap();
    let (code, stderr) = run(&[os("convert"), os(&scene), os("-o"), os(&existing)]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("existing.toml: exists already: this command writes new files only"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&existing).unwrap(), "# mine\n");

    // compare's table over a CSV of someone else's.
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    std::fs::write(out_dir.join("compare.csv"), "name,score\n").unwrap();
    let (code, stderr) = run(&[
        os("compare"),
        os(&scene),
        os("--reference"),
        os(&picture),
        os("--time-limit"),
        os("1"),
        os("--out"),
        os(&out_dir),
    ]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("compare.csv: exists and is another kind of file, not of the kind of the table"), "{stderr}");
}

/// Outputs are checked before the scene is loaded: a checkpoint in a directory that does not
/// exist, an image path ending in `/`, the same file named twice, a checkpoint interval that
/// is not a number of seconds.
#[test]
fn outputs_and_settings_are_checked_before_any_work() {
    let dir = scene_dir("early");
    // A scene that fails to load: each refusal below must come before it is read.
    let scene = dir.join("broken.toml");
    std::fs::write(&scene, "this is not toml [").unwrap();
    let out = dir.join("out.png");
    let (nodir, ck, partial) = (dir.join("nodir/ck.bin"), dir.join("ck.bin"), dir.join("p.exr/"));
    let cases: [(&[&std::ffi::OsStr], &str); 5] = [
        (&[os("--checkpoint"), os(&nodir), os("--checkpoint-every"), os("3")], "does not exist"),
        (&[os("--checkpoint"), os(&ck), os("--checkpoint-every"), os("nan")], "--checkpoint-every must be"),
        (&[os("--checkpoint"), os(&ck), os("--checkpoint-every=-1")], "--checkpoint-every must be"),
        (&[os("--checkpoint"), os(&out)], "named as two outputs of one run"),
        (&[os("--partial"), os(&partial), os("--passes"), os("0..2")], "names a directory"),
    ];
    for (args, words) in cases {
        let mut all = vec![os(&scene), os("-o"), os(&out)];
        all.extend_from_slice(args);
        let (code, stderr) = run(&all);
        assert_eq!(code, Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(words), "{args:?}: {stderr}");
        assert!(!stderr.contains("not toml"), "{args:?}: refused only after loading: {stderr}");
    }
    let (code, stderr) = run(&[os(&dir.join("scene.toml")), os("-o"), os(&dir.join("x.png/"))]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("names a directory"), "{stderr}");
    assert!(!dir.join("ck.bin").exists() && !dir.join("x.png").exists());
}
