//! Participating media in the scene model (issue 35, host side): `[media]` in our TOML,
//! `<medium>` in Mitsuba XML of both eras, the coefficients each form gives, every malformed
//! medium refused with its file, line and key, scenes without media loading as before, and the
//! render refusing a scene with media until the kernels land.

use crate::common;
use crate::common::scene_text::BASE;
use glam::Vec3;
use sppm_gpu::scene::{self, Medium, Phase, Scene, SceneError, ShapeKind};
use std::path::{Path, PathBuf};

fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The 1-based line of the first line of `text` containing `needle`.
#[track_caller]
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap_or_else(|| panic!("{needle:?} is not in the text")) + 1
}

#[track_caller]
fn close(a: Vec3, b: Vec3) {
    assert!((a - b).abs().max_element() <= 1e-5 * b.abs().max_element().max(1.0), "{a} != {b}");
}

fn toml(text: &str) -> Result<Scene, SceneError> {
    scene::load_str(text, Path::new("media.toml"))
}

#[track_caller]
fn toml_ok(text: &str) -> Scene {
    toml(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Loading `text` fails at the line holding `at`, about `key`, with a message holding `words`.
#[track_caller]
fn toml_error(text: &str, at: &str, key: &str, words: &[&str]) {
    let e = match toml(text) {
        Ok(_) => panic!("loaded without error:\n{text}"),
        Err(e) => e,
    };
    assert_eq!(e.file, Path::new("media.toml"), "{e}");
    assert_eq!((e.line, e.key.as_deref()), (Some(line_of(text, at)), Some(key)), "wrong place: {e}");
    for w in words {
        assert!(e.message.contains(w), "{w:?} is not in: {e}");
    }
}

/// [`BASE`] with a lit quad, then `extra` (tables and shapes).
fn with_media(extra: &str) -> String {
    format!(
        "{BASE}[[shapes]]\ntype = \"quad\"\ncorner = [-1, -1, -2]\nu = [2, 0, 0]\nv = [0, 2, 0]\nmaterial = \"white\"\n\
         emission = [1, 1, 1]\n{extra}"
    )
}

const FOG: &str = "[media.fog]\nsigma_a = [0.1, 0.2, 0.3]\nsigma_s = [0.5, 0.5, 0.5]\n";

#[test]
fn toml_media_read_in_both_forms_with_scale_and_phase() {
    let text = with_media(
        "[media.fog]\nsigma_a = [0.1, 0.2, 0.3]\nsigma_s = 0.5\nscale = 2\n\
         [media.water]\nsigma_t = [2, 1, 0.5]\nalbedo = [0.5, 0.8, 1]\nphase = \"hg\"\ng = 0.5\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0.5\nmaterial = \"white\"\ninterior = \"water\"\n\
         exterior = \"fog\"\n\
         [[shapes]]\ntype = \"cube\"\nscale = 0.2\ntranslate = [0.5, 0.5, 0]\nmaterial = \"white\"\ninterior = \"fog\"\n",
    );
    let text = text.replace("fov = 40", "fov = 40\nmedium = \"fog\"");
    let s = toml_ok(&text);
    assert_eq!(s.media.len(), 2);
    let fog = &s.media[0];
    assert_eq!((fog.name.as_str(), fog.line), ("fog", line_of(&text, "[media.fog]")));
    close(fog.sigma_a, Vec3::new(0.2, 0.4, 0.6));
    close(fog.sigma_s, Vec3::splat(1.0));
    assert_eq!(fog.phase, Phase::Isotropic);
    let water = &s.media[1];
    close(water.sigma_s, Vec3::new(1.0, 0.8, 0.5));
    close(water.sigma_a, Vec3::new(1.0, 0.2, 0.0));
    close(water.sigma_t(), Vec3::new(2.0, 1.0, 0.5));
    close(water.albedo(), Vec3::new(0.5, 0.8, 1.0));
    assert_eq!(water.phase, Phase::HenyeyGreenstein { g: 0.5 });
    assert_eq!(s.camera.medium, Some(0));
    assert_eq!((s.shapes[0].interior, s.shapes[0].exterior), (None, None));
    assert_eq!((s.shapes[1].kind, s.shapes[1].interior, s.shapes[1].exterior), (ShapeKind::Sphere, Some(1), Some(0)));
    assert_eq!((s.shapes[2].kind, s.shapes[2].interior), (ShapeKind::Cube, Some(0)));
    // `type = "homogeneous"` may be given; an exterior on an open quad is allowed, and an
    // interior (the medium a path enters crossing the quad against its normal, as Mitsuba 3
    // and pbrt-v4 read it).
    let s = toml_ok(&with_media(&format!("{FOG}type = \"homogeneous\"\n")).replace("emission", "exterior = \"fog\"\nemission"));
    assert_eq!(s.shapes[0].exterior, Some(0));
    let s = toml_ok(&with_media(FOG).replace("emission", "interior = \"fog\"\nemission"));
    assert_eq!(s.shapes[0].interior, Some(0));
}

#[test]
fn toml_media_refused_with_line_and_key() {
    let bad = |body: &str| with_media(&format!("[media.fog]\n{body}"));
    toml_error(&bad("sigma_a = [-0.1, 0, 0]\nsigma_s = 1\n"), "sigma_a", "media.fog.sigma_a", &["at least 0"]);
    toml_error(&bad("sigma_a = 0\nsigma_s = nan\n"), "sigma_s", "media.fog.sigma_s", &["finite"]);
    toml_error(&bad("sigma_t = inf\nalbedo = 0.5\n"), "sigma_t", "media.fog.sigma_t", &["finite"]);
    toml_error(&bad("sigma_t = 1\nalbedo = 1.5\n"), "albedo = 1.5", "media.fog.albedo", &["between 0 and 1"]);
    toml_error(&bad("sigma_t = 1\nalbedo = 0.5\nscale = -2\n"), "scale", "media.fog.scale", &["at least 0"]);
    toml_error(&bad("sigma_t = 1\nalbedo = 0.5\nphase = \"hg\"\ng = 1\n"), "g = 1", "media.fog.g", &["less than 1"]);
    toml_error(&bad("sigma_t = 1\nalbedo = 0.5\nphase = \"hg\"\ng = -1.5\n"), "g = -1.5", "media.fog.g", &["greater than -1"]);
    toml_error(&bad("sigma_t = 1\nalbedo = 0.5\nphase = \"hg\"\n"), "[media.fog]", "media.fog.g", &["missing required key `g`"]);
    toml_error(&bad("sigma_t = 1\nalbedo = 0.5\ng = 0.3\n"), "g = 0.3", "media.fog.g", &["belongs to phase = \"hg\""]);
    toml_error(&bad("sigma_t = 1\nalbedo = 0.5\nphase = \"rayleigh\"\n"), "phase", "media.fog.phase", &["unknown phase type"]);
    toml_error(
        &bad("type = \"heterogeneous\"\nsigma_t = 1\nalbedo = 0.5\n"),
        "type = \"heterogeneous\"",
        "media.fog.type",
        &["unknown medium type"],
    );
    toml_error(&bad("sigma_a = 1\nsigma_s = 1\nalbedo = 0.5\n"), "albedo = 0.5", "media.fog.albedo", &["not keys of both forms"]);
    toml_error(&bad("sigma_a = 1\n"), "[media.fog]", "media.fog.sigma_s", &["missing required key `sigma_s`"]);
    toml_error(&bad("albedo = 0.5\n"), "[media.fog]", "media.fog.sigma_t", &["missing required key `sigma_t`"]);
    toml_error(&bad("scale = 2\n"), "[media.fog]", "media.fog", &["sigma_a and sigma_s, or sigma_t and albedo"]);
    toml_error(&bad("sigma_t = 1\nalbedo = 0.5\ndensity = 2\n"), "density", "media.fog.density", &["unknown key `density`"]);
    toml_error(&bad("sigma_t = [1, 2]\nalbedo = 0.5\n"), "sigma_t", "media.fog.sigma_t", &["array of 3 numbers"]);
    // Unknown media, named by the camera and by shapes.
    let text = with_media(FOG).replace("fov = 40", "fov = 40\nmedium = \"smoke\"");
    toml_error(&text, "medium = ", "camera.medium", &["unknown medium `smoke`", "defined media: fog"]);
    let text = with_media("").replace("emission", "exterior = \"fog\"\nemission");
    toml_error(&text, "exterior", "shapes[0].exterior", &["unknown medium `fog`", "no media are defined"]);
}

/// A tetrahedron as an OBJ file, each face with vertices of its own (duplicated by position),
/// without its last face when `open`.
fn tetrahedron(open: bool) -> String {
    let p = ["0 0 0", "1 0 0", "0 1 0", "0 0 1"];
    let faces: &[[usize; 3]] = &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let mut obj = String::new();
    let mut n = 0;
    for f in &faces[..if open { 3 } else { 4 }] {
        for &v in f {
            obj += &format!("v {}\n", p[v]);
        }
        obj += &format!("f {} {} {}\n", n + 1, n + 2, n + 3);
        n += 3;
    }
    obj
}

/// A mesh's interior, closed or open: an open one is the medium a path enters crossing it
/// against its normals (Mitsuba 3 and pbrt-v4 accept both; Bitterli's volumetric-caustic fills
/// its room through one open quad).
#[test]
fn toml_interior_of_a_mesh_open_or_closed() {
    let dir = common::scratch("media-mesh");
    std::fs::write(dir.join("closed.obj"), tetrahedron(false)).unwrap();
    std::fs::write(dir.join("open.obj"), tetrahedron(true)).unwrap();
    let mesh = |file: &str| {
        with_media(&format!("{FOG}[[shapes]]\ntype = \"mesh\"\nfile = \"{file}\"\nmaterial = \"white\"\ninterior = \"fog\"\n"))
    };
    for file in ["closed.obj", "open.obj"] {
        let s = scene::load_str(&mesh(file), &dir.join("scene.toml")).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(s.shapes[1].interior, Some(0), "{file}");
    }
}

/// Every TOML scene of the repository and of ../shared/scenes, and every Mitsuba test scene,
/// loads as before: no media, no medium around the camera or in any shape.
#[test]
fn scenes_without_media_load_unchanged() {
    let mut paths = Vec::new();
    for dir in [repo("scenes"), repo("../shared/scenes"), repo("scenes/mitsuba"), repo("tests/scenes/mitsuba-era")] {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            eprintln!("{} not present", dir.display());
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
            if (ext == "toml" || ext == "xml") && !path.ends_with("legacy-walls.xml") {
                paths.push(path);
            }
        }
    }
    assert!(paths.len() >= 20, "{paths:?}");
    for path in paths {
        let s = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(s.media.is_empty() && s.camera.medium.is_none(), "{}", path.display());
        assert!(s.shapes.iter().all(|sh| sh.interior.is_none() && sh.exterior.is_none()), "{}", path.display());
    }
}

fn media_scene(name: &str) -> Scene {
    scene::load(&repo("scenes/media").join(name)).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn mitsuba_3_test_scenes_read_their_media() {
    let fog = media_scene("fog-cornell.xml");
    assert_eq!(fog.media.len(), 1);
    let m: &Medium = &fog.media[0];
    assert_eq!(m.name, "fog");
    close(m.sigma_t(), Vec3::splat(0.5));
    close(m.sigma_s, Vec3::splat(0.4));
    close(m.sigma_a, Vec3::splat(0.1));
    assert_eq!(m.phase, Phase::Isotropic);
    assert_eq!(fog.camera.medium, Some(0));
    assert!(fog.shapes.iter().all(|s| s.interior.is_none() && s.exterior.is_none()));
    // volpath with max_depth -1: unbounded, as path's.
    assert_eq!(fog.render.max_depth, 1024);

    let water = media_scene("murky-water.xml");
    assert_eq!((water.media.len(), water.camera.medium), (1, None));
    let w = &water.media[0];
    close(w.sigma_t(), Vec3::new(2.2, 1.21, 0.99));
    close(w.sigma_s, Vec3::new(2.2 * 0.55, 1.21 * 0.85, 0.99 * 0.8));
    close(w.sigma_a, w.sigma_t() - w.sigma_s);
    assert_eq!(w.phase, Phase::HenyeyGreenstein { g: 0.5 });
    let holders: Vec<_> = water.shapes.iter().filter(|s| s.interior.is_some()).collect();
    assert_eq!(holders.len(), 1);
    assert_eq!((holders[0].kind, holders[0].interior, holders[0].exterior), (ShapeKind::Cube, Some(0), None));

    let caustic = media_scene("volumetric-caustic.xml");
    assert_eq!((caustic.media.len(), caustic.camera.medium), (1, Some(0)));
    close(caustic.media[0].sigma_s, Vec3::splat(0.225));
    let glass: Vec<_> = caustic.shapes.iter().filter(|s| s.exterior.is_some()).collect();
    assert_eq!(glass.len(), 1);
    assert_eq!((glass[0].kind, glass[0].interior, glass[0].exterior), (ShapeKind::Sphere, None, Some(0)));

    // Fog that enters an open room through its open side: a null rectangle with the fog inside.
    let open = media_scene("bitterli-volumetric-caustic.xml");
    assert_eq!((open.media.len(), open.camera.medium), (1, None));
    let front: Vec<_> = open.shapes.iter().filter(|s| s.interior.is_some()).collect();
    assert_eq!(front.len(), 1);
    assert_eq!((front[0].kind, front[0].interior, front[0].exterior), (ShapeKind::Quad, Some(0), None));
}

/// A Mitsuba scene of version `version` around `body`: a camera (holding `sensor_extra`) and
/// a lit rectangle.
fn xml(version: &str, sensor_extra: &str, body: &str) -> String {
    let to_world = if version.starts_with('0') { "toWorld" } else { "to_world" };
    format!(
        r#"<scene version="{version}">
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="{to_world}"><lookat origin="0, 0, 4" target="0, 0, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
{sensor_extra}
    </sensor>
    <shape type="rectangle">
        <emitter type="area"><rgb name="radiance" value="1"/></emitter>
    </shape>
{body}
</scene>
"#
    )
}

/// Loads `text` as `s.xml` in a folder of its own, with its warnings.
fn load_xml(test: &str, text: &str) -> (Result<Scene, SceneError>, Vec<SceneError>) {
    let dir = common::scratch(&format!("media-{test}"));
    std::fs::write(dir.join("s.xml"), text).unwrap();
    scene::mitsuba::load_with_warnings(&dir.join("s.xml"), &[])
}

#[track_caller]
fn xml_ok(test: &str, text: &str) -> (Scene, Vec<SceneError>) {
    let (s, w) = load_xml(test, text);
    (s.unwrap_or_else(|e| panic!("{e}\n{text}")), w)
}

/// Loading `text` fails in s.xml at the line holding `at`, about `key`, with `words`.
#[track_caller]
fn xml_error(test: &str, text: &str, at: &str, key: Option<&str>, words: &[&str]) {
    let e = match load_xml(test, text).0 {
        Ok(_) => panic!("{test}: loaded without error:\n{text}"),
        Err(e) => e,
    };
    assert!(e.file.ends_with("s.xml"), "{test}: {e}");
    assert_eq!((e.line, e.key.as_deref()), (Some(line_of(text, at)), key), "{test}: wrong place: {e}");
    for w in words {
        assert!(e.message.contains(w), "{test}: {w:?} is not in: {e}");
    }
}

#[test]
fn mitsuba_3_medium_forms_and_defaults() {
    // Defaults: sigma_t 1, albedo 0.75, isotropic; an hg phase's g 0.8. A nested medium in the
    // sensor and a nested interior in a sphere; a referenced exterior; a referenced phase.
    let body = r#"    <phase type="hg" id="forward"><float name="g" value="-0.25"/></phase>
    <medium type="homogeneous" id="thin">
        <spectrum name="sigma_t" value="3"/>
        <float name="albedo" value="0.5"/>
        <float name="scale" value="0.1"/>
        <boolean name="sample_emitters" value="true"/>
        <ref id="forward"/>
    </medium>
    <shape type="sphere">
        <medium type="homogeneous" name="interior"><phase type="hg"/></medium>
        <ref name="exterior" id="thin"/>
    </shape>
    <shape type="cube"><ref name="interior" id="thin"/></shape>
    <shape type="rectangle"><ref name="interior" id="thin"/></shape>"#;
    let (s, warnings) = xml_ok("forms", &xml("3.0.0", r#"        <medium type="homogeneous"/>"#, body));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(s.media.len(), 3);
    let camera = &s.media[s.camera.medium.unwrap() as usize];
    close(camera.sigma_s, Vec3::splat(0.75));
    close(camera.sigma_a, Vec3::splat(0.25));
    assert_eq!(camera.phase, Phase::Isotropic);
    let sphere = &s.shapes[1];
    let inside = &s.media[sphere.interior.unwrap() as usize];
    assert_eq!(inside.phase, Phase::HenyeyGreenstein { g: 0.8 });
    let thin = &s.media[sphere.exterior.unwrap() as usize];
    assert_eq!(thin.name, "thin");
    close(thin.sigma_t(), Vec3::splat(0.3));
    close(thin.sigma_s, Vec3::splat(0.15));
    assert_eq!(thin.phase, Phase::HenyeyGreenstein { g: -0.25 });
    // One medium, however often it is referred to; an interior on an open shape too, as
    // Mitsuba 3 renders it (the medium a path enters crossing it against its normal).
    assert_eq!(s.shapes[2].interior, sphere.exterior);
    assert_eq!((s.shapes[3].kind, s.shapes[3].interior), (ShapeKind::Quad, sphere.exterior));
    // sample_emitters false: warned.
    let body = r#"    <medium type="homogeneous" id="m"><boolean name="sample_emitters" value="false"/></medium>"#;
    let (_, warnings) = xml_ok("sample-emitters", &xml("3.0.0", r#"        <ref id="m"/>"#, body));
    assert!(warnings.iter().any(|w| w.key.as_deref() == Some("sample_emitters") && w.message.contains("noise")), "{warnings:?}");
}

#[test]
fn mitsuba_3_media_refused_with_file_line_and_key() {
    let medium = |inner: &str| format!("    <medium type=\"homogeneous\" id=\"m\">{inner}</medium>");
    for (test, body, at, key, words) in [
        (
            "heterogeneous",
            r#"    <medium type="heterogeneous" id="smoke"/>"#.to_owned(),
            "heterogeneous",
            Some("type"),
            &["heterogeneous", "participating media"][..],
        ),
        ("other type", r#"    <medium type="foggy" id="m"/>"#.to_owned(), "foggy", Some("type"), &["`foggy`"][..]),
        ("no id", r#"    <medium type="homogeneous"/>"#.to_owned(), "<medium", Some("id"), &["`id`"][..]),
        ("negative sigma_t", medium(r#"<float name="sigma_t" value="-1"/>"#), "sigma_t", Some("sigma_t"), &["negative"][..]),
        ("albedo above 1", medium(r#"<rgb name="albedo" value="1.5, 0.5, 0.5"/>"#), "albedo", Some("albedo"), &["[0, 1]"][..]),
        ("negative scale", medium(r#"<float name="scale" value="-2"/>"#), "scale", Some("scale"), &["negative"][..]),
        ("rgb sigma_t above 1", medium(r#"<rgb name="sigma_t" value="2, 1, 1"/>"#), "sigma_t", Some("sigma_t"), &["`scale`"][..]),
        ("nan", medium(r#"<float name="sigma_t" value="nan"/>"#), "sigma_t", Some("sigma_t"), &["finite"][..]),
        ("g of 1", medium(r#"<phase type="hg"><float name="g" value="1"/></phase>"#), "<phase", Some("g"), &["|g| < 1"][..]),
        (
            "g below -1",
            medium(r#"<phase type="hg"><float name="g" value="-1.5"/></phase>"#),
            "<phase",
            Some("g"),
            &["(-1, 1)"][..],
        ),
        ("phase type", medium(r#"<phase type="rayleigh"/>"#), "rayleigh", Some("type"), &["`rayleigh` phase function"][..]),
        ("two phases", medium(r#"<phase type="isotropic"/><phase type="hg"/>"#), "<medium", None, &["second phase"][..]),
        ("unknown parameter", medium(r#"<float name="sigma_a" value="1"/>"#), "sigma_a", Some("sigma_a"), &["no parameter"][..]),
        (
            "volume",
            medium(r#"<volume type="gridvolume" name="sigma_t"><string name="filename" value="d.vol"/></volume>"#),
            "gridvolume",
            None,
            &["heterogeneous"][..],
        ),
        (
            "textured albedo",
            medium(r#"<texture type="checkerboard" name="albedo"/>"#),
            "checkerboard",
            Some("albedo"),
            &["heterogeneous"][..],
        ),
        (
            "unknown medium",
            r#"    <shape type="sphere"><ref name="interior" id="nothing"/></shape>"#.to_owned(),
            "nothing",
            Some("id"),
            &["no element has id \"nothing\""][..],
        ),
        (
            "medium named foo",
            r#"    <shape type="sphere"><medium type="homogeneous" name="foo"/></shape>"#.to_owned(),
            "foo",
            Some("name"),
            &["\"interior\"", "\"exterior\""][..],
        ),
        (
            "two interiors",
            r#"    <medium type="homogeneous" id="m"/>
    <shape type="sphere"><ref name="interior" id="m"/><medium type="homogeneous" name="interior"/></shape>"#
                .to_owned(),
            "<shape type=\"sphere\"",
            Some("interior"),
            &["second interior"][..],
        ),
        (
            "heterogeneous in a shape",
            r#"    <shape type="sphere"><medium type="heterogeneous" name="interior"/></shape>"#.to_owned(),
            "heterogeneous",
            Some("type"),
            &["heterogeneous"][..],
        ),
    ] {
        xml_error(test, &xml("3.0.0", "", &body), at, key, words);
    }
    // Two media around the camera.
    let text = xml("3.0.0", "        <medium type=\"homogeneous\"/>\n        <medium type=\"homogeneous\"/>", "");
    let second = text.lines().enumerate().filter(|(_, l)| l.contains("<medium")).nth(1).unwrap().0 + 1;
    let e = load_xml("two", &text).0.unwrap_err();
    assert_eq!(e.line, Some(second), "{e}");
    assert!(e.message.contains("second medium in the sensor"), "{e}");
}

#[test]
fn mitsuba_0_6_media_read_as_0_6_reads_them() {
    // sigmaA and sigmaS times scale; sigmaT and albedo; densityMultiplier read as scale;
    // the sampling strategy warned; volpath_simple's maxDepth as path's.
    let body = r#"    <medium type="homogeneous" id="a">
        <rgb name="sigmaA" value="0.1, 0.2, 0.3"/>
        <spectrum name="sigmaS" value="0.5, 1, 2"/>
        <float name="scale" value="2"/>
        <string name="strategy" value="maximum"/>
        <phase type="hg"><float name="g" value="0.3"/></phase>
    </medium>
    <medium type="homogeneous" id="b">
        <float name="sigmaT" value="4"/>
        <rgb name="albedo" value="0.25, 0.5, 1"/>
        <float name="densityMultiplier" value="0.5"/>
    </medium>
    <integrator type="volpath_simple"><integer name="maxDepth" value="9"/></integrator>
    <shape type="sphere"><ref name="interior" id="a"/><ref name="exterior" id="b"/></shape>"#;
    let (s, warnings) = xml_ok("legacy", &xml("0.6.0", "", body));
    let a = &s.media[s.shapes[1].interior.unwrap() as usize];
    close(a.sigma_a, Vec3::new(0.2, 0.4, 0.6));
    close(a.sigma_s, Vec3::new(1.0, 2.0, 4.0));
    assert_eq!(a.phase, Phase::HenyeyGreenstein { g: 0.3 });
    let b = &s.media[s.shapes[1].exterior.unwrap() as usize];
    close(b.sigma_t(), Vec3::splat(2.0));
    close(b.sigma_s, Vec3::new(0.5, 1.0, 2.0));
    close(b.sigma_a, Vec3::new(1.5, 1.0, 0.0));
    assert_eq!(s.render.max_depth, 8);
    let keys: Vec<_> = warnings.iter().filter_map(|w| w.key.as_deref()).collect();
    assert!(keys.contains(&"strategy") && keys.contains(&"density_multiplier"), "{warnings:?}");
    // The sensor's medium by reference, as 0.6 files give it.
    let (s, _) = xml_ok(
        "legacy-sensor",
        &xml(
            "0.6.0",
            r#"        <ref id="fog"/>"#,
            r#"    <medium type="homogeneous" id="fog"><float name="sigmaT" value="1"/><float name="albedo" value="0.5"/></medium>"#,
        ),
    );
    assert_eq!(s.camera.medium, Some(0));
}

#[test]
fn mitsuba_0_6_media_refused_with_file_line_and_key() {
    let medium = |inner: &str| format!("    <medium type=\"homogeneous\" id=\"m\">{inner}</medium>");
    for (test, body, at, key, words) in [
        ("preset", medium(r#"<string name="material" value="Ketchup"/>"#), "Ketchup", "material", &["preset", "sigmaA"][..]),
        ("no coefficients", medium(""), "<medium", "sigma_a", &["skin1"][..]),
        ("half a pair", medium(r#"<float name="sigmaS" value="1"/>"#), "<medium", "sigma_a", &["both sigmaA and sigmaS"][..]),
        (
            "both forms",
            medium(r#"<float name="sigmaS" value="1"/><float name="sigmaA" value="1"/><float name="albedo" value="1"/>"#),
            "<medium",
            "albedo",
            &["both forms"][..],
        ),
        (
            "negative sigmaA",
            medium(r#"<float name="sigmaA" value="-1"/><float name="sigmaS" value="1"/>"#),
            "<medium",
            "sigma_a",
            &["negative"][..],
        ),
        (
            "medium g",
            medium(r#"<float name="sigmaT" value="1"/><float name="albedo" value="1"/><float name="g" value="0.5"/>"#),
            "<medium",
            "g",
            &["reduced scattering"][..],
        ),
        (
            "monochromatic",
            medium(
                r#"<float name="sigmaT" value="1"/><float name="albedo" value="1"/><boolean name="monochromatic" value="true"/>"#,
            ),
            "<medium",
            "monochromatic",
            &["monochromatic"][..],
        ),
        (
            "scale twice",
            medium(
                r#"<float name="sigmaT" value="1"/><float name="albedo" value="1"/><float name="scale" value="2"/><float name="densityMultiplier" value="2"/>"#,
            ),
            "<medium",
            "density_multiplier",
            &["one parameter"][..],
        ),
        (
            "hg g",
            medium(
                r#"<float name="sigmaT" value="1"/><float name="albedo" value="1"/><phase type="hg"><float name="g" value="1"/></phase>"#,
            ),
            "<medium",
            "g",
            &["|g| < 1"][..],
        ),
        (
            "kkay",
            medium(r#"<float name="sigmaT" value="1"/><float name="albedo" value="1"/><phase type="kkay"/>"#),
            "<medium",
            "type",
            &["`kkay`"][..],
        ),
    ] {
        xml_error(test, &xml("0.6.0", "", &body), at, Some(key), words);
    }
}
