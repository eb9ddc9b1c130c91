//! The path tracers against the same references as SPPM: PT-NEE converges to the reference on
//! every canonical scene it can render, naive PT on those lit by area lights; and where a
//! method cannot see a light, the test pins that behaviour.

use crate::common;

use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::metrics::{compare, downsample_box};
use sppm_gpu::scene::{Method, Scene};

const SIZE: u32 = 64;

fn render(scene: &Scene, method: Method, passes: u32) -> Rgb32Image {
    common::render_at(scene, method, SIZE, passes)
}

/// relMSE and channel mean ratios against the 256x256 reference, both reduced to 8x8.
fn check(name: &str, method: Method, passes: u32, max_rel_mse: f64) {
    let scene = common::load_scene(&format!("{name}.toml"));
    let img = render(&scene, method, passes);
    let reference = downsample_box(&common::reference(&format!("{name}.exr")), 256 / SIZE).unwrap();
    let c = compare(&img, &reference, 8).unwrap();
    eprintln!("{name} {method:?} {passes} spp: {c:?}");
    assert!(c.rel_mse < max_rel_mse, "{name} {method:?}: relMSE {}", c.rel_mse);
    for r in c.mean_ratio {
        assert!((r - 1.0).abs() < 0.03, "{name} {method:?}: channel mean ratios {:?}", c.mean_ratio);
    }
}

#[test]
fn pt_nee_matches_the_references() {
    if common::gpu().is_none() {
        return;
    }
    for name in ["cornell-box", "cornell-glossy", "textured", "point-light"] {
        check(name, Method::PtNee, 128, 0.003);
    }
    // Light through the glass sphere makes fireflies: at 128 spp relMSE over seeds 0..6 is
    // 1.6e-3 to 2.7e-3 with one outlier of 4.6e-3 (seed 0, the Sobol sampler; the independent
    // sampler 1.8e-3 to 2.4e-3): twice the samples, the same bound.
    check("depth-of-field", Method::PtNee, 256, 0.003);
}

#[test]
fn naive_pt_matches_the_cornell_box() {
    if common::gpu().is_none() {
        return;
    }
    check("cornell-box", Method::Pt, 256, 0.006);
}

/// Every surface has albedo 0.5 and emits 1 in a closed box: 2 everywhere, for both.
#[test]
fn path_tracers_give_two_in_the_furnace() {
    if common::gpu().is_none() {
        return;
    }
    let scene = common::load_scene("furnace.toml");
    for method in [Method::Pt, Method::PtNee] {
        let mean = render(&scene, method, 64).mean();
        for c in mean {
            assert!((c - 2.0).abs() < 0.02, "{method:?}: furnace mean {mean:?}");
        }
    }
}

/// Naive path tracing never hits a point light, so a scene lit only by one stays black;
/// next-event estimation sees it.
#[test]
fn naive_pt_cannot_see_a_point_light() {
    if common::gpu().is_none() {
        return;
    }
    let scene = common::load_scene("point-light.toml");
    let naive = render(&scene, Method::Pt, 4);
    assert!(naive.pixels.iter().all(|p| *p == [0.0; 3]), "naive PT found light from a point light");
    let nee = render(&scene, Method::PtNee, 4);
    assert!(nee.mean()[0] > 0.05, "PT-NEE saw no light: {:?}", nee.mean());
}
