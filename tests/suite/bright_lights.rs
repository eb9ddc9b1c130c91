//! Lights too bright for the renderer's 32-bit arithmetic (issue 40 item 4). A constant
//! environment of radiance 1e37 once rendered every pixel 0, a point light of 1e37 left half
//! the image black, and an emission of 3e38 was called "no light": the kernels' f32 sums (the
//! lights' power, SPPM's tau times that power, a path's and a pixel's samples) overflowed and
//! their guards zeroed the result. Now a light brighter than `MAX_EMISSION` in a channel, or
//! lights more powerful than `MAX_LIGHT_POWER` together, are refused when the renderer builds
//! the scene (`SceneData::new`), with an error at the light's entry; at the bounds SPPM and
//! PT-NEE render the image of the same scene at unit brightness times the bound, to rounding
//! (light transport is linear in emission).

use crate::common;

use sppm_gpu::gpu::scene_buffers::{SceneData, MAX_EMISSION, MAX_LIGHT_POWER};
use sppm_gpu::image_io::{write_exr, Rgb32Image};
use sppm_gpu::integrators;
use sppm_gpu::scene::{self, Scene, SceneBuilder, SceneError};
use std::path::{Path, PathBuf};

/// Why a light is refused, as every such error says it.
const BEYOND: &str = "beyond what the renderer's 32-bit arithmetic holds: at most";

/// The brightest value a light may have, as the f32 the loader makes of `1e18`.
fn at_bound() -> f32 {
    MAX_EMISSION as f32
}

/// The next f32 above the bound: just too bright.
fn over_bound() -> f32 {
    let v = f32::from_bits(at_bound().to_bits() + 1);
    assert!(v as f64 > MAX_EMISSION && at_bound() as f64 <= MAX_EMISSION);
    v
}

/// The kinds of light, each set by one value `v` (`[v, v, v]`, or an envmap's scale or
/// brightest texel).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Area,
    Point,
    Spot,
    Directional,
    Constant,
    EnvmapScale,
    EnvmapTexels,
}

impl Kind {
    /// The key the error names.
    fn key(self) -> &'static str {
        match self {
            Kind::Area => "shapes[3].emission",
            Kind::Point | Kind::Spot => "lights[0].intensity",
            Kind::Directional => "lights[0].irradiance",
            Kind::Constant => "lights[0].radiance",
            Kind::EnvmapScale => "lights[0].scale",
            Kind::EnvmapTexels => "lights[0].file",
        }
    }
}

/// An environment map of 16x8 texels in (0, 1], the brightest exactly 1, times `v`.
fn envmap_image(v: f32) -> Rgb32Image {
    let mut img = Rgb32Image::new(16, 8);
    for (k, p) in img.pixels.iter_mut().enumerate() {
        let (x, y) = ((k % 16) as f32, (k / 16) as f32);
        let t = if k == 35 { [1.0; 3] } else { [0.2 + 0.02 * x, 0.1 + 0.05 * y, 0.3] };
        *p = t.map(|c| c * v);
    }
    img
}

/// A floor, a back wall and a red sphere under one light of kind `kind` and value `v`, the
/// last entry of the file: 16x16 pixels, two passes of `method` (seed fixed).
fn small_scene(kind: Kind, v: f32, method: &str) -> String {
    let mut s = format!(
        r#"[render]
width = 16
height = 16
method = "{method}"
iterations = 2
photons = 4000
seed = 3

[camera]
position = [0, 1, 4]
look_at = [0, 0.8, 0]
fov = 50

[materials]
white = {{ type = "diffuse", albedo = [0.6, 0.6, 0.6] }}
red = {{ type = "diffuse", albedo = [0.7, 0.2, 0.2] }}
black = {{ type = "diffuse", albedo = [0, 0, 0] }}

[[shapes]]
type = "quad"
corner = [-2, 0, 2]
u = [4, 0, 0]
v = [0, 0, -4]
material = "white"

[[shapes]]
type = "quad"
corner = [-2, 0, -1]
u = [4, 0, 0]
v = [0, 2.5, 0]
material = "white"

[[shapes]]
type = "sphere"
center = [0, 0.5, 0]
radius = 0.5
material = "red"
"#
    );
    let v3 = format!("[{v:e}, {v:e}, {v:e}]");
    s += &match kind {
        // Visible on the wall, facing the camera.
        Kind::Area => format!(
            "\n[[shapes]]\ntype = \"quad\"\ncorner = [-0.3, 1.6, -0.99]\nu = [0.6, 0, 0]\nv = [0, 0.4, 0]\nmaterial = \"black\"\nemission = {v3}\n"
        ),
        Kind::Point => format!("\n[[lights]]\ntype = \"point\"\nposition = [0.3, 1.8, 0.8]\nintensity = {v3}\n"),
        Kind::Spot => format!(
            "\n[[lights]]\ntype = \"spot\"\nposition = [0.3, 1.8, 0.8]\ndirection = [-0.2, -1, -0.3]\ncutoff_angle = 50\nintensity = {v3}\n"
        ),
        Kind::Directional => format!("\n[[lights]]\ntype = \"directional\"\ndirection = [0.3, -1, -0.4]\nirradiance = {v3}\n"),
        Kind::Constant => format!("\n[[lights]]\ntype = \"constant\"\nradiance = {v3}\n"),
        Kind::EnvmapScale => format!("\n[[lights]]\ntype = \"envmap\"\nfile = \"env.exr\"\nscale = {v:e}\n"),
        Kind::EnvmapTexels => "\n[[lights]]\ntype = \"envmap\"\nfile = \"env.exr\"\n".to_owned(),
    };
    s
}

/// Line of the last table header in `text`: the light's entry.
fn last_header(text: &str) -> usize {
    text.lines().enumerate().filter(|(_, l)| l.starts_with("[[")).map(|(i, _)| i + 1).last().unwrap()
}

/// Writes `text` as `scene.toml` in a fresh directory, with the envmap image (texels times
/// `texels`) beside it, and loads it: the directory (removed when dropped), the scene's path
/// and the scene.
fn write_and_load(name: &str, text: &str, texels: f32) -> (common::Scratch, PathBuf, Scene) {
    let dir = common::scratch(&format!("bright-lights-{name}"));
    write_exr(&dir.join("env.exr"), &envmap_image(texels)).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = scene::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    (dir, path, scene)
}

/// The scene of `kind` at value `v`, loaded.
fn light_scene(name: &str, kind: Kind, v: f32, method: &str) -> (PathBuf, Scene, String) {
    let text = small_scene(kind, v, method);
    let texels = if kind == Kind::EnvmapTexels { v } else { 1.0 };
    let (_, path, scene) = write_and_load(name, &text, texels);
    (path, scene, text)
}

/// `SceneData::new`'s error for `scene`, which it must refuse.
#[track_caller]
fn refusal(scene: &Scene) -> SceneError {
    match SceneData::new(scene) {
        Ok(_) => panic!("{}: SceneData::new accepted it", scene.path.display()),
        Err(e) => e,
    }
}

/// The error is at `path`, `line`, `key`, and says why with the bound `bound` and each of
/// `words`.
#[track_caller]
fn assert_refusal(e: &SceneError, path: &Path, line: Option<usize>, key: &str, bound: &str, words: &[&str]) {
    assert_eq!((e.file.as_path(), e.line, e.key.as_deref()), (path, line, Some(key)), "wrong place: {e}");
    let text = e.to_string();
    assert!(text.contains(&format!("{BEYOND} {bound}")), "{text}");
    for w in words {
        assert!(text.contains(w), "no {w:?} in: {text}");
    }
}

/// Renders `bright` and `unit` with the method they name, on one device, sharing their kernels
/// (the two differ in their lights' values alone: one compile serves both).
fn render_pair(bright: &Scene, unit: &Scene) -> (Rgb32Image, Rgb32Image) {
    let gpu = common::gpu().expect("checked by the caller");
    sppm_gpu::gpu::share_kernels(|| {
        let render = |scene: &Scene| {
            let mut integrator = integrators::create(&gpu.device, &gpu.queue, scene).unwrap_or_else(|e| panic!("{e}"));
            common::run_passes(integrator.as_mut(), scene.render.iterations)
        };
        (render(bright), render(unit))
    })
}

/// `bright` is `unit` times `s`, to f32 rounding: every channel within 1e-5 of it (rounding
/// over a path's products is about 1e-7; measured at most 2.6e-7), finite, and lit wherever
/// `unit` is, so that no contribution was lost to an overflow.
#[track_caller]
fn assert_scaled(bright: &Rgb32Image, unit: &Rgb32Image, s: f64, what: &str) {
    let lit = unit.pixels.iter().filter(|p| p.iter().any(|&c| c > 0.0)).count();
    assert!(lit > unit.pixels.len() / 4, "{what}: the unit image is mostly black ({lit} lit pixels)");
    for (i, (b, u)) in bright.pixels.iter().zip(&unit.pixels).enumerate() {
        for c in 0..3 {
            let expected = u[c] as f64 * s;
            let got = b[c] as f64;
            assert!(
                got.is_finite() && (got - expected).abs() <= 1e-5 * expected,
                "{what}: pixel {i} channel {c} is {got:e}, where the unit image times {s:e} is {expected:e}"
            );
        }
    }
}

/// The light of `kind` just over the bound is refused at its entry, and at the bound SPPM and
/// PT-NEE render the unit scene's image times the bound.
fn check_kind(kind: Kind) {
    let name = format!("{kind:?}");
    let (path, scene, text) = light_scene(&format!("{name}-over"), kind, over_bound(), "sppm");
    let e = refusal(&scene);
    assert_refusal(&e, &path, Some(last_header(&text)), kind.key(), "1e18", &["in each channel"]);
    let Some(_) = common::gpu() else { return };
    for method in ["sppm", "pt-nee"] {
        let (_, unit, _) = light_scene(&format!("{name}-{method}-unit"), kind, 1.0, method);
        let (_, bright, _) = light_scene(&format!("{name}-{method}-bound"), kind, at_bound(), method);
        let (bright, unit) = render_pair(&bright, &unit);
        assert_scaled(&bright, &unit, at_bound() as f64, &format!("{name} {method}"));
    }
}

#[test]
fn area_light_over_the_bound_is_refused_and_at_it_renders_scaled() {
    check_kind(Kind::Area);
}

#[test]
fn point_light_over_the_bound_is_refused_and_at_it_renders_scaled() {
    check_kind(Kind::Point);
}

#[test]
fn spot_light_over_the_bound_is_refused_and_at_it_renders_scaled() {
    check_kind(Kind::Spot);
}

#[test]
fn directional_light_over_the_bound_is_refused_and_at_it_renders_scaled() {
    check_kind(Kind::Directional);
}

#[test]
fn constant_environment_over_the_bound_is_refused_and_at_it_renders_scaled() {
    check_kind(Kind::Constant);
}

#[test]
fn envmap_scale_over_the_bound_is_refused_and_at_it_renders_scaled() {
    check_kind(Kind::EnvmapScale);
}

#[test]
fn envmap_texels_over_the_bound_are_refused_and_at_them_render_scaled() {
    check_kind(Kind::EnvmapTexels);
}

/// An envmap's radiance is its brightest texel times its scale, and the error blames the one
/// past the bound: texels of 1e10 pass at scale 1 and are refused at scale 1e9 (the scale's
/// fault); texels of 1e20 are refused at scale 1 (the file's) and pass at scale 1e-3.
#[test]
fn envmap_radiance_is_brightest_texel_times_scale() {
    let text = |scale: f32| format!("{}scale = {scale:e}\n", small_scene(Kind::EnvmapTexels, 0.0, "sppm"));
    let line = Some(last_header(&text(1.0)));
    let (_, _, fine) = write_and_load("env-fine", &text(1.0), 1e10);
    SceneData::new(&fine).expect("1e10 is under the bound");
    let (_, path, scaled) = write_and_load("env-scaled", &text(1e9), 1e10);
    let words = ["radiance reaches 1e19", "brightest texel 1e10 times scale 1e9"];
    assert_refusal(&refusal(&scaled), &path, line, "lights[0].scale", "1e18", &words);
    let (_, path, bright) = write_and_load("env-bright", &text(1.0), 1e20);
    assert_refusal(&refusal(&bright), &path, line, "lights[0].file", "1e18", &["brightest texel 1e20 times scale 1)"]);
    let (_, _, dimmed) = write_and_load("env-dimmed", &text(1e-3), 1e20);
    SceneData::new(&dimmed).expect("1e20 times 1e-3 is under the bound");
}

/// An emission of 3e38, whose channels' sum overflows f32, was refused as "the scene has no
/// light": now it is the bound that refuses it, at the shape.
#[test]
fn an_emission_that_overflows_is_not_called_no_light() {
    let text = small_scene(Kind::Area, 3e38, "sppm");
    let (_, path, scene) = write_and_load("overflow", &text, 1.0);
    let e = refusal(&scene);
    assert_refusal(&e, &path, Some(last_header(&text)), "shapes[3].emission", "1e18", &["emission 3e38"]);
    assert!(!e.message.contains("no light"), "{e}");
}

/// The command line refuses a constant environment of 1e37 (once every pixel 0, exit 0) with
/// the error and exit status 1, writing no image.
#[test]
fn command_line_refuses_a_blinding_environment() {
    let text = small_scene(Kind::Constant, 1e37, "sppm");
    let (_dir, path, _) = write_and_load("cli", &text, 1.0);
    let out = path.with_file_name("out.exr");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
        .arg(&path)
        .arg("-o")
        .arg(&out)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let expected = format!(
        "error: {}:{}: key `lights[0].radiance`: radiance 1e37 is {BEYOND} 1e18 in each channel",
        path.display(),
        last_header(&text)
    );
    assert!(stderr.contains(&expected), "{stderr}");
    assert!(!out.exists(), "an image was written");
}

/// A scene 100,000 units across, lit by one light of kind `kind` (area, directional or
/// constant) at value `v`: the lights' power grows with the scene, past the bound on power
/// while each value stays under the bound on radiance.
fn large_scene(kind: Kind, v: f32, method: &str) -> String {
    let mut s = format!(
        r#"[render]
width = 16
height = 16
method = "{method}"
iterations = 2
photons = 4000
seed = 5

[camera]
position = [0, 150000, 150000]
look_at = [0, 0, 0]
fov = 40

[materials]
white = {{ type = "diffuse", albedo = [0.6, 0.6, 0.6] }}
red = {{ type = "diffuse", albedo = [0.7, 0.2, 0.2] }}
black = {{ type = "diffuse", albedo = [0, 0, 0] }}

[[lights]]
type = "point"
position = [0, 30000, 30000]
intensity = [1, 1, 1]

[[shapes]]
type = "quad"
corner = [-50000, 0, 50000]
u = [100000, 0, 0]
v = [0, 0, -100000]
material = "white"

[[shapes]]
type = "sphere"
center = [0, 20000, 0]
radius = 20000
material = "red"
"#
    );
    let v3 = format!("[{v:e}, {v:e}, {v:e}]");
    s += &match kind {
        Kind::Area => format!(
            "\n[[shapes]]\ntype = \"quad\"\ncorner = [-50000, 0, -50000]\nu = [100000, 0, 0]\nv = [0, 40000, 0]\nmaterial = \"black\"\nemission = {v3}\n"
        ),
        Kind::Directional => format!("\n[[lights]]\ntype = \"directional\"\ndirection = [0.3, -1, -0.4]\nirradiance = {v3}\n"),
        Kind::Constant => format!("\n[[lights]]\ntype = \"constant\"\nradiance = {v3}\n"),
        _ => unreachable!("large scenes have area, directional or constant lights"),
    };
    s
}

/// Lights whose power sums past the bound (1e28) are refused at the one that gives the most
/// (not the dim point light before it), saying how its power comes about; just under it, SPPM
/// and PT-NEE render the unit scene's image times the light's value.
#[test]
fn power_over_the_bound_is_refused_and_under_it_renders_scaled() {
    let cases = [
        (Kind::Area, "shapes[2].emission", "its emission times its area times pi"),
        (Kind::Directional, "lights[1].irradiance", "its irradiance times the area of the disk of radius"),
        (Kind::Constant, "lights[1].radiance", "its radiance times 4 pi times the area of the disk of radius"),
    ];
    let gpu = common::gpu();
    for (kind, key, how) in cases {
        let name = format!("large-{kind:?}");
        // The scene's power per unit of the light's value (the point light's 4 pi aside).
        let (_, _, unit) = write_and_load(&format!("{name}-unit"), &large_scene(kind, 1.0, "sppm"), 1.0);
        let per_unit = SceneData::new(&unit).unwrap().power_total as f64 - 4.0 * std::f64::consts::PI;
        let (over, under) = ((MAX_LIGHT_POWER / per_unit * 1.001) as f32, (MAX_LIGHT_POWER / per_unit * 0.999) as f32);
        assert!((over as f64) < MAX_EMISSION, "{name}: {over:e} would be refused for its radiance alone");
        let text = large_scene(kind, over, "sppm");
        let (_, path, scene) = write_and_load(&format!("{name}-over"), &text, 1.0);
        let e = refusal(&scene);
        assert_refusal(&e, &path, Some(last_header(&text)), key, "1e28", &["the lights' power is 1.001e28", how]);
        if gpu.is_none() {
            continue;
        }
        for method in ["sppm", "pt-nee"] {
            let (_, _, unit) = write_and_load(&format!("{name}-{method}-unit"), &large_scene(kind, 1.0, method), 1.0);
            let (_, _, bright) = write_and_load(&format!("{name}-{method}-under"), &large_scene(kind, under, method), 1.0);
            SceneData::new(&bright).expect("under the bound");
            // The dim point light is not scaled: only the image of the scaled light is compared,
            // with the point light dark in both.
            let (unit, bright) = (without_point_light(unit), without_point_light(bright));
            let (bright, unit) = render_pair(&bright, &unit);
            assert_scaled(&bright, &unit, under as f64, &format!("{name} {method}"));
        }
    }
}

/// `scene` without its first `[[lights]]` entry (the large scenes' dim point light).
fn without_point_light(mut scene: Scene) -> Scene {
    scene.lights.remove(0);
    scene
}

/// A Mitsuba scene's emitters are refused at their elements, by the parameter's name: a point
/// emitter's `intensity`, a shape's area emitter's `radiance` (at the `<shape>`).
#[test]
fn mitsuba_emitters_over_the_bound_are_refused_at_their_elements() {
    let over = format!("{:e}", over_bound());
    let scene = |area: &str, point: &str| {
        let emitter = format!(
            "    <emitter type=\"point\">\n        <point name=\"position\" x=\"0\" y=\"0\" z=\"2\"/>\n        \
             <rgb name=\"intensity\" value=\"{point}\"/>\n    </emitter>"
        );
        common::scene_text::mitsuba_with("3.0.0", area, &emitter)
    };
    let dir = common::scratch("bright-lights-mitsuba");
    for (file, text, line, key) in
        [("area.xml", scene(&over, "1"), 7, "radiance"), ("point.xml", scene("1", &over), 10, "intensity")]
    {
        let path = dir.join(file);
        std::fs::write(&path, text).unwrap();
        let scene = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_refusal(&refusal(&scene), &path, Some(line), key, "1e18", &[]);
    }
}

/// A scene built in code names the light by its builder key, without a line.
#[test]
fn builder_lights_over_the_bound_are_refused_by_key() {
    let scene = SceneBuilder::new(8, 8)
        .camera([0.0, 0.0, 5.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 40.0)
        .diffuse("white", [0.5, 0.5, 0.5])
        .quad([-1.0, -1.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], "white")
        .point_light([0.0, 0.0, 1.0], [1.0, 1.0, 1.0])
        .directional_light([0.0, 0.0, -1.0], [0.0, over_bound(), 0.0])
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let e = refusal(&scene);
    assert_refusal(&e, &scene.path, None, "lights[1].irradiance", "1e18", &[&format!("irradiance {:e} is", over_bound())]);
}
