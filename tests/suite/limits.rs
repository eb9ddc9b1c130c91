//! Where each method fails, pinned: what pt-nee misses, how SPPM's radius leaks light and
//! what stops it, that a tiny radius costs noise but not bias, and the warnings the user gets.

use crate::common;

use glam::Vec3;
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators::{self, limitations, Sppm};
use sppm_gpu::scene::{Method, Scene, SceneBuilder};

fn render(gpu: &sppm_gpu::gpu::GpuContext, scene: &Scene) -> Rgb32Image {
    let mut integrator = integrators::create(&gpu.device, &gpu.queue, scene).unwrap_or_else(|e| panic!("{e}"));
    common::run_passes(&mut *integrator, scene.render.iterations)
}

/// Mean of the first channel over pixels [x0, x1) x [y0, y1).
fn region_mean(img: &Rgb32Image, x0: u32, x1: u32, y0: u32, y1: u32) -> f64 {
    let mut sum = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            sum += img.pixels[(y * img.width + x) as usize][0] as f64;
        }
    }
    sum / ((x1 - x0) * (y1 - y0)) as f64
}

/// A floor (albedo 0.5) lit by a point light of intensity 10 one unit above (0.5, 0, 0), and
/// a perfect mirror wall at x = 1; the camera looks straight down at (0.5, 0, 0).
fn mirror_scene(method: Method) -> Scene {
    SceneBuilder::new(32, 32)
        .method(method)
        .iterations(32)
        .photons(100_000)
        .camera([0.5, 3.0, 0.0], [0.5, 0.0, 0.0], [0.0, 0.0, -1.0], 20.0)
        .diffuse("floor", [0.5, 0.5, 0.5])
        .mirror("mirror", [1.0, 1.0, 1.0])
        .quad([-2.0, 0.0, 2.0], [3.0, 0.0, 0.0], [0.0, 0.0, -4.0], "floor")
        .quad([1.0, 0.0, -2.0], [0.0, 0.0, 4.0], [0.0, 2.0, 0.0], "mirror")
        .point_light([0.5, 1.0, 0.0], [10.0, 10.0, 10.0])
        .build()
        .unwrap()
}

/// Light from a point light reflected by a mirror onto a diffuse floor (a caustic path,
/// L S D E) reaches SPPM's photons but not pt-nee: its shadow rays aim at the light itself,
/// and no sampled direction hits a point. At (0.5, 0, 0) the direct irradiance is I / 1^2
/// and the mirrored one I cos(45) / 2 (the light's image at (1.5, 1, 0)), so the floor's
/// radiance is 0.5 / pi * 10 * (1 + 0.354) with the mirror and 0.5 / pi * 10 without.
#[test]
fn pt_nee_misses_point_light_caustics_sppm_does_not() {
    let Some(gpu) = common::gpu() else { return };
    let direct = 0.5 / std::f64::consts::PI * 10.0;
    let mirrored = direct * std::f64::consts::FRAC_1_SQRT_2 / 2.0;
    let sppm = region_mean(&render(&gpu, &mirror_scene(Method::Sppm)), 15, 17, 15, 17);
    let nee = region_mean(&render(&gpu, &mirror_scene(Method::PtNee)), 15, 17, 15, 17);
    assert!((nee / direct - 1.0).abs() < 0.03, "pt-nee {nee}, direct light alone {direct}");
    assert!((sppm / (direct + mirrored) - 1.0).abs() < 0.05, "sppm {sppm}, direct plus mirrored {}", direct + mirrored);
    // The user is told.
    let warnings = limitations(&mirror_scene(Method::PtNee));
    assert!(warnings.iter().any(|w| w.contains("caustics")), "{warnings:?}");
    assert!(limitations(&mirror_scene(Method::Sppm)).is_empty());
}

#[test]
fn naive_pt_with_point_lights_warns() {
    let warnings = limitations(&mirror_scene(Method::Pt));
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("spot or directional light"), "{warnings:?}");
    // Without lights outside the surfaces there is nothing to warn about.
    let scene = common::load_scene("cornell-box.toml");
    for method in [Method::Pt, Method::PtNee, Method::Sppm] {
        let mut s = scene.clone();
        s.render.method = method;
        assert!(limitations(&s).is_empty(), "{method:?}: {:?}", limitations(&s));
    }
}

/// A floor split by a thin wall (two faces 0.01 apart) with a point light on the -x side and
/// the camera on the +x side, which no light reaches. The camera sees the wall's dark face
/// and the dark floor beside it.
fn thin_wall_scene(radius: f32, iterations: u32) -> Scene {
    SceneBuilder::new(48, 48)
        .iterations(iterations)
        .photons(100_000)
        .radius(radius)
        .camera([2.0, 1.0, 0.0], [0.0, 0.4, 0.0], [0.0, 1.0, 0.0], 50.0)
        .diffuse("white", [0.8, 0.8, 0.8])
        .quad([-2.0, 0.0, 2.0], [4.0, 0.0, 0.0], [0.0, 0.0, -4.0], "white")
        // Lit face, facing -x, and dark face, facing +x.
        .quad([-0.005, 0.0, -3.0], [0.0, 3.0, 0.0], [0.0, 0.0, 6.0], "white")
        .quad([0.005, 0.0, -3.0], [0.0, 0.0, 6.0], [0.0, 3.0, 0.0], "white")
        .point_light([-1.0, 1.0, 0.0], [5.0, 5.0, 5.0])
        .build()
        .unwrap()
}

/// With a radius of 0.3, thirty times the wall's thickness: visible points on the wall's dark
/// face lie within the radius of photons on its lit face, but those photons arrive from
/// behind the point's surface and are rejected, so the face stays exactly black (except
/// within a radius of the floor, whose photons come from the front). Points on the dark
/// floor beside the wall gather photons from the lit floor, which faces the same way: that
/// leak is there, and it shrinks as the radii shrink with the passes.
#[test]
fn large_radius_leaks_only_along_the_floor_and_less_with_passes() {
    let Some(gpu) = common::gpu() else { return };
    let scene = thin_wall_scene(0.3, 64);
    let mut sppm = Sppm::new(&gpu.device, &gpu.queue, &scene).unwrap();
    let mut leak_at = Vec::new();
    let mut wall_at = Vec::new();
    for pass in 1..=scene.render.iterations {
        sppm.run_pass().unwrap();
        if pass == 4 || pass == 64 {
            // Pixels by what their visible point of this pass lies on: the dark face, or
            // the dark floor within the radius of the wall.
            let points = sppm.visible_point_positions().unwrap();
            let img = sppm.image().unwrap();
            let (mut wall, mut leak) = ((0.0, 0), (0.0, 0));
            for (q, p) in points.iter().zip(&img.pixels) {
                let v = Vec3::new(q[0], q[1], q[2]);
                // Above the radius: the face's foot also gathers floor photons (below).
                if (v.x - 0.005).abs() < 1e-4 && v.y > 0.35 {
                    wall = (wall.0 + p[0] as f64, wall.1 + 1);
                } else if v.y.abs() < 1e-4 && v.x > 0.005 && v.x < 0.25 {
                    leak = (leak.0 + p[0] as f64, leak.1 + 1);
                }
            }
            assert!(wall.1 > 100 && leak.1 > 20, "pixels on the wall {} and by its foot {}", wall.1, leak.1);
            wall_at.push(wall.0 / wall.1 as f64);
            leak_at.push(leak.0 / leak.1 as f64);
        }
    }
    assert!(wall_at.iter().all(|&w| w == 0.0), "light through the wall: {wall_at:?}");
    // The scene's diagonal is 7.8: a radius of 0.3 is under the 5% the warning starts at,
    // 0.5 over it.
    assert!(limitations(&scene).is_empty(), "{:?}", limitations(&scene));
    let warned = limitations(&thin_wall_scene(0.5, 1));
    assert!(warned.len() == 1 && warned[0].contains("thin walls"), "{warned:?}");
    assert!(leak_at[0] > 1e-3, "no leak along the floor at pass 4: {leak_at:?}");
    assert!(leak_at[1] < 0.7 * leak_at[0], "the leak does not shrink with the radius: {leak_at:?}");
}

/// A radius a tenth of the automatic one: the furnace is still 2.0 on average (the estimate
/// is consistent at any radius), but each pixel is far noisier than with the automatic one.
#[test]
fn tiny_radius_is_noisy_but_unbiased() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("furnace.toml");
    scene.render.width = 32;
    scene.render.height = 32;
    scene.render.iterations = 64;
    scene.render.photons = 50_000;
    let auto = sppm_gpu::integrators::sppm::auto_radius(&scene);
    let spread = |img: &Rgb32Image| img.pixels.iter().map(|p| (p[0] as f64 - 2.0).powi(2)).sum::<f64>() / img.pixels.len() as f64;
    let normal = render(&gpu, &scene);
    scene.render.radius = Some(0.1 * auto);
    let tiny = render(&gpu, &scene);
    let mean = tiny.mean()[0];
    assert!((mean - 2.0).abs() < 0.04, "tiny radius: mean {mean}");
    assert!(spread(&tiny) > 4.0 * spread(&normal), "variance {} (tiny) vs {} (automatic)", spread(&tiny), spread(&normal));
}
