//! Scene loading: the canonical scenes, the geometry each shape turns into, and one error
//! (with its exact line and key) for each way a scene can be wrong.

use crate::common;
use crate::common::scene_text::{edit, with_light, with_shape, BASE, QUAD};
use glam::{Vec2, Vec3};
use sppm_gpu::scene::{self, LightKind, MaterialKind, Method, Microfacet, Scene, SceneError, ShapeKind};
use std::path::Path;

const SCENES: [&str; 7] =
    ["cornell-box", "cornell-glossy", "cornell-spheres", "depth-of-field", "furnace", "point-light", "textured"];

fn canonical(name: &str) -> Scene {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes")).join(format!("{name}.toml"));
    scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn load(text: &str) -> Result<Scene, SceneError> {
    scene::load_str(text, Path::new("test.toml"))
}

fn load_ok(text: &str) -> Scene {
    load(text).unwrap_or_else(|e| panic!("{e}"))
}

/// The error of loading `text`, which must fail.
#[track_caller]
fn error_of(text: &str) -> SceneError {
    match load(text) {
        Ok(_) => panic!("loaded without error:\n{text}"),
        Err(error) => error,
    }
}

/// Loading `text` fails at `line` about `key`, with a message holding each of `words`.
#[track_caller]
fn assert_error(text: &str, line: usize, key: &str, words: &[&str]) {
    let error = error_of(text);
    assert_eq!((error.line, error.key.as_deref()), (Some(line), Some(key)), "wrong place: {error}");
    assert_message(&error, words);
}

#[track_caller]
fn assert_message(error: &SceneError, words: &[&str]) {
    assert_eq!(error.file, Path::new("test.toml"));
    for word in words {
        assert!(error.message.contains(word), "{word:?} is not in the message of: {error}");
    }
}

/// Loads `text` as `dir/scene.toml`, so that its file names resolve against `dir`.
fn load_in(dir: &Path, text: &str) -> Result<Scene, SceneError> {
    scene::load_str(text, &dir.join("scene.toml"))
}

fn geometric_normal(p: [Vec3; 3]) -> Vec3 {
    (p[1] - p[0]).cross(p[2] - p[0]).normalize()
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!(a.abs_diff_eq(b, 1e-5), "{a} != {b}");
}

// --- The canonical scenes ---

#[test]
fn every_canonical_scene_loads() {
    for name in SCENES {
        let scene = canonical(name);
        assert!(!scene.shapes.is_empty(), "{name}");
        assert!(scene.triangles.iter().all(|t| (t.shape as usize) < scene.shapes.len()));
        assert!(scene.spheres.iter().all(|s| (s.shape as usize) < scene.shapes.len()));
    }
}

#[test]
fn cornell_box_geometry_and_settings() {
    let scene = canonical("cornell-box");
    assert_eq!(scene.triangles.len(), 5 * 2 + 2 + 12 * 2);
    assert_eq!(scene.spheres.len(), 0);
    assert_eq!(scene.shapes.len(), 8);
    assert_eq!(scene.shapes[5].emission, Some(Vec3::new(17.0, 12.0, 4.0)));
    assert_eq!(scene.shapes[5].line, 61);
    assert_eq!(scene.shapes[6].kind, ShapeKind::Cube);
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["white", "red", "green", "black"], "file order");
    assert_eq!(scene.materials[1].line, 20);
    assert_eq!(scene.shape_material(3).name, "red");
    let r = &scene.render;
    assert_eq!((r.width, r.height, r.iterations, r.photons, r.spp), (256, 256, 64, 200_000, 1));
    assert_eq!((r.method, r.radius, r.time_limit), (Method::Sppm, None, None));
    assert!((scene.camera.focus_distance - 3.9).abs() < 1e-6, "defaults to |look_at - position|");
    assert_eq!(scene.camera.aperture_line, None);
}

#[test]
fn depth_of_field_camera() {
    let camera = canonical("depth-of-field").camera;
    assert_eq!((camera.aperture_radius, camera.focus_distance), (0.06, 3.6));
    assert_eq!(camera.aperture_line, Some(17));
}

#[test]
fn point_light_scene() {
    let scene = canonical("point-light");
    let expected = LightKind::Point { position: Vec3::new(0.0, 1.7, 0.2), intensity: Vec3::new(6.0, 5.0, 4.0) };
    assert_eq!(scene.lights.len(), 1);
    assert_eq!((&scene.lights[0].kind, scene.lights[0].line), (&expected, 74));
}

#[test]
fn textured_scene_decodes_its_texture() {
    let scene = canonical("textured");
    assert_eq!(scene.textures.len(), 1, "one path, one texture");
    let texture = &scene.textures[0];
    assert_eq!(texture.texels.len(), (texture.width * texture.height) as usize);
    assert!(texture.texels.iter().all(|t| t.cmpge(Vec3::ZERO).all() && t.cmple(Vec3::ONE).all()));
    let checker = scene.materials.iter().position(|m| m.name == "checker").unwrap();
    assert_eq!(scene.materials[checker].kind, MaterialKind::Diffuse { albedo: Vec3::ONE, texture: Some(0) });
    let floor = &scene.triangles[0];
    assert_eq!(floor.uv, Some([Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(2.0, 2.0)]));
}

/// An 8-bit texture is stored palette-coded (4 bytes a texel rather than 16: Bitterli's
/// staircase's nine images did not fit lavapipe's 128 MiB binding as floats), and decoding the
/// palette as the kernels do gives back the very floats; a texture of more distinct values
/// stays floats.
#[test]
fn textures_are_palette_coded_without_loss() {
    use sppm_gpu::gpu::scene_buffers::{palette_coded, SceneData};
    use sppm_gpu::layout::{PALETTE_ENTRIES, TEXTURE_PALETTE};
    let scene = canonical("textured");
    let texels = &scene.textures[0].texels;
    let coded = palette_coded(texels).expect("an 8-bit image has at most 256 channel values");
    let palette = (PALETTE_ENTRIES / 4) as usize;
    assert_eq!(coded.len(), palette + texels.len().div_ceil(4));
    let value = |code: u32| coded[code as usize / 4][code as usize % 4];
    for (i, t) in texels.iter().enumerate() {
        let word = coded[palette + i / 4][i % 4].to_bits();
        let decoded = Vec3::new(value(word & 0xff), value(word >> 8 & 0xff), value(word >> 16 & 0xff));
        assert_eq!(decoded.to_array().map(f32::to_bits), t.to_array().map(f32::to_bits), "texel {i}");
    }
    // Stored so only where the images pass PALETTE_ABOVE_BYTES as floats (or where told):
    // the header's flags (second header texel's w) say so.
    let flags = |scene: &Scene| SceneData::new(scene).unwrap().texels[1][3].to_bits();
    assert_eq!(flags(&scene) & TEXTURE_PALETTE, 0);
    let mut told = scene.clone();
    told.render.texture_palettes = true;
    assert_ne!(flags(&told) & TEXTURE_PALETTE, 0);
    // 257 distinct values: floats.
    let ramp: Vec<Vec3> = (0..257).map(|i| Vec3::splat(i as f32 / 256.0)).collect();
    assert!(palette_coded(&ramp).is_none());
    assert!(palette_coded(&ramp[..256]).is_some());
    // An image of 86 texels or fewer takes no more room as floats than with a palette:
    // floats (memory's estimate, 16 bytes a texel, stays an upper bound).
    assert!(palette_coded(&ramp[..86]).is_none());
    assert!(palette_coded(&ramp[..87]).is_some());
    // The table's mark for an empty slot, a NaN, is not taken for a value found there: floats.
    let mut marked = ramp[..200].to_vec();
    marked[150].y = f32::from_bits(0x7fff_ffff);
    assert!(palette_coded(&marked).is_none());
}

// --- Defaults and values ---

#[test]
fn defaults_apply() {
    let scene = load_ok(BASE);
    let r = &scene.render;
    assert_eq!((r.method, r.spp, r.photons, r.alpha, r.max_depth, r.seed), (Method::Sppm, 1, 100_000, 0.6667, 64, 0));
    assert_eq!((r.direct, r.direct_samples), (sppm_gpu::scene::DirectLight::Sampled, None));
    assert_eq!((r.radius, r.time_limit), (None, None));
    let c = &scene.camera;
    assert_eq!((c.up, c.fov, c.aperture_radius, c.focus_distance), (Vec3::Y, 40.0, 0.0, 5.0));
    assert!(scene.shapes.is_empty() && scene.lights.is_empty());
}

#[test]
fn every_render_key_is_read() {
    let text = edit(
        "iterations = 1",
        "iterations = 3\nmethod = \"pt-nee\"\nspp = 2\nphotons = 0x10\nradius = 1\nalpha = 0.5\nmax_depth = 7\nseed = 1_000\ntime_limit = 2.5",
    );
    let r = load_ok(&text).render;
    assert_eq!((r.iterations, r.method, r.spp, r.photons, r.radius), (3, Method::PtNee, 2, 16, Some(1.0)));
    assert_eq!((r.alpha, r.max_depth, r.seed, r.time_limit), (0.5, 7, 1000, Some(2.5)));
}

#[test]
fn materials_of_every_type() {
    let text = format!(
        "{BASE}{}",
        r#"gold = { type = "glossy", albedo = [1.0, 0.78, 0.34], roughness = 0.2 }
glass = { type = "dielectric", ior = 1.5 }
ice = { type = "dielectric", ior = 1.31, roughness = 0.15 }
chrome = { type = "mirror", albedo = [0.9, 0.9, 0.9] }
"#
    );
    let scene = load_ok(&text);
    let kinds: Vec<&MaterialKind> = scene.materials.iter().map(|m| &m.kind).collect();
    assert_eq!(
        kinds[1],
        &MaterialKind::Conductor {
            albedo: Vec3::new(1.0, 0.78, 0.34),
            texture: None,
            roughness: 0.2,
            distribution: Microfacet::Ggx,
            fresnel: None
        }
    );
    let (reflectance, transmittance) = (Vec3::ONE, Vec3::ONE);
    let ggx = Microfacet::Ggx;
    assert_eq!(kinds[2], &MaterialKind::Dielectric { ior: 1.5, roughness: 0.0, distribution: ggx, reflectance, transmittance });
    assert_eq!(kinds[3], &MaterialKind::Dielectric { ior: 1.31, roughness: 0.15, distribution: ggx, reflectance, transmittance });
    assert_eq!(
        kinds[4],
        &MaterialKind::Conductor {
            albedo: Vec3::splat(0.9),
            texture: None,
            roughness: 0.0,
            distribution: Microfacet::Ggx,
            fresnel: None
        }
    );
    assert_eq!(scene.materials[4].line, 16);
}

#[test]
fn emission_velocity_and_spheres() {
    let text = with_shape(
        "type = \"sphere\"\ncenter = [1, 2, 3]\nradius = 0.5\nmaterial = \"white\"\nemission = [1, 2, 3]\nvelocity = [0.3, 0, 0]\n",
    );
    let scene = load_ok(&text);
    let shape = &scene.shapes[0];
    assert_eq!((shape.kind, shape.line, shape.material), (ShapeKind::Sphere, 13, 0));
    assert_eq!(shape.emission, Some(Vec3::new(1.0, 2.0, 3.0)));
    assert_eq!((shape.velocity, shape.velocity_line), (Some(Vec3::new(0.3, 0.0, 0.0)), Some(19)));
    assert_eq!(scene.spheres.len(), 1);
    assert_eq!((scene.spheres[0].center, scene.spheres[0].radius, scene.spheres[0].shape), (Vec3::new(1.0, 2.0, 3.0), 0.5, 0));
}

#[test]
fn directional_light_is_normalized() {
    let scene = load_ok(&with_light("type = \"directional\"\ndirection = [0, -2, 0]\nirradiance = [3, 3, 3]\n"));
    let expected = LightKind::Directional { direction: Vec3::NEG_Y, irradiance: Vec3::splat(3.0) };
    assert_eq!((&scene.lights[0].kind, scene.lights[0].line), (&expected, 13));
}

// --- Geometry ---

#[test]
fn quad_normal_follows_cross_u_v() {
    let text = with_shape(&QUAD.replace("v = [0, 1, 0]", "v = [0, 0, -2]\nuv_scale = [2, 3]"));
    let scene = load_ok(&text);
    assert_eq!(scene.triangles.len(), 2);
    let (u, v) = (Vec3::X, Vec3::new(0.0, 0.0, -2.0));
    for t in &scene.triangles {
        assert_close(geometric_normal(t.p), u.cross(v).normalize());
        assert_eq!((t.n, t.shape), (None, 0));
    }
    let [a, b] = [&scene.triangles[0], &scene.triangles[1]];
    assert_eq!(a.p, [Vec3::ZERO, u, u + v]);
    assert_eq!(b.p, [Vec3::ZERO, u + v, v]);
    assert_eq!(a.uv, Some([Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(2.0, 3.0)]));
    assert_eq!(b.uv, Some([Vec2::ZERO, Vec2::new(2.0, 3.0), Vec2::new(0.0, 3.0)]));
}

/// The triangles of one cube with the given transform keys.
fn cube(transform: &str) -> Vec<scene::Triangle> {
    let scene = load_ok(&with_shape(&format!("type = \"cube\"\nmaterial = \"white\"\n{transform}")));
    assert_eq!(scene.triangles.len(), 12);
    assert!(scene.triangles.iter().all(|t| t.n.is_none() && t.uv.is_none()));
    scene.triangles
}

#[test]
fn cube_normals_point_outward() {
    for transform in [
        "",
        "scale = [0.3, 0.6, 0.3]\nrotate = [10, 20, 30]\ntranslate = [-0.35, 0.6, -0.3]",
        "scale = [-1, 2, 0.5]\ntranslate = [-0.35, 0.6, -0.3]",
        "scale = -2\nrotate = [0, 45, 0]\ntranslate = [-0.35, 0.6, -0.3]",
    ] {
        let center = if transform.is_empty() { Vec3::ZERO } else { Vec3::new(-0.35, 0.6, -0.3) };
        for t in cube(transform) {
            let centroid = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
            assert!(geometric_normal(t.p).dot(centroid - center) > 0.0, "inward face with {transform:?}");
        }
    }
}

/// Half the size of the bounding box of some triangles.
fn half_extent(triangles: &[scene::Triangle]) -> Vec3 {
    let points = triangles.iter().flat_map(|t| t.p);
    let (low, high) = points.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), p| (l.min(p), h.max(p)));
    (high - low) / 2.0
}

#[test]
fn rotation_is_about_x_then_y_then_z() {
    // (1, 2, 4) about x by 90 is (1, -4, 2), then about y by 90 is (2, -4, -1);
    // in the other order it would end as (4, 1, 2).
    let extent = half_extent(&cube("scale = [1, 2, 4]\nrotate = [90, 90, 0]"));
    assert!(extent.abs_diff_eq(Vec3::new(2.0, 4.0, 1.0), 1e-5), "{extent}");
    // (1, 2, 4) about y by 90 is (4, 2, -1), then about z by 90 is (-2, 4, -1).
    let extent = half_extent(&cube("scale = [1, 2, 4]\nrotate = [0, 90, 90]"));
    assert!(extent.abs_diff_eq(Vec3::new(2.0, 4.0, 1.0), 1e-5), "{extent}");
    // Translation comes last, rotation before it: the centre stays at `translate`.
    let triangles = cube("rotate = [30, 40, 50]\ntranslate = [5, 6, 7]");
    let sum: Vec3 = triangles.iter().flat_map(|t| t.p).sum();
    assert_close(sum / 36.0, Vec3::new(5.0, 6.0, 7.0));
}

/// Writes `obj` to `dir/mesh.obj` and loads one mesh shape with `keys` that uses it.
fn load_mesh(dir: &Path, obj: &str, keys: &str) -> Result<Scene, SceneError> {
    std::fs::write(dir.join("mesh.obj"), obj).unwrap();
    load_in(dir, &with_shape(&format!("type = \"mesh\"\nfile = \"mesh.obj\"\nmaterial = \"white\"\n{keys}")))
}

/// Two triangles folded along the y axis: one facing +z (area 1/2), one facing +x (area 1).
const FOLD: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 2\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";

#[test]
fn mesh_smooth_normals_are_area_weighted_averages() {
    let dir = common::scratch("scene-load-smooth");
    let scene = load_mesh(&dir, FOLD, "smooth = true\nscale = 2\ntranslate = [1, 0, 0]").unwrap();
    assert_eq!(scene.triangles.len(), 2);
    let [a, b] = [&scene.triangles[0], &scene.triangles[1]];
    assert_eq!(a.p, [Vec3::new(1.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0)]);
    let shared = Vec3::new(2.0, 0.0, 1.0).normalize();
    let [n0, n1, n2] = a.n.expect("smooth normals");
    assert_close(n0, shared);
    assert_close(n1, Vec3::Z);
    assert_close(n2, shared);
    assert_close(b.n.unwrap()[2], Vec3::X);
    assert_eq!(a.uv, Some([Vec2::ZERO, Vec2::X, Vec2::Y]));

    let flat = load_mesh(&dir, FOLD, "").unwrap();
    assert!(flat.triangles.iter().all(|t| t.n.is_none()));
}

#[test]
fn mesh_file_normals_use_the_inverse_transpose() {
    let dir = common::scratch("scene-load-file-normals");
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 1\nf 1//1 2//1 3//1\n";
    let scene = load_mesh(&dir, obj, "smooth = true\nscale = [1, 1, 2]").unwrap();
    for n in scene.triangles[0].n.unwrap() {
        assert_close(n, Vec3::new(2.0, 0.0, 1.0).normalize());
    }
    assert_eq!(scene.triangles[0].uv, None);
}

#[test]
fn mirrored_mesh_keeps_its_front_side() {
    let dir = common::scratch("scene-load-mirrored");
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let scene = load_mesh(&dir, obj, "scale = [-1, 1, 1]").unwrap();
    // Mirrored in x, the triangle still faces +z (the front side is kept, not turned around).
    assert_close(geometric_normal(scene.triangles[0].p), Vec3::Z);
}

#[test]
fn degenerate_mesh_triangles_are_skipped() {
    let dir = common::scratch("scene-load-degenerate");
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n";
    let scene = load_mesh(&dir, obj, "").unwrap();
    assert_eq!(scene.triangles.len(), 1);
    assert_eq!(scene.triangles[0].p[2], Vec3::Y);
}

// --- Errors ---

#[test]
fn malformed_toml_is_an_error() {
    // The key is the one assigned on the error's line, or the one whose array is still open.
    for (text, line, key, words) in [
        (edit("height = 8", "height = = 8"), 3, "render.height", "extra `=`"),
        (edit("fov = 40", "fov = 40 40"), 9, "camera.fov", "quoted"),
        // Arrays may span lines: an unclosed one is found where the next table starts.
        (edit("fov = 40", "fov = [1, 2"), 11, "camera.fov", "expected `,`"),
        (edit("fov = 40", "fov = 40\nfov = 41"), 10, "camera.fov", "duplicate key"),
    ] {
        let error = error_of(&text);
        assert_eq!((error.line, error.key.as_deref()), (Some(line), Some(key)), "{error}");
        assert_message(&error, &[words]);
        assert!(error.to_string().starts_with(&format!("test.toml:{line}: key `{key}`: ")), "{error}");
    }
}

#[test]
fn unknown_keys_are_errors() {
    assert_error(
        &edit("height = 8", "height = 8\nsamples = 4"),
        4,
        "render.samples",
        &["unknown key `samples`", "spp", "photons"],
    );
    assert_error(&format!("{BASE}[output]\nfile = \"x\"\n"), 13, "output", &["render", "camera"]);
    assert_error(&edit("fov = 40", "fov = 40\nzoom = 2"), 10, "camera.zoom", &["look_at"]);
    assert_error(&edit("0.5] }", "0.5], colour = 1 }"), 12, "materials.white.colour", &["albedo", "texture"]);
    assert_error(&with_shape(&format!("{QUAD}radius = 1\n")), 19, "shapes[0].radius", &["corner", "uv_scale"]);
    assert_error(
        &with_shape("type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"white\"\nuv_scale = [1, 1]\n"),
        18,
        "shapes[0].uv_scale",
        &["radius"],
    );
    assert_error(
        &with_light("type = \"point\"\nposition = [0, 0, 0]\nintensity = [1, 1, 1]\nradius = 1\n"),
        17,
        "lights[0].radius",
        &["intensity"],
    );
}

#[test]
fn wrong_types_are_errors() {
    assert_error(&edit("width = 8", "width = \"8\""), 2, "render.width", &["expected an integer, found a string"]);
    assert_error(&edit("width = 8", "width = 256.5"), 2, "render.width", &["expected an integer, found the float 256.5"]);
    assert_error(&edit("fov = 40", "fov = \"40\""), 9, "camera.fov", &["expected a number, found a string"]);
    assert_error(
        &edit("look_at = [0, 0, 0]", "look_at = [0, 0]"),
        8,
        "camera.look_at",
        &["expected an array of 3 numbers, found 2 items"],
    );
    assert_error(
        &edit("look_at = [0, 0, 0]", "look_at = [0,\n  \"0\", 0]"),
        9,
        "camera.look_at",
        &["expected a number, found a string"],
    );
    assert_error(
        &edit("look_at = [0, 0, 0]", "look_at = 0"),
        8,
        "camera.look_at",
        &["expected an array of 3 numbers, found an integer"],
    );
    let camera_on = &BASE[BASE.find("[camera]").unwrap()..];
    assert_error(&format!("render = 1\n{camera_on}"), 1, "render", &["expected a table, found an integer"]);
    assert_error(&edit("white = {", "white = 3 #"), 12, "materials.white", &["expected a table"]);
    assert_error(&with_shape(&QUAD.replace("\"white\"", "1")), 18, "shapes[0].material", &["expected a string"]);
    assert_error(&format!("shapes = 1\n{BASE}"), 1, "shapes", &["expected an array"]);
    assert_error(
        &with_shape("type = \"mesh\"\nfile = \"m.obj\"\nmaterial = \"white\"\nsmooth = 1\n"),
        17,
        "shapes[0].smooth",
        &["expected a boolean"],
    );
}

#[test]
fn missing_required_keys_are_errors() {
    assert_error(&edit("iterations = 1\n", ""), 1, "render.iterations", &["missing required key `iterations`"]);
    assert_error(&edit("width = 8\n", ""), 1, "render.width", &["missing"]);
    assert_error(&edit("fov = 40\n", ""), 6, "camera.fov", &["missing"]);
    assert_error(&edit("position = [0, 0, 5]\n", ""), 6, "camera.position", &["missing"]);
    assert_error(&with_shape(&QUAD.replace("material = \"white\"\n", "")), 13, "shapes[0].material", &["missing"]);
    assert_error(&with_shape(&QUAD.replace("u = [1, 0, 0]\n", "")), 13, "shapes[0].u", &["missing"]);
    assert_error(&with_shape("material = \"white\"\n"), 13, "shapes[0].type", &["missing"]);
    assert_error(&with_light("type = \"point\"\nposition = [0, 0, 0]\n"), 13, "lights[0].intensity", &["missing"]);
    assert_error(
        &edit("white = { type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }", "white = { type = \"diffuse\" }"),
        12,
        "materials.white.albedo",
        &["texture"],
    );
    assert_error(
        &edit(
            "white = { type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }",
            "white = { type = \"glossy\", albedo = [0.5, 0.5, 0.5] }",
        ),
        12,
        "materials.white.roughness",
        &["missing"],
    );
    let no_render = BASE.replace("[render]\nwidth = 8\nheight = 8\niterations = 1\n", "");
    let error = error_of(&no_render);
    assert_eq!((error.line, error.key.as_deref()), (None, Some("render")), "{error}");
    assert_message(&error, &["missing required key `render`"]);
}

#[test]
fn unknown_names_are_errors() {
    assert_error(
        &with_shape(&QUAD.replace("\"white\"", "\"whyte\"")),
        18,
        "shapes[0].material",
        &["unknown material `whyte`", "white"],
    );
    assert_error(
        &with_shape(&QUAD.replace("\"quad\"", "\"cone\"")),
        14,
        "shapes[0].type",
        &["unknown shape type `cone`", "quad, sphere, cube, mesh"],
    );
    assert_error(
        &with_light("type = \"area\"\n"),
        14,
        "lights[0].type",
        &["unknown light type `area`", "point, directional, spot"],
    );
    assert_error(
        &edit("\"diffuse\"", "\"lambert\""),
        12,
        "materials.white.type",
        &["unknown material type `lambert`", "dielectric"],
    );
    assert_error(
        &edit("width = 8", "width = 8\nmethod = \"bdpt\""),
        3,
        "render.method",
        &["unknown method `bdpt`", "sppm, pt, pt-nee"],
    );
    let no_materials = BASE.replace("[materials]\nwhite = { type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }\n", "");
    assert_error(&format!("{no_materials}[[shapes]]\n{QUAD}"), 16, "shapes[0].material", &["no materials"]);
}

#[test]
fn non_finite_numbers_are_errors() {
    assert_error(&edit("fov = 40", "fov = nan"), 9, "camera.fov", &["must be a finite number, found nan"]);
    assert_error(&edit("fov = 40", "fov = inf"), 9, "camera.fov", &["finite"]);
    assert_error(&edit("position = [0, 0, 5]", "position = [0, -inf, 5]"), 7, "camera.position", &["finite"]);
    assert_error(&edit("iterations = 1", "iterations = 1\nalpha = -nan"), 5, "render.alpha", &["finite"]);
    assert_error(&edit("iterations = 1", "iterations = 1\ntime_limit = inf"), 5, "render.time_limit", &["finite"]);
    assert_error(&with_shape(&format!("{QUAD}emission = [1, inf, 1]\n")), 19, "shapes[0].emission", &["finite"]);
    assert_error(&with_shape(&format!("{QUAD}velocity = [nan, 0, 0]\n")), 19, "shapes[0].velocity", &["finite"]);
    assert_error(&edit("position = [0, 0, 5]", "position = [0, 1e39, 5]"), 7, "camera.position", &["1e39 is out of the range"]);
    assert_error(&edit("iterations = 1", "iterations = 1\nradius = 1e-50"), 5, "render.radius", &["out of the range"]);
}

#[test]
fn render_values_out_of_range_are_errors() {
    for (old, new, key, words) in [
        ("width = 8", "width = 0", "render.width", "between 1 and 16384, found 0"),
        ("width = 8", "width = 16385", "render.width", "between 1 and 16384"),
        ("height = 8", "height = -3", "render.height", "between 1 and 16384"),
        ("iterations = 1", "iterations = 0", "render.iterations", "between 1 and 4294967295"),
    ] {
        let line = BASE.lines().position(|l| l == old).unwrap() + 1;
        assert_error(&edit(old, new), line, key, &[words]);
    }
    for (new, key, words) in [
        ("spp = 0", "render.spp", "between 1 and 4294967295, found 0"),
        ("photons = 0", "render.photons", "between 1 and"),
        ("photons = 5000000000", "render.photons", "found 5000000000"),
        ("radius = 0.0", "render.radius", "greater than 0"),
        ("alpha = 1.0", "render.alpha", "greater than 0 and less than 1"),
        ("alpha = 0", "render.alpha", "less than 1"),
        ("max_depth = 0", "render.max_depth", "between 1 and"),
        ("seed = -1", "render.seed", "between 0 and 4294967295"),
        ("time_limit = 0", "render.time_limit", "greater than 0"),
    ] {
        assert_error(&edit("iterations = 1", &format!("iterations = 1\n{new}")), 5, key, &[words]);
    }
}

#[test]
fn camera_errors() {
    assert_error(&edit("fov = 40", "fov = 180"), 9, "camera.fov", &["less than 180"]);
    assert_error(&edit("fov = 40", "fov = 0"), 9, "camera.fov", &["greater than 0"]);
    assert_error(&edit("fov = 40", "fov = 40\naperture_radius = -0.1"), 10, "camera.aperture_radius", &["at least 0"]);
    assert_error(&edit("fov = 40", "fov = 40\nfocus_distance = 0"), 10, "camera.focus_distance", &["greater than 0"]);
    assert_error(&edit("look_at = [0, 0, 0]", "look_at = [0, 0, 5]"), 8, "camera.look_at", &["position"]);
    assert_error(&edit("fov = 40", "fov = 40\nup = [0, 0, -2]"), 10, "camera.up", &["parallel"]);
    // `up` left at [0, 1, 0] while looking straight down: the error is at the header.
    assert_error(&edit("look_at = [0, 0, 0]", "look_at = [0, -1, 5]"), 6, "camera.up", &["parallel"]);
    let camera = load_ok(&edit("fov = 40", "fov = 40\naperture_radius = 0.1")).camera;
    assert_eq!((camera.aperture_radius, camera.aperture_line), (0.1, Some(10)));
}

#[test]
fn material_values_out_of_range_are_errors() {
    let material = |m: &str| format!("{BASE}m = {m}\n");
    assert_error(
        &material("{ type = \"diffuse\", albedo = [0.5, 1.5, 0.5] }"),
        13,
        "materials.m.albedo",
        &["between 0 and 1, found 1.5"],
    );
    assert_error(
        &material("{ type = \"mirror\", albedo = [-0.1, 0.5, 0.5] }"),
        13,
        "materials.m.albedo",
        &["between 0 and 1, found -0.1"],
    );
    assert_error(
        &material("{ type = \"glossy\", albedo = [1, 1, 1], roughness = 1.5 }"),
        13,
        "materials.m.roughness",
        &["between 0 and 1"],
    );
    assert_error(&material("{ type = \"dielectric\", ior = 0 }"), 13, "materials.m.ior", &["greater than 0"]);
    assert_error(
        &material("{ type = \"dielectric\", ior = 1.5, roughness = -1 }"),
        13,
        "materials.m.roughness",
        &["between 0 and 1"],
    );
    assert_error(
        &material("{ type = \"diffuse\", albedo = [1, 1, 1], texture = \"t.png\" }"),
        13,
        "materials.m.texture",
        &["not both"],
    );
    // An ior of 1 is allowed.
    load_ok(&material("{ type = \"dielectric\", ior = 1 }"));
}

#[test]
fn shape_values_out_of_range_are_errors() {
    let sphere = "type = \"sphere\"\ncenter = [0, 0, 0]\nmaterial = \"white\"\n";
    assert_error(&with_shape(&format!("{sphere}radius = 0\n")), 17, "shapes[0].radius", &["greater than 0"]);
    assert_error(&with_shape(&format!("{QUAD}emission = [1, -1, 1]\n")), 19, "shapes[0].emission", &["at least 0"]);
    // Both sides of nothing: emission_two_sided needs an emission.
    assert_error(&with_shape(&format!("{QUAD}emission_two_sided = true\n")), 19, "shapes[0].emission_two_sided", &["emission"]);
    let two_sided = load_ok(&with_shape(&format!("{QUAD}emission = [1, 1, 1]\nemission_two_sided = true\n")));
    assert!(two_sided.shapes[0].emission_two_sided);
    assert_error(&with_shape(&QUAD.replace("v = [0, 1, 0]", "v = [2, 0, 0]")), 17, "shapes[0].v", &["no area"]);
    let cube = "type = \"cube\"\nmaterial = \"white\"\n";
    assert_error(&with_shape(&format!("{cube}scale = 0\n")), 16, "shapes[0].scale", &["nonzero"]);
    assert_error(&with_shape(&format!("{cube}scale = [1, 0.0, 1]\n")), 16, "shapes[0].scale", &["nonzero"]);
    assert_error(&with_shape(&format!("{cube}scale = [1, nan, 1]\n")), 16, "shapes[0].scale", &["finite"]);
    // The second shape is `shapes[1]`, its errors at its own lines.
    let two = format!("{}[[shapes]]\n{sphere}radius = -1\n", with_shape(QUAD));
    assert_error(&two, 23, "shapes[1].radius", &["greater than 0"]);
}

#[test]
fn light_values_out_of_range_are_errors() {
    assert_error(
        &with_light("type = \"point\"\nposition = [0, 0, 0]\nintensity = [1, -1, 1]\n"),
        16,
        "lights[0].intensity",
        &["at least 0"],
    );
    assert_error(
        &with_light("type = \"directional\"\ndirection = [0, -1, 0]\nirradiance = [-3, 3, 3]\n"),
        16,
        "lights[0].irradiance",
        &["at least 0"],
    );
    assert_error(
        &with_light("type = \"directional\"\ndirection = [0, 0, 0]\nirradiance = [3, 3, 3]\n"),
        15,
        "lights[0].direction",
        &["zero"],
    );
}

/// The error of a scene in `dir` that fails, checked for its place and for naming `file`.
#[track_caller]
fn assert_file_error(dir: &Path, text: &str, line: usize, key: &str, file: &str) {
    let error = load_in(dir, text).expect_err("an error");
    assert_eq!((error.line, error.key.as_deref()), (Some(line), Some(key)), "{error}");
    let path = dir.join(file).display().to_string();
    assert!(error.message.contains(&path), "{path} is not in: {error}");
}

#[test]
fn missing_and_corrupt_files_are_errors() {
    let dir = common::scratch("scene-load-files");
    let mesh = |file: &str| with_shape(&format!("type = \"mesh\"\nmaterial = \"white\"\nfile = \"{file}\"\n"));
    assert_file_error(&dir, &mesh("missing.obj"), 16, "shapes[0].file", "missing.obj");
    std::fs::write(dir.join("corrupt.obj"), "v 0 0 zero\nf 1 2 3\n").unwrap();
    assert_file_error(&dir, &mesh("corrupt.obj"), 16, "shapes[0].file", "corrupt.obj");
    std::fs::write(dir.join("out-of-range.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 9\n").unwrap();
    assert_file_error(&dir, &mesh("out-of-range.obj"), 16, "shapes[0].file", "out-of-range.obj");
    std::fs::write(dir.join("points.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    assert_file_error(&dir, &mesh("points.obj"), 16, "shapes[0].file", "points.obj");
    std::fs::write(dir.join("flat.obj"), "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    assert_file_error(&dir, &mesh("flat.obj"), 16, "shapes[0].file", "flat.obj");

    let texture = |file: &str| format!("{BASE}t = {{ type = \"diffuse\", texture = \"{file}\" }}\n");
    assert_file_error(&dir, &texture("missing.png"), 13, "materials.t.texture", "missing.png");
    std::fs::write(dir.join("corrupt.png"), b"\x89PNG\r\n\x1a\nthis is not a png").unwrap();
    assert_file_error(&dir, &texture("corrupt.png"), 13, "materials.t.texture", "corrupt.png");

    let missing_scene = dir.join("no-such-scene.toml");
    let error = scene::load(&missing_scene).expect_err("an error");
    assert_eq!(error.file, missing_scene);
}

#[test]
fn textures_decode_srgb_top_row_first_once_per_path() {
    let dir = common::scratch("scene-load-texture");
    // Two rows: black and white on top, mid grey and a colour below.
    let pixels = [0u8, 0, 0, 255, 255, 255, 128, 128, 128, 255, 128, 0];
    image::save_buffer(dir.join("t.png"), &pixels, 2, 2, image::ExtendedColorType::Rgb8).unwrap();
    let text = format!(
        "{BASE}a = {{ type = \"diffuse\", texture = \"t.png\" }}\nb = {{ type = \"diffuse\", texture = \"./t.png\" }}\nc = {{ type = \"diffuse\", texture = \"t.png\" }}\n"
    );
    let scene = load_in(&dir, &text).unwrap();
    let srgb = |c: f32| {
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let grey = srgb(128.0 / 255.0);
    let texture = &scene.textures[0];
    assert_eq!((texture.width, texture.height), (2, 2));
    assert_close(texture.texels[0], Vec3::ZERO);
    assert_close(texture.texels[1], Vec3::ONE);
    assert_close(texture.texels[2], Vec3::splat(grey));
    assert_close(texture.texels[3], Vec3::new(1.0, grey, 0.0));
    assert!((grey - 0.2158605).abs() < 1e-6);
    let indices: Vec<_> = scene.materials.iter().map(|m| m.kind.clone()).collect();
    assert_eq!(indices[1], MaterialKind::Diffuse { albedo: Vec3::ONE, texture: Some(0) });
    assert_eq!(indices[3], MaterialKind::Diffuse { albedo: Vec3::ONE, texture: Some(0) });
    assert_eq!(indices[2], MaterialKind::Diffuse { albedo: Vec3::ONE, texture: Some(0) });
    assert_eq!(scene.textures.len(), 1, "one path, one texture");
}

#[test]
fn odd_obj_files_do_not_panic() {
    let dir = common::scratch("scene-load-odd-obj");
    for obj in [
        "f 0 0 0\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -5 1 2\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/3/4 2 3\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2 3\n",
        "v 1e400 0 0\nv nan 0 0\nv 0 inf 0\nf 1 2 3\n",
        "v 0 0 0 1 1\nf\nvt\nvn\nmtllib missing.mtl\nusemtl nothing\n",
        "\u{0}\u{1}binary\n",
    ] {
        let _ = load_mesh(&dir, obj, "smooth = true");
    }
    std::fs::write(dir.join("bytes.obj"), [0xff, 0xfe, 0x00, 0x80]).unwrap();
    let text = with_shape("type = \"mesh\"\nfile = \"bytes.obj\"\nmaterial = \"white\"\n");
    assert!(load_in(&dir, &text).is_err());
}

#[test]
fn no_input_panics() {
    // Truncations of a full scene: each is an error or a scene, never a panic.
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell-box.toml")).unwrap();
    for end in (0..text.len()).step_by(7) {
        let _ = load(&text[..end]);
    }
    for odd in ["", "=", "[[render]]", "[render]\nwidth = 0x7fffffffffffffffff", "[camera]\nposition = [[1], {}, 1979-05-27]"] {
        assert!(load(odd).is_err(), "{odd:?}");
    }
}

/// Beyond v1, what a Mitsuba scene needs and `sppm-gpu convert` will write: `one_sided`
/// materials and the pixel filter.
/// SPPM's radius schedule where the scene gives none: the global one where its passes splat
/// through a tent or gaussian (one camera sample a pixel a pass, the plain radius rule), a
/// radius per point elsewhere; a schedule given by the file or an override stays, and the
/// overrides and the device's pass work settle it again.
#[test]
fn the_radius_schedule_follows_the_filter_where_none_is_given() {
    use sppm_gpu::scene::{Overrides, PassWork, RadiusRule, RadiusSchedule, SettingNames};
    let render = |extra: &str| load_ok(&edit("iterations = 1\n", &format!("iterations = 1\n{extra}\n"))).render;
    for (extra, schedule) in [
        ("", RadiusSchedule::PerPoint),
        ("filter = \"gaussian\"", RadiusSchedule::Global),
        ("filter = \"tent\"", RadiusSchedule::Global),
        // A tent no wider than the box splats nothing.
        ("filter = \"tent\"\nfilter_radius = 0.5", RadiusSchedule::PerPoint),
        ("filter = \"gaussian\"\nspp = 4", RadiusSchedule::PerPoint),
        ("filter = \"gaussian\"\nradius_rule = \"adaptive\"", RadiusSchedule::PerPoint),
        ("filter = \"gaussian\"\nradius_schedule = \"per-point\"", RadiusSchedule::PerPoint),
        ("radius_schedule = \"global\"", RadiusSchedule::Global),
    ] {
        assert_eq!(render(extra).radius_schedule, schedule, "{extra:?}");
    }
    let mut scene = load_ok(&edit("iterations = 1\n", "iterations = 1\nfilter = \"gaussian\"\n"));
    // An override of the rule, then of the camera samples, each settles it again.
    let overrides = Overrides { radius_rule: Some(RadiusRule::Adaptive), ..Default::default() };
    overrides.apply_to_scene(&mut scene, SettingNames::Options).unwrap();
    assert_eq!(scene.render.radius_schedule, RadiusSchedule::PerPoint);
    scene.render.radius_rule = RadiusRule::Shrink;
    scene.render.fit_pass_work(PassWork::DEFAULT);
    assert_eq!(scene.render.radius_schedule, RadiusSchedule::Global);
    scene.render.fit_pass_work(PassWork::GPU);
    assert_eq!(scene.render.radius_schedule, RadiusSchedule::PerPoint, "the GPU's 4 samples a pass");
    // A schedule given by an override stays.
    let mut scene = load_ok(&edit("iterations = 1\n", "iterations = 1\nfilter = \"gaussian\"\n"));
    let overrides = Overrides { radius_schedule: Some(RadiusSchedule::PerPoint), ..Default::default() };
    overrides.apply_to_scene(&mut scene, SettingNames::Options).unwrap();
    scene.render.fit_pass_work(PassWork::DEFAULT);
    assert_eq!(scene.render.radius_schedule, RadiusSchedule::PerPoint);
}

#[test]
fn one_sided_materials_and_pixel_filters() {
    use sppm_gpu::scene::PixelFilter;
    let s = load_ok(&edit(
        "white = { type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }",
        "white = { type = \"diffuse\", albedo = [0.5, 0.5, 0.5], one_sided = true }",
    ));
    assert!(s.materials[0].one_sided);
    assert!(!load_ok(BASE).materials[0].one_sided, "two-sided by default");
    assert_eq!(load_ok(BASE).render.filter, PixelFilter::Box);
    let render = |extra: &str| edit("iterations = 1\n", &format!("iterations = 1\n{extra}\n"));
    assert_eq!(load_ok(&render("filter = \"tent\"")).render.filter, PixelFilter::Tent { radius: 1.0 });
    assert_eq!(load_ok(&render("filter = \"tent\"\nfilter_radius = 1.5")).render.filter, PixelFilter::Tent { radius: 1.5 });
    assert_eq!(load_ok(&render("filter = \"gaussian\"")).render.filter, PixelFilter::Gaussian { stddev: 0.5 });
    assert_eq!(
        load_ok(&render("filter = \"gaussian\"\nfilter_stddev = 0.25")).render.filter,
        PixelFilter::Gaussian { stddev: 0.25 }
    );
    assert_error(&render("filter = \"mitchell\""), 5, "render.filter", &["mitchell"]);
    assert_error(&render("filter = \"box\"\nfilter_stddev = 0.5"), 6, "render.filter_stddev", &["gaussian"]);
    assert_error(&render("filter = \"gaussian\"\nfilter_stddev = 0"), 6, "render.filter_stddev", &[]);
    assert_error(
        &edit(
            "white = { type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }",
            "white = { type = \"dielectric\", ior = 1.5, one_sided = true }",
        ),
        12,
        "materials.white.one_sided",
        &["both sides"],
    );
}

/// The keys that let `sppm-gpu convert` write every scene the Mitsuba reader reads: conductor
/// Fresnel terms, microfacet distributions, tinted dielectrics, plastics, thin dielectrics,
/// null surfaces, spot lights and crop windows, each with a refusal at its line and key.
#[test]
fn materials_lights_and_crop_beyond_v1() {
    use sppm_gpu::scene::{ComplexIor, CropWindow};
    let material = |m: &str| {
        let s = load(&edit("white = { type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }", &format!("white = {m}")));
        s.map(|s| s.materials[0].kind.clone())
    };
    let half = Vec3::splat(0.5);
    assert_eq!(
        material(r#"{ type = "glossy", albedo = [0.5, 0.5, 0.5], roughness = 0.2, distribution = "beckmann", eta = [0.2, 0.9, 1.1], k = [3, 2.5, 2] }"#).unwrap(),
        MaterialKind::Conductor {
            albedo: half,
            texture: None,
            roughness: 0.2,
            distribution: Microfacet::Beckmann,
            fresnel: Some(ComplexIor { eta: Vec3::new(0.2, 0.9, 1.1), k: Vec3::new(3.0, 2.5, 2.0) }),
        }
    );
    assert_eq!(
        material(r#"{ type = "dielectric", ior = 1.5, reflectance = [0.3, 0.3, 0.3], transmittance = [0.9, 0.6, 0.3] }"#)
            .unwrap(),
        MaterialKind::Dielectric {
            ior: 1.5,
            roughness: 0.0,
            distribution: Microfacet::Ggx,
            reflectance: Vec3::splat(0.3),
            transmittance: Vec3::new(0.9, 0.6, 0.3),
        }
    );
    assert_eq!(
        material(r#"{ type = "plastic", albedo = [0.5, 0.5, 0.5], ior = 1.9, roughness = 0.1, nonlinear = true }"#).unwrap(),
        MaterialKind::Plastic {
            albedo: half,
            texture: None,
            specular: Vec3::ONE,
            ior: 1.9,
            roughness: 0.1,
            distribution: Microfacet::Ggx,
            nonlinear: true,
            thickness: 0.0,
            scatterings: 0,
        }
    );
    assert_eq!(
        material(r#"{ type = "thin_dielectric", ior = 1.5 }"#).unwrap(),
        MaterialKind::ThinDielectric { ior: 1.5, reflectance: Vec3::ONE, transmittance: Vec3::ONE }
    );
    assert_eq!(material(r#"{ type = "null" }"#).unwrap(), MaterialKind::Null);
    let refused = |m: &str, key: &str, words: &[&str]| {
        let e = material(m).unwrap_err();
        assert_eq!((e.line, e.key.as_deref()), (Some(12), Some(key)), "{e}");
        assert_message(&e, words);
    };
    refused(r#"{ type = "mirror", albedo = [1, 1, 1], eta = [1, 1, 1] }"#, "materials.white.eta", &["k"]);
    refused(
        r#"{ type = "glossy", albedo = [1, 1, 1], roughness = 0.1, distribution = "phong" }"#,
        "materials.white.distribution",
        &["phong", "beckmann"],
    );
    refused(r#"{ type = "plastic", albedo = [1, 1, 1], ior = 1, roughness = 0.1 }"#, "materials.white.ior", &["rough"]);
    refused(r#"{ type = "plastic", albedo = 0.5, ior = 1.5, thickness = -0.1 }"#, "materials.white.thickness", &["at least 0"]);
    refused(r#"{ type = "plastic", albedo = 0.5, ior = 1.5, scatterings = 2.5 }"#, "materials.white.scatterings", &["integer"]);
    // pbrt-v4's layer under the coating.
    assert!(matches!(
        material(r#"{ type = "plastic", albedo = 0.5, ior = 1.5, thickness = 0.01, scatterings = 5 }"#).unwrap(),
        MaterialKind::Plastic { thickness: 0.01, scatterings: 5, .. }
    ));
    refused(r#"{ type = "null", one_sided = true }"#, "materials.white.one_sided", &["both sides"]);
    refused(r#"{ type = "null", albedo = [1, 1, 1] }"#, "materials.white.albedo", &["unknown key"]);

    let spot = load_ok(&with_light(
        "type = \"spot\"\nposition = [0, 2, 0]\ndirection = [0, -2, 0]\nintensity = [5, 5, 5]\ncutoff_angle = 30\n",
    ));
    assert_eq!(
        spot.lights[0].kind,
        LightKind::Spot {
            position: Vec3::new(0.0, 2.0, 0.0),
            direction: Vec3::NEG_Y,
            intensity: Vec3::splat(5.0),
            cutoff_angle: 30.0,
            beam_width: 22.5
        }
    );
    assert_error(
        &with_light("type = \"spot\"\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nintensity = [5, 5, 5]\ncutoff_angle = 200\n"),
        18,
        "lights[0].cutoff_angle",
        &["180"],
    );

    let crop = load_ok(&edit("fov = 40\n", "fov = 40\ncrop = [0.25, 0, 0.75, 0.5]\n"));
    assert_eq!(crop.camera.crop, Some(CropWindow { min: Vec2::new(0.25, 0.0), max: Vec2::new(0.75, 0.5) }));
    assert_error(&edit("fov = 40\n", "fov = 40\ncrop = [0.5, 0, 0.25, 1]\n"), 10, "camera.crop", &["x0 < x1"]);
}

/// Photons and samples a pass that the scene leaves out follow the device
/// (`RenderSettings::fit_pass_work` with `GpuContext::pass_work`); those it gives, or that the
/// builder sets, stay.
#[test]
fn pass_work_left_out_follows_the_device() {
    use sppm_gpu::scene::{PassWork, WorkGiven};
    let device = PassWork { photons: 7_000, spp: 3 };
    let mut r = load_ok(&edit("iterations = 1", "iterations = 1")).render;
    assert_eq!(r.work_given, WorkGiven::default());
    assert_eq!((r.photons, r.spp), (PassWork::DEFAULT.photons, PassWork::DEFAULT.spp));
    r.fit_pass_work(device);
    assert_eq!((r.photons, r.spp), (7_000, 3));
    let mut r = load_ok(&edit("iterations = 1", "iterations = 1\nphotons = 5000")).render;
    assert_eq!(r.work_given, WorkGiven { photons: true, spp: false });
    r.fit_pass_work(device);
    assert_eq!((r.photons, r.spp), (5_000, 3));
    let mut r = sppm_gpu::scene::SceneBuilder::new(8, 8)
        .camera(Vec3::Z, Vec3::ZERO, Vec3::Y, 40.0)
        .point_light(Vec3::Y, [1.0; 3])
        .spp(2)
        .photons(100)
        .build()
        .unwrap()
        .render;
    assert_eq!(r.work_given, WorkGiven::ALL);
    r.fit_pass_work(device);
    assert_eq!((r.photons, r.spp), (100, 2));
}

/// Each mode's one name table ([`sppm_gpu::scene::Named`]) reads back what it writes, and the
/// TOML reader takes exactly its names.
#[test]
fn mode_names_come_from_one_table() {
    use sppm_gpu::scene::{DirectLight, Named, RadiusRule, RadiusSchedule};
    fn round_trip<T: Named + std::fmt::Debug>() {
        for &(name, value) in T::NAMES {
            assert_eq!(value.name(), name);
            assert_eq!(T::from_name(name), Ok(value));
        }
        let e = T::from_name("nonesuch").unwrap_err();
        assert!(e.contains(&T::names().join(", ")), "{e}");
    }
    round_trip::<Method>();
    round_trip::<DirectLight>();
    round_trip::<RadiusSchedule>();
    round_trip::<RadiusRule>();
    round_trip::<sppm_gpu::sampler::Sampler>();
    for &(name, method) in Method::NAMES {
        let text = edit("iterations = 1", &format!("iterations = 1\nmethod = \"{name}\""));
        assert_eq!(load_ok(&text).render.method, method);
    }
}

/// A disk: 256 triangles about its centre, facing its normal, on the circle of its radius,
/// with Mitsuba's disk's texture coordinates (r, phi / 2 pi); a mesh among the shape kinds.
#[test]
fn disk_faces_its_normal_on_its_circle() {
    let disk = "type = \"disk\"\ncenter = [1, 2, 3]\nnormal = [0, -2, 0]\nradius = 0.5\nmaterial = \"white\"\n";
    let scene = load_ok(&with_shape(&format!("{disk}emission = [1, 1, 1]\n")));
    assert_eq!((scene.shapes[0].kind, scene.shapes[0].emission), (ShapeKind::Mesh, Some(Vec3::ONE)));
    assert_eq!((scene.triangles.len(), scene.spheres.len()), (256, 0));
    let center = Vec3::new(1.0, 2.0, 3.0);
    let mut area = 0.0;
    for t in &scene.triangles {
        assert_close(geometric_normal(t.p), Vec3::NEG_Y);
        assert_eq!((t.p[0], t.n, t.shape), (center, None, 0));
        for p in &t.p[1..] {
            assert!(((*p - center).length() - 0.5).abs() < 1e-6 && (p.y - 2.0).abs() < 1e-6, "{p}");
        }
        let uv = t.uv.unwrap();
        assert_eq!((uv[0].x, uv[1].x, uv[2].x), (0.0, 1.0, 1.0));
        area += 0.5 * (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).length();
    }
    // 256 segments: the area 0.01% short of the circle's.
    let circle = std::f32::consts::PI * 0.25;
    assert!((area / circle - 1.0).abs() < 2e-4, "{area} against {circle}");
    // Any normal, +z's opposite included.
    for (normal, expected) in [("[0, 0, -1]", Vec3::NEG_Z), ("[1, 1, 1]", Vec3::ONE.normalize()), ("[0, 0, 1e-30]", Vec3::Z)] {
        let scene = load_ok(&with_shape(&disk.replace("[0, -2, 0]", normal)));
        assert!(scene.triangles.iter().all(|t| geometric_normal(t.p).abs_diff_eq(expected, 1e-4)), "{normal}");
    }
    // Its keys, and what is refused.
    assert_error(&with_shape(&disk.replace("[0, -2, 0]", "[0, 0, 0]")), 16, "shapes[0].normal", &["must not be zero"]);
    assert_error(&with_shape(&disk.replace("0.5", "0")), 17, "shapes[0].radius", &["greater than 0"]);
    assert_error(&with_shape(&disk.replace("radius = 0.5\n", "")), 13, "shapes[0].radius", &["missing required key"]);
    assert_error(&with_shape(&format!("{disk}corner = [0, 0, 0]\n")), 19, "shapes[0].corner", &["center, normal, radius"]);
    assert_error(
        &with_shape(&disk.replace("center = [1, 2, 3]", "center = [1e30, 0, 0]").replace("0.5", "1e-30")),
        17,
        "shapes[0].radius",
        &["no area"],
    );
    // A medium inside an open shape: the one a path enters crossing it against its normal.
    let fog = "[media.fog]\nsigma_t = 1\nalbedo = 0.5\n";
    let scene = load_ok(&format!("{}{fog}[[shapes]]\n{disk}interior = \"fog\"\n", BASE));
    assert_eq!(scene.shapes.last().unwrap().interior, Some(0));
}

/// Every colour-valued key takes one number as grey, as a medium's coefficients do (and
/// Mitsuba's `<rgb value="0.6"/>`); anything but a number or an array is refused naming both.
#[test]
fn a_single_number_is_a_grey_colour() {
    let grey = Vec3::splat(0.6);
    let material = |m: &str| load_ok(&edit("{ type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }", m)).materials[0].kind.clone();
    assert_eq!(material("{ type = \"diffuse\", albedo = 0.6 }").albedo(), Some((grey, None)));
    match material("{ type = \"mirror\", albedo = 1, eta = 0.2, k = 3 }") {
        MaterialKind::Conductor { albedo, roughness, fresnel: Some(f), .. } => {
            assert_eq!((albedo, roughness, f.eta, f.k), (Vec3::ONE, 0.0, Vec3::splat(0.2), Vec3::splat(3.0)))
        }
        other => panic!("{other:?}"),
    }
    match material("{ type = \"plastic\", albedo = 0.6, specular = 0.5, ior = 1.5 }") {
        MaterialKind::Plastic { albedo, specular, .. } => assert_eq!((albedo, specular), (grey, Vec3::splat(0.5))),
        other => panic!("{other:?}"),
    }
    match material("{ type = \"dielectric\", ior = 1.5, reflectance = 0.6, transmittance = 0.5 }") {
        MaterialKind::Dielectric { reflectance, transmittance, .. } => {
            assert_eq!((reflectance, transmittance), (grey, Vec3::splat(0.5)))
        }
        other => panic!("{other:?}"),
    }
    let shape = load_ok(&with_shape(&format!("{QUAD}emission = 4\n")));
    assert_eq!(shape.shapes[0].emission, Some(Vec3::splat(4.0)));
    let lights = [
        (
            "type = \"point\"\nposition = [0, 1, 0]\nintensity = 2\n",
            LightKind::Point { position: Vec3::Y, intensity: Vec3::splat(2.0) },
        ),
        (
            "type = \"directional\"\ndirection = [0, -1, 0]\nirradiance = 0.5\n",
            LightKind::Directional { direction: Vec3::NEG_Y, irradiance: Vec3::splat(0.5) },
        ),
        ("type = \"constant\"\nradiance = 3\n", LightKind::Constant { radiance: Vec3::splat(3.0) }),
    ];
    for (body, kind) in lights {
        assert_eq!(load_ok(&with_light(body)).lights[0].kind, kind, "{body}");
    }
    let spot = load_ok(&with_light("type = \"spot\"\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\nintensity = 5\n"));
    assert!(matches!(spot.lights[0].kind, LightKind::Spot { intensity, .. } if intensity == Vec3::splat(5.0)));
    // Bounds as for each channel; other types named.
    assert_error(
        &edit("albedo = [0.5, 0.5, 0.5]", "albedo = 1.5"),
        12,
        "materials.white.albedo",
        &["between 0 and 1, found 1.5"],
    );
    assert_error(&with_shape(&format!("{QUAD}emission = -1\n")), 19, "shapes[0].emission", &["at least 0"]);
    assert_error(
        &edit("albedo = [0.5, 0.5, 0.5]", "albedo = \"grey\""),
        12,
        "materials.white.albedo",
        &["expected one number or an array of 3 numbers, found a string"],
    );
}

/// A sphere's `uv_frame`: the axes its texture coordinates are taken in, kept bit for bit;
/// axes not orthonormal are refused.
#[test]
fn a_sphere_takes_its_uv_frame() {
    let sphere = "type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"white\"\n";
    assert_eq!(load_ok(&with_shape(sphere)).shapes[0].sphere_frame, None);
    let (c, s) = (0.8f32, 0.6f32);
    let frame = format!("uv_frame = [[{c}, {s}, 0], [-{s}, {c}, 0], [0, 0, 1]]\n");
    let scene = load_ok(&with_shape(&format!("{sphere}{frame}")));
    let expected = glam::Mat3::from_cols(Vec3::new(c, s, 0.0), Vec3::new(-s, c, 0.0), Vec3::Z);
    assert_eq!(scene.shapes[0].sphere_frame, Some(expected));
    let bad = |f: &str| with_shape(&format!("{sphere}uv_frame = {f}\n"));
    assert_error(&bad("[[1, 0, 0], [1, 0, 0], [0, 0, 1]]"), 18, "shapes[0].uv_frame", &["unit length and at right angles"]);
    assert_error(&bad("[[2, 0, 0], [0, 1, 0], [0, 0, 1]]"), 18, "shapes[0].uv_frame", &["unit length"]);
    assert_error(&bad("[[1, 0, 0], [0, 1, 0]]"), 18, "shapes[0].uv_frame", &["expected 3 axes [x, y, z], found 2 items"]);
    assert_error(&bad("[[1, 0, 0], [0, 1, 0], [0, 1]]"), 18, "shapes[0].uv_frame", &["array of 3 numbers"]);
    assert_error(&with_shape(&format!("{QUAD}uv_frame = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n")), 19, "shapes[0].uv_frame", &[]);
}
