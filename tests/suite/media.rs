//! Participating media in the kernels (issue 35; shared/medium.wgsl): analytic cases (the
//! transmittance of a slab, a white furnace filled with a scattering medium), every method
//! against the others in fog around an open box (where the grid of visible points must reach
//! past the surfaces), and the Mitsuba `volpath` references of scenes/media/. The samplers'
//! chi-square tests are in chi_square.rs (henyey_greenstein_sampling, free_flight_sampling).

use crate::common;

use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators::{self, Integrator};
use sppm_gpu::metrics::{compare, downsample_box};
use sppm_gpu::scene::{self, Method, Scene};
use std::path::Path;

fn load(text: &str) -> Scene {
    scene::load_str(text, Path::new("media-test.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn render(gpu: &sppm_gpu::gpu::GpuContext, scene: &Scene, method: Method, passes: u32) -> Rgb32Image {
    let mut scene = scene.clone();
    scene.render.method = method;
    let mut integrator: Box<dyn Integrator> =
        integrators::create(&gpu.device, &gpu.queue, &scene).unwrap_or_else(|e| panic!("{e}"));
    common::run_passes(&mut *integrator, passes)
}

/// An emitter of radiance 1 seen through a slab of unit thickness (a `null` cube holding a
/// medium that only absorbs, sigma_a = (0.5, 1, 2)): every pixel is exp(-sigma_a) (the rays
/// cross it within 1.5 degrees of its normal, 1 / cos below 1.0004), by each method.
#[test]
fn a_slab_transmits_exp_minus_its_optical_depth() {
    let Some(gpu) = common::gpu() else { return };
    let scene = load(
        r#"[render]
width = 16
height = 16
iterations = 1
max_depth = 8

[media.ink]
sigma_a = [0.5, 1.0, 2.0]
sigma_s = [0.0, 0.0, 0.0]

[camera]
position = [0, 0, 10]
look_at = [0, 0, 0]
fov = 3

[materials]
black = { type = "diffuse", albedo = [0, 0, 0] }
clear = { type = "null" }

[[shapes]]
type = "quad"
corner = [-5, -5, -3]
u = [10, 0, 0]
v = [0, 10, 0]
material = "black"
emission = [1, 1, 1]

[[shapes]]
type = "cube"
scale = [5, 5, 0.5]
material = "clear"
interior = "ink"
"#,
    );
    let expected = [0.5f64, 1.0, 2.0].map(|s| (-s).exp());
    for (method, passes) in [(Method::Pt, 256), (Method::PtNee, 256), (Method::Sppm, 64)] {
        let m = render(&gpu, &scene, method, passes).mean();
        eprintln!("slab {method:?}: {m:?} against {expected:?}");
        for c in 0..3 {
            // 16x16 pixels x passes binary samples (through or not) of probability p: the
            // standard error of the mean's weight is below 0.3% of it.
            assert!((m[c] / expected[c] - 1.0).abs() < 0.01, "{method:?}: channel {c} {} against {}", m[c], expected[c]);
        }
    }
}

/// A white furnace (furnace.toml: walls of albedo 0.5 emitting 1, radiance 2 everywhere)
/// filled with a medium that scatters and does not absorb (albedo 1): the radiance stays 2
/// along every ray, what each method must find; SPPM through visible points in the medium.
#[test]
fn a_furnace_filled_with_a_white_medium_stays_uniform() {
    let Some(gpu) = common::gpu() else { return };
    let text = std::fs::read_to_string(common::scene_path("furnace.toml")).unwrap();
    let text = text.replacen(
        "[camera]",
        "[media.white]\nsigma_a = [0, 0, 0]\nsigma_s = [1.5, 1.0, 0.5]\n\n[camera]\nmedium = \"white\"",
        1,
    );
    let mut scene = load(&text);
    scene.render.width = 32;
    scene.render.height = 32;
    // The automatic radius follows the pixels, large in so small an image; the spheres of the
    // points in the medium (twice it) would reach through the walls by a tenth of the box.
    scene.render.radius = Some(0.02);
    for (method, passes) in [(Method::Pt, 512), (Method::PtNee, 256), (Method::Sppm, 32)] {
        let img = render(&gpu, &scene, method, passes);
        let m = img.mean();
        // Each 8x8 block of pixels against 2, within five standard errors of its mean (the
        // pixels' spread, as the image should be uniform) and 1% for the estimators' bias.
        let values: Vec<f64> = img.pixels.iter().flatten().map(|&v| v as f64).collect();
        let var = values.iter().map(|v| (v - 2.0) * (v - 2.0)).sum::<f64>() / values.len() as f64;
        let allowed = 5.0 * (var / 64.0).sqrt() + 0.02;
        let blocks = downsample_box(&img, 8).unwrap();
        let worst = blocks.pixels.iter().flatten().map(|&v| (v as f64 - 2.0).abs()).fold(0.0, f64::max);
        eprintln!("furnace {method:?}: mean {m:?}, worst 8x8 block off by {worst:.4} (allowed {allowed:.4})");
        for c in 0..3 {
            assert!((m[c] / 2.0 - 1.0).abs() < 0.01, "{method:?}: mean {m:?}, not 2");
        }
        assert!(worst < allowed, "{method:?}: an 8x8 block off by {worst}");
    }
}

/// The Cornell box (open at the front) in chromatic fog that fills the scene, the camera in
/// it: SPPM against pt-nee. Visible points lie in the fog in front of the box, outside the
/// surfaces' bounds; the grid that once covered only those left them no photons (SPPM 11%
/// dark, worst at the image's edges).
#[test]
fn sppm_in_fog_around_an_open_box_matches_pt_nee() {
    let Some(gpu) = common::gpu() else { return };
    let text = std::fs::read_to_string(common::scene_path("cornell-box.toml")).unwrap();
    let text = text.replacen(
        "[camera]",
        "[media.fog]\nsigma_a = [0.05, 0.05, 0.05]\nsigma_s = [0.25, 0.3, 0.35]\n\n[camera]\nmedium = \"fog\"",
        1,
    );
    let mut scene = load(&text);
    scene.render.width = 64;
    scene.render.height = 64;
    scene.render.radius = Some(0.02);
    let reference = render(&gpu, &scene, Method::PtNee, 2048);
    let sppm = render(&gpu, &scene, Method::Sppm, 48);
    let c = compare(&sppm, &reference, 8).unwrap();
    eprintln!("open fog, SPPM against pt-nee: {c:?}");
    for r in c.mean_ratio {
        assert!((r - 1.0).abs() < 0.01, "channel mean ratios {:?}", c.mean_ratio);
    }
    assert!(c.rel_mse < 2e-3, "relMSE {}", c.rel_mse);
}

/// pt-nee and SPPM against Mitsuba 3's `volpath` renders of the same files
/// (tests/references/mitsuba/media/, scenes/media/README.md): the fog-filled Cornell box and
/// the box holding a block of murky water (dielectric boundary, forward scattering).
#[test]
fn media_scenes_match_mitsuba_volpath() {
    let Some(gpu) = common::gpu() else { return };
    // pt-nee's passes: at 128 on murky-water (2026-11-28) its relMSE read 3.4e-4 and its
    // channel means 1.0001 to 1.0008; pt-nee is unbiased, so 64 passes double the variance
    // part at most (about 7e-4, under the bound 2e-3 by 3x; the means' noise about 0.1%,
    // against 1%), as on fog-cornell at 64 (4.1e-4). SPPM's passes on murky-water: at 64
    // (2026-11-30) its relMSE read 4.5e-5 and its channel means within 0.04%; at 16 1.4e-4
    // and within 0.06%, under the bounds by 14x. fog-cornell's SPPM keeps 64: its channel
    // means read 0.9945 there, nearer the 1% bound.
    for (name, passes_pt, passes_sppm) in [("fog-cornell", 64, 64), ("murky-water", 64, 16)] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/media").join(format!("{name}.xml"));
        let mut scene = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        scene.render.width = 128;
        scene.render.height = 128;
        let reference = downsample_box(&common::reference(&format!("mitsuba/media/{name}.exr")), 2).unwrap();
        for (method, passes) in [(Method::PtNee, passes_pt), (Method::Sppm, passes_sppm)] {
            let img = render(&gpu, &scene, method, passes);
            let c = compare(&img, &reference, 8).unwrap();
            eprintln!("{name} {method:?}: {c:?}");
            for r in c.mean_ratio {
                assert!((r - 1.0).abs() < 0.01, "{name} {method:?}: channel mean ratios {:?}", c.mean_ratio);
            }
            assert!(c.rel_mse < 2e-3, "{name} {method:?}: relMSE {}", c.rel_mse);
        }
    }
}

/// Fog inside a `null` box in the middle of the Cornell box (vacuum around it, the light
/// outside): next-event estimation from the fog crosses the null boundary to the light
/// (shadow_transmittance) and phase sampling that hits the light through it is weighted against
/// it, which pt (light found only by hitting it) checks; SPPM's photons enter the box through
/// the boundary. Channel means within 1% of pt's (pt-nee) and 2% (SPPM, whose means at this size
/// and pass count scatter by about 0.4%, and whose spheres reach past the box's walls, a bias
/// of 0.5% at 64 passes that shrinks with the radius). Before the photons stopped counting null
/// crossings as bounces, SPPM counted the direct light in the box twice: 15% bright. pt's and
/// pt-nee's passes: at 4096 and 1024 (2026-11-28, 16 independent batches each) the channel
/// means' relative standard errors read 0.15 to 0.20% (pt) and 0.10 to 0.15% (pt-nee); at half
/// the passes about 0.21 to 0.28% and 0.15 to 0.21%, so the ratio of the two scatters by about
/// 0.35% at most, under the 1% bound by 2.9x (and pt's part of SPPM's ratio, against 2%).
/// SPPM's passes: against pt at 8192 passes (2026-11-30, seeds 0, 1 and 2) its channel means
/// read within 0.13% at 64 passes, 0.17% at 32 and 0.44% at 16 (within 0.74% at 32 passes of
/// half the photons): at 32, with pt's 0.28%, under half the 2% bound.
#[test]
fn next_event_estimation_crosses_null_boundaries() {
    let Some(gpu) = common::gpu() else { return };
    let text = std::fs::read_to_string(common::scene_path("cornell-box.toml")).unwrap();
    let text = text
        .replacen("[camera]", "[media.fog]\nsigma_a = [0.1, 0.1, 0.1]\nsigma_s = [1.5, 1.0, 0.6]\n\n[camera]", 1)
        .replacen("[materials]", "[materials]\nclear = { type = \"null\" }", 1)
        + "\n[[shapes]]\ntype = \"cube\"\nscale = [0.5, 0.25, 0.5]\ntranslate = [0.1, 1.55, 0.2]\nmaterial = \"clear\"\ninterior = \"fog\"\n";
    let mut scene = load(&text);
    scene.render.width = 48;
    scene.render.height = 48;
    // Small against the box of fog (the automatic radius of so small an image is a third of it).
    scene.render.radius = Some(0.01);
    let pt = render(&gpu, &scene, Method::Pt, 2048);
    for (method, passes) in [(Method::PtNee, 512), (Method::Sppm, 32)] {
        let img = render(&gpu, &scene, method, passes);
        let c = compare(&img, &pt, 8).unwrap();
        eprintln!("fog in a null box, {method:?} against pt: {c:?}");
        let tolerance = if method == Method::Sppm { 0.02 } else { 0.01 };
        for r in c.mean_ratio {
            assert!((r - 1.0).abs() < tolerance, "{method:?}: channel mean ratios {:?}", c.mean_ratio);
        }
    }
}

/// A null boundary is no scattering event (Mitsuba 3's volpath, pbrt-v4's `interface`, and
/// our photons): seen through a null sphere holding an empty medium (sigma_t 0) in front of the
/// open box, the room at max_depth 2 is the room without the sphere. Counting the sphere's two
/// crossings as bounces, camera paths lost the last two: the pixels through it were black but
/// for the light's own emission.
#[test]
fn null_boundaries_are_not_bounces() {
    let Some(gpu) = common::gpu() else { return };
    let text =
        std::fs::read_to_string(common::scene_path("cornell-box.toml")).unwrap().replacen("max_depth = 64", "max_depth = 2", 1);
    let with_sphere = text.replacen("[camera]", "[media.empty]\nsigma_t = 0\nalbedo = 0.5\n\n[camera]", 1).replacen(
        "[materials]",
        "[materials]\nclear = { type = \"null\" }",
        1,
    )
        + "\n[[shapes]]\ntype = \"sphere\"\ncenter = [0.0, 1.0, 2.0]\nradius = 0.4\nmaterial = \"clear\"\ninterior = \"empty\"\n";
    let mut plain = load(&text);
    let mut through = load(&with_sphere);
    for scene in [&mut plain, &mut through] {
        scene.render.width = 32;
        scene.render.height = 32;
        scene.render.radius = Some(0.02);
    }
    // The pixels whose rays cross the sphere: the central 12 x 12 (it spans about 19).
    let centre_mean = |img: &Rgb32Image| {
        let (x0, y0) = (img.width / 2 - 6, img.height / 2 - 6);
        Rgb32Image::from_fn(12, 12, |x, y| img.get(x0 + x, y0 + y)).mean().iter().sum::<f64>() / 3.0
    };
    // pt shares the loop (shared/camera_path.wgsl), with noise a tight bound would not take.
    // SPPM's passes: the two renders draw the same random numbers, and at 64 passes
    // (2026-11-30) the centre means read 0.1343 and 0.1343; at 16, over seeds 0, 1 and 2, the
    // ratio was within 0.09% of 1 (pt-nee's at 128 within 0.38%), against the 2% bound and
    // the lost bounces' black.
    for (method, passes) in [(Method::PtNee, 128), (Method::Sppm, 16)] {
        let (a, b) = (centre_mean(&render(&gpu, &plain, method, passes)), centre_mean(&render(&gpu, &through, method, passes)));
        eprintln!("{method:?}: centre mean {a:.4} without the sphere, {b:.4} through it");
        assert!((b / a - 1.0).abs() < 0.02, "{method:?}: centre mean {b} through a null sphere, {a} without it");
    }
}

/// Single scattering from a point light in an infinite medium (the camera's, chromatic, no
/// surface anywhere), max_depth 1: along the camera ray d the radiance is
///   L = integral over t of sigma_s / (4 pi) I exp(-sigma_t (t + r(t))) / r(t)^2 dt,
/// r(t) the distance from the point at t to the light, which the test integrates by the
/// trapezoid rule (to 1e-6) over every pixel's area; pt-nee (next-event estimation at the one
/// scattering event) and SPPM (the same estimate at its visible points; photons, which would
/// add a second event, are beyond max_depth) against it.
#[test]
fn single_scattering_from_a_point_light_matches_its_integral() {
    let Some(gpu) = common::gpu() else { return };
    let (sigma_a, sigma_s, intensity, light) = ([0.05, 0.05, 0.05], [0.1, 0.2, 0.3], 10.0, [0.5, 0.0, 2.0]);
    let scene = load(&format!(
        r#"[render]
width = 32
height = 32
iterations = 1
max_depth = 1
photons = 1000

[media.haze]
sigma_a = {sigma_a:?}
sigma_s = {sigma_s:?}

[camera]
position = [0, 0, 0]
look_at = [0, 0, 1]
fov = 1
medium = "haze"

[materials]
black = {{ type = "diffuse", albedo = [0, 0, 0] }}

[[lights]]
type = "point"
position = {light:?}
intensity = [{intensity}, {intensity}, {intensity}]
"#
    ));
    // The integral along direction d, t in [0, 400] (exp(-0.15 400) is negligible).
    let along = |d: [f64; 3]| -> [f64; 3] {
        let mut sum = [0.0; 3];
        let (steps, t_max) = (40_000, 400.0);
        for k in 0..=steps {
            // Denser near the light: t = t_max s^2.
            let s = k as f64 / steps as f64;
            let t = t_max * s * s;
            let dt = 2.0 * t_max * s / steps as f64 * if k == 0 || k == steps { 0.5 } else { 1.0 };
            let r2 = (0..3).map(|i| (t * d[i] - light[i]).powi(2)).sum::<f64>();
            for c in 0..3 {
                let sigma_t = sigma_a[c] + sigma_s[c];
                sum[c] += sigma_s[c] / (4.0 * std::f64::consts::PI) * intensity * (-sigma_t * (t + r2.sqrt())).exp() / r2 * dt;
            }
        }
        sum
    };
    // The image's mean: the midpoint rule on the image plane at distance 1, one direction a
    // pixel (its centre). The integral is smooth across so narrow a view (1 degree; the light
    // lies outside it): 4x4 directions a pixel (the rule's grid 4 times finer, 16 times the
    // work: 16 s of the test's 21 s of CPU) move the mean by under 3e-7 of it (2026-11-28),
    // below the trapezoid rule's 1e-6 and far below the 1% asked of the renders.
    let half = (0.5f64).to_radians().tan();
    let (n, sub) = (32, 1);
    let mut expected = [0.0; 3];
    for j in 0..n {
        for i in 0..n {
            for b in 0..sub {
                for a in 0..sub {
                    let x = ((i as f64 + (a as f64 + 0.5) / sub as f64) / n as f64 * 2.0 - 1.0) * half;
                    let y = ((j as f64 + (b as f64 + 0.5) / sub as f64) / n as f64 * 2.0 - 1.0) * half;
                    let len = (x * x + y * y + 1.0).sqrt();
                    let l = along([x / len, y / len, 1.0 / len]);
                    for c in 0..3 {
                        expected[c] += l[c] / (n * n * sub * sub) as f64;
                    }
                }
            }
        }
    }
    for (method, passes) in [(Method::PtNee, 256), (Method::Sppm, 128)] {
        let m = render(&gpu, &scene, method, passes).mean();
        eprintln!("single scattering {method:?}: {m:?} against {expected:?}");
        for c in 0..3 {
            assert!((m[c] / expected[c] - 1.0).abs() < 0.01, "{method:?}: channel {c} {} against {}", m[c], expected[c]);
        }
    }
}
