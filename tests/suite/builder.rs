//! `SceneBuilder`: a Cornell box built in code is the loaded `scenes/cornell-box.toml`,
//! primitive for primitive, and every mistake is an `Err` naming the key.

use glam::Vec3;
use sppm_gpu::scene::{self, LightKind, MaterialKind, Method, Scene, SceneBuilder, SceneError, ShapeKind};
use std::path::Path;

fn scene_path(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name)
}

/// `scenes/cornell-box.toml`, call for call.
fn cornell_box() -> SceneBuilder {
    SceneBuilder::new(256, 256)
        .iterations(64)
        .photons(200_000)
        .alpha(0.6667)
        .max_depth(64)
        .seed(0)
        .camera([0.0, 1.0, 3.9], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0], 39.3)
        .diffuse("white", [0.725, 0.71, 0.68])
        .diffuse("red", [0.63, 0.065, 0.05])
        .diffuse("green", [0.14, 0.45, 0.091])
        .diffuse("black", [0.0, 0.0, 0.0])
        .quad([-1.0, 0.0, 1.0], [2.0, 0.0, 0.0], [0.0, 0.0, -2.0], "white")
        .quad([-1.0, 2.0, -1.0], [2.0, 0.0, 0.0], [0.0, 0.0, 2.0], "white")
        .quad([-1.0, 0.0, -1.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], "white")
        .quad([-1.0, 0.0, 1.0], [0.0, 0.0, -2.0], [0.0, 2.0, 0.0], "red")
        .quad([1.0, 0.0, -1.0], [0.0, 0.0, 2.0], [0.0, 2.0, 0.0], "green")
        .quad([-0.25, 1.98, -0.25], [0.5, 0.0, 0.0], [0.0, 0.0, 0.5], "black")
        .emission([17.0, 12.0, 4.0])
        .cube([0.3, 0.6, 0.3], [0.0, 20.0, 0.0], [-0.35, 0.6, -0.3], "white")
        .cube([0.3, 0.3, 0.3], [0.0, -17.0, 0.0], [0.35, 0.3, 0.35], "white")
}

/// Everything but the file name and the lines, which only a file has.
fn assert_same_scene(built: &Scene, loaded: &Scene) {
    assert_eq!(built.render, loaded.render);
    assert_eq!(built.camera, loaded.camera);
    let materials = |s: &Scene| s.materials.iter().map(|m| (m.name.clone(), m.kind.clone())).collect::<Vec<_>>();
    assert_eq!(materials(built), materials(loaded));
    let shapes = |s: &Scene| s.shapes.iter().map(|x| (x.kind, x.material, x.emission, x.velocity)).collect::<Vec<_>>();
    assert_eq!(shapes(built), shapes(loaded));
    assert_eq!(built.triangles.len(), loaded.triangles.len());
    for (i, (a, b)) in built.triangles.iter().zip(&loaded.triangles).enumerate() {
        assert_eq!(a, b, "triangle {i}");
    }
    assert_eq!(built.spheres, loaded.spheres);
    assert_eq!(built.textures, loaded.textures);
    let lights = |s: &Scene| s.lights.iter().map(|l| l.kind.clone()).collect::<Vec<_>>();
    assert_eq!(lights(built), lights(loaded));
}

#[test]
fn cornell_box_equals_the_loaded_file() {
    let built = cornell_box().build().unwrap_or_else(|e| panic!("{e}"));
    let loaded = scene::load(&scene_path("cornell-box.toml")).unwrap_or_else(|e| panic!("{e}"));
    assert_same_scene(&built, &loaded);
    // 6 quads of 2 triangles, 2 cubes of 12.
    assert_eq!(built.triangles.len(), 6 * 2 + 2 * 12);
    assert_eq!(built.shapes[5].emission, Some(Vec3::new(17.0, 12.0, 4.0)));
}

#[test]
fn materials_may_follow_the_shapes_that_use_them() {
    let b = SceneBuilder::new(8, 8)
        .camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0)
        .quad([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "light")
        .emission([1.0; 3])
        .sphere([0.0, 0.0, -1.0], 0.5, "white")
        .diffuse("white", [0.5; 3])
        .diffuse("light", [0.0; 3]);
    let s = b.build().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.shapes[0].material, 1);
    assert_eq!(s.shapes[1].material, 0);
    assert_eq!(s.spheres.len(), 1);
    assert_eq!(s.spheres[0].shape, 1);
}

/// Every kind of shape, material and light, against the same scene as a file.
#[test]
fn every_feature_equals_its_file() {
    let toml = r#"
[render]
width = 32
height = 24
method = "pt-nee"
iterations = 3
spp = 2
photons = 5000
radius = 0.05
alpha = 0.5
max_depth = 7
seed = 9
time_limit = 2.5

[camera]
position = [0, 1, 4]
look_at = [0, 1, 0]
up = [0, 1, 0]
fov = 45
aperture_radius = 0.1
focus_distance = 3.5

[materials]
matte = { type = "diffuse", albedo = [0.5, 0.5, 0.5] }
chrome = { type = "mirror", albedo = [0.9, 0.9, 0.9] }
brushed = { type = "glossy", albedo = [0.8, 0.6, 0.2], roughness = 0.3 }
glass = { type = "dielectric", ior = 1.5, roughness = 0.1 }
checker = { type = "diffuse", texture = "textures/checker.png" }

[[shapes]]
type = "quad"
corner = [-1, 0, 1]
u = [2, 0, 0]
v = [0, 0, -2]
uv_scale = [4, 4]
material = "checker"

[[shapes]]
type = "sphere"
center = [0.5, 0.4, 0]
radius = 0.4
material = "glass"
velocity = [0.1, 0, 0]

[[shapes]]
type = "cube"
scale = 0.2
rotate = [10, 20, 30]
translate = [-0.5, 0.2, 0]
material = "brushed"
emission = [1, 2, 3]

[[shapes]]
type = "mesh"
file = "gallery/meshes/bunny.obj"
smooth = true
scale = [2, 2, 2]
rotate = [0, 90, 0]
translate = [0, 0.5, -0.5]
material = "chrome"

[[lights]]
type = "point"
position = [0, 1.9, 0]
intensity = [5, 5, 5]

[[lights]]
type = "directional"
direction = [1, -2, 0]
irradiance = [0.5, 0.5, 0.5]
"#;
    let dir = scene_path("");
    let file = dir.join("builder-test.toml");
    let loaded = scene::load_str(toml, &file).unwrap_or_else(|e| panic!("{e}"));

    let built = SceneBuilder::new(32, 24)
        .path(&file)
        .method(Method::PtNee)
        .iterations(3)
        .spp(2)
        .photons(5000)
        .radius(0.05)
        .alpha(0.5)
        .max_depth(7)
        .seed(9)
        .time_limit(2.5)
        .thin_lens(0.1, 3.5)
        .camera([0.0, 1.0, 4.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0], 45.0)
        .diffuse("matte", [0.5; 3])
        .mirror("chrome", [0.9; 3])
        .glossy("brushed", [0.8, 0.6, 0.2], 0.3)
        .dielectric("glass", 1.5, 0.1)
        .textured("checker", "textures/checker.png")
        .quad([-1.0, 0.0, 1.0], [2.0, 0.0, 0.0], [0.0, 0.0, -2.0], "checker")
        .uv_scale([4.0, 4.0])
        .sphere([0.5, 0.4, 0.0], 0.4, "glass")
        .velocity([0.1, 0.0, 0.0])
        .cube(Vec3::splat(0.2), [10.0, 20.0, 30.0], [-0.5, 0.2, 0.0], "brushed")
        .emission([1.0, 2.0, 3.0])
        .mesh("gallery/meshes/bunny.obj", [2.0; 3], [0.0, 90.0, 0.0], [0.0, 0.5, -0.5], "chrome")
        .smooth(true)
        .point_light([0.0, 1.9, 0.0], [5.0; 3])
        .directional_light([1.0, -2.0, 0.0], [0.5; 3])
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    // The loader records the line of `aperture_radius`; a built camera has none.
    let mut camera = loaded.camera.clone();
    camera.aperture_line = None;
    assert_eq!(built.camera, camera);
    let loaded = Scene { camera, ..loaded };
    assert_same_scene(&built, &loaded);
    assert_eq!(built.path, file);
    let kinds: Vec<ShapeKind> = built.shapes.iter().map(|s| s.kind).collect();
    assert_eq!(&kinds[..3], &[ShapeKind::Quad, ShapeKind::Sphere, ShapeKind::Cube]);
    match built.lights[1].kind {
        LightKind::Directional { direction, .. } => assert!((direction.length() - 1.0).abs() < 1e-6),
        _ => panic!("second light is directional"),
    }
}

/// A valid two-quad scene to break one piece at a time.
fn base() -> SceneBuilder {
    SceneBuilder::new(8, 8)
        .camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0)
        .diffuse("white", [0.5; 3])
        .quad([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "white")
        .emission([1.0; 3])
}

fn err(b: SceneBuilder) -> SceneError {
    match b.build() {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

/// The error's key and a piece of its message; its display names the key too.
fn assert_err(b: SceneBuilder, key: &str, message: &str) {
    let e = err(b);
    assert_eq!(e.key.as_deref(), Some(key), "{e}");
    assert!(e.message.contains(message), "{e}: expected {message:?}");
    assert!(e.to_string().contains(&format!("key `{key}`")), "{e}");
}

#[test]
fn the_base_scene_builds() {
    let s = base().build().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.triangles.len(), 2);
    assert_eq!(s.path, Path::new("<scene builder>"));
    assert_eq!(s.camera.focus_distance, 5.0);
    assert_eq!(s.render.method, Method::Sppm);
    assert_eq!(s.render.photons, 100_000);
    assert_eq!(s.render.radius, None);
}

#[test]
fn render_settings_out_of_range() {
    assert_err(base().size(0, 8), "render.width", "between 1 and 16384, found 0");
    assert_err(base().size(8, 16385), "render.height", "between 1 and 16384");
    assert_err(base().iterations(0), "render.iterations", "between 1");
    assert_err(base().spp(0), "render.spp", "between 1");
    assert_err(base().photons(0), "render.photons", "between 1");
    assert_err(base().max_depth(0), "render.max_depth", "between 1");
    assert_err(base().direct_samples(0), "render.direct_samples", "between 1 and 1024, found 0");
    assert_err(base().direct_samples(1025), "render.direct_samples", "between 1 and 1024, found 1025");
    assert_err(base().radius(0.0), "render.radius", "greater than 0");
    assert_err(base().radius(f32::NAN), "render.radius", "finite");
    assert_err(base().alpha(1.0), "render.alpha", "less than 1");
    assert_err(base().alpha(0.0), "render.alpha", "greater than 0");
    assert_err(base().time_limit(-1.0), "render.time_limit", "greater than 0");
    assert_err(base().time_limit(f64::INFINITY), "render.time_limit", "finite");
}

#[test]
fn camera_errors() {
    let no_camera = SceneBuilder::new(8, 8)
        .diffuse("white", [0.5; 3])
        .quad([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "white")
        .emission([1.0; 3]);
    assert_err(no_camera, "camera", "no camera");
    assert_err(base().camera([0.0; 3], [0.0; 3], [0.0, 1.0, 0.0], 40.0), "camera", "no view direction");
    assert_err(base().camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 0.0, 1.0], 40.0), "camera", "parallel");
    assert_err(base().camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 180.0), "camera", "fov");
    assert_err(base().camera([0.0, 0.0, f32::NAN], [0.0; 3], [0.0, 1.0, 0.0], 40.0), "camera", "finite");
    assert_err(base().thin_lens(-0.1, 1.0), "camera", "aperture_radius");
    assert_err(base().thin_lens(0.1, 0.0), "camera", "focus_distance");
}

#[test]
fn material_errors() {
    assert_err(base().diffuse("white", [0.1; 3]), "materials.white", "defined twice");
    assert_err(base().diffuse("", [0.1; 3]), "materials.", "needs a name");
    assert_err(base().diffuse("x", [1.5, 0.0, 0.0]), "materials.x.albedo", "between 0 and 1, found 1.5");
    assert_err(base().mirror("x", [0.5, f32::NAN, 0.5]), "materials.x.albedo", "finite");
    assert_err(base().glossy("x", [0.5; 3], 2.0), "materials.x.roughness", "between 0 and 1");
    assert_err(base().dielectric("x", 0.0, 0.0), "materials.x.ior", "greater than 0");
    assert_err(base().dielectric("x", 1.5, -0.5), "materials.x.roughness", "between 0 and 1");
    assert_err(
        base().material("x", MaterialKind::Diffuse { albedo: Vec3::ONE, texture: Some(0) }),
        "materials.x.texture",
        "SceneBuilder::textured",
    );
    assert_err(base().textured("x", "/no/such/texture.png"), "materials.x.texture", "cannot read texture /no/such/texture.png");
}

#[test]
fn shape_errors() {
    assert_err(base().sphere([0.0; 3], 1.0, "chalk"), "shapes[1].material", "unknown material `chalk`; defined materials: white");
    assert_err(base().quad([0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], "white"), "shapes[1].v", "no area");
    assert_err(base().quad([0.0, f32::INFINITY, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "white"), "shapes[1].corner", "finite");
    assert_err(base().uv_scale([f32::NAN, 1.0]), "shapes[0].uv_scale", "finite");
    assert_err(base().sphere([0.0; 3], 0.0, "white"), "shapes[1].radius", "greater than 0");
    assert_err(base().sphere([0.0; 3], -1.0, "white"), "shapes[1].radius", "greater than 0");
    assert_err(base().cube([1.0, 0.0, 1.0], [0.0; 3], [0.0; 3], "white"), "shapes[1].scale", "nonzero");
    assert_err(base().cube([1.0; 3], [f32::NAN; 3], [0.0; 3], "white"), "shapes[1].rotate", "finite");
    assert_err(base().emission([-1.0, 0.0, 0.0]), "shapes[0].emission", "at least 0");
    assert_err(base().velocity([f32::NAN; 3]), "shapes[0].velocity", "finite");
    assert_err(
        base().mesh("/no/such/mesh.obj", [1.0; 3], [0.0; 3], [0.0; 3], "white"),
        "shapes[1].file",
        "cannot read mesh /no/such/mesh.obj",
    );
}

#[test]
fn modifiers_need_a_shape_of_their_kind() {
    let empty = SceneBuilder::new(8, 8).camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0);
    assert_err(empty.clone().emission([1.0; 3]), "shapes[0].emission", "before any shape");
    assert_err(empty.velocity([1.0; 3]), "shapes[0].velocity", "before any shape");
    assert_err(
        base().sphere([0.0; 3], 1.0, "white").uv_scale([2.0, 2.0]),
        "shapes[1].uv_scale",
        "applies to a quad shape, not a sphere",
    );
    assert_err(base().smooth(true), "shapes[0].smooth", "applies to a mesh shape, not a quad");
}

#[test]
fn light_errors() {
    assert_err(base().point_light([0.0; 3], [-1.0, 0.0, 0.0]), "lights[0].intensity", "at least 0");
    assert_err(base().point_light([f32::NAN; 3], [1.0; 3]), "lights[0].position", "finite");
    assert_err(base().directional_light([0.0; 3], [1.0; 3]), "lights[0].direction", "must not be zero");
    assert_err(base().directional_light([0.0, -1.0, 0.0], [1.0, -1.0, 1.0]), "lights[0].irradiance", "at least 0");
}

#[test]
fn a_scene_without_light_is_an_error() {
    let dark = SceneBuilder::new(8, 8).camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0).diffuse("white", [0.5; 3]).quad(
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        "white",
    );
    // Where a light goes, or the first emission or light given, all zero.
    assert_err(dark.clone(), "lights", "no light");
    assert_err(dark.clone().emission([0.0; 3]), "shapes[0].emission", "no light");
    assert_err(dark.clone().directional_light([0.0, -1.0, 0.0], [0.0; 3]), "lights[0].irradiance", "no light");
    assert!(dark.clone().point_light([0.0, 1.0, 0.0], [1.0; 3]).build().is_ok());
    assert!(dark.directional_light([0.0, -1.0, 0.0], [1.0; 3]).build().is_ok());
}

#[test]
fn the_first_error_is_reported_and_the_builder_is_reusable() {
    // Render settings are checked before materials and shapes.
    assert_err(base().size(0, 8).diffuse("white", [2.0; 3]), "render.width", "found 0");
    let b = base();
    assert!(b.build().is_ok());
    assert!(b.build().is_ok(), "build takes &self");
}
