//! One-sided materials (Mitsuba 3's rule: a BSDF not wrapped in `twosided` is zero for
//! cos_theta <= 0 in the shading frame, for the direction back along the arriving ray and for
//! the scattered or light direction; dielectrics are two-sided by nature). Every scene here
//! is built twice, with its material one-sided and two-sided, and rendered by SPPM, PT-NEE
//! and, where it can see the light, naive PT: light that has to leave or arrive at the back
//! of a one-sided surface is absent, exactly, and present when the surface is two-sided; a
//! one-sided surface seen from the front renders the same bits as a two-sided one. The kernels
//! are compiled with the check only for scenes that have a one-sided material.
//!
//! A scene's two-sided render carries an unused one-sided material ([`with_the_check`]), so
//! that it runs the same kernels as the one-sided render, compiled with the check: the two
//! differ only in the material's flag, and each geometry's kernels are compiled once rather
//! than twice (a cold driver cache compiles the three tracing kernels of every distinct
//! scene anew: seconds each on lavapipe). Kernels compiled without the check are what every
//! shipped scene runs, and `one_sided_quad_seen_from_the_front_is_unchanged` compares them.

use crate::common;

use glam::Vec3;
use sppm_gpu::gpu::scene_buffers::SceneData;
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators;
use sppm_gpu::layout::Features;
use sppm_gpu::metrics::{count_negative, count_non_finite};
use sppm_gpu::scene::{DirectLight, MaterialKind, Method, Scene, SceneBuilder};

const SIZE: u32 = 32;
const METHODS: [Method; 3] = [Method::Sppm, Method::PtNee, Method::Pt];

/// `passes` passes of `method` over `scene`.
fn render(scene: &Scene, method: Method, passes: u32) -> Rgb32Image {
    let gpu = common::gpu().expect("checked by the caller");
    let mut scene = scene.clone();
    scene.render.method = method;
    let mut integrator = integrators::create(&gpu.device, &gpu.queue, &scene).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..passes {
        integrator.run_pass().unwrap();
    }
    let img = integrator.image().unwrap();
    assert_eq!(count_non_finite(&img), 0, "NaN or infinite pixels");
    assert_eq!(count_negative(&img), 0, "negative pixels");
    gpu.check().unwrap();
    img
}

fn mean(img: &Rgb32Image) -> f64 {
    img.mean().iter().sum::<f64>() / 3.0
}

fn is_black(img: &Rgb32Image) -> bool {
    img.pixels.iter().all(|p| *p == [0.0; 3])
}

fn bits(img: &Rgb32Image) -> Vec<[u32; 3]> {
    img.pixels.iter().map(|p| p.map(f32::to_bits)).collect()
}

/// `scene` with material `name` one-sided.
fn one_sided(mut scene: Scene, name: &str) -> Scene {
    let m = scene.materials.iter_mut().find(|m| m.name == name).unwrap_or_else(|| panic!("no material {name}"));
    m.one_sided = true;
    scene
}

/// The name of the unused one-sided material of [`with_the_check`].
const SPARE: &str = "spare one-sided";

/// `scene` with an unused material (no shape has it) that is one-sided: its kernels are
/// compiled with the one-sided check whether or not its own materials are one-sided, and its
/// image is the same.
fn with_the_check(mut scene: Scene) -> Scene {
    let mut spare = scene.materials[0].clone();
    spare.name = SPARE.into();
    spare.kind = MaterialKind::Diffuse { albedo: Vec3::splat(0.5), texture: None };
    spare.one_sided = true;
    scene.materials.push(spare);
    assert!(Features::of(&SceneData::new(&scene).unwrap()).one_sided, "the spare material switches the check on");
    assert!(scene.shapes.iter().all(|s| scene.materials[s.material as usize].name != SPARE), "no shape has the spare");
    scene
}

/// Common settings: a small image, a fixed radius, photons enough to light it.
fn settings(builder: SceneBuilder) -> SceneBuilder {
    builder.photons(20_000).radius(0.05).max_depth(8).seed(7)
}

/// A diffuse quad ("receiver", [-2, 2]^2 in the plane z = 0) under a camera at z = 0.8 looking
/// straight down, lit by a quad light at z = 1.2 above the camera that emits downwards, whose
/// own material ("black") is black. The receiver's front (its winding's normal) faces the
/// camera and the light when `facing_up`, and the other way when not; nothing lies below it,
/// so no ray reaches its lower side.
fn quad_under_a_light(facing_up: bool) -> Scene {
    receiver_under_the_camera(facing_up)
        // Its front faces -z: Y x X.
        .quad([-1.0, -1.0, 1.2], 2.0 * Vec3::Y, 2.0 * Vec3::X, "black")
        .emission([4.0, 4.0, 4.0])
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// [`quad_under_a_light`] without its light.
fn receiver_under_the_camera(facing_up: bool) -> SceneBuilder {
    let (u, v) = if facing_up { (Vec3::X, Vec3::Y) } else { (Vec3::Y, Vec3::X) };
    settings(SceneBuilder::new(SIZE, SIZE))
        .camera([0.0, 0.0, 0.8], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 60.0)
        .diffuse("receiver", [0.7, 0.7, 0.7])
        .diffuse("black", [0.0, 0.0, 0.0])
        .quad([-2.0, -2.0, 0.0], 4.0 * u, 4.0 * v, "receiver")
}

/// Seen from behind, a one-sided diffuse surface is black in every method (no visible point,
/// no next-event estimate, no bounce), while a two-sided one lit from the same side is not.
#[test]
fn one_sided_quad_seen_from_behind_is_black() {
    if common::gpu().is_none() {
        return;
    }
    let scene = with_the_check(quad_under_a_light(false));
    for method in METHODS {
        let two = render(&scene, method, 4);
        let one = render(&one_sided(scene.clone(), "receiver"), method, 4);
        eprintln!("{method:?}: two-sided mean {}, one-sided mean {}", mean(&two), mean(&one));
        assert!(mean(&two) > 0.05, "{method:?}: the two-sided back is dark: {}", mean(&two));
        assert!(is_black(&one), "{method:?}: the one-sided back shows light: mean {}", mean(&one));
    }
}

/// Seen from the front, one-sided and two-sided give the same image bit for bit: every ray in
/// this scene meets the receiver from its front, where the one-sided checks (cos_theta_o <= 0,
/// and cos_theta_i <= 0 for light and BSDF samples) reject only what the side tests against
/// the geometric normal, equal to the shading normal here, already reject. The light's own
/// material is one-sided in both renders (it too is met only from its front), so both run the
/// same kernels, compiled with the check. Against kernels compiled without it (everything
/// two-sided) the arithmetic is the same but the compiler's code is not, so that image only has
/// to agree within noise.
#[test]
fn one_sided_quad_seen_from_the_front_is_unchanged() {
    if common::gpu().is_none() {
        return;
    }
    let plain = quad_under_a_light(true);
    let two = one_sided(plain.clone(), "black");
    let one = one_sided(two.clone(), "receiver");
    assert!(!Features::of(&SceneData::new(&plain).unwrap()).one_sided);
    assert!(Features::of(&SceneData::new(&two).unwrap()).one_sided);
    for method in METHODS {
        let a = render(&two, method, 4);
        let b = render(&one, method, 4);
        let c = render(&plain, method, 4);
        eprintln!(
            "{method:?}: mean {} (one-sided {}, without the check {}, bit for bit with it: {})",
            mean(&a),
            mean(&b),
            mean(&c),
            bits(&a) == bits(&c)
        );
        assert!(mean(&a) > 0.05, "{method:?}: the receiver is dark: {}", mean(&a));
        assert!(bits(&a) == bits(&b), "{method:?}: one-sided and two-sided differ seen from the front");
        assert!((mean(&c) / mean(&a) - 1.0).abs() < 0.02, "{method:?}: kernels without the check: {} vs {}", mean(&c), mean(&a));
    }
}

/// A floor ([-2, 2]^2 at z = 0, facing up, two-sided) under a camera at z = 0.8 looking
/// down, and a light beside the camera at z = 1 that emits only upwards, so that its black back
/// hides it from the floor. Above them at z = 2, a reflector ("reflector") faces away from the
/// floor: light reaches the floor only by reflecting off the reflector's back.
fn floor_under_a_reflector(reflector: SceneBuilder) -> Scene {
    settings(reflector)
        .camera([0.0, 0.0, 0.8], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 60.0)
        .diffuse("floor", [0.7, 0.7, 0.7])
        .diffuse("black", [0.0, 0.0, 0.0])
        .quad([-2.0, -2.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], "floor")
        // Front +z, towards the reflector.
        .quad([1.0, -0.25, 1.0], [0.5, 0.0, 0.0], [0.0, 0.5, 0.0], "black")
        .emission([40.0, 40.0, 40.0])
        // Front +z, away from the floor.
        .quad([-3.0, -3.0, 2.0], [6.0, 0.0, 0.0], [0.0, 6.0, 0.0], "reflector")
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Light reflected by the back of a one-sided reflector, diffuse, mirror or glossy, reaches neither
/// photons (SPPM, where the floor is lit only by photons that bounced off it) nor paths (PT-NEE
/// and PT: a path from the floor ends at the reflector's back); with a two-sided reflector it
/// lights the floor in every method. Each scene also holds unused materials of the other two
/// kinds (and [`with_the_check`]'s), so that the three scenes, of the same geometry, share
/// their kernels: one compile of each for the test's 18 renders of a method, not six.
#[test]
fn light_off_the_back_of_a_one_sided_reflector_is_absent() {
    if common::gpu().is_none() {
        return;
    }
    let spares = |b: SceneBuilder| {
        b.diffuse("spare diffuse", [0.8, 0.8, 0.8]).mirror("spare mirror", [0.9, 0.9, 0.9]).glossy(
            "spare glossy",
            [0.9, 0.9, 0.9],
            0.3,
        )
    };
    let reflectors = [
        ("diffuse", spares(SceneBuilder::new(SIZE, SIZE)).diffuse("reflector", [0.8, 0.8, 0.8])),
        ("mirror", spares(SceneBuilder::new(SIZE, SIZE)).mirror("reflector", [0.9, 0.9, 0.9])),
        ("glossy", spares(SceneBuilder::new(SIZE, SIZE)).glossy("reflector", [0.9, 0.9, 0.9], 0.3)),
    ];
    let features: Vec<Features> = reflectors
        .iter()
        .map(|(_, b)| Features::of(&SceneData::new(&with_the_check(floor_under_a_reflector(b.clone()))).unwrap()))
        .collect();
    assert!(features.iter().all(|f| *f == features[0]), "the three scenes' features differ: {features:?}");
    for (kind, builder) in reflectors {
        let scene = with_the_check(floor_under_a_reflector(builder));
        for method in METHODS {
            let two = render(&scene, method, 8);
            let one = render(&one_sided(scene.clone(), "reflector"), method, 8);
            eprintln!("{kind} {method:?}: two-sided mean {}, one-sided mean {}", mean(&two), mean(&one));
            assert!(mean(&two) > 0.01, "{kind} {method:?}: no light off the two-sided reflector: {}", mean(&two));
            assert!(is_black(&one), "{kind} {method:?}: light off the back of the one-sided reflector: {}", mean(&one));
        }
    }
}

/// A floor ([-1, 1]^2 at z = 0, albedo 0.7) whose geometric normal is +z and whose shading
/// normal, on the same side, leans towards +x: ns = normalize(1, 0, 0.5). Seen or lit from
/// the +x side a direction is in front of ns, from the far -x side behind it, on either side of
/// the floor's plane; so these scenes separate each one-sided check from the side tests the
/// kernels make against the geometric normal. With [`with_the_check`]'s spare material.
fn tilted_floor(builder: SceneBuilder) -> Scene {
    let mut scene = with_the_check(
        settings(builder)
            .diffuse("floor", [0.7, 0.7, 0.7])
            .diffuse("black", [0.0, 0.0, 0.0])
            .quad([-1.0, -1.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], "floor")
            .build()
            .unwrap_or_else(|e| panic!("{e}")),
    );
    let ns = Vec3::new(1.0, 0.0, 0.5).normalize();
    let floor = scene.shapes.iter().position(|s| scene.materials[s.material as usize].name == "floor").unwrap() as u32;
    for t in scene.triangles.iter_mut().filter(|t| t.shape == floor) {
        t.n = Some([ns; 3]);
    }
    scene
}

/// `scene` rendered two-sided and with `material` one-sided by each of `methods` (with
/// SPPM's direct light from `direct`): light must show in the first, none in the second.
fn black_only_when_one_sided(what: &str, scene: &Scene, material: &str, methods: &[(Method, DirectLight)], passes: u32) {
    for &(method, direct) in methods {
        let mut scene = scene.clone();
        scene.render.direct = direct;
        let two = render(&scene, method, passes);
        let one = render(&one_sided(scene, material), method, passes);
        eprintln!("{what}, {method:?} {direct:?}: two-sided mean {}, one-sided mean {}", mean(&two), mean(&one));
        assert!(mean(&two) > 0.01, "{what}, {method:?} {direct:?}: dark when two-sided: {}", mean(&two));
        assert!(is_black(&one), "{what}, {method:?} {direct:?}: light when one-sided: {}", mean(&one));
    }
}

const SAMPLED: DirectLight = DirectLight::Sampled;

/// Seen from behind its shading normal but in front of its geometric normal (camera at -x,
/// above), a one-sided floor is black, though the light above it (at +x, in front of both
/// normals) lights every direction a camera path could scatter to: the camera paths' own
/// check (cos_theta_o <= 0) ends them, in SPPM (no visible point, no next-event estimate)
/// and in both path tracers.
#[test]
fn seen_from_behind_the_shading_normal_is_black() {
    if common::gpu().is_none() {
        return;
    }
    let scene = tilted_floor(
        SceneBuilder::new(SIZE, SIZE)
            .camera([-3.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 30.0)
            // Front -z, towards the floor; out of the camera's view.
            .quad([1.5, -0.5, 3.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], "black")
            .emission([20.0, 20.0, 20.0]),
    );
    let methods =
        [(Method::Sppm, SAMPLED), (Method::Sppm, DirectLight::Photons), (Method::PtNee, SAMPLED), (Method::Pt, SAMPLED)];
    black_only_when_one_sided("seen from behind ns", &scene, "floor", &methods, 4);
}

/// Seen from in front of its shading normal (camera at +x, above), a one-sided floor gets
/// nothing from a point light at -x, behind ns though in front of the geometric normal: not
/// by next-event estimation (cos_theta_i <= 0 for the light's direction: SPPM's camera pass
/// and PT-NEE), and not from photons (SPPM with photons carrying direct light, which arrive
/// from behind ns and deposit nothing).
#[test]
fn light_from_behind_the_shading_normal_is_absent() {
    if common::gpu().is_none() {
        return;
    }
    let scene = tilted_floor(
        SceneBuilder::new(SIZE, SIZE)
            .camera([2.0, 0.0, 2.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 50.0)
            .point_light([-3.0, 0.0, 1.0], [30.0, 30.0, 30.0]),
    );
    let methods = [(Method::Sppm, SAMPLED), (Method::Sppm, DirectLight::Photons), (Method::PtNee, SAMPLED)];
    black_only_when_one_sided("light behind ns", &scene, "floor", &methods, 4);
}

/// Seen from below the floor's plane but in front of its shading normal (camera at +x,
/// below), a one-sided floor scatters nothing towards an area light below it at -x, behind ns:
/// the cosine-sampled direction about the side the path arrived on lies behind ns and is
/// refused (cos_theta_i <= 0 for a BSDF sample: naive PT, PT-NEE's and SPPM's BSDF side of
/// MIS), and so is the light's direction in next-event estimation.
#[test]
fn scattering_behind_the_shading_normal_is_absent() {
    if common::gpu().is_none() {
        return;
    }
    let scene = tilted_floor(
        SceneBuilder::new(SIZE, SIZE)
            .camera([3.0, 0.0, -1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 30.0)
            // Front +x, towards the floor; out of the camera's view.
            .quad([-3.0, -0.5, -2.5], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], "black")
            .emission([20.0, 20.0, 20.0]),
    );
    let methods = [(Method::Sppm, SAMPLED), (Method::PtNee, SAMPLED), (Method::Pt, SAMPLED)];
    black_only_when_one_sided("scattered behind ns", &scene, "floor", &methods, 8);
}

/// Lit from below the floor's plane but in front of its shading normal (an area light at +x,
/// below, facing up), a one-sided floor sends no photon on behind ns: photons arriving there
/// scatter about the side they came from, behind ns, and are refused (cos_theta_i <= 0 for a
/// photon's BSDF sample). A screen below the floor at -x, under the light's plane so that only
/// such photons reach it, is what the camera sees: black in SPPM, as in PT-NEE, whose paths
/// from the screen meet the floor from behind ns (naive PT cannot find the light from there:
/// the floor scatters it away from the light).
#[test]
fn photons_scatter_nothing_behind_the_shading_normal() {
    if common::gpu().is_none() {
        return;
    }
    let scene = tilted_floor(
        SceneBuilder::new(SIZE, SIZE)
            .camera([0.0, 0.0, -2.75], [-3.0, 0.0, -2.75], [0.0, 0.0, 1.0], 30.0)
            .diffuse("screen", [0.7, 0.7, 0.7])
            // Front +x, towards the camera.
            .quad([-3.0, -2.0, -4.0], [0.0, 4.0, 0.0], [0.0, 0.0, 2.5], "screen")
            // Front +z, towards the floor; behind the camera.
            .quad([1.75, -0.25, -1.0], [0.5, 0.0, 0.0], [0.0, 0.5, 0.0], "black")
            .emission([400.0, 400.0, 400.0]),
    );
    let methods = [(Method::Sppm, SAMPLED), (Method::PtNee, SAMPLED)];
    black_only_when_one_sided("photons scattered behind ns", &scene, "floor", &methods, 8);
}

/// `Features::of` switches the check on exactly when some non-dielectric material is
/// one-sided, and the GPU materials carry the flag (never for a dielectric, which ignores it);
/// every scene shipped in TOML is two-sided, so its kernels are compiled without the check.
#[test]
fn the_one_sided_feature_follows_the_materials() {
    let scene = SceneBuilder::new(8, 8)
        .camera([0.0, 0.0, 3.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 40.0)
        .diffuse("matte", [0.5, 0.5, 0.5])
        .dielectric("glass", 1.5, 0.0)
        .glossy("metal", [0.9, 0.9, 0.9], 0.2)
        .quad([-1.0, -1.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], "matte")
        .sphere([0.0, 0.0, 0.5], 0.3, "glass")
        .sphere([0.5, 0.0, 0.5], 0.1, "metal")
        .emission([1.0, 1.0, 1.0])
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let flags = |scene: &Scene| {
        let data = SceneData::new(scene).unwrap();
        (Features::of(&data).one_sided, data.materials.iter().map(|m| m.one_sided).collect::<Vec<_>>())
    };
    assert_eq!(flags(&scene), (false, vec![0, 0, 0]));
    assert_eq!(flags(&one_sided(scene.clone(), "matte")), (true, vec![1, 0, 0]));
    assert_eq!(flags(&one_sided(scene.clone(), "metal")), (true, vec![0, 0, 1]));
    assert_eq!(flags(&one_sided(scene.clone(), "glass")), (false, vec![0, 0, 0]));
    let constant = |scene: &Scene| {
        let constants = Features::of(&SceneData::new(scene).unwrap()).constants();
        constants.iter().find(|(name, _)| *name == "USES_ONE_SIDED").expect("USES_ONE_SIDED").1
    };
    assert_eq!(constant(&scene), 0.0);
    assert_eq!(constant(&one_sided(scene.clone(), "matte")), 1.0);
    let mut names: Vec<_> = std::fs::read_dir(common::scene_path(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 8, "{names:?}");
    for name in names {
        let scene = common::load_scene(&name);
        assert!(scene.materials.iter().all(|m| !m.one_sided), "{name}");
        assert!(!Features::of(&SceneData::new(&scene).unwrap()).one_sided, "{name}");
    }
}

/// The receiver of [`quad_under_a_light`] facing up, lit by its light and by a second, smaller
/// one-sided light beside it (so that each light's share of the power, by which the lights are
/// chosen, counts); the first light faces down, or up with its emission leaving both sides.
fn receiver_under_two_lights(two_sided_facing_up: bool) -> Scene {
    let b = receiver_under_the_camera(true);
    let b = if two_sided_facing_up {
        b.quad([-1.0, -1.0, 1.2], 2.0 * Vec3::X, 2.0 * Vec3::Y, "black").emission([4.0, 4.0, 4.0]).emission_two_sided()
    } else {
        b.quad([-1.0, -1.0, 1.2], 2.0 * Vec3::Y, 2.0 * Vec3::X, "black").emission([4.0, 4.0, 4.0])
    };
    b.quad([1.2, 0.5, 1.0], 0.5 * Vec3::Y, 0.5 * Vec3::X, "black")
        .emission([8.0, 8.0, 8.0])
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A light whose emission leaves both sides (pbrt-v4's `twosided`), turned away from the
/// receiver, lights it as the same light facing it: by every method, in the mean over the
/// image (the camera sees neither light). Its power, and so its share of the lights' choice,
/// doubles; where its density or its photons' weight missed the second side by a factor of 2
/// the image would be off by a fifth or more.
#[test]
fn two_sided_light_turned_away_lights_as_facing() {
    if common::gpu().is_none() {
        return;
    }
    let (facing, turned) = (receiver_under_two_lights(false), receiver_under_two_lights(true));
    for (method, passes) in
        [(Method::Sppm, 16), (Method::PtNee, 64), (Method::Pt, 256), (Method::Lt, 256), (Method::Bpt, 16), (Method::Vcm, 16)]
    {
        let (a, b) = (mean(&render(&facing, method, passes)), mean(&render(&turned, method, passes)));
        eprintln!("{method:?}: facing {a:.5}, turned away and two-sided {b:.5}, ratio {:.4}", b / a);
        assert!(a > 0.0 && (b / a - 1.0).abs() < 0.02, "{method:?}: {b} against {a}");
    }
}
