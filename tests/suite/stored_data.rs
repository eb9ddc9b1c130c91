//! Stored data is not trusted (issue 40): an image whose header claims more pixels than any
//! render, or more bytes than the file holds, is refused before anything is allocated for it;
//! a partial image or a checkpoint altered since it was written is refused by its checksum; a
//! partial with pixels not finite or negative is refused by `merge`; a state no render could
//! have left is refused by `restore`.

use crate::common;

use sppm_gpu::batch::{merge, read_partial, write_partial};
use sppm_gpu::checkpoint::{self, Checkpoint, Fingerprint};
use sppm_gpu::image_io::{self, ImageErrorKind, Rgb32Image};
use sppm_gpu::integrators;
use sppm_gpu::scene::{Method, PixelFilter, Scene};
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

fn binary() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"));
    command.env("XDG_RUNTIME_DIR", std::env::temp_dir());
    command
}

/// Exit status and stderr of `command`.
fn run(command: &mut Command) -> (Option<i32>, String) {
    let out = command.output().expect("the binary runs");
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// `bytes` with the EXR attribute `name` of type `box2i` set to `[x_min, y_min, x_max, y_max]`.
fn set_box2i(bytes: &mut [u8], name: &str, value: [i32; 4]) {
    let key = [name.as_bytes(), b"\0box2i\0", &16i32.to_le_bytes()].concat();
    let at = bytes.windows(key.len()).position(|w| w == key).unwrap_or_else(|| panic!("no {name} in the header")) + key.len();
    for (i, v) in value.iter().enumerate() {
        bytes[at + 4 * i..at + 4 * i + 4].copy_from_slice(&v.to_le_bytes());
    }
}

/// A 4x4 EXR of the renderer's own, its windows patched to `[x_min, y_min, x_max, y_max]`: a
/// header claiming that size over the body of a 4x4 image.
fn exr_claiming(path: &Path, window: [i32; 4]) {
    image_io::write_exr(path, &Rgb32Image::from_fn(4, 4, |x, y| [x as f32, y as f32, 1.0])).unwrap();
    let mut bytes = std::fs::read(path).unwrap();
    set_box2i(&mut bytes, "dataWindow", window);
    set_box2i(&mut bytes, "displayWindow", window);
    std::fs::write(path, bytes).unwrap();
}

/// Reading `path` fails at once (before the pixels could be allocated) with an error that
/// names the file.
fn refused_quickly(path: &Path) -> image_io::ImageError {
    let start = Instant::now();
    let e = image_io::read_image(path).expect_err("the image is refused");
    assert!(start.elapsed() < Duration::from_secs(2), "took {:?}", start.elapsed());
    assert!(e.to_string().contains(&path.display().to_string()), "{e}");
    e
}

#[test]
fn an_exr_claiming_60000_squared_is_refused_before_allocating() {
    let dir = common::scratch("stored-data-huge-exr");
    let huge = dir.join("huge.exr");
    exr_claiming(&huge, [0, 0, 59_999, 59_999]);
    assert!(std::fs::metadata(&huge).unwrap().len() < 1000);
    let e = refused_quickly(&huge);
    assert!(matches!(e.kind(), ImageErrorKind::TooLarge { width: 60_000, height: 60_000 }), "{e}");
    assert!(e.to_string().contains("60000x60000"), "{e}");
    // One column over the largest image.
    exr_claiming(&huge, [0, 0, 16_384, 16_383]);
    assert!(refused_quickly(&huge).to_string().contains("16385x16384"));
    // The widest box a header can hold (2^32 columns): refused by the EXR reader, no panic.
    exr_claiming(&huge, [i32::MIN, 0, i32::MAX, 0]);
    refused_quickly(&huge);

    // The command line: `diff` (either side) and `merge` exit 1 with the message.
    let small = dir.join("small.exr");
    image_io::write_exr(&small, &Rgb32Image::new(4, 4)).unwrap();
    exr_claiming(&huge, [0, 0, 59_999, 59_999]);
    for args in [[&huge, &small], [&small, &huge]] {
        let (code, stderr) = run(binary().arg("diff").args(args));
        assert_eq!(code, Some(1), "{stderr}");
        assert!(stderr.contains("huge.exr") && stderr.contains("60000x60000"), "{stderr}");
    }
    let (code, stderr) = run(binary().arg("merge").arg(&huge).arg("-o").arg(dir.join("merged.exr")));
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("huge.exr") && stderr.contains("60000x60000"), "{stderr}");
}

/// Within the limit, a header claiming more uncompressed samples than the file holds is
/// refused as truncated rather than allocated (3 GiB here) and then read.
#[test]
fn an_uncompressed_exr_shorter_than_its_header_is_refused() {
    use exr::prelude::*;
    let dir = common::scratch("stored-data-short-exr");
    let path = dir.join("short.exr");
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| (x as f32, y as f32, 0.5f32));
    let layer = Layer::new((8, 8), LayerAttributes::default(), Encoding::UNCOMPRESSED, channels);
    Image::from_layer(layer).write().to_file(&path).unwrap();
    assert_eq!(image_io::read_exr(&path).unwrap().get(3, 5), [3.0, 5.0, 0.5]);
    let mut bytes = std::fs::read(&path).unwrap();
    set_box2i(&mut bytes, "dataWindow", [0, 0, 16_383, 16_383]);
    set_box2i(&mut bytes, "displayWindow", [0, 0, 16_383, 16_383]);
    std::fs::write(&path, bytes).unwrap();
    let e = refused_quickly(&path);
    assert!(matches!(e.kind(), ImageErrorKind::Truncated { .. }), "{e}");
    assert!(e.to_string().contains("truncated"), "{e}");
}

/// CRC-32 (ISO 3309, as PNG uses) of `bytes`.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 { 0xedb8_8320 ^ (c >> 1) } else { c >> 1 };
        }
    }
    !c
}

#[test]
fn a_png_claiming_60000_squared_is_refused_naming_its_size() {
    let dir = common::scratch("stored-data-huge-png");
    let path = dir.join("huge.png");
    image_io::write_png(&path, &Rgb32Image::new(4, 4)).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    // IHDR: length, type, width, height, ..., CRC of type and data.
    assert_eq!(&bytes[12..16], b"IHDR");
    bytes[16..20].copy_from_slice(&60_000u32.to_be_bytes());
    bytes[20..24].copy_from_slice(&60_000u32.to_be_bytes());
    let crc = crc32(&bytes[12..29]);
    bytes[29..33].copy_from_slice(&crc.to_be_bytes());
    std::fs::write(&path, bytes).unwrap();
    let e = refused_quickly(&path);
    assert!(matches!(e.kind(), ImageErrorKind::TooLarge { width: 60_000, height: 60_000 }), "{e}");
    assert!(e.to_string().contains("60000x60000"), "{e}");
}

fn fingerprint() -> Fingerprint {
    Fingerprint { settings: "width = 6\nheight = 4\n".into(), camera: "Camera".into(), geometry: 7, appearance: 9 }
}

/// A 6x4 mean estimate, every pixel different.
fn mean() -> Rgb32Image {
    Rgb32Image::from_fn(6, 4, |x, y| [0.1 * x as f32 + 0.01, 0.2 * y as f32 + 0.02, 0.3 + 0.05 * (x * y) as f32])
}

#[test]
fn merge_refuses_a_part_with_nan_infinite_or_negative_pixels() {
    let dir = common::scratch("stored-data-bad-pixels");
    let good = dir.join("good.exr");
    write_partial(&good, &mean(), None, 0, 2, &fingerprint()).unwrap();
    for (name, value) in [("nan", f32::NAN), ("inf", f32::INFINITY), ("negative", -0.25)] {
        let path = dir.join(format!("{name}.exr"));
        let mut bad = mean();
        bad.set(4, 1, [0.5, value, 0.5]);
        write_partial(&path, &bad, None, 2, 3, &fingerprint()).unwrap();
        // Its checksum holds: the pixel is what was written.
        let part = read_partial(&path).unwrap_or_else(|e| panic!("{e}"));
        let e = merge(&[read_partial(&good).unwrap(), part]).expect_err("a bad pixel is refused").to_string();
        assert!(e.contains(&path.display().to_string()) && e.contains("pixel (4, 1)"), "{name}: {e}");
        let out = dir.join("merged.exr");
        let (code, stderr) = run(binary().arg("merge").arg(&good).arg(&path).arg("-o").arg(&out));
        assert_eq!(code, Some(1), "{name}: {stderr}");
        assert!(stderr.contains(&format!("{name}.exr")) && stderr.contains("pixel (4, 1)"), "{name}: {stderr}");
        assert!(!out.exists(), "{name}: written");
    }
    // The good parts still merge.
    let other = dir.join("other.exr");
    write_partial(&other, &mean(), None, 2, 3, &fingerprint()).unwrap();
    let (merged, _) = merge(&[read_partial(&good).unwrap(), read_partial(&other).unwrap()]).unwrap();
    assert!((merged.get(5, 3)[2] - mean().get(5, 3)[2]).abs() < 1e-6);
}

/// A partial whose pixels or header changed after it was written, or without a checksum, is
/// refused; the untouched one reads.
#[test]
fn a_partial_altered_after_writing_is_refused() {
    let dir = common::scratch("stored-data-partial-checksum");
    let path = dir.join("part.exr");
    write_partial(&path, &mean(), None, 0, 3, &fingerprint()).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(read_partial(&path).unwrap().end, 3);
    let refused = |altered: &[u8]| {
        std::fs::write(&path, altered).unwrap();
        read_partial(&path).expect_err("an altered partial is refused").to_string()
    };
    // The last byte is pixel data (the last tile's, a literal or a run's value in RLE).
    let mut pixel = bytes.clone();
    *pixel.last_mut().unwrap() ^= 0x10;
    let e = refused(&pixel);
    assert!(e.contains("part.exr") && e.contains("checksum mismatch"), "{e}");
    // The pass range 0..3 made 0..4.
    let mut range = bytes.clone();
    let at = range.windows(4).position(|w| w == b"0..3").expect("the pass range");
    range[at + 3] = b'4';
    let e = refused(&range);
    assert!(e.contains("checksum mismatch"), "{e}");
    // A partial without a checksum (as before it had one).
    let text = [
        ("sppm-gpu passes", "0..3"),
        ("sppm-gpu settings", "width = 6\nheight = 4\n"),
        ("sppm-gpu camera", "Camera"),
        ("sppm-gpu geometry", "0000000000000007"),
        ("sppm-gpu appearance", "0000000000000009"),
    ];
    image_io::write_exr_with_text(&path, &mean(), &text).unwrap();
    let e = read_partial(&path).expect_err("no checksum").to_string();
    assert!(e.contains("part.exr") && e.contains("sppm-gpu checksum"), "{e}");
}

/// A partial's splat sums (a splatting filter's weighted samples and weights) read back as
/// written and are in its checksum: a weight changed, or a splat channel missing, is refused.
#[test]
fn a_partial_keeps_its_splat_sums() {
    let dir = common::scratch("stored-data-partial-splats");
    let path = dir.join("part.exr");
    let pixels = 6 * 4;
    let camera: Vec<[f32; 4]> = (0..pixels).map(|i| [0.1 * i as f32, 0.2, 0.3, 1.0 + 0.01 * i as f32]).collect();
    let light = Some((0..pixels).map(|i| [0.01 * i as f32, 0.02, 0.03, 3.0]).collect());
    let splat = sppm_gpu::integrators::SplatSums { camera, light };
    write_partial(&path, &mean(), Some(&splat), 0, 3, &fingerprint()).unwrap();
    let part = read_partial(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(part.splat.as_ref(), Some(&splat), "the sums as written (the light's passes the batch's 3)");
    // The merge of one part is its sums' ratio plus the light's mean: pixel 5.
    let (merged, _) = merge(&[part]).unwrap();
    let expected = 0.5 / 1.05 + 0.05 / 3.0;
    assert!((merged.pixels[5][0] - expected).abs() < 1e-6, "{} against {expected}", merged.pixels[5][0]);
    // The same file with one weight changed, and with the splat's W channel alone left out.
    let (image, text) = image_io::read_exr_with_text(&path).unwrap();
    let text: Vec<(&str, &str)> = text.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    let names = ["splat.R", "splat.G", "splat.B", "splat.W", "light.R", "light.G", "light.B"];
    let planes: Vec<Vec<f32>> =
        image_io::read_exr_channels(&path, &names).unwrap().planes.into_iter().map(Option::unwrap).collect();
    let mut weights = planes.clone();
    weights[3][7] += 0.5;
    let with = |planes: &[Vec<f32>], names: &[&'static str]| -> Vec<(&'static str, Vec<f32>)> {
        names.iter().zip(planes).map(|(n, p)| (*n, p.clone())).collect()
    };
    for (what, channels, expected) in [
        ("a weight changed", with(&weights, &names), "checksum mismatch"),
        ("splat.W missing", with(&[&planes[..3], &planes[4..]].concat(), &[&names[..3], &names[4..]].concat()), "missing"),
    ] {
        let extra: Vec<(&str, &[f32])> = channels.iter().map(|(n, p)| (*n, p.as_slice())).collect();
        image_io::write_exr_with_channels(&path, &image, &extra, &text).unwrap();
        let e = read_partial(&path).expect_err(what).to_string();
        assert!(e.contains("part.exr") && e.contains(expected), "{what}: {e}");
    }
}

fn state() -> Vec<u8> {
    (0..200u32).flat_map(|i| (i * 2_654_435_761).to_le_bytes()).collect()
}

fn saved(pilot: Option<&str>) -> Checkpoint {
    Checkpoint { fingerprint: fingerprint(), state: state(), pilot: pilot.map(String::from) }
}

/// Every byte of a checkpoint flipped, bytes appended, cut short: refused as corrupt, naming
/// the file; the file as written reads back.
#[test]
fn a_checkpoint_altered_after_writing_is_refused() {
    let dir = common::scratch("stored-data-checkpoint-checksum");
    let path = dir.join("ck");
    for pilot in [None, Some("0/1@1")] {
        checkpoint::write(&path, &saved(pilot)).unwrap();
        assert_eq!(checkpoint::read(&path).unwrap(), saved(pilot));
    }
    let bytes = std::fs::read(&path).unwrap();
    let refused = |altered: &[u8]| {
        std::fs::write(&path, altered).unwrap();
        let e = checkpoint::read(&path).expect_err("an altered checkpoint is refused").to_string();
        assert!(e.contains(&path.display().to_string()), "{e}");
        e
    };
    for i in 0..bytes.len() {
        let mut flipped = bytes.clone();
        flipped[i] ^= 1 << (i % 8);
        let e = refused(&flipped);
        // Past the magic and the version, the checksum tells.
        if i >= 22 {
            assert!(e.contains("checksum mismatch"), "byte {i}: {e}");
        }
    }
    for tail in [&[0u8][..], &[0; 8], b"more bytes after the end"] {
        let e = refused(&[&bytes[..], tail].concat());
        assert!(e.contains("corrupt"), "{e}");
    }
    for len in [0, 10, 22, 30, bytes.len() - 8, bytes.len() - 1] {
        refused(&bytes[..len]);
    }
}

/// A checkpoint of format version 2 (before vcm's pilot's choice was kept) reads, with no
/// choice.
#[test]
fn a_checkpoint_of_version_2_reads() {
    let dir = common::scratch("stored-data-checkpoint-version-2");
    let path = dir.join("ck");
    checkpoint::write(&path, &saved(Some("0/1"))).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    // Version 3 less its last field (the choice: a length of 8 bytes and 3 of text) and the
    // digest, as version 2, with the digest (64-bit FNV-1a) of the bytes before it.
    let mut old = bytes[..bytes.len() - 8 - 8 - 3].to_vec();
    old[checkpoint::MAGIC.len()..checkpoint::MAGIC.len() + 4].copy_from_slice(&2u32.to_le_bytes());
    let digest = old.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3));
    old.extend_from_slice(&digest.to_le_bytes());
    std::fs::write(&path, &old).unwrap();
    assert_eq!(checkpoint::read(&path).unwrap(), saved(None));
}

/// A failed write (here the rename, onto a directory) leaves no temporary file behind.
#[test]
fn a_failed_checkpoint_write_leaves_no_temporary_file() {
    let dir = common::scratch("stored-data-checkpoint-failed-write");
    let target = dir.join("ck");
    std::fs::create_dir_all(target.join("inside")).unwrap();
    let e = checkpoint::write(&target, &saved(None)).expect_err("cannot replace a directory").to_string();
    assert!(e.contains("cannot write the checkpoint"), "{e}");
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left, [std::ffi::OsString::from("ck")], "left behind: {left:?}");
}

/// The Cornell box, 16x16, 1000 photons a pass.
fn tiny(method: Method) -> Scene {
    let mut scene = common::load_scene("cornell-box.toml");
    scene.render.width = 16;
    scene.render.height = 16;
    scene.render.photons = 1000;
    scene.render.method = method;
    scene
}

/// `state` with its f32 word `word` of the buffer (after the pass count and the work) set to
/// `value`.
fn with_word(state: &[u8], word: usize, value: f32) -> Vec<u8> {
    let mut s = state.to_vec();
    s[12 + 4 * word..16 + 4 * word].copy_from_slice(&value.to_le_bytes());
    s
}

/// States no render could have left are refused by `restore`: a pass count of u32::MAX, passes
/// that disagree with the work or the sample counts (under a splatting filter, weights of 0 or
/// beyond any pass's), sums not finite or negative. A true state restores.
#[test]
fn restore_refuses_states_no_render_could_leave() {
    let Some(gpu) = common::gpu() else { return };
    let gaussian = PixelFilter::Gaussian { stddev: 0.5 };
    for (method, filter) in
        [(Method::Sppm, PixelFilter::Box), (Method::PtNee, PixelFilter::Box), (Method::PtNee, gaussian), (Method::Sppm, gaussian)]
    {
        let mut scene = tiny(method);
        scene.render.filter = filter;
        // SPPM splats its passes' estimates under the global schedule.
        scene.render.radius_schedule = sppm_gpu::scene::RadiusSchedule::Global;
        let mut first = integrators::create(&gpu.device, &gpu.queue, &scene).unwrap();
        first.run_pass().unwrap();
        first.run_pass().unwrap();
        let state = first.state().unwrap();
        // The state's image, made on the host (a lost device's last checkpoint), is the GPU's.
        let (host, image) = (first.image_of_state(&state).unwrap(), first.image().unwrap());
        for (a, b) in host.pixels.iter().flatten().zip(image.pixels.iter().flatten()) {
            assert!((a - b).abs() <= 1e-6 * b.abs(), "{method:?} {filter:?}: the state's image {a} against {b}");
        }
        let mut fresh = integrators::create(&gpu.device, &gpu.queue, &scene).unwrap();
        let mut refused = |altered: &[u8], what: &str| {
            let e = fresh.restore(altered).expect_err(what).to_string();
            assert!(e.contains("corrupt"), "{method:?}, {what}: {e}");
            assert_eq!(fresh.passes(), 0, "{method:?}, {what}: restored");
            e
        };
        let mut passes = state.clone();
        passes[..4].copy_from_slice(&u32::MAX.to_le_bytes());
        let e = refused(&passes, "a pass count of u32::MAX");
        assert!(e.contains("4294967295"), "{e}");
        passes[..4].copy_from_slice(&3u32.to_le_bytes());
        refused(&passes, "3 passes with the work of 2");
        // Words of the first point's or pixel's sums (SPPM: tau, N, ld, r; the path tracers and
        // splatting SPPM: r, g, b, count or weight).
        for (word, value) in [(0, f32::NAN), (1, f32::INFINITY), (2, -1.0), (3, f32::NAN)] {
            let e = refused(&with_word(&state, word, value), "a sum not finite or negative");
            assert!(e.contains("pixel (0, 0)"), "{method:?}: {e}");
        }
        if method == Method::PtNee && filter == PixelFilter::Box {
            refused(&with_word(&state, 3, 5.0), "a pixel of 5 samples after 2 passes");
        } else if filter != PixelFilter::Box {
            refused(&with_word(&state, 3, 0.0), "a pixel of no weight after 2 passes");
            refused(&with_word(&state, 3, 1e3), "a pixel of more weight than 2 passes splat");
        }
        fresh.restore(&state).unwrap_or_else(|e| panic!("{method:?}: {e}"));
        assert_eq!(fresh.passes(), 2);
    }
}

/// Through the command line: `--resume` of a checkpoint with a byte flipped, with bytes
/// appended, or with a pass count of u32::MAX (its checksum rewritten) exits 1 naming the
/// file, and writes no image.
#[test]
fn resume_refuses_a_corrupt_checkpoint() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("stored-data-resume-corrupt");
    let (ck, out) = (dir.join("ck"), dir.join("out.exr"));
    let render = |extra: &[&str]| {
        let mut command = binary();
        command
            .arg(common::scene_path("cornell-box.toml"))
            .args(["--width", "16", "--height", "16", "--photons", "1000", "-o"])
            .arg(&out)
            .args(extra);
        run(&mut command)
    };
    let ck_arg = ck.to_str().unwrap();
    let (code, stderr) = render(&["--iterations", "2", "--checkpoint", ck_arg]);
    assert_eq!(code, Some(0), "{stderr}");
    std::fs::remove_file(&out).unwrap();
    let bytes = std::fs::read(&ck).unwrap();
    let written = checkpoint::read(&ck).unwrap();

    let mut flipped = bytes.clone();
    flipped[bytes.len() / 2] ^= 0x40;
    let mut passes = written.clone();
    passes.state[..4].copy_from_slice(&u32::MAX.to_le_bytes());
    for (what, expected) in [("flipped", "checksum mismatch"), ("appended", "corrupt"), ("passes", "the saved state is corrupt")]
    {
        match what {
            "flipped" => std::fs::write(&ck, &flipped).unwrap(),
            "appended" => std::fs::write(&ck, [&bytes[..], b"tail"].concat()).unwrap(),
            _ => checkpoint::write(&ck, &passes).unwrap(),
        }
        let (code, stderr) = render(&["--iterations", "3", "--resume", ck_arg]);
        assert_eq!(code, Some(1), "{what}: {stderr}");
        assert!(stderr.contains(ck_arg) && stderr.contains(expected), "{what}: {stderr}");
        assert!(!stderr.contains("panicked"), "{what}: {stderr}");
        assert!(!out.exists(), "{what}: an image was written");
    }
}
