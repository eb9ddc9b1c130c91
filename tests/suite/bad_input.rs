//! Bad scene input, read from real files: every case gives an error naming the file, the line
//! and the key (or, for degenerate mesh triangles, one warning), and the command line exits
//! with status 1 and no panic. `tests/suite/scene_load.rs` checks the exact line and key of each
//! TOML-level error through `load_str`; here the files are on disk, the messages are the ones
//! the "Bad input" table of docs/guide/rendering.md shows, and the cases beyond the TOML (OBJ contents, values
//! that overflow 32-bit floats in world space, a scene with no light) are covered.

use crate::common;

use crate::common::scene_text::{edit, with_light, with_shape, BASE, QUAD};
use sppm_gpu::gpu::scene_buffers::SceneData;
use sppm_gpu::scene::{self, LightKind, SceneBuilder, SceneError};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A mesh shape naming `m.obj`: `file` is on line 16 after [`with_shape`].
const MESH: &str = "type = \"mesh\"\nmaterial = \"white\"\nfile = \"m.obj\"\n";

/// Writes `scene.toml` holding `text` and the `files` beside it into a fresh directory: the
/// directory (removed when dropped) and the scene's path.
fn write_scene(name: &str, text: &str, files: &[(&str, &[u8])]) -> (common::Scratch, PathBuf) {
    let dir = common::scratch(&format!("bad-input-{name}"));
    for (file, bytes) in files {
        std::fs::write(dir.join(file), bytes).unwrap();
    }
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

/// Loads `text` (with `files` beside it) from disk; it must fail.
#[track_caller]
fn load_error(name: &str, text: &str, files: &[(&str, &[u8])]) -> (PathBuf, SceneError) {
    let (_dir, path) = write_scene(name, text, files);
    match scene::load(&path) {
        Ok(_) => panic!("{name}: loaded without error:\n{text}"),
        Err(e) => (path, e),
    }
}

/// The error names `path`, `line` and `key` in its fields and in its message, which holds
/// each of `words`.
#[track_caller]
fn assert_names(error: &SceneError, path: &Path, line: usize, key: &str, words: &[&str]) {
    assert_eq!((error.file.as_path(), error.line, error.key.as_deref()), (path, Some(line), Some(key)), "wrong place: {error}");
    let text = error.to_string();
    let place = format!("{}:{line}: key `{key}`: ", path.display());
    assert!(text.starts_with(&place), "{text:?} does not start with {place:?}");
    for word in words {
        assert!(text.contains(word), "{word:?} is not in: {text}");
    }
}

/// Loading `text` from disk fails at `line` about `key`, with each of `words` in the message.
#[track_caller]
fn assert_error(name: &str, text: &str, files: &[(&str, &[u8])], line: usize, key: &str, words: &[&str]) {
    let (path, error) = load_error(name, text, files);
    assert_names(&error, &path, line, key, words);
}

/// One row of the "Bad input" table of docs/guide/rendering.md: what is wrong, the scene (with files beside
/// it), and the message after `scene.toml:LINE: key `KEY`: ` exactly as printed; `{dir}` in
/// it stands for the scene's directory.
struct Case {
    what: &'static str,
    scene: String,
    files: Vec<(&'static str, &'static [u8])>,
    line: usize,
    key: &'static str,
    message: &'static str,
}

fn readme_cases() -> Vec<Case> {
    let case = |what, scene: String, line, key, message| Case { what, scene, files: Vec::new(), line, key, message };
    let mesh_case = |what, obj: &'static str, message| Case {
        what,
        scene: with_shape(MESH),
        files: vec![("m.obj", obj.as_bytes())],
        line: 16,
        key: "shapes[0].file",
        message,
    };
    let sphere =
        |radius: &str| with_shape(&format!("type = \"sphere\"\ncenter = [0, 0, 0]\nmaterial = \"white\"\nradius = {radius}\n"));
    let material = |m: &str| format!("{BASE}m = {m}\n");
    Vec::from([
        case(
            "malformed TOML",
            edit("iterations = 1", "iterations = 1\nmethod = sppm"),
            5,
            "render.method",
            "string values must be quoted, expected literal string",
        ),
        case(
            "unknown key",
            edit("height = 8", "height = 8\nsamples = 4"),
            4,
            "render.samples",
            "unknown key `samples`; allowed keys: width, height, method, iterations, spp, \
             photons, radius, alpha, max_depth, seed, time_limit, direct, direct_samples, light_paths, connect_share, merge_share, \
             radius_schedule, radius_rule, \
             filter, filter_radius, filter_stddev, sampler",
        ),
        case("wrong type", edit("width = 8", "width = \"8\""), 2, "render.width", "expected an integer, found a string"),
        case(
            "no light subpaths, yet connections",
            edit("height = 8", "height = 8\nmethod = \"vcm\"\nlight_paths = 0\nconnect_share = 0.5"),
            5,
            "render.light_paths",
            "light_paths = 0 traces no light subpath to connect or merge with, but connect_share = 0.5",
        ),
        case("missing required key", edit("fov = 40\n", ""), 6, "camera.fov", "missing required key `fov`"),
        case(
            "shape names an unknown material",
            with_shape(&QUAD.replace("\"white\"", "\"whyte\"")),
            18,
            "shapes[0].material",
            "unknown material `whyte`; defined materials: white",
        ),
        case(
            "unknown material type",
            edit("\"diffuse\"", "\"lambert\""),
            12,
            "materials.white.type",
            "unknown material type `lambert`; expected one of: diffuse, mirror, glossy, \
             dielectric, plastic, thin_dielectric, null",
        ),
        case(
            "unknown shape type",
            with_shape(&QUAD.replace("\"quad\"", "\"cone\"")),
            14,
            "shapes[0].type",
            "unknown shape type `cone`; expected one of: quad, sphere, cube, mesh, disk",
        ),
        case(
            "unknown light type",
            with_light("type = \"area\"\n"),
            14,
            "lights[0].type",
            "unknown light type `area`; expected one of: point, directional, spot, constant, envmap",
        ),
        Case {
            what: "missing OBJ file",
            scene: with_shape(MESH),
            files: Vec::new(),
            line: 16,
            key: "shapes[0].file",
            message: "cannot read mesh {dir}/m.obj: No such file or directory (os error 2)",
        },
        mesh_case("OBJ with garbage", "v 0 0 zero\n", "cannot read mesh {dir}/m.obj: line 1: `zero` is not a number"),
        mesh_case(
            "OBJ face naming a missing vertex",
            "v 0 0 0\nv 1 0 0\nf 1 2 9\n",
            "cannot read mesh {dir}/m.obj: line 3: vertex index 9 does not exist (the file has \
             2 vertices)",
        ),
        mesh_case(
            "OBJ vertex with NaN",
            "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
            "cannot read mesh {dir}/m.obj: line 2: `nan` is not a finite number",
        ),
        Case {
            what: "missing texture",
            scene: material("{ type = \"diffuse\", texture = \"t.png\" }"),
            files: Vec::new(),
            line: 13,
            key: "materials.m.texture",
            message: "cannot read texture {dir}/t.png: No such file or directory (os error 2)",
        },
        Case {
            what: "corrupt texture",
            scene: material("{ type = \"diffuse\", texture = \"t.png\" }"),
            files: vec![("t.png", b"not an image")],
            line: 13,
            key: "materials.m.texture",
            message: "cannot read texture {dir}/t.png: The image format could not be determined",
        },
        case("NaN or infinity", edit("fov = 40", "fov = nan"), 9, "camera.fov", "must be a finite number, found nan"),
        case(
            "albedo outside [0, 1]",
            material("{ type = \"diffuse\", albedo = [0.5, -0.1, 0.5] }"),
            13,
            "materials.m.albedo",
            "must be between 0 and 1, found -0.1",
        ),
        case(
            "negative emission",
            with_shape(&format!("{QUAD}emission = [1, -1, 1]\n")),
            19,
            "shapes[0].emission",
            "must be at least 0, found -1",
        ),
        case("radius 0 or negative", sphere("-1"), 17, "shapes[0].radius", "must be greater than 0, found -1"),
        case(
            "ior 0 or negative",
            material("{ type = \"dielectric\", ior = 0 }"),
            13,
            "materials.m.ior",
            "must be greater than 0, found 0",
        ),
        case(
            "roughness outside [0, 1]",
            material("{ type = \"glossy\", albedo = [1, 1, 1], roughness = 1.5 }"),
            13,
            "materials.m.roughness",
            "must be between 0 and 1, found 1.5",
        ),
        case(
            "fov outside (0, 180)",
            edit("fov = 40", "fov = 180"),
            9,
            "camera.fov",
            "must be greater than 0 and less than 180, found 180",
        ),
        case("width or height 0", edit("width = 8", "width = 0"), 2, "render.width", "must be between 1 and 16384, found 0"),
        case(
            "photons or iterations 0",
            edit("iterations = 1", "iterations = 0"),
            4,
            "render.iterations",
            "must be between 1 and 4294967295, found 0",
        ),
        case(
            "alpha outside (0, 1)",
            edit("iterations = 1", "iterations = 1\nalpha = 1.5"),
            5,
            "render.alpha",
            "must be greater than 0 and less than 1, found 1.5",
        ),
        case(
            "velocity NaN",
            with_shape(&format!("{QUAD}velocity = [nan, 0, 0]\n")),
            19,
            "shapes[0].velocity",
            "must be a finite number, found nan",
        ),
        case(
            "number beyond 32-bit floats",
            edit("position = [0, 0, 5]", "position = [0, 1e39, 5]"),
            7,
            "camera.position",
            "1e39 is out of the range of 32-bit floats",
        ),
        case(
            "shape too large for 32-bit floats",
            sphere("1e30"),
            13,
            "shapes[0]",
            "the shape lies beyond the range of 32-bit floats: a vertex, an edge or an area \
             overflows (position, size or scale too large)",
        ),
        case(
            "zero-area quad (or light)",
            with_shape(&format!("{QUAD}emission = [5, 5, 5]\n").replace("v = [0, 1, 0]", "v = [2, 0, 0]")),
            17,
            "shapes[0].v",
            "u and v are parallel or zero: the quad has no area",
        ),
    ])
}

/// The guide table's messages, exactly, each from a scene file on disk.
#[test]
fn readme_table_messages() {
    for (i, case) in readme_cases().into_iter().enumerate() {
        let (path, error) = load_error(&format!("readme-{i}"), &case.scene, &case.files);
        let dir = path.parent().unwrap().display().to_string();
        let expected = format!("{}:{}: key `{}`: {}", path.display(), case.line, case.key, case.message.replace("{dir}", &dir));
        assert_eq!(error.to_string(), expected, "case: {}", case.what);
        assert_names(&error, &path, case.line, case.key, &[]);
    }
}

#[test]
fn toml_syntax_errors_name_the_key_on_their_line() {
    // Inside an inline table: the material's key.
    assert_error("syntax-inline", &edit("albedo = [0.5, 0.5, 0.5]", "albedo = [0.5, , 0.5]"), &[], 12, "materials.white", &[]);
    // In the second `[[shapes]]` entry: counted from 0.
    let two = format!("{}[[shapes]]\n{}", with_shape(QUAD), QUAD.replace("u = [1, 0, 0]", "u = [1, 0 0]"));
    assert_error("syntax-array", &two, &[], 22, "shapes[1].u", &[]);
    // A duplicate key: at the second one.
    assert_error("syntax-duplicate", &edit("fov = 40", "fov = 40\nfov = 41"), &[], 10, "camera.fov", &["duplicate key"]);
    // A key without `=`: its first word.
    assert_error("syntax-no-value", &edit("fov = 40", "fov 40"), &[], 9, "camera.fov", &["expected `=`"]);
    // An array left open: the error is found on a later line, and named after the key that
    // opened it, not the key on that line.
    assert_error(
        "syntax-open",
        &edit("position = [0, 0, 5]", "position = [0, 0, 5"),
        &[],
        8,
        "camera.position",
        &["expected `,`"],
    );
    // Numbers the TOML reader passes but that are not numbers or do not fit.
    assert_error(
        "syntax-no-digits",
        &edit("width = 8", "width = 0x"),
        &[],
        2,
        "render.width",
        &["`0x` is not a valid integer: it has no digits"],
    );
    assert_error(
        "syntax-huge-integer",
        &edit("fov = 40", "fov = 99999999999999999999"),
        &[],
        9,
        "camera.fov",
        &["99999999999999999999 is beyond the range of 64-bit integers; write it as a float"],
    );
    // A broken header names no key, but still the file and the line.
    let (path, error) = load_error("syntax-header", &edit("[camera]", "[camera"), &[]);
    assert_eq!((error.line, error.key.as_deref()), (Some(6), None), "{error}");
    assert!(error.to_string().starts_with(&format!("{}:6: ", path.display())), "{error}");
}

#[test]
fn scene_file_not_utf8_names_the_line() {
    let mut bytes = BASE.as_bytes().to_vec();
    let at = BASE.find("fov").unwrap();
    bytes.splice(at..at, [0xff, 0xfe]);
    let dir = common::scratch("bad-input-not-utf8");
    let path = dir.join("scene.toml");
    std::fs::write(&path, bytes).unwrap();
    let error = scene::load(&path).expect_err("not UTF-8");
    assert_eq!((error.file.as_path(), error.line), (path.as_path(), Some(9)), "{error}");
    assert!(error.to_string().contains("not UTF-8"), "{error}");
}

#[test]
fn obj_numbers_that_are_not_finite_are_errors_at_their_obj_line() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (obj, obj_line, word) in [
        (format!("{tri}v inf 0 0\nf 1 2 3\nf 1 2 4\n"), 4, "`inf` is not a finite number"),
        (format!("{tri}v 1e39 0 0\nf 1 2 3\n"), 4, "`1e39` is not a finite number"),
        (format!("{tri}vn 0 0 NaN\nf 1//1 2//1 3//1\n"), 4, "`NaN` is not a finite number"),
        (format!("{tri}vt 0 -inf\nf 1/1 2/1 3/1\n"), 4, "`-inf` is not a finite number"),
        // A weight w divides the coordinates: 0, or one that overflows them.
        (format!("v 0 0 0 0\n{tri}f 2 3 4\n"), 1, "the weight w = 0 does not give finite coordinates"),
        (format!("{tri}v 1 1 1 1e-45\nf 1 2 3\n"), 4, "the weight w = 1e-45"),
        (format!("{tri}vn 0 0\nf 1 2 3\n"), 4, "a normal needs 3 numbers, found 2"),
    ] {
        let (path, error) = load_error("obj-finite", &with_shape(MESH), &[("m.obj", obj.as_bytes())]);
        let obj_path = path.with_file_name("m.obj");
        let expected = format!("cannot read mesh {}: line {obj_line}: {word}", obj_path.display());
        assert_names(&error, &path, 16, "shapes[0].file", &[&expected]);
    }
}

#[test]
fn obj_face_indices_out_of_range_are_errors_at_their_obj_line() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (obj, message) in [
        (format!("{tri}f 0 1 2\n"), "line 4: vertex index 0 in `0` (OBJ indices start at 1)"),
        (format!("{tri}f -4 -2 -1\n"), "line 4: vertex index -4 in `-4` reaches back past the 3 vertices defined before it"),
        // Relative indices count back from their line, not from the end of the file.
        (format!("v 0 0 0\nf -1 -2 -3\n{tri}"), "line 2: vertex index -2 in `-2` reaches back past the 1 vertices"),
        (format!("{tri}f 1 2 4\n"), "line 4: vertex index 4 does not exist (the file has 3 vertices)"),
        (
            format!("{tri}f 1/1 2/1 3/1\n"),
            "line 4: texture coordinate index 1 does not exist (the file has 0 texture \
             coordinates)",
        ),
        (format!("{tri}vn 0 0 1\nf 1//1 2//1 3//2\n"), "line 5: normal index 2 does not exist (the file has 1 normals)"),
        (format!("{tri}f 1 2 3\nf 1 2 99999999999999999999\n"), "line 5: `99999999999999999999` is not a face vertex"),
        (format!("{tri}f 1 2 3/1/1/1\n"), "line 4: `3/1/1/1` is not a face vertex"),
        (format!("{tri}f 1 2 x\n"), "line 4: `x` is not a face vertex"),
        (format!("{tri}f 1 2\n"), "line 4: a face needs at least 3 vertices, found 2"),
        (
            format!("{tri}v 0 0 0 1 1\nf 1 2 3\n"),
            "line 4: a vertex has 3 numbers, 4 (with a weight w) or 6 (with a colour), found 5",
        ),
    ] {
        let (path, error) = load_error("obj-index", &with_shape(MESH), &[("m.obj", obj.as_bytes())]);
        assert_names(&error, &path, 16, "shapes[0].file", &["cannot read mesh", "m.obj: ", message]);
    }
    // Forward references are allowed, as the OBJ reader allows them.
    let obj = "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let (_dir, path) = write_scene("obj-forward", &with_shape(MESH), &[("m.obj", obj.as_bytes())]);
    assert_eq!(scene::load(&path).unwrap().triangles.len(), 1);
}

#[test]
fn obj_not_utf8_names_its_line() {
    let obj: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 \xff\nf 1 2 3\n";
    let (path, error) = load_error("obj-utf8", &with_shape(MESH), &[("m.obj", obj)]);
    assert_names(&error, &path, 16, "shapes[0].file", &["m.obj: line 3: not UTF-8 text"]);
}

#[test]
fn geometry_beyond_32_bit_floats_is_an_error() {
    const TOO_LARGE: &str = "the shape lies beyond the range of 32-bit floats";
    let cube = "type = \"cube\"\nmaterial = \"white\"\n";
    // The quad's edges are finite but its area overflows.
    let big_quad = QUAD.replace("u = [1, 0, 0]", "u = [3e38, 0, 0]").replace("v = [0, 1, 0]", "v = [0, 3e38, 0]");
    assert_error("big-quad", &with_shape(&big_quad), &[], 13, "shapes[0]", &[TOO_LARGE]);
    // A translate that pushes a corner to infinity.
    assert_error(
        "big-cube",
        &with_shape(&format!("{cube}translate = [3.4e38, 0, 0]\nscale = 1e38\n")),
        &[],
        13,
        "shapes[0]",
        &[TOO_LARGE],
    );
    // A mesh whose finite coordinates overflow once scaled.
    let tri: &[u8] = b"v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n";
    assert_error("big-mesh", &with_shape(&format!("{MESH}scale = 1e10\n")), &[("m.obj", tri)], 13, "shapes[0]", &[TOO_LARGE]);
    // Finite at rest, beyond the range at the end of the shutter.
    let moving = "type = \"sphere\"\ncenter = [3e38, 0, 0]\nradius = 1\nmaterial = \"white\"\n\
                  velocity = [3e38, 0, 0]\n";
    assert_error(
        "big-velocity",
        &with_shape(moving),
        &[],
        18,
        "shapes[0].velocity",
        &["moved by its velocity, the shape lies beyond"],
    );
    // An emitting sphere whose area would overflow the light's power.
    let sun = "type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1e19\nmaterial = \"white\"\n\
               emission = [1, 1, 1]\n";
    assert_error("big-sphere", &with_shape(sun), &[], 13, "shapes[0]", &[TOO_LARGE]);
    // The camera's view vector overflowing.
    assert_error(
        "far-camera",
        &edit("look_at = [0, 0, 0]", "look_at = [0, 0, -3.4e38]").replace("[0, 0, 5]", "[0, 0, 3.4e38]"),
        &[],
        8,
        "camera.look_at",
        &["look_at is too far from position"],
    );
}

#[test]
fn shapes_that_vanish_in_32_bit_floats_are_errors() {
    // A unit quad a billion units from the origin: corner + u rounds back to corner.
    let far_quad = QUAD.replace("corner = [0, 0, 0]", "corner = [1e9, 0, 0]");
    assert_error("far-quad", &with_shape(&far_quad), &[], 15, "shapes[0].corner", &["the quad has no area in 32-bit floats"]);
    // A cube scaled to nothing: every triangle's area underflows.
    let cube = "type = \"cube\"\nmaterial = \"white\"\nscale = 1e-30\n";
    assert_error("tiny-cube", &with_shape(cube), &[], 16, "shapes[0].scale", &["all 12 triangles of the cube have no area"]);
}

#[test]
fn zero_area_light_is_an_error() {
    let light = format!("{QUAD}emission = [10, 10, 10]\n").replace("u = [1, 0, 0]", "u = [0, 0, 0]");
    assert_error("zero-light", &with_shape(&light), &[], 17, "shapes[0].v", &["no area"]);
}

#[test]
fn environment_errors_name_line_and_key() {
    let sky = "type = \"constant\"\nradiance = [1, 1, 1]\n";
    let negative = with_light(&sky.replace("[1, 1, 1]", "[1, -1, 1]"));
    assert_error("negative-radiance", &negative, &[], 15, "lights[0].radiance", &["must be at least 0, found -1"]);
    // At most one environment: the second is named, at its header.
    let two = format!("{}[[lights]]\n{sky}", with_light(sky));
    assert_error("two-environments", &two, &[], 16, "lights[1]", &["at most one environment light", "another is at line 13"]);
}

#[test]
fn huge_light_directions_still_normalize() {
    let light = "type = \"directional\"\ndirection = [3e38, -3e38, 0]\nirradiance = [1, 1, 1]\n";
    let (_dir, path) = write_scene("big-direction", &with_light(light), &[]);
    let scene = scene::load(&path).unwrap();
    let LightKind::Directional { direction, .. } = scene.lights[0].kind else { panic!("not directional") };
    let expected = glam::Vec3::new(1.0, -1.0, 0.0).normalize();
    assert!(direction.abs_diff_eq(expected, 1e-6), "{direction}");
}

#[test]
fn scene_without_light_is_an_error_of_scene_data() {
    // With no emission or light at all: the file, and `lights`, where one goes; else the
    // first emission or light in the file, all of them zero, at its entry's line.
    let black_light = "type = \"point\"\nposition = [0, 0, 0]\nintensity = [0, 0, 0]\n";
    let unlit = [
        ("no-shapes", BASE.to_owned(), "", "lights"),
        ("no-emission", with_shape(QUAD), "", "lights"),
        ("black-emission", with_shape(&format!("{QUAD}emission = [0, 0, 0]\n")), ":13", "shapes[0].emission"),
        ("black-point-light", with_light(black_light), ":13", "lights[0].intensity"),
        (
            "black-light-first",
            format!("{}\n[[shapes]]\n{QUAD}emission = 0\n", with_light(black_light)),
            ":13",
            "lights[0].intensity",
        ),
    ];
    for (name, text, line, key) in unlit {
        let (_dir, path) = write_scene(name, &text, &[]);
        let scene = scene::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let error = match SceneData::new(&scene) {
            Ok(_) => panic!("{name}: SceneData::new accepted a scene with no light"),
            Err(e) => e,
        };
        assert_eq!(
            error.to_string(),
            format!(
                "{}{line}: key `{key}`: the scene has no light: give a shape an \
                 `emission` greater than zero, or add a [[lights]] entry with positive \
                 intensity or irradiance",
                path.display()
            ),
            "{name}"
        );
        assert_eq!(error.file, path, "{name}");
    }
    // The same scene with a light is accepted.
    let (_dir, path) = write_scene("lit", &with_shape(&format!("{QUAD}emission = [1, 1, 1]\n")), &[]);
    SceneData::new(&scene::load(&path).unwrap()).expect("a lit scene");
}

#[test]
fn builder_checks_geometry_as_the_loader_does() {
    let builder = || {
        SceneBuilder::new(8, 8).camera([0.0, 0.0, 5.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 40.0).diffuse("white", [0.5, 0.5, 0.5])
    };
    let error = builder().sphere([0.0, 0.0, 0.0], 1e30, "white").emission([1.0, 1.0, 1.0]).build().unwrap_err();
    assert_eq!(error.key.as_deref(), Some("shapes[0]"), "{error}");
    assert!(error.message.contains("beyond the range of 32-bit floats"), "{error}");
    let error =
        builder().quad([1e9, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "white").emission([1.0, 1.0, 1.0]).build().unwrap_err();
    assert_eq!(error.key.as_deref(), Some("shapes[0].corner"), "{error}");
    let error = builder()
        .camera([0.0, 0.0, 3.4e38], [0.0, 0.0, -3.4e38], [0.0, 1.0, 0.0], 40.0)
        .quad([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "white")
        .emission([1.0, 1.0, 1.0])
        .build()
        .unwrap_err();
    assert!(error.message.contains("too far"), "{error}");
}

// --- The command line ---

/// The binary rendering `scene` to `output` with `args`, ready to run.
fn binary(scene: &Path, output: &Path, args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"));
    command.arg(scene).arg("-o").arg(output).args(args).env("XDG_RUNTIME_DIR", std::env::temp_dir());
    command
}

/// Runs the binary on `scene`, writing to `out.png` beside it; its exit code and stderr.
fn run_binary(scene: &Path) -> (Option<i32>, String) {
    let output = binary(scene, &scene.with_file_name("out.png"), &[]).output().expect("the binary runs");
    (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned())
}

#[test]
fn binary_exits_1_on_a_bad_scene_value() {
    let (_dir, scene) = write_scene("bin-value", &edit("fov = 40", "fov = -5"), &[]);
    let (code, stderr) = run_binary(&scene);
    assert_eq!(code, Some(1), "{stderr}");
    let expected =
        format!("error: {}:9: key `camera.fov`: must be greater than 0 and less than 180, found -5\n", scene.display());
    assert_eq!(stderr, expected);
    assert!(!scene.with_file_name("out.png").exists(), "no image is written");
}

#[test]
fn binary_exits_1_on_a_corrupt_mesh_and_malformed_toml() {
    let obj: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 nan\nf 1 2 3\n";
    let (_dir, scene) = write_scene("bin-mesh", &with_shape(MESH), &[("m.obj", obj)]);
    let (code, stderr) = run_binary(&scene);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let place = format!("error: {}:16: key `shapes[0].file`: cannot read mesh ", scene.display());
    assert!(stderr.starts_with(&place), "{stderr}");
    assert!(stderr.contains("m.obj: line 4: `nan` is not a finite number"), "{stderr}");

    let (_dir, scene) = write_scene("bin-toml", &edit("height = 8", "height = = 8"), &[]);
    let (code, stderr) = run_binary(&scene);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.starts_with(&format!("error: {}:3: key `render.height`: ", scene.display())), "{stderr}");
}

#[test]
fn binary_warns_once_about_degenerate_mesh_triangles() {
    // Two of three triangles have no area; a later shape's error stops the run before any
    // GPU work, so the test needs no device.
    let obj: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 2 4 1\n";
    let text = format!("{}[[shapes]]\n{}", with_shape(MESH), QUAD.replace("\"quad\"", "\"cone\""));
    let (_dir, scene) = write_scene("bin-warning", &text, &[("m.obj", obj)]);
    let (code, stderr) = run_binary(&scene);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let warning = format!(
        "warning: {}:16: key `shapes[0].file`: 2 degenerate triangles (zero area) skipped \
         in mesh {}\n",
        scene.display(),
        scene.with_file_name("m.obj").display()
    );
    assert_eq!(stderr.matches("warning:").count(), 1, "{stderr}");
    assert!(stderr.starts_with(&warning), "{stderr}");
    assert!(stderr.contains("key `shapes[1].type`: unknown shape type `cone`"), "{stderr}");
}

/// Output to a pipe whose reader has gone (`sppm-gpu bench ... | head -1`) is dropped, not a
/// panic: the render goes on and writes its image.
#[test]
fn binary_survives_a_closed_stdout() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("bad-input-closed-stdout");
    let out = dir.join("closed-stdout.png");
    let mut child = binary(
        &common::scene_path("cornell-box.toml"),
        &out,
        &["--width", "16", "--height", "16", "--iterations", "2", "--photons", "1000"],
    )
    .stdout(std::process::Stdio::piped())
    .stderr(std::process::Stdio::piped())
    .spawn()
    .expect("the binary runs");
    // The reader goes before the first line is written.
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.exists(), "the image is written");
}

/// An output the render could not write is refused before the scene is loaded: a missing
/// directory, or a directory where the image should go. (Unwritable directories are refused
/// the same way, but a test run as root could write there anyway.)
#[test]
fn binary_checks_the_output_before_rendering() {
    let scene = common::scene_path("cornell-box.toml");
    let run = |output: &Path| {
        let start = std::time::Instant::now();
        let output = binary(&scene, output, &[]).output().expect("the binary runs");
        (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned(), start.elapsed())
    };
    let scratch = common::scratch("bad-input-output-checks");
    let missing = scratch.join("sppm-gpu-no-such-dir").join("out.png");
    let (code, stderr, took) = run(&missing);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("does not exist") && stderr.contains("sppm-gpu-no-such-dir"), "{stderr}");
    assert!(took.as_secs_f64() < 5.0, "refused at once, not after rendering: {took:?}");
    assert!(!stderr.contains("panicked"), "{stderr}");

    let dir = scratch.join("sppm-gpu-output-is-a-dir.png");
    std::fs::create_dir_all(&dir).unwrap();
    let (code, stderr, _) = run(&dir);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("names a directory"), "{stderr}");
}

/// Runs the binary rendering `scene` to `out` with `args`, held by the `SPPM_GPU_HOLD` hook at
/// `stage` (src/cli/render.rs): once its stderr says it is held there, sends `signal`. Its
/// exit code and whole stderr.
fn signal_when_held(scene: &Path, out: &Path, args: &[&str], stage: &str, signal: &str) -> (Option<i32>, String) {
    use std::io::{BufRead, Read};
    let mut child = binary(scene, out, args)
        .env("SPPM_GPU_HOLD", stage)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut text = String::new();
    // Reading blocks until the line comes: the state is observed, not waited for.
    while !text.contains(&format!("held {stage}")) {
        if stderr.read_line(&mut text).unwrap() == 0 {
            panic!("the binary ended before it was held {stage}: {text}");
        }
    }
    let kill = Command::new("kill").arg(format!("-{signal}")).arg(child.id().to_string()).status().unwrap();
    assert!(kill.success());
    stderr.read_to_string(&mut text).unwrap();
    (child.wait().unwrap().code(), text)
}

/// SIGINT and SIGTERM end a render after the pass under way: the image of the passes done is
/// written, and the exit code says which signal (130, 143).
#[test]
fn binary_writes_the_passes_done_when_interrupted() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("bad-input-signal");
    for (signal, code) in [("INT", 130), ("TERM", 143)] {
        let out = dir.join(format!("signal-{signal}.exr"));
        let args = ["--iterations", "1000000", "--width", "32", "--height", "24", "--photons", "2000"];
        let (status, stderr) = signal_when_held(&common::scene_path("cornell-box.toml"), &out, &args, "after 2 passes", signal);
        assert_eq!(status, Some(code), "SIG{signal}: {stderr}");
        assert!(stderr.contains(&format!("interrupted by SIG{signal} after ")), "{stderr}");
        let image = sppm_gpu::image_io::read_exr(&out).unwrap_or_else(|e| panic!("SIG{signal}: {e}"));
        assert_eq!((image.width, image.height), (32, 24));
        assert!(image.pixels.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
        let mean = image.pixels.iter().flatten().sum::<f32>() / (3 * 32 * 24) as f32;
        assert!(mean > 0.05, "SIG{signal}: mean {mean}");
    }
}

/// A signal before the first pass (loading the scene, starting the GPU, compiling the kernels)
/// ends the run at once with the signal's exit code and a word of where it was; nothing is
/// written, and no internal error is shown.
#[test]
fn binary_honours_a_signal_before_the_first_pass() {
    let scene = common::scene_path("cornell-box.toml");
    let dir = common::scratch("bad-input-early-signal");
    let mut stages = vec!["loading the scene"];
    if common::gpu().is_some() {
        stages.extend(["starting the GPU", "compiling the kernels"]);
    }
    for stage in stages {
        for (signal, code) in [("INT", 130), ("TERM", 143)] {
            let out = dir.join(format!("early-signal-{signal}.exr"));
            let args = ["--iterations", "4", "--width", "16", "--height", "16", "--photons", "1000"];
            let (status, stderr) = signal_when_held(&scene, &out, &args, stage, signal);
            assert_eq!(status, Some(code), "{stage}, SIG{signal}: {stderr}");
            let said = format!("interrupted by SIG{signal} while {stage}: nothing was rendered or written");
            assert!(stderr.contains(&said), "{stage}: {stderr}");
            assert!(!stderr.contains("error"), "{stage}: {stderr}");
            assert!(!out.exists(), "{stage}: nothing is written");
        }
    }
}

/// A render that needs more memory than it may have is refused at once, with the sizes, and
/// nothing is written; one that fits renders.
#[test]
fn binary_refuses_a_render_beyond_the_memory_limit() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("bad-input-memory-limit");
    let out = dir.join("memory-limit.png");
    let run = |size: &str, limit: &str| {
        let start = std::time::Instant::now();
        let args = ["--width", size, "--height", size, "--iterations", "1", "--photons", "1000", "--memory-limit", limit];
        let output = binary(&common::scene_path("cornell-box.toml"), &out, &args).output().expect("the binary runs");
        (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned(), start.elapsed())
    };
    // 2048x2048 needs about 0.8 GiB: 168 bytes a pixel of buffers and 40 of host image.
    let (code, stderr, took) = run("2048", "64M");
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("a 2048x2048 image (spp 1) needs about 0.8 GiB"), "{stderr}");
    assert!(stderr.contains("the --memory-limit (0.1 GiB)"), "{stderr}");
    assert!(took.as_secs_f64() < 5.0, "refused at once: {took:?}");
    assert!(!out.exists(), "nothing is written");
    let (code, stderr, _) = run("32", "64M");
    assert_eq!(code, Some(0), "{stderr}");
    assert!(out.exists());
    let (code, stderr, _) = run("32", "lots");
    assert_eq!(code, Some(2), "a bad limit is a usage error: {stderr}");
    assert!(stderr.contains("a number of bytes"), "{stderr}");
}

/// A radius whose disc SPPM cannot estimate with (1e-30: its area underflows and every
/// estimate is 0/0, the image black even where direct light falls; 1e30: its area overflows)
/// is refused with the range it may take; one at the edge of the range renders.
#[test]
fn radii_beyond_what_32_bit_floats_estimate_with_are_refused() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("cornell-box.toml");
    (scene.render.width, scene.render.height, scene.render.photons) = (8, 8, 1000);
    let (lo, hi) = scene.bounds();
    let diagonal = (hi - lo).length();
    for radius in [1e-30, 1e30, 0.9e-6 * diagonal, 11.0 * diagonal] {
        scene.render.radius = Some(radius);
        let error = match sppm_gpu::integrators::create(&gpu.device, &gpu.queue, &scene) {
            Ok(_) => panic!("radius {radius} accepted"),
            Err(e) => e.to_string(),
        };
        assert!(error.contains("is outside what SPPM can estimate with") && error.contains("cornell-box.toml"), "{error}");
    }
    scene.render.radius = Some(1.01e-6 * diagonal);
    let mut sppm = sppm_gpu::integrators::create(&gpu.device, &gpu.queue, &scene).unwrap();
    let image = common::run_passes(sppm.as_mut(), 1);
    assert!(image.mean().iter().all(|&m| m > 0.01), "direct light at the smallest radius: {:?}", image.mean());
}
