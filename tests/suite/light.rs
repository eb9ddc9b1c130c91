//! The light tracer (`lt`): it converges to the references on every canonical scene whose
//! camera sees no mirror or glass (what light tracing cannot join to a pinhole), splats
//! through each pixel filter as camera samples are drawn from it, gives the same bits for the
//! same seed, and refuses what it cannot render before any work.

use crate::common;

use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators;
use sppm_gpu::metrics::{compare, downsample_box};
use sppm_gpu::scene::{Method, PixelFilter, Scene};

const SIZE: u32 = 64;

fn render(scene: &Scene, method: Method, passes: u32) -> Rgb32Image {
    common::render_at(scene, method, SIZE, passes)
}

/// relMSE and channel mean ratios against the 256x256 reference, both reduced to 8x8.
fn check(name: &str, passes: u32, max_rel_mse: f64, max_mean_error: f64) {
    let scene = common::load_scene(&format!("{name}.toml"));
    let img = render(&scene, Method::Lt, passes);
    let reference = downsample_box(&common::reference(&format!("{name}.exr")), 256 / SIZE).unwrap();
    let c = compare(&img, &reference, 8).unwrap();
    eprintln!("{name} lt {passes} passes: {c:?}");
    assert!(c.rel_mse < max_rel_mse, "{name} lt: relMSE {}", c.rel_mse);
    for r in c.mean_ratio {
        assert!((r - 1.0).abs() < max_mean_error, "{name} lt: channel mean ratios {:?}", c.mean_ratio);
    }
}

#[test]
fn light_tracing_matches_the_references() {
    if common::gpu().is_none() {
        return;
    }
    check("cornell-box", 64, 2e-4, 0.01);
    check("textured", 64, 2e-4, 0.01);
    check("point-light", 128, 5e-4, 0.01);
    // Glossy highlights seen by the camera are where light tracing is noisiest: relMSE 5e-4
    // to 3.4e-3 over seeds 1 to 3 at 256 passes.
    check("cornell-glossy", 256, 5e-3, 0.02);
}

/// Every other light kind, against Mitsuba 3's renders of the same files at their own size:
/// two spot lights, a point and a directional light, and an area light over textures.
#[test]
fn light_tracing_matches_mitsuba_for_every_light_kind() {
    let Some(gpu) = common::gpu() else { return };
    // lights.xml: relMSE 5.7e-4 at 128 passes, 1.5e-4 at 512 (noise, falling as 1 / passes).
    for (name, passes) in [("spot", 128), ("lights", 512), ("textures", 64)] {
        common::check_mitsuba_reference(&gpu, name, Method::Lt, passes, 3e-4);
    }
}

/// Every surface has albedo 0.5 and emits 1 in a closed box: radiance 2 everywhere.
#[test]
fn light_tracing_passes_the_furnace() {
    if common::gpu().is_none() {
        return;
    }
    let scene = common::load_scene("furnace.toml");
    let img = render(&scene, Method::Lt, 256);
    let n = img.pixels.len() as f64;
    let mean: Vec<f64> = (0..3).map(|c| img.pixels.iter().map(|p| p[c] as f64).sum::<f64>() / n).collect();
    eprintln!("furnace lt: mean {mean:?}");
    for m in mean {
        assert!((m / 2.0 - 1.0).abs() < 0.005, "furnace lt: mean {m}, expected 2");
    }
}

/// Light splatted through a tent or a gaussian filter lands where the path tracer's camera
/// samples, drawn from the filter, find it: the two images agree block by block.
#[test]
fn light_tracing_splats_through_each_filter() {
    if common::gpu().is_none() {
        return;
    }
    for filter in [PixelFilter::Tent { radius: 1.5 }, PixelFilter::Gaussian { stddev: 0.5 }] {
        let mut scene = common::load_scene("cornell-box.toml");
        scene.render.filter = filter;
        let lt = render(&scene, Method::Lt, 64);
        let pt = render(&scene, Method::PtNee, 256);
        let c = compare(&lt, &pt, 4).unwrap();
        eprintln!("{filter:?}: lt against pt-nee {c:?}");
        assert!(c.rel_mse < 1e-3, "{filter:?}: relMSE {}", c.rel_mse);
        for r in c.mean_ratio {
            assert!((r - 1.0).abs() < 0.01, "{filter:?}: channel mean ratios {:?}", c.mean_ratio);
        }
    }
}

/// Through a thin lens: light joined to a point of the lens lands where pt-nee's rays through
/// that lens find it, out of focus alike.
#[test]
fn light_tracing_through_a_thin_lens() {
    if common::gpu().is_none() {
        return;
    }
    let mut scene = common::load_scene("cornell-box.toml");
    scene.camera.aperture_radius = 0.15;
    scene.camera.focus_distance = 2.0;
    let lt = render(&scene, Method::Lt, 64);
    let pt = render(&scene, Method::PtNee, 256);
    let c = compare(&lt, &pt, 4).unwrap();
    eprintln!("thin lens: lt against pt-nee {c:?}");
    assert!(c.rel_mse < 1e-3, "thin lens: relMSE {}", c.rel_mse);
    for r in c.mean_ratio {
        assert!((r - 1.0).abs() < 0.01, "thin lens: channel mean ratios {:?}", c.mean_ratio);
    }
    // The same lens as a pinhole is another image: the test sees the blur.
    let mut pinhole = scene.clone();
    pinhole.camera.aperture_radius = 0.0;
    let sharp = render(&pinhole, Method::Lt, 64);
    assert!(compare(&sharp, &pt, 4).unwrap().rel_mse > 3.0 * c.rel_mse, "the lens changed nothing");
}

/// The same seed gives the same bits: splats are summed in fixed point, in any order.
#[test]
fn light_tracing_is_bit_exact_per_seed() {
    if common::gpu().is_none() {
        return;
    }
    let scene = common::load_scene("cornell-box.toml");
    let a = render(&scene, Method::Lt, 3);
    let b = render(&scene, Method::Lt, 3);
    assert!(a.pixels == b.pixels, "two renders of one seed differ");
    let mut other = scene.clone();
    other.render.seed += 1;
    assert!(render(&other, Method::Lt, 3).pixels != a.pixels, "another seed gave the same image");
}

/// Media and an environment light are refused before any pass, naming the scene.
#[test]
fn light_tracing_refuses_what_it_cannot_render() {
    let Some(gpu) = common::gpu() else { return };
    for (name, what) in [("media/fog-cornell.xml", "participating media"), ("furnace-environment.toml", "environment light")] {
        let mut scene = common::load_scene(name);
        scene.render.method = Method::Lt;
        let err = match integrators::create(&gpu.device, &gpu.queue, &scene) {
            Ok(_) => panic!("{name}: rendered with lt"),
            Err(e) => e.to_string(),
        };
        assert!(err.contains(what) && err.contains("method lt") && err.contains(name), "{name}: {err}");
    }
}
