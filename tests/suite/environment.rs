//! The constant environment (issue 25) against its analytic furnace: under radiance 1 from
//! every direction, a lone convex diffuse sphere of albedo a reflects a everywhere (all it sees
//! is the environment), a smooth glass sphere passes 1 (it only redirects light), and the
//! background reads 1. Each method is checked on the mean over the pixels that lie wholly on
//! the sphere (the sphere's mean, and its inner disk's and outer ring's apart, so that an error
//! that grows towards grazing angles cannot hide) and over those wholly off it; pixels that
//! straddle the silhouette mix the two and are left out. SPPM runs with direct light sampled
//! (the camera pass's next-event estimation and escaped rays) and from photons alone (the
//! environment's photons and their flux).

use crate::common;

use glam::DVec3;
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators;
use sppm_gpu::scene::envmap::Envmap;
use sppm_gpu::scene::{DirectLight, Light, LightKind, Method, Scene, SceneBuilder};

const SIZE: u32 = 64;
const EYE: [f32; 3] = [0.0, 0.0, 4.0];
const FOV: f32 = 40.0;
const RADIUS: f64 = 1.0;

/// The furnace: one sphere of `material` (built by `with`) at the origin, seen from +z.
fn furnace(
    with: impl FnOnce(SceneBuilder) -> SceneBuilder,
    method: Method,
    direct: DirectLight,
    passes: u32,
    photons: u32,
) -> Scene {
    let b = SceneBuilder::new(SIZE, SIZE)
        .method(method)
        .iterations(passes)
        .photons(photons.max(1))
        .camera(EYE, [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], FOV)
        .constant_environment([1.0, 1.0, 1.0]);
    let mut scene = with(b).sphere([0.0, 0.0, 0.0], RADIUS as f32, "m").build().unwrap_or_else(|e| panic!("{e}"));
    scene.render.direct = direct;
    scene
}

fn render(scene: &Scene) -> Rgb32Image {
    let gpu = common::gpu().expect("checked by the caller");
    let mut integrator = integrators::create(&gpu.device, &gpu.queue, scene).unwrap();
    common::run_passes(integrator.as_mut(), scene.render.iterations)
}

/// Where pixel (x, y) lies: `Some(true)` wholly on the sphere, `Some(false)` wholly off it,
/// `None` across the silhouette. The pixel's square, grown by half a pixel on every side (the
/// box filter's support and a margin), is tested at a grid of points.
fn coverage(x: u32, y: u32) -> Option<bool> {
    let eye = DVec3::new(EYE[0] as f64, EYE[1] as f64, EYE[2] as f64);
    let tan = (FOV as f64 / 2.0).to_radians().tan();
    // Rays meet the sphere within this angle of the direction to its centre.
    let sin_max = RADIUS / eye.length();
    let (mut on, mut off) = (false, false);
    for i in 0..=4 {
        for j in 0..=4 {
            let px = x as f64 - 0.5 + 2.0 * i as f64 / 4.0;
            let py = y as f64 - 0.5 + 2.0 * j as f64 / 4.0;
            let d = DVec3::new((2.0 * px / SIZE as f64 - 1.0) * tan, (1.0 - 2.0 * py / SIZE as f64) * tan, -1.0).normalize();
            let sin = d.cross(-eye.normalize()).length();
            if sin < sin_max {
                on = true;
            } else {
                off = true;
            }
        }
    }
    match (on, off) {
        (true, false) => Some(true),
        (false, true) => Some(false),
        _ => None,
    }
}

/// The mean of the RGB average over the sphere's inner disk (within half its
/// image radius of the centre), its outer ring, all of it, and the background.
struct Means {
    inner: f64,
    outer: f64,
    sphere: f64,
    background: f64,
}

/// The part of the image pixel (x, y) lies wholly in, `None` across the silhouette.
#[derive(Clone, Copy, PartialEq)]
enum Part {
    /// On the sphere, within half its image radius of the centre.
    Inner,
    /// On the sphere, farther out.
    Outer,
    Background,
}

fn part(x: u32, y: u32) -> Option<Part> {
    // The sphere's image radius in pixels.
    let eye = EYE[2] as f64;
    let r_image = (RADIUS / (eye * eye - RADIUS * RADIUS).sqrt()) / (FOV as f64 / 2.0).to_radians().tan() * SIZE as f64 / 2.0;
    let r = (x as f64 + 0.5 - SIZE as f64 / 2.0).hypot(y as f64 + 0.5 - SIZE as f64 / 2.0);
    match coverage(x, y)? {
        true if r < 0.5 * r_image => Some(Part::Inner),
        true => Some(Part::Outer),
        false => Some(Part::Background),
    }
}

/// The RGB average of every pixel wholly in `which`.
fn values(img: &Rgb32Image, which: Part) -> Vec<f64> {
    (0..SIZE * SIZE)
        .filter(|&i| part(i % SIZE, i / SIZE) == Some(which))
        .map(|i| img.pixels[i as usize].iter().map(|&c| c as f64).sum::<f64>() / 3.0)
        .collect()
}

fn means(img: &Rgb32Image) -> Means {
    let [inner, outer, background] = [Part::Inner, Part::Outer, Part::Background].map(|p| values(img, p));
    assert!(
        inner.len() > 100 && outer.len() > 100 && background.len() > 1000,
        "{} {} {}",
        inner.len(),
        outer.len(),
        background.len()
    );
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    Means {
        inner: mean(&inner),
        outer: mean(&outer),
        sphere: (inner.iter().sum::<f64>() + outer.iter().sum::<f64>()) / (inner.len() + outer.len()) as f64,
        background: mean(&background),
    }
}

/// The sphere reads `expected` (mean within 0.5%, inner disk and outer ring within 1% each)
/// and the background 1 (within 0.5%).
fn check(what: &str, with: impl FnOnce(SceneBuilder) -> SceneBuilder, expected: f64, run: (Method, DirectLight, u32, u32)) {
    check_edited(what, with, |_| {}, expected, run)
}

/// [`check`] on the furnace changed by `edit`.
fn check_edited(
    what: &str,
    with: impl FnOnce(SceneBuilder) -> SceneBuilder,
    edit: impl FnOnce(&mut Scene),
    expected: f64,
    (method, direct, passes, photons): (Method, DirectLight, u32, u32),
) {
    if common::gpu().is_none() {
        return;
    }
    let mut scene = furnace(with, method, direct, passes, photons);
    edit(&mut scene);
    let m = means(&render(&scene));
    eprintln!(
        "{what} {method:?} {direct:?}: sphere {:.5} (inner {:.5}, outer {:.5}), background {:.5}; expected {expected}",
        m.sphere, m.inner, m.outer, m.background
    );
    assert!((m.sphere / expected - 1.0).abs() < 0.005, "{what} {method:?}: sphere mean {} (expected {expected})", m.sphere);
    for (part, v) in [("inner disk", m.inner), ("outer ring", m.outer)] {
        assert!((v / expected - 1.0).abs() < 0.01, "{what} {method:?}: the sphere's {part} {v} (expected {expected})");
    }
    assert!((m.background - 1.0).abs() < 0.005, "{what} {method:?}: background {}", m.background);
}

fn white(b: SceneBuilder) -> SceneBuilder {
    b.diffuse("m", [1.0, 1.0, 1.0])
}

fn grey(b: SceneBuilder) -> SceneBuilder {
    b.diffuse("m", [0.8, 0.8, 0.8])
}

fn glass(b: SceneBuilder) -> SceneBuilder {
    b.dielectric("m", 1.5, 0.0)
}

/// Method, SPPM's direct light, passes and photons per pass. From photons alone, the density
/// estimate on the curved sphere reads low by a part that shrinks with the radius (albedo 0.8:
/// -0.7% after 8 passes of 50,000, -0.5% after 32, -0.03% after 128; +0.07% after 32 of
/// 400,000), so that run has more photons.
const ALL: [(Method, DirectLight, u32, u32); 4] = [
    (Method::Pt, DirectLight::Sampled, 16, 0),
    (Method::PtNee, DirectLight::Sampled, 64, 0),
    (Method::Sppm, DirectLight::Sampled, 16, 50_000),
    (Method::Sppm, DirectLight::Photons, 32, 200_000),
];

#[test]
fn furnace_diffuse_albedo_one_reads_one() {
    for run in ALL {
        check("albedo 1", white, 1.0, run);
    }
}

#[test]
fn furnace_diffuse_albedo_point_eight_reads_point_eight() {
    for run in ALL {
        check("albedo 0.8", grey, 0.8, run);
    }
}

#[test]
fn furnace_smooth_glass_reads_one() {
    for run in ALL {
        check("glass", glass, 1.0, run);
    }
}

/// Russian roulette in the path tracers judges the throughput without the 1 / eta^2 that a
/// radiance path carries inside glass (pbrt-v4's etaScale). In the furnace every path through a
/// smooth sphere of index 2.42 (a diamond's) sees 1 when it leaves, so each pixel reads 1 but
/// for the roulette's weights: with them judged on eta^2 beta (about 1 inside), a path that
/// reflects inside twice survives at 95% and weighs 1 / 0.95; judged on beta (0.17 inside), it
/// survived at 17% and weighed 5.9, which spread the inner disk's pixels five times as wide
/// (naive pt, 16 passes: RMS 0.043 against 0.0084). The RMS over the inner disk must stay
/// below 0.03.
#[test]
fn furnace_diamond_roulette_keeps_the_weight() {
    if common::gpu().is_none() {
        return;
    }
    for method in [Method::Pt, Method::PtNee] {
        let scene = furnace(|b| b.dielectric("m", 2.42, 0.0), method, DirectLight::Sampled, 16, 1);
        let inner = values(&render(&scene), Part::Inner);
        let n = inner.len();
        let mean = inner.iter().sum::<f64>() / n as f64;
        let rms = (inner.iter().map(|v| (v - 1.0) * (v - 1.0)).sum::<f64>() / n as f64).sqrt();
        eprintln!("diamond {method:?}: inner disk of {n} pixels, mean {mean:.5}, RMS about 1 {rms:.4}");
        assert!(n > 100, "{n} pixels");
        assert!((mean - 1.0).abs() < 0.01, "diamond {method:?}: inner disk mean {mean}");
        assert!(rms < 0.03, "diamond {method:?}: the inner disk's pixels spread by {rms} about 1");
    }
}

/// The furnace under an environment map of radiance 1 everywhere (8x4 texels, turned) in place
/// of the constant: the map's lookup, its sampling and density (next-event estimation and the
/// MIS of escaping rays) and its photons give the albedo as the constant's do.
fn envmap_of_one(scene: &mut Scene) {
    let turn = glam::Mat3::from_rotation_x(0.4) * glam::Mat3::from_rotation_y(1.0);
    let map = Envmap::new("ones.exr".into(), 8, 4, vec![glam::Vec3::ONE; 32], 1.0, turn).unwrap();
    scene.lights = vec![Light { kind: LightKind::Envmap(std::sync::Arc::new(map)), line: 0 }];
}

#[test]
fn furnace_envmap_of_one_reads_albedo() {
    for run in ALL {
        check_edited("envmap, albedo 0.8", grey, envmap_of_one, 0.8, run);
        check_edited("envmap, glass", glass, envmap_of_one, 1.0, run);
    }
}

/// bpt, and vcm at every strategy (connections and merging at every camera vertex), under the
/// constant environment and the map of ones: light subpaths leave the environment's disk with a
/// light at infinity's densities, and camera subpaths weigh the environment they escape to or
/// sample against the light subpaths' strategies. With a speck far behind the camera the
/// scene's bounding sphere grows to 27 times the furnace's sphere, and the light subpaths are
/// aimed at what the camera sees (90% through a disk around the sphere): the disk densities'
/// mixture in every weight (the speck hides 1e-5 of the sky).
#[test]
fn furnace_bidirectional_reads_albedo() {
    for method in [Method::Bpt, Method::Vcm] {
        let run = (method, DirectLight::Sampled, 64, 1);
        let shares = |s: &mut Scene| {
            if s.render.method == Method::Vcm {
                (s.render.connect_share, s.render.merge_share) = (Some(1.0), Some(1.0));
            }
        };
        check_edited("albedo 0.8", grey, shares, 0.8, run);
        check_edited("glass", glass, shares, 1.0, run);
        check_edited(
            "envmap, albedo 0.8",
            grey,
            |s| {
                envmap_of_one(s);
                shares(s);
            },
            0.8,
            run,
        );
        let speck = |b: SceneBuilder| grey(b).sphere([0.0, 0.0, 50.0], 0.1, "m");
        check_edited("aimed, albedo 0.8", speck, shares, 0.8, run);
    }
}

/// The TOML scene of the furnace renders the same answer from the command line's path.
#[test]
fn furnace_scene_file_reads_point_eight() {
    if common::gpu().is_none() {
        return;
    }
    let mut scene = common::load_scene("furnace-environment.toml");
    scene.render.iterations = 8;
    let m = means(&render(&scene));
    eprintln!("furnace-environment.toml: sphere {:.5}, background {:.5}", m.sphere, m.background);
    assert!(
        (m.sphere / 0.8 - 1.0).abs() < 0.005 && (m.background - 1.0).abs() < 0.005,
        "sphere {} background {}",
        m.sphere,
        m.background
    );
}

/// TOML's `envmap` light (`file`, `scale`, `rotate` in degrees as a shape's) gives the map that
/// envmap.xml's `<emitter type="envmap">` gives (rotate y 200, scale 1.5); a missing file and
/// a key it lacks are errors naming the line and key.
#[test]
fn toml_envmap_matches_the_mitsuba_one() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let xml = sppm_gpu::scene::load(&dir.join("mitsuba/envmap.xml")).unwrap_or_else(|e| panic!("{e}"));
    let scene = |light: &str| {
        let text = format!(
            "[render]\nwidth = 8\nheight = 8\niterations = 1\n\n[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\n\
             [materials]\ngrey = {{ type = \"diffuse\", albedo = [0.8, 0.8, 0.8] }}\n\n[[shapes]]\ntype = \"sphere\"\n\
             center = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"grey\"\n\n[[lights]]\ntype = \"envmap\"\n{light}"
        );
        sppm_gpu::scene::load_str(&text, &dir.join("envmap-test.toml"))
    };
    let toml = scene("file = \"mitsuba/textures/envmap-test.exr\"\nscale = 1.5\nrotate = [0.0, 200.0, 0.0]\n")
        .unwrap_or_else(|e| panic!("{e}"));
    let (LightKind::Envmap(a), LightKind::Envmap(b)) = (&toml.lights[0].kind, &xml.lights[0].kind) else { panic!() };
    assert_eq!((a.width, a.height, a.scale, &a.texels), (b.width, b.height, b.scale, &b.texels));
    assert!((0..3).all(|i| (a.to_world.col(i) - b.to_world.col(i)).abs().max_element() < 1e-6));
    let e = scene("file = \"nowhere.exr\"\n").unwrap_err();
    assert!(e.to_string().contains("nowhere.exr") && e.line == Some(22), "{e}");
    let e = scene("file = \"mitsuba/textures/envmap-test.exr\"\nradiance = [1.0, 1.0, 1.0]\n").unwrap_err();
    assert!(e.to_string().contains("radiance"), "{e}");
}

/// Environment photons aimed at the visible points (`Sppm::set_environment_aim`,
/// `environment_origin` in photon_pass.wgsl) against the furnace where those points cover a
/// small part of the scene: a diffuse sphere of radius 10 and albedo 0.8 under radiance 1, seen
/// from 2 units off its surface, so that the disk about the visible points is about a tenth of
/// the scene's across and takes most photons that reach them (90% of photons drawn from it at
/// about 100 times the density). Photons carry all light (`direct = "photons"`: on a convex
/// sphere no photon bounces back, so with direct light sampled they would add nothing). The
/// image reads 0.8 everywhere, within 0.5% (0.8003 when written); aimed photons that missed
/// the small disk's part of the mixture's density would read up to 100 times too bright.
/// (Only photons from within the small disk reach these points; the whole disk's part of the
/// weight, which the photons that bounce on their way to the visible points test, is checked
/// by sky.xml against Mitsuba, `tests/suite/mitsuba_xml.rs`.)
#[test]
fn furnace_aimed_environment_photons_read_albedo() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = SceneBuilder::new(SIZE, SIZE)
        .method(Method::Sppm)
        .iterations(32)
        .photons(200_000)
        .camera([0.0, 0.0, 12.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], FOV)
        .constant_environment([1.0, 1.0, 1.0])
        .diffuse("m", [0.8, 0.8, 0.8])
        .sphere([0.0, 0.0, 0.0], 10.0, "m")
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    scene.render.direct = DirectLight::Photons;
    // Unaimed, the same photons (0.3% of them reach the patch) read 0.83 with the centre at
    // 0.97 and a corner at 0.73: too noisy to test; the unaimed photons are the furnaces' above.
    let aim = 0.9;
    let mut sppm = sppm_gpu::integrators::sppm::Sppm::new(&gpu.device, &gpu.queue, &scene).unwrap();
    sppm.set_environment_aim(aim);
    assert_eq!(sppm.environment_aim(), aim);
    let img = common::run_passes(&mut sppm, scene.render.iterations);
    let mean = img.pixels.iter().map(|p| p.iter().map(|&c| c as f64).sum::<f64>() / 3.0).sum::<f64>() / img.pixels.len() as f64;
    // The centre and the corners apart: the camera sees the sphere at every pixel.
    let at = |x: u32, y: u32| img.pixels[(y * SIZE + x) as usize].iter().map(|&c| c as f64).sum::<f64>() / 3.0;
    eprintln!("aimed furnace, aim {aim}: mean {mean:.5}, centre {:.4}, corner {:.4}", at(SIZE / 2, SIZE / 2), at(0, 0));
    assert!((mean / 0.8 - 1.0).abs() < 0.005, "aim {aim}: mean {mean} (expected 0.8)");
}

/// Where the ray from `eye` along `d` first meets one of `spheres` (centre, radius): the
/// index of that sphere, or `None`.
fn first_sphere(eye: DVec3, d: DVec3, spheres: &[(DVec3, f64)]) -> Option<usize> {
    let mut best: Option<(f64, usize)> = None;
    for (i, &(c, r)) in spheres.iter().enumerate() {
        // |eye + t d - c|^2 = r^2 with |d| = 1.
        let oc = eye - c;
        let b = oc.dot(d);
        let disc = b * b - (oc.length_squared() - r * r);
        if disc < 0.0 {
            continue;
        }
        let t = -b - disc.sqrt();
        if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
            best = Some((t, i));
        }
    }
    best.map(|(_, i)| i)
}

/// The aimed environment photons' other part, the photons from the scene's whole disk, where
/// they carry most of the light: a white furnace (albedo 1 everywhere under radiance 1 reads 1
/// on every surface, whatever the geometry) of a small sphere B (radius 2) resting on a large
/// one A (radius 10). The camera sees B alone, so the disk about the visible points covers B
/// and little of A. Direct light is sampled (B's points see the environment except where A
/// hides it), so the photons carry only the light bounced off A onto B: half of what B's
/// lower half receives, and most of it from parts of A outside the aimed disk, which only the
/// whole disk's photons reach (10% of them). B's halves must read 1 within 1%, aimed (0.9:
/// 0.9990 and 1.0015 when written) and unaimed (0, every photon from the whole disk: 0.9944,
/// 1.0027). The whole disk's part of the mixture's density halved (its photons' flux doubled)
/// read 1.050 and 1.024.
#[test]
fn furnace_whole_disk_photons_carry_the_bounced_light() {
    let Some(gpu) = common::gpu() else { return };
    let (a, b) = ((DVec3::ZERO, 10.0), (DVec3::new(0.0, 12.0, 0.0), 2.0));
    let eye = DVec3::new(0.0, 12.0, 10.0);
    let fov = 25.0f64;
    let scene = SceneBuilder::new(SIZE, SIZE)
        .method(Method::Sppm)
        .iterations(32)
        .photons(200_000)
        .camera(eye.as_vec3(), b.0.as_vec3(), [0.0, 1.0, 0.0], fov as f32)
        .constant_environment([1.0, 1.0, 1.0])
        .diffuse("m", [1.0, 1.0, 1.0])
        .sphere(a.0.as_vec3(), a.1 as f32, "m")
        .sphere(b.0.as_vec3(), b.1 as f32, "m")
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.render.direct, DirectLight::Sampled);
    // B's pixels (every point of the pixel grown by half a pixel meets B first), by half.
    let tan = (fov / 2.0).to_radians().tan();
    let mut lower_half = vec![];
    let mut upper_half = vec![];
    for y in 0..SIZE {
        for x in 0..SIZE {
            let on_b = (0..=4).all(|i| {
                (0..=4).all(|j| {
                    let px = x as f64 - 0.5 + 2.0 * i as f64 / 4.0;
                    let py = y as f64 - 0.5 + 2.0 * j as f64 / 4.0;
                    let d = DVec3::new((2.0 * px / SIZE as f64 - 1.0) * tan, (1.0 - 2.0 * py / SIZE as f64) * tan, -1.0);
                    first_sphere(eye, d.normalize(), &[a, b]) == Some(1)
                })
            });
            if on_b {
                if y >= SIZE / 2 { &mut lower_half } else { &mut upper_half }.push((y * SIZE + x) as usize);
            }
        }
    }
    assert!(lower_half.len() > 500 && upper_half.len() > 500, "{} {}", lower_half.len(), upper_half.len());
    for aim in [0.9, 0.0] {
        let mut sppm = sppm_gpu::integrators::sppm::Sppm::new(&gpu.device, &gpu.queue, &scene).unwrap();
        sppm.set_environment_aim(aim);
        let img = common::run_passes(&mut sppm, scene.render.iterations);
        let mean = |pixels: &[usize]| {
            pixels.iter().map(|&p| img.pixels[p].iter().map(|&c| c as f64).sum::<f64>() / 3.0).sum::<f64>() / pixels.len() as f64
        };
        let (lower, upper) = (mean(&lower_half), mean(&upper_half));
        eprintln!("white furnace of two spheres, aim {aim}: B's lower half {lower:.5}, upper half {upper:.5}");
        for (part, v) in [("lower", lower), ("upper", upper)] {
            assert!((v - 1.0).abs() < 0.01, "aim {aim}: B's {part} half reads {v} (expected 1)");
        }
    }
}

/// `EnvAimTestParams` in tests/shaders/env_aim_test.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct EnvAimParams {
    count: u32,
    fraction: f32,
    big: f32,
    small: f32,
    centre: [f32; 3],
    _pad0: f32,
    w: [f32; 3],
    _pad1: f32,
}

/// The aimed disk's density, which every MIS weight of bpt and vcm takes for an environment's
/// light subpaths (`environment_disk_density`), is the one `environment_origin` draws them
/// from: for 65,536 draws each, weight times density is 1, with the small disk inside the
/// large one, across its rim, at two shares and from several directions. (A wrong density
/// leaves the images unbiased but not their noise: on Mitsuba's sky.xml, the aim with the
/// unaimed density in the weights read 1.54e-2 at 30 s against 4.0e-3.)
#[test]
fn aimed_disk_weights_are_their_density() {
    use sppm_gpu::gpu::readback::{read_buffer, staging_buffer};
    use sppm_gpu::gpu::scene_buffers::storage_buffer;
    use sppm_gpu::gpu::Resource;
    use wgpu::util::DeviceExt;
    let Some(gpu) = common::gpu() else { return };
    let kernel = common::test_kernel(&gpu, "env_aim_test", &[], &[]);
    let count = 65_536u32;
    let cases = [
        (0.9, [0.5, 0.2, -0.3], [0.3, 0.8, 0.5]),
        (0.5, [0.5, 0.2, -0.3], [-0.6, 0.1, 0.7]),
        // The aimed sphere reaches past the scene's rim seen from w.
        (0.9, [9.5, 0.0, 0.0], [0.0, 1.0, 0.0]),
        (0.7, [0.0, 9.0, 2.0], [1.0, 0.2, -0.1]),
    ];
    for (fraction, centre, w) in cases {
        let params = EnvAimParams { count, fraction, big: 10.0, small: 2.0, centre, _pad0: 0.0, w, _pad1: 0.0 };
        let uniform = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("test_params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let out = storage_buffer(&gpu.device, "test_out", &vec![[0f32; 4]; count as usize]);
        let resources = [Resource { name: "test_params", buffer: &uniform }, Resource { name: "test_out", buffer: &out }];
        let group = kernel.bind_group(&gpu.device, &resources).unwrap_or_else(|e| panic!("{e}"));
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        kernel.dispatch(&mut encoder, &group, count);
        gpu.queue.submit([encoder.finish()]);
        let staging = staging_buffer(&gpu.device, "test_out_staging", out.size());
        let draws: Vec<[f32; 4]> = read_buffer(&gpu.device, &gpu.queue, &out, &staging, out.size()).unwrap();
        let off = draws.iter().filter(|d| (d[0] - 1.0).abs() > 1e-4).count();
        // Both parts drawn: points in the small disk (weight below 1 / (1 - f) / 2 at these
        // sizes) and in the large one alone (weight 1 / (1 - f)).
        let (small, large) = (draws.iter().filter(|d| d[1] < 0.5).count(), draws.iter().filter(|d| d[1] > 0.5).count());
        eprintln!("aim {fraction} at {centre:?} from {w:?}: {off} of {count} off, {small} in the small disk, {large} in the large alone");
        assert!(
            off <= (count / 10_000) as usize,
            "aim {fraction} at {centre:?} from {w:?}: {off} draws' weight times density off 1"
        );
        assert!(small > 1000 && large > 1000, "aim {fraction} at {centre:?}: {small} and {large} draws in each part");
    }
}
