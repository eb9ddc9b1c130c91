//! Tests for `image_io` (PNG/EXR reading and writing) and `metrics`.

use crate::common;
use crate::common::Rng;
use std::fs;
use std::path::{Path, PathBuf};

use sppm_gpu::image_io::{linear_to_srgb, read_exr, read_image, write_exr, write_image, write_png, Rgb32Image};
use sppm_gpu::metrics::{
    channel_mean_ratio, compare, count_negative, count_non_finite, downsample_box, false_colour, rel_mse, rmse, NON_FINITE_COLOUR,
};

/// References kept in the repository (a subset of the shared ones).
fn repo_references() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/references")
}

/// The full set of Mitsuba references, in the `shared/` folder beside the checkout, where
/// this machine has it.
fn shared_references() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/references")
}

/// Names of the entries in `dir`, sorted.
fn dir_entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// A test image with distinct values per pixel and channel, including
/// out-of-[0,1] radiance.
fn gradient(width: u32, height: u32) -> Rgb32Image {
    Rgb32Image::from_fn(width, height, |x, y| {
        let t = (x + y * width) as f32 / (width * height) as f32;
        [t * 1.5 - 0.1, (x as f32 / width as f32).powi(3), 0.37 * y as f32]
    })
}

/// An image of `width` columns from row-major `pixels`.
fn from_rows(width: u32, pixels: &[[f32; 3]]) -> Rgb32Image {
    let height = pixels.len() as u32 / width;
    assert_eq!((width * height) as usize, pixels.len(), "ragged rows");
    Rgb32Image { width, height, pixels: pixels.to_vec() }
}

fn assert_close(actual: f64, expected: f64, tol: f64) {
    assert!((actual - expected).abs() <= tol, "{actual} differs from {expected} by more than {tol}");
}

// ---------------------------------------------------------------- image_io

#[test]
fn rgb32_image_helpers() {
    let img = Rgb32Image::from_fn(3, 2, |x, y| [x as f32, y as f32, 1.0]);
    assert_eq!(img.pixels.len(), 6);
    assert_eq!(img.get(2, 1), [2.0, 1.0, 1.0]);
    assert_eq!(img.pixels[5], img.get(2, 1), "row-major layout");
    assert_eq!(img.mean(), [1.0, 0.5, 1.0]);
    assert_eq!(Rgb32Image::new(4, 5).pixels, vec![[0.0; 3]; 20]);
}

#[test]
fn exr_round_trip_is_exact() {
    let dir = common::scratch("image-metrics-exr_round_trip");
    let mut img = gradient(37, 23);
    img.set(0, 0, [f32::INFINITY, -1e-30, 6.5e4 * 3.0]);
    img.set(36, 22, [f32::MIN_POSITIVE, f32::MAX, -7.25]);
    let path = dir.join("round.exr");
    write_exr(&path, &img).unwrap();
    assert_eq!(read_exr(&path).unwrap(), img);
    assert_eq!(read_image(&path).unwrap(), img);
}

#[test]
fn png_round_trip_within_one_code_value() {
    let dir = common::scratch("image-metrics-png_round_trip");
    let img = gradient(41, 19);
    let path = dir.join("round.png");
    write_png(&path, &img).unwrap();
    let back = read_image(&path).unwrap();
    assert_eq!((back.width, back.height), (img.width, img.height));
    for (orig, read) in img.pixels.iter().zip(&back.pixels) {
        for c in 0..3 {
            let want = linear_to_srgb(orig[c]).clamp(0.0, 1.0);
            let got = linear_to_srgb(read[c]);
            assert!((got - want).abs() <= 1.0 / 255.0, "{orig:?} read back as {read:?}");
        }
    }
}

#[test]
fn png_maps_nan_to_black_and_infinity_to_white() {
    let dir = common::scratch("image-metrics-png_non_finite");
    let img = from_rows(2, &[[f32::NAN; 3], [f32::INFINITY; 3]]);
    let path = dir.join("nf.png");
    write_png(&path, &img).unwrap();
    let back = read_image(&path).unwrap();
    assert_eq!(back.pixels, vec![[0.0; 3], [1.0; 3]]);
}

#[test]
fn write_image_dispatches_on_case_insensitive_extension() {
    let dir = common::scratch("image-metrics-dispatch");
    let img = gradient(8, 4);
    for name in ["a.EXR", "b.Exr", "c.PNG", "d.png"] {
        let path = dir.join(name);
        write_image(&path, &img).unwrap();
        let magic = &fs::read(&path).unwrap()[..4];
        if name.to_lowercase().ends_with(".exr") {
            assert_eq!(magic, [0x76, 0x2f, 0x31, 0x01], "{name} is not an EXR");
        } else {
            assert_eq!(magic, b"\x89PNG", "{name} is not a PNG");
        }
        assert_eq!(read_image(&path).unwrap().width, 8);
    }
}

#[test]
fn unknown_extension_errors() {
    let dir = common::scratch("image-metrics-unknown_ext");
    let img = gradient(2, 2);
    for name in ["out.jpg", "out", "out.png.bak"] {
        let path = dir.join(name);
        let err = write_image(&path, &img).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains(name), "{msg}");
        assert!(msg.contains(".png") && msg.contains(".exr"), "{msg}");
        assert!(read_image(&path).is_err());
    }
    assert!(dir_entries(&dir).is_empty(), "nothing written on error");
}

#[test]
fn exr_reads_f16_channels_by_name_and_ignores_alpha() {
    use exr::prelude::{f16, write_rgba_file};
    let dir = common::scratch("image-metrics-exr_f16");
    let path = dir.join("half.exr");
    // Distinct per-channel values: a reader that confused channel order would
    // read them back in the wrong slots.
    write_rgba_file(&path, 5, 3, |x, y| {
        let v = (x + 10 * y) as f32;
        (f16::from_f32(v), f16::from_f32(v + 0.5), f16::from_f32(-v), f16::from_f32(0.25))
    })
    .unwrap();
    let img = read_exr(&path).unwrap();
    assert_eq!((img.width, img.height), (5, 3));
    assert_eq!(img.get(0, 0), [0.0, 0.5, 0.0]);
    assert_eq!(img.get(4, 2), [24.0, 24.5, -24.0], "row 0 at the top, R/G/B by name");
}

#[test]
fn corrupt_exr_errors_without_panic() {
    let dir = common::scratch("image-metrics-corrupt_exr");
    let good = dir.join("good.exr");
    write_exr(&good, &gradient(16, 16)).unwrap();
    let bytes = fs::read(&good).unwrap();

    let mut flipped = bytes.clone();
    for b in flipped.iter_mut().skip(8).step_by(7).take(40) {
        *b ^= 0xA5;
    }
    let cases: [(&str, &[u8]); 5] = [
        ("empty.exr", &[]),
        ("garbage.exr", b"this is not an OpenEXR file at all"),
        ("png-bytes.exr", b"\x89PNG\r\n\x1a\n"),
        ("truncated.exr", &bytes[..bytes.len() / 2]),
        ("flipped.exr", &flipped),
    ];
    for (name, content) in cases {
        let path = dir.join(name);
        fs::write(&path, content).unwrap();
        // Bit flips may leave a readable file; only a panic would fail here.
        if let Err(err) = read_image(&path) {
            assert!(err.to_string().contains(name), "{err}");
        } else {
            assert_eq!(name, "flipped.exr", "{name} should not decode");
        }
    }
    let missing = dir.join("missing.exr");
    let err = read_exr(&missing).unwrap_err();
    assert!(err.to_string().contains("missing.exr"), "{err}");
}

#[test]
fn truncated_reference_never_panics() {
    let bytes = fs::read(repo_references().join("furnace.exr")).unwrap();
    let dir = common::scratch("image-metrics-truncated_reference");
    let path = dir.join("t.exr");
    for len in (0..bytes.len()).step_by(997) {
        fs::write(&path, &bytes[..len]).unwrap();
        assert!(read_exr(&path).is_err(), "a {len}-byte prefix decoded");
    }
}

#[test]
fn corrupt_png_errors_without_panic() {
    let dir = common::scratch("image-metrics-corrupt_png");
    let path = dir.join("bad.png");
    fs::write(&path, b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let err = read_image(&path).unwrap_err();
    assert!(err.to_string().contains("bad.png"), "{err}");
}

#[test]
fn mismatched_pixel_buffer_is_an_error() {
    let dir = common::scratch("image-metrics-bad_buffer");
    let img = Rgb32Image { width: 3, height: 3, pixels: vec![[0.0; 3]; 8] };
    for name in ["a.png", "a.exr"] {
        let err = write_image(&dir.join(name), &img).unwrap_err();
        assert!(err.to_string().contains("3x3"), "{err}");
    }
}

#[test]
fn atomic_write_leaves_no_temp_file() {
    let dir = common::scratch("image-metrics-atomic");
    let first = gradient(8, 8);
    let second = Rgb32Image::from_fn(4, 2, |_, _| [1.0, 2.0, 3.0]);
    for name in ["img.exr", "img.png"] {
        let path = dir.join(name);
        write_image(&path, &first).unwrap();
        write_image(&path, &second).unwrap(); // replaces the old file
        assert_eq!(read_image(&path).unwrap().width, 4);
    }
    assert_eq!(dir_entries(&dir), ["img.exr", "img.png"]);

    // A failed rename (the target is a directory) must clean up too.
    let blocker = dir.join("blocked.exr");
    fs::create_dir(&blocker).unwrap();
    let err = write_image(&blocker, &first).unwrap_err();
    assert!(err.to_string().contains("blocked.exr"), "{err}");
    assert_eq!(dir_entries(&dir), ["blocked.exr", "img.exr", "img.png"]);
}

#[test]
fn references_load_with_expected_size() {
    let mut dirs = vec![repo_references()];
    if shared_references().is_dir() {
        dirs.push(shared_references());
    } else {
        eprintln!("{} not present; checking the repository's copies only", shared_references().display());
    }
    let mut loaded = 0;
    for dir in dirs {
        for entry in fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "exr") {
                continue;
            }
            let img = read_image(&path).unwrap_or_else(|e| panic!("{e}"));
            let expected = if path.ends_with("furnace.exr") { 64 } else { 256 };
            assert_eq!((img.width, img.height), (expected, expected), "{}", path.display());
            assert_eq!(count_non_finite(&img), 0, "{}", path.display());
            assert_eq!(count_negative(&img), 0, "{}", path.display());
            loaded += 1;
        }
    }
    assert!(loaded >= 3, "only {loaded} references found");
}

#[test]
fn furnace_reference_is_two_everywhere() {
    let img = read_exr(&repo_references().join("furnace.exr")).unwrap();
    let devs: Vec<f64> = img.pixels.iter().flatten().map(|&v| (f64::from(v) - 2.0).abs()).collect();
    let max_dev = devs.iter().copied().fold(0.0, f64::max);
    let rms_dev = (devs.iter().map(|d| d * d).sum::<f64>() / devs.len() as f64).sqrt();
    let within = devs.iter().filter(|&&d| d <= 1e-3).count();
    let small = downsample_box(&img, 8).unwrap();
    let small_max_dev = small.pixels.iter().flatten().map(|&v| (v - 2.0).abs()).fold(0.0, f32::max);
    let equal_channels = img.pixels.iter().filter(|p| p[0] == p[1] && p[1] == p[2]).count();
    println!(
        "furnace: mean {:?}, max |v - 2| {max_dev:.3e}, rms {rms_dev:.3e}, \
         {within}/{} samples within 1e-3; 8x8 box: max |v - 2| {small_max_dev:.3e}; \
         {equal_channels}/{} pixels with R = G = B",
        img.mean(),
        devs.len(),
        img.pixels.len()
    );
    // Per pixel the reference carries Monte Carlo noise (rms ~1e-2 at 1024
    // spp); the mean and the 8x8-downsampled image are within 1e-3 and 1e-2.
    for mean in img.mean() {
        assert_close(mean, 2.0, 1e-3);
    }
    assert!(small_max_dev <= 1e-2, "8x8 furnace deviates from 2.0 by {small_max_dev}");
}

// ----------------------------------------------------------------- metrics

#[test]
fn rel_mse_of_image_with_itself_is_zero() {
    let img = gradient(16, 8);
    assert_eq!(rel_mse(&img, &img).unwrap(), 0.0);
    assert_eq!(rmse(&img, &img).unwrap(), 0.0);
    let cmp = compare(&img, &img, 4).unwrap();
    assert_eq!((cmp.rel_mse, cmp.rmse), (0.0, 0.0));
}

#[test]
fn rel_mse_hand_computed_2x2() {
    let reference = from_rows(2, &[[1.0, 0.0, 0.5], [2.0, 0.1, 1.0], [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]);
    let img = from_rows(2, &[[1.1, 0.1, 0.5], [2.0, 0.0, 0.0], [0.0, 0.0, 0.2], [1.0, 1.0, 1.0]]);
    // Non-zero terms: (0.1^2)/(1 + 0.01), (0.1^2)/(0 + 0.01), (0.1^2)/(0.01 + 0.01),
    // (1^2)/(1 + 0.01), (0.2^2)/(0 + 0.01); 12 terms in all.
    let expected = (0.01 / 1.01 + 0.01 / 0.01 + 0.01 / 0.02 + 1.0 / 1.01 + 0.04 / 0.01) / 12.0;
    assert_close(rel_mse(&img, &reference).unwrap(), expected, 1e-6);
    // Squared errors: 0.01 + 0.01 + 0.01 + 1 + 0.04 = 1.07 over 12 terms.
    assert_close(rmse(&img, &reference).unwrap(), (1.07f64 / 12.0).sqrt(), 1e-6);
}

#[test]
fn downsample_4x4_known() {
    let img = Rgb32Image::from_fn(4, 4, |x, y| {
        let v = (x + 4 * y) as f32;
        [v, 2.0 * v, 1.0]
    });
    let half = downsample_box(&img, 2).unwrap();
    assert_eq!((half.width, half.height), (2, 2));
    // Block (0,0) holds 0, 1, 4, 5; (1,0): 2, 3, 6, 7; (0,1): 8, 9, 12, 13; (1,1): 10, 11, 14, 15.
    let means = [2.5, 4.5, 10.5, 12.5];
    for (p, m) in half.pixels.iter().zip(means) {
        assert_eq!(*p, [m, 2.0 * m, 1.0]);
    }
    let whole = downsample_box(&img, 4).unwrap();
    assert_eq!(whole.pixels, vec![[7.5, 15.0, 1.0]]);
    assert_eq!(downsample_box(&img, 1).unwrap(), img);
}

#[test]
fn downsample_requires_divisible_size() {
    let img = gradient(6, 4);
    assert!(downsample_box(&img, 4).is_err());
    assert!(downsample_box(&img, 0).is_err());
    assert!(compare(&img, &img, 3).is_err());
    assert!(downsample_box(&img, 2).is_ok());
}

#[test]
fn size_mismatch_errors() {
    let (a, b) = (gradient(4, 4), gradient(4, 2));
    let msg = rel_mse(&a, &b).unwrap_err();
    assert!(msg.contains("4x4") && msg.contains("4x2"), "{msg}");
    assert!(rmse(&a, &b).is_err());
    assert!(compare(&a, &b, 1).is_err());
    assert!(compare(&a, &b, 2).is_err());
    assert!(false_colour(&a, &b).is_err());
}

#[test]
fn mean_ratio_and_counts() {
    let reference = Rgb32Image::from_fn(2, 2, |_, _| [1.0, 2.0, 4.0]);
    let img = Rgb32Image::from_fn(2, 2, |_, _| [1.5, 2.0, 1.0]);
    assert_eq!(channel_mean_ratio(&img, &reference), [1.5, 1.0, 0.25]);
    assert_eq!(compare(&img, &reference, 2).unwrap().mean_ratio, [1.5, 1.0, 0.25]);

    let odd =
        from_rows(5, &[[f32::NAN, 0.0, 0.0], [0.0, f32::INFINITY, -1.0], [-0.5, 0.0, 0.0], [-0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]);
    assert_eq!(count_non_finite(&odd), 2);
    assert_eq!(count_negative(&odd), 2);
}

#[test]
fn false_colour_follows_log_scale() {
    // Reference 0 makes the per-pixel relative error |x| / 0.1.
    let reference = Rgb32Image::new(6, 1);
    let errors = [0.0, 1e-3, 1e-2, 1e-1, 1.0, 10.0];
    let img = Rgb32Image::from_fn(6, 1, |x, _| [(errors[x as usize] * 0.1) as f32; 3]);
    let fc = false_colour(&img, &reference).unwrap();
    let expected = [
        [0.0, 0.0, 0.0],     // below 1e-3: black
        [0.0, 0.0, 0.0],     // 1e-3: black
        [0.0, 0.333, 0.667], // 1e-2: between blue and green
        [0.667, 1.0, 0.0],   // 1e-1: between green and yellow
        [1.0, 0.0, 0.0],     // 1: red
        [1.0, 0.0, 0.0],     // above 1: red
    ];
    for (got, want) in fc.pixels.iter().zip(expected) {
        for c in 0..3 {
            assert_close(got[c].into(), want[c], 2e-3);
        }
    }
    let nan = from_rows(1, &[[f32::NAN; 3]]);
    assert_eq!(false_colour(&nan, &Rgb32Image::new(1, 1)).unwrap().pixels, [NON_FINITE_COLOUR]);
}

/// Sanity figures for the references; run with `--nocapture` to see them.
#[test]
fn reference_sanity_figures() {
    let mut rng = Rng(0x5EED);
    for name in ["cornell-box.exr", "cornell-spheres.exr"] {
        let reference = read_exr(&repo_references().join(name)).unwrap();
        let noisy = Rgb32Image {
            pixels: reference.pixels.iter().map(|p| p.map(|v| v * (1.0 + 0.01 * rng.gaussian() as f32))).collect(),
            ..reference.clone()
        };
        let full = compare(&noisy, &reference, 1).unwrap();
        let down = compare(&noisy, &reference, 8).unwrap();
        let self_down = compare(&reference, &reference, 8).unwrap();
        println!(
            "{name}: mean {:?}; 1% noise relMSE {:.3e} (1x1), {:.3e} (8x8), rmse {:.3e} (8x8); \
             self relMSE (8x8) {}",
            reference.mean(),
            full.rel_mse,
            down.rel_mse,
            down.rmse,
            self_down.rel_mse
        );
        assert_eq!(self_down.rel_mse, 0.0);
        // 1% relative noise gives relMSE <= 1e-4 per pixel, and 8x8 averaging
        // divides the variance by about 64.
        assert!(full.rel_mse > 0.0 && full.rel_mse <= 1.2e-4, "{}", full.rel_mse);
        assert!(down.rel_mse < full.rel_mse / 20.0, "{}", down.rel_mse);
    }
}
