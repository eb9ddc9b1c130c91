//! The experiments' tooling without a GPU: snapshot schedule, CSV and chart writers on
//! synthetic data, montages, and `sppm-gpu diff --error-image`.

use crate::common;

use sppm_gpu::experiments::plot::{self, Chart, Series, Tile};
use sppm_gpu::experiments::{self, Snapshot, SweepParam};
use sppm_gpu::image_io::{self, Rgb32Image};
use sppm_gpu::scene::{DirectLight, Method, Named};
use std::process::Command;

/// The PNG at `path` as 8-bit RGB: (width, height, bytes).
fn read_rgb8(path: &std::path::Path) -> (u32, u32, Vec<u8>) {
    let img = image_io::read_png(path).unwrap();
    (img.width, img.height, plot::srgb8(&img))
}

#[test]
fn snapshot_times_double_up_to_the_limit() {
    assert_eq!(experiments::snapshot_times(0.5, 60.0), [0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 60.0]);
    assert_eq!(experiments::snapshot_times(0.5, 4.0), [0.5, 1.0, 2.0, 4.0]);
    assert_eq!(experiments::snapshot_times(1.0, 1.0), [1.0]);
    assert_eq!(experiments::snapshot_times(2.0, 1.0), [1.0]);
    assert_eq!(experiments::snapshot_times(0.25, 1.5), [0.25, 0.5, 1.0, 1.5]);
}

#[test]
fn methods_and_sweep_parameters_parse_and_check_ranges() {
    for v in experiments::Variant::ALL {
        assert_eq!(experiments::Variant::parse(v.name()).unwrap(), v);
    }
    for m in [Method::Sppm, Method::Pt, Method::PtNee] {
        let v = experiments::Variant::parse(m.name()).unwrap();
        assert_eq!((v.method, v.direct), (m, DirectLight::Sampled));
    }
    assert!(experiments::Variant::parse("bdpt").is_err());
    let photons = experiments::Variant::parse("sppm-photons").unwrap();
    assert_eq!((photons.method, photons.direct), (Method::Sppm, DirectLight::Photons));
    assert!(experiments::Variant::parse("pt-photons").is_err());
    let adaptive = experiments::Variant::parse("sppm-adaptive/sobol").unwrap();
    assert_eq!(adaptive.radius_rule, Some(sppm_gpu::scene::RadiusRule::Adaptive));
    assert_eq!(adaptive.name(), "sppm-adaptive/sobol");
    let mut render = sppm_gpu::scene::load(std::path::Path::new("scenes/cornell-box.toml")).unwrap().render;
    adaptive.apply(&mut render);
    assert_eq!(render.radius_rule, sppm_gpu::scene::RadiusRule::Adaptive);
    assert_eq!(experiments::Variant::parse("sppm-shrink").unwrap().radius_rule, Some(sppm_gpu::scene::RadiusRule::Shrink));
    assert_eq!(experiments::Variant::parse("sppm").unwrap().radius_rule, None);

    let scene = sppm_gpu::scene::load(std::path::Path::new("scenes/cornell-box.toml")).unwrap();
    let mut r = scene.render.clone();
    SweepParam::parse("radius").unwrap().apply(&mut r, 0.05).unwrap();
    assert_eq!(r.radius, Some(0.05));
    SweepParam::Alpha.apply(&mut r, 0.3).unwrap();
    assert_eq!(r.alpha, 0.3);
    SweepParam::Photons.apply(&mut r, 10000.0).unwrap();
    assert_eq!(r.photons, 10000);
    assert!(SweepParam::Radius.apply(&mut r, 0.0).is_err());
    assert!(SweepParam::Alpha.apply(&mut r, 1.0).is_err());
    assert!(SweepParam::Photons.apply(&mut r, 2.5).is_err());
    assert!(SweepParam::parse("gamma").is_err());
}

fn synthetic_snapshots() -> Vec<Snapshot> {
    let mut out = Vec::new();
    for (label, scale) in [("sppm", 0.01), ("pt", 1.0), ("pt-nee", 0.1)] {
        for k in 0..6 {
            let seconds = 0.5 * 2f64.powi(k) * 1.05;
            out.push(Snapshot {
                label: label.into(),
                seconds,
                passes: 1 << k,
                rel_mse: scale / seconds,
                rmse: (scale / seconds).sqrt(),
            });
        }
    }
    out
}

#[test]
fn compare_csv_has_one_row_per_snapshot() {
    let dir = common::scratch("compare-csv");
    let path = dir.join("compare.csv");
    experiments::write_compare_csv(&path, &synthetic_snapshots()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "method,seconds,passes,relMSE,RMSE");
    assert_eq!(lines.len(), 1 + 18);
    let fields: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(fields[0], "sppm");
    assert_eq!(fields[1], "0.525");
    assert_eq!(fields[2], "1");
    let rel: f64 = fields[3].parse().unwrap();
    assert!((rel - 0.01 / 0.525).abs() < 1e-8);
    // Fields with commas are quoted.
    plot::write_csv(&path, &["a", "b"], &[vec!["x,y".into(), "say \"hi\"".into()]]).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n\"x,y\",\"say \"\"hi\"\"\"\n");
}

#[test]
fn time_chart_is_drawn_with_one_colour_per_method() {
    let dir = common::scratch("compare-chart");
    let path = dir.join("relmse-vs-time.png");
    experiments::write_time_chart(&path, "synthetic: relMSE against time", "relMSE", "a note", &synthetic_snapshots()).unwrap();
    let (w, h, rgb) = read_rgb8(&path);
    assert_eq!((w, h), (860, 540));
    let count = |c: [u8; 3]| rgb.chunks_exact(3).filter(|p| *p == c).count();
    // The first three palette colours (tab10 blue, orange, green) all appear.
    for colour in [[31, 119, 180], [255, 127, 14], [44, 160, 44]] {
        assert!(count(colour) > 100, "colour {colour:?} drawn {} times", count(colour));
    }
    // Text was drawn (the embedded font works): dark pixels outside the lines.
    assert!(count([0, 0, 0]) > 500);

    // Linear axes, a single point, and non-positive values on a log axis do not fail.
    let series = [Series { name: "one".into(), points: vec![(1.0, 0.0), (2.0, 5.0)] }];
    for (log_x, log_y) in [(false, false), (true, false), (false, true), (true, true)] {
        let chart = Chart { title: "t", x_desc: "x", y_desc: "y", log_x, log_y, note: "" };
        plot::write_chart(&dir.join(format!("c-{log_x}-{log_y}.png")), &chart, &series).unwrap();
    }
}

#[test]
fn tick_labels_are_short() {
    assert_eq!(plot::tick_label(0.0), "0");
    assert_eq!(plot::tick_label(1.0), "1");
    assert_eq!(plot::tick_label(0.5), "0.5");
    assert_eq!(plot::tick_label(0.001), "1e-3");
    assert_eq!(plot::tick_label(0.0002), "2e-4");
    assert_eq!(plot::tick_label(32.0), "32");
}

#[test]
fn png_bytes_survive_the_srgb_round_trip() {
    let dir = common::scratch("compare-png");
    let path = dir.join("bytes.png");
    let rgb: Vec<u8> = (0..=255u8).flat_map(|v| [v, 255 - v, v / 2]).collect();
    plot::write_rgb8_png(&path, &rgb, 16, 16).unwrap();
    assert_eq!(read_rgb8(&path), (16, 16, rgb));
}

#[test]
fn montage_lays_out_tiles_with_captions_and_legend() {
    let dir = common::scratch("compare-montage");
    let path = dir.join("montage.png");
    let grey = Rgb32Image::from_fn(32, 24, |_, _| [0.2; 3]);
    let rows = vec![
        vec![Tile::render(&grey, vec!["one".into()]), Tile::render(&grey, vec!["two".into(), "lines".into()])],
        vec![Tile::blank(32, 24), Tile::colours(&grey, Vec::new())],
    ];
    plot::write_montage(&path, "title", &rows, Some("legend")).unwrap();
    let (w, h, rgb) = read_rgb8(&path);
    assert_eq!(w, 520, "at least the colour bar's width");
    assert!(h > 2 * 24 + 2 * 17);
    let srgb_grey = plot::srgb8(&grey)[0];
    assert!(rgb.chunks_exact(3).filter(|p| p.iter().all(|&c| c == srgb_grey)).count() >= 2 * 32 * 24);
}

#[test]
fn diff_writes_a_false_colour_error_image() {
    let dir = common::scratch("compare-diff");
    let reference = Rgb32Image::from_fn(16, 8, |_, _| [0.5; 3]);
    // Left half exact, right half off by a factor of 3.
    let image = Rgb32Image::from_fn(16, 8, |x, _| if x < 8 { [0.5; 3] } else { [1.5; 3] });
    let (a, b, out) = (dir.join("a.exr"), dir.join("ref.exr"), dir.join("error.png"));
    image_io::write_image(&a, &image).unwrap();
    image_io::write_image(&b, &reference).unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
        .args([
            "diff".as_ref(),
            a.as_os_str(),
            b.as_os_str(),
            "--downsample".as_ref(),
            "4".as_ref(),
            "--error-image".as_ref(),
            out.as_os_str(),
        ])
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    assert!(String::from_utf8_lossy(&status.stdout).contains("relMSE"));
    let (w, h, rgb) = read_rgb8(&out);
    assert_eq!((w, h), (16, 8), "enlarged back to the images' size");
    let px = |x: u32, y: u32| &rgb[((y * w + x) * 3) as usize..((y * w + x) * 3 + 3) as usize];
    assert_eq!(px(0, 0), [0, 0, 0], "no error is black");
    // Relative error sqrt(1 / 0.26) ~ 2 > 1: red.
    assert_eq!(px(15, 7), [255, 0, 0]);

    // Mismatched sizes fail with a message and no image.
    let small = dir.join("small.exr");
    image_io::write_image(&small, &Rgb32Image::new(8, 8)).unwrap();
    let out2 = dir.join("error2.png");
    let status = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
        .args(["diff".as_ref(), small.as_os_str(), b.as_os_str(), "--error-image".as_ref(), out2.as_os_str()])
        .output()
        .unwrap();
    assert!(!status.status.success());
    assert!(!out2.exists());
}

#[test]
fn log_ticks_pick_a_readable_density() {
    assert_eq!(plot::log_ticks(&(0.4..80.0), 10), [0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0]);
    assert_eq!(plot::log_ticks(&(0.95..12.0), 10), [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0]);
    assert_eq!(plot::log_ticks(&(1e-5..2.0), 9), [1e-5, 1e-4, 1e-3, 1e-2, 0.1, 1.0]);
    assert_eq!(plot::log_ticks(&(0.003..0.3), 9), [0.005, 0.01, 0.02, 0.05, 0.1, 0.2]);
}
