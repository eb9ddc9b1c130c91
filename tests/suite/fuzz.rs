//! Fuzzing the scene loader with proptest: mutated copies of the canonical scenes, and random
//! OBJ files behind a mesh shape. The loader must answer each with a scene or an error that
//! names the scene file (and a line inside it), never a panic; what it accepts must be finite
//! geometry the renderer can use. Mutated copies of the Mitsuba XML test scenes (lines, numbers,
//! attribute values) go through the XML reader the same way.
//!
//! 2048 cases per property (about two seconds in all in release mode), from a fixed seed so
//! that CI runs the same cases every time; `PROPTEST_CASES=N` and `PROPTEST_RNG_SEED=S` fuzz
//! longer or elsewhere.

use crate::common;
use crate::common::serialized_writer;
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::{Config, RngSeed};
use serialized_writer::serialized_file;
use sppm_gpu::gpu::scene_buffers::SceneData;
use sppm_gpu::scene::{self, Scene, SceneError};
use std::path::{Path, PathBuf};

fn config() -> Config {
    let mut config = Config::default(); // reads PROPTEST_* from the environment
    if std::env::var_os("PROPTEST_CASES").is_none() {
        config.cases = 2048;
    }
    if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
        config.rng_seed = RngSeed::Fixed(0x5ce7e);
    }
    config.failure_persistence = None;
    config
}

/// The canonical scenes: path and text.
fn canonical_scenes() -> Vec<(PathBuf, String)> {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes"));
    let mut scenes: Vec<(PathBuf, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "toml"))
        .map(|path| {
            let text = std::fs::read_to_string(&path).unwrap();
            (path, text)
        })
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 8, "the canonical scenes are missing");
    scenes
}

/// Values that a number in a scene is replaced with.
const ODD_VALUES: &[&str] = &[
    "nan",
    "-nan",
    "inf",
    "-inf",
    "-1",
    "1e39",
    "-1e39",
    "0",
    "-0.0",
    "1e-50",
    "1e30",
    "3.4e38",
    "99999999999999999999",
    "0x",
    "4294967296",
    "\"1\"",
    "[]",
    "[1, 2]",
    "true",
    "{}",
    "1979-05-27",
];

/// A value for a number in a scene: an odd one, or a number of any sign and magnitude
/// (written as an integer or a float), which keeps the scene valid more often and takes its
/// sizes and positions to extremes.
fn number_value() -> impl Strategy<Value = String> {
    prop_oneof![
        1 => prop::sample::select(ODD_VALUES).prop_map(str::to_owned),
        1 => (-1.0f64..1.0, -45i32..45).prop_map(|(m, e)| format!("{:e}", m * 10f64.powi(e))),
        1 => (-3i64..300).prop_map(|i| i.to_string()),
    ]
}

/// Lines inserted into a scene: headers, keys of every kind, and broken TOML.
const ODD_LINES: &[&str] = &[
    "[render]",
    "[camera]",
    "[materials]",
    "[[shapes]]",
    "[[lights]]",
    "[[render]]",
    "[",
    "]]",
    "= =",
    "x = 1",
    "type = \"mesh\"",
    "type = \"sphere\"",
    "type = \"cube\"",
    "type = \"point\"",
    "type = \"directional\"",
    "file = \"missing.obj\"",
    "file = \"textures/checker.png\"",
    "file = \"textures\"",
    "texture = \"missing.png\"",
    "material = \"nothing\"",
    "material = \"white\"",
    "emission = [1, 1, 1]",
    "velocity = [1e38, 0, 0]",
    "scale = 1e-30",
    "scale = [1e30, 1, 1]",
    "radius = 1e30",
    "corner = [1e9, 0, 0]",
    "u = [0, 0, 0]",
    "m = { type = \"glossy\", albedo = [1, 1, 1], roughness = 0.5 }",
    "m = { type = \"diffuse\" }",
    "\"quoted key\" = 1",
    "a.b.c = 1",
    "name = \"\\u0000\"",
    "# comment",
    "",
];

/// One edit of a scene's text.
#[derive(Clone, Debug)]
enum Mutation {
    Delete(Index),
    Duplicate(Index),
    Swap(Index, Index),
    /// Replace the n-th number in the text with a value.
    Number(Index, String),
    Insert(Index, Index),
    Truncate(Index),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        1 => any::<Index>().prop_map(Mutation::Delete),
        1 => any::<Index>().prop_map(Mutation::Duplicate),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Mutation::Swap(a, b)),
        4 => (any::<Index>(), number_value()).prop_map(|(a, b)| Mutation::Number(a, b)),
        2 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Mutation::Insert(a, b)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
    ]
}

/// Byte ranges of the numbers in `text` (a digit, with the sign, digits, `.`, `e` and `_`
/// around it).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let part = |b: u8| b.is_ascii_digit() || b"+-.eE_".contains(&b);
    let mut ranges = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_digit() || (bytes[i] == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit)) {
            let start = i;
            while i < bytes.len() && part(bytes[i]) {
                i += 1;
            }
            ranges.push((start, i));
        } else {
            i += 1;
        }
    }
    ranges
}

fn apply(text: &str, mutation: &Mutation) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    match mutation {
        Mutation::Delete(i) if !lines.is_empty() => {
            lines.remove(i.index(lines.len()));
        }
        Mutation::Duplicate(i) if !lines.is_empty() => {
            let i = i.index(lines.len());
            lines.insert(i, lines[i].clone());
        }
        Mutation::Swap(a, b) if !lines.is_empty() => {
            let (a, b) = (a.index(lines.len()), b.index(lines.len()));
            lines.swap(a, b);
        }
        Mutation::Number(which, value) => {
            let ranges = numbers(text);
            if ranges.is_empty() {
                return text.to_owned();
            }
            let (start, end) = ranges[which.index(ranges.len())];
            return format!("{}{}{}", &text[..start], value, &text[end..]);
        }
        Mutation::Insert(at, line) => {
            lines.insert(at.index(lines.len() + 1), line.get(ODD_LINES).to_string());
        }
        Mutation::Truncate(at) => {
            let mut end = at.index(text.len() + 1);
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            return text[..end].to_owned();
        }
        _ => {}
    }
    lines.join("\n") + "\n"
}

/// An error must name the scene file, and a line inside it when it has one.
fn check_error(error: &SceneError, path: &Path, text: &str) -> Result<(), TestCaseError> {
    prop_assert_eq!(&error.file, path, "{}", error);
    prop_assert!(error.to_string().starts_with(&path.display().to_string()), "{}", error);
    if let Some(line) = error.line {
        prop_assert!(line >= 1 && line <= text.lines().count() + 1, "line {} of {} lines: {}", line, text.lines().count(), error);
    }
    prop_assert!(!error.message.is_empty());
    Ok(())
}

/// What the loader accepts is geometry the renderer can use: finite vertices and normals,
/// triangles with an area, spheres with a finite positive radius; and the GPU scene data
/// (BVH, light distribution) is built from it, or refused with an error, without a panic.
fn check_scene(scene: &Scene) -> Result<(), TestCaseError> {
    for t in &scene.triangles {
        prop_assert!(t.p.iter().all(|p| p.is_finite()), "{:?}", t);
        let n = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]);
        prop_assert!(n.length_squared() > 0.0 && n.length_squared().is_finite(), "{:?}", t);
        if let Some(normals) = t.n {
            prop_assert!(normals.iter().all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-3), "{:?}", t);
        }
        if let Some(uv) = t.uv {
            prop_assert!(uv.iter().all(|uv| uv.is_finite()), "{:?}", t);
        }
    }
    for s in &scene.spheres {
        prop_assert!(s.center.is_finite() && s.radius > 0.0 && (s.radius * s.radius).is_finite(), "{:?}", s);
    }
    let r = &scene.render;
    prop_assert!(r.width >= 1 && r.height >= 1 && r.iterations >= 1 && r.photons >= 1);
    prop_assert!(r.alpha > 0.0 && r.alpha < 1.0);
    let c = &scene.camera;
    prop_assert!(c.fov > 0.0 && c.fov < 180.0 && c.focus_distance.is_finite() && c.focus_distance > 0.0);
    match SceneData::new(scene) {
        Ok(data) => prop_assert!(data.power_total > 0.0 && data.power_total.is_finite()),
        Err(error) => prop_assert!(!error.message.is_empty()),
    }
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    /// Mutated canonical scenes: a scene or a placed error, never a panic.
    #[test]
    fn mutated_scenes_never_panic(
        which in any::<Index>(),
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let scenes = canonical_scenes();
        let (path, original) = which.get(&scenes);
        let text = mutations.iter().fold(original.clone(), |text, m| apply(&text, m));
        match scene::load_str(&text, path) {
            Ok(scene) => check_scene(&scene)?,
            Err(error) => check_error(&error, path, &text)?,
        }
    }
}

// --- OBJ files ---

/// A token where a number goes in an OBJ file: mostly plain numbers, some odd ones.
fn obj_number() -> impl Strategy<Value = String> {
    prop_oneof![
        40 => (-10.0f32..10.0).prop_map(|x| x.to_string()),
        1 => prop::sample::select(vec![
            "nan", "-nan", "inf", "-inf", "1e39", "-1e39", "0", "-0", "1e-45", "3.4e38", "x", "1,5",
            "",
        ])
        .prop_map(str::to_owned),
    ]
}

/// `count` numbers, mostly `usual` of them.
fn obj_numbers(usual: usize, others: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = String> {
    let count = prop_oneof![8 => Just(usual), 1 => others];
    count.prop_flat_map(|n| prop::collection::vec(obj_number(), n)).prop_map(|n| n.join(" "))
}

/// One face vertex: `v`, `v/vt`, `v//vn`, `v/vt/vn`, or a malformed one. The file starts
/// with three of each, so small indices mostly exist.
fn face_vertex() -> impl Strategy<Value = String> {
    let index = prop_oneof![
        30 => prop_oneof![1i64..=3, -3i64..=-1].prop_map(|i| i.to_string()),
        1 => prop::sample::select(vec![
            "0",
            "99",
            "99999999999999999999",
            "-9223372036854775808",
            "9223372036854775807",
            "x",
            "",
        ])
        .prop_map(str::to_owned),
    ];
    let form = prop_oneof![40 => 0..4usize, 1 => Just(4)];
    (form, prop::collection::vec(index, 4)).prop_map(|(form, i)| match form {
        0 => i[0].clone(),
        1 => format!("{}/{}", i[0], i[1]),
        2 => format!("{}//{}", i[0], i[2]),
        3 => format!("{}/{}/{}", i[0], i[1], i[2]),
        _ => i.join("/"),
    })
}

/// One line of an OBJ file.
fn obj_line() -> impl Strategy<Value = String> {
    prop_oneof![
        5 => obj_numbers(3, 0..=7).prop_map(|n| format!("v {n}")),
        1 => obj_numbers(4, 4..=6).prop_map(|n| format!("v {n}")),
        2 => obj_numbers(2, 0..=3).prop_map(|n| format!("vt {n}")),
        2 => obj_numbers(3, 0..=4).prop_map(|n| format!("vn {n}")),
        6 => prop_oneof![8 => 3..5usize, 1 => 0..8usize]
            .prop_flat_map(|n| prop::collection::vec(face_vertex(), n))
            .prop_map(|f| format!("f {}", f.join(" "))),
        1 => prop::collection::vec(face_vertex(), 0..3).prop_map(|f| format!("l {}", f.join(" "))),
        1 => prop::sample::select(vec![
            "o part", "g", "s 1", "usemtl none", "mtllib missing.mtl", "#", "", "p 1", "vp 0 0",
            "\u{0}",
        ])
        .prop_map(str::to_owned),
        1 => "[ -~]{0,24}",
    ]
}

/// Writes `obj` as `dir/name.obj` beside a scene that uses it as a mesh (with `extra` keys
/// in the shape); the scene's path.
fn mesh_scene(dir: &Path, name: &str, obj: &[u8], extra: &str) -> PathBuf {
    std::fs::write(dir.join(format!("{name}.obj")), obj).unwrap();
    let text = format!(
        "[render]\nwidth = 8\nheight = 8\niterations = 1\n\n[camera]\nposition = [0, 0, 5]\n\
         look_at = [0, 0, 0]\nfov = 40\n\n[materials]\n\
         white = {{ type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }}\n\
         [[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\nfile = \"{name}.obj\"\n{extra}"
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Vertices, and faces as vertex indices with a flag: written with relative indices.
type Mesh = (Vec<[f32; 3]>, Vec<(Vec<usize>, bool)>);

/// 3 to 11 random vertices and 1 to 9 faces of 3 or 4 distinct ones, each written with
/// absolute indices or (when its flag is set) relative ones.
fn valid_mesh() -> impl Strategy<Value = Mesh> {
    prop::collection::vec(prop::array::uniform3(-10.0f32..10.0), 3..12).prop_flat_map(|vertices| {
        let n = vertices.len();
        let face = (prop::sample::subsequence((0..n).collect::<Vec<usize>>(), 3..=n.min(4)), any::<bool>());
        (Just(vertices), prop::collection::vec(face, 1..10))
    })
}

/// Random OBJ text: a scene or an error at the mesh's `file` key (or the shape), never
/// a panic.
#[test]
fn random_obj_files_never_panic() {
    let dir = common::scratch("fuzz-random-obj");
    proptest!(config(), |(
        lines in prop::collection::vec(obj_line(), 0..16),
        smooth in any::<bool>(),
        bytes in prop::option::weighted(0.1, prop::collection::vec(any::<u8>(), 0..16)),
    )| {
        // Three vertices with texture coordinates and normals, then the random lines.
        let start = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
                     vn 0 0 1\nvn 0 0 1\nvn 0 0 1\n";
        let mut obj = (start.to_owned() + &lines.join("\n")).into_bytes();
        if let Some(bytes) = bytes {
            obj.extend(bytes);
        }
        let path = mesh_scene(&dir, "random", &obj, &format!("smooth = {smooth}\n"));
        match scene::load(&path) {
            Ok(scene) => check_scene(&scene)?,
            Err(error) => {
                let text = std::fs::read_to_string(&path).unwrap();
                check_error(&error, &path, &text)?;
                // The OBJ's own errors are at `file`; geometry beyond 32-bit floats at the shape.
                let line = match error.key.as_deref() {
                    Some("shapes[0].file") => 16,
                    Some("shapes[0]") => 13,
                    _ => return Err(TestCaseError::fail(format!("wrong key: {error}"))),
                };
                prop_assert_eq!(error.line, Some(line), "{}", error);
            }
        }
    });
}

/// Well-formed OBJ files (faces of distinct vertices, absolute or relative indices, with
/// or without texture coordinates and normals) load, one triangle for each face corner
/// past the second.
#[test]
fn valid_obj_files_load() {
    let dir = common::scratch("fuzz-valid-obj");
    proptest!(config(), |(
        (vertices, faces) in valid_mesh(),
        attributes in 0..4u8,
    )| {
        let (with_vt, with_vn) = (attributes & 1 != 0, attributes & 2 != 0);
        let mut obj = String::new();
        for v in &vertices {
            obj += &format!("v {} {} {}\n", v[0], v[1], v[2]);
            if with_vt {
                obj += &format!("vt {} {}\n", v[0], v[1]);
            }
            if with_vn {
                obj += "vn 0 0 1\n";
            }
        }
        let n = vertices.len();
        let mut corners = 0;
        for (face, relative) in &faces {
            let index = |i: usize| {
                if *relative {
                    format!("-{}", n - i)
                } else {
                    (i + 1).to_string()
                }
            };
            let vertex = |i: usize| match (with_vt, with_vn) {
                (false, false) => index(i),
                (true, false) => format!("{}/{}", index(i), index(i)),
                (false, true) => format!("{}//{}", index(i), index(i)),
                (true, true) => format!("{}/{}/{}", index(i), index(i), index(i)),
            };
            let vertices: Vec<String> = face.iter().map(|&i| vertex(i)).collect();
            obj += &format!("f {}\n", vertices.join(" "));
            corners += face.len() - 2;
        }
        let path = mesh_scene(&dir, "valid", obj.as_bytes(), "smooth = true\n");
        let scene = scene::load(&path).map_err(|e| TestCaseError::fail(format!("{e}\n{obj}")))?;
        check_scene(&scene)?;
        // Random vertices are in general position: no triangle is degenerate.
        prop_assert_eq!(scene.triangles.len(), corners, "{}", obj);
        prop_assert_eq!(scene.triangles.iter().all(|t| t.uv.is_some()), with_vt);
    });
}

// --- PLY and Mitsuba .serialized files ---

/// Writes `bytes` as mesh file `dir/file` beside a scene `dir/file.toml` that uses it (with
/// `extra` keys in the shape; the scene is rewritten only when its text changes, writing
/// files being slow); the scene's path. Its `file` key is on line 16, the shape on 13.
fn mesh_file_scene(dir: &Path, file: &str, bytes: &[u8], extra: &str) -> PathBuf {
    std::fs::write(dir.join(file), bytes).unwrap();
    let text = format!(
        "[render]\nwidth = 8\nheight = 8\niterations = 1\n\n[camera]\nposition = [0, 0, 5]\n\
         look_at = [0, 0, 0]\nfov = 40\n\n[materials]\n\
         white = {{ type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }}\n\
         [[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\nfile = \"{file}\"\n{extra}"
    );
    let path = dir.join(format!("{file}.toml"));
    if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
        std::fs::write(&path, text).unwrap();
    }
    path
}

/// Loads a scene whose one shape is a mesh file: a scene that passes `check_scene`, or an
/// error at the mesh's `file` key (or, for geometry beyond 32-bit floats, the shape).
fn check_mesh_file_scene(path: &Path) -> Result<(), TestCaseError> {
    match scene::load(path) {
        Ok(scene) => check_scene(&scene),
        Err(error) => {
            let text = std::fs::read_to_string(path).unwrap();
            check_error(&error, path, &text)?;
            let line = match error.key.as_deref() {
                Some("shapes[0].file") => 16,
                Some("shapes[0]") => 13,
                _ => return Err(TestCaseError::fail(format!("wrong key: {error}"))),
            };
            prop_assert_eq!(error.line, Some(line), "{}", error);
            Ok(())
        }
    }
}

/// A quad (one four-sided face) and a triangle, with normals and texture coordinates, as
/// ASCII PLY.
const PLY_ASCII: &str = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
    property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\n\
    property float v\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n\
    0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n0.5 0.5 1 0 1 1 0.5 0.5\n\
    4 0 1 2 3\n3 0 4 1\n";

/// [`PLY_ASCII`] in `encoding`: 0 ASCII, 1 binary little endian, 2 big endian.
fn valid_ply(encoding: u8) -> Vec<u8> {
    if encoding == 0 {
        return PLY_ASCII.as_bytes().to_vec();
    }
    let big = encoding == 2;
    let (header, payload) = PLY_ASCII.split_once("end_header\n").unwrap();
    let format = if big { "binary_big_endian" } else { "binary_little_endian" };
    let mut out = header.replace("ascii", format).into_bytes();
    out.extend(b"end_header\n");
    let lines: Vec<&str> = payload.lines().collect();
    for line in &lines[..5] {
        for x in line.split(' ').map(|x| x.parse::<f32>().unwrap()) {
            out.extend(if big { x.to_be_bytes() } else { x.to_le_bytes() });
        }
    }
    for line in &lines[5..] {
        let mut words = line.split(' ');
        out.push(words.next().unwrap().parse().unwrap());
        for i in words.map(|i| i.parse::<i32>().unwrap()) {
            out.extend(if big { i.to_be_bytes() } else { i.to_le_bytes() });
        }
    }
    out
}

/// PLY header lines, valid and not, for random headers.
const PLY_LINES: &[&str] = &[
    "format ascii 1.0",
    "format binary_little_endian 1.0",
    "format binary_big_endian 1.0",
    "format ascii 2.0",
    "element vertex 3",
    "element vertex 0",
    "element vertex 4294967296",
    "element vertex 99999999999999999999",
    "element face 1",
    "element face 18446744073709551615",
    "element edge 2",
    "property float x",
    "property double y",
    "property uchar z",
    "property int z",
    "property float nx",
    "property float u",
    "property float v",
    "property list uchar int vertex_indices",
    "property list int uint vertex_index",
    "property list uint float vertex_indices",
    "property list char char vertex_indices",
    "property list uchar int x",
    "comment x",
    "obj_info y",
    "end_header",
    "",
];

/// One edit of a file's bytes.
#[derive(Clone, Debug)]
enum ByteEdit {
    Xor(Index, u8),
    Truncate(Index),
    Insert(Index, Vec<u8>),
    Delete(Index, usize),
    /// Overwrite with the low `width` bytes of an odd number, little or big endian.
    Word(Index, u64, usize, bool),
}

/// Numbers that counts, offsets, indices and floats are replaced with.
const ODD_WORDS: &[u64] = &[
    0,
    1,
    2,
    3,
    4,
    5,
    0xff,
    0xffff,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    1 << 32,
    1 << 40,
    u64::MAX,
    0x7fc0_0000,           // f32 NaN
    0x7f80_0000,           // f32 infinity
    0x7ff8_0000_0000_0000, // f64 NaN
    0x7fef_ffff_ffff_ffff, // f64 maximum
    0x3f80_0000,           // f32 1
];

fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    prop_oneof![
        3 => (any::<Index>(), 1..=255u8).prop_map(|(i, x)| ByteEdit::Xor(i, x)),
        1 => any::<Index>().prop_map(ByteEdit::Truncate),
        1 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..16)).prop_map(|(i, b)| ByteEdit::Insert(i, b)),
        1 => (any::<Index>(), 1..16usize).prop_map(|(i, n)| ByteEdit::Delete(i, n)),
        3 => (any::<Index>(), prop::sample::select(ODD_WORDS), prop::sample::select(vec![1usize, 2, 4, 8]), any::<bool>())
            .prop_map(|(i, w, n, big)| ByteEdit::Word(i, w, n, big)),
    ]
}

fn apply_bytes(bytes: &mut Vec<u8>, edit: &ByteEdit) {
    let len = bytes.len();
    match edit {
        ByteEdit::Xor(i, x) if len > 0 => bytes[i.index(len)] ^= x,
        ByteEdit::Truncate(i) => bytes.truncate(i.index(len + 1)),
        ByteEdit::Insert(i, new) => {
            let at = i.index(len + 1);
            bytes.splice(at..at, new.iter().copied());
        }
        ByteEdit::Delete(i, n) if len > 0 => {
            let at = i.index(len);
            bytes.drain(at..(at + n).min(len));
        }
        ByteEdit::Word(i, word, width, big) if len > 0 => {
            let at = i.index(len);
            let le = word.to_le_bytes();
            let word: Vec<u8> = if *big { le[..*width].iter().rev().copied().collect() } else { le[..*width].to_vec() };
            for (k, b) in word.into_iter().enumerate() {
                if let Some(byte) = bytes.get_mut(at + k) {
                    *byte = b;
                }
            }
        }
        _ => {}
    }
}

/// A PLY file: edits of a valid one in any encoding, a header of random lines and random
/// payload bytes, or random bytes.
fn ply_file() -> impl Strategy<Value = Vec<u8>> {
    let edited = (0..3u8, prop::collection::vec(byte_edit(), 1..4)).prop_map(|(encoding, edits)| {
        let mut bytes = valid_ply(encoding);
        edits.iter().for_each(|edit| apply_bytes(&mut bytes, edit));
        bytes
    });
    let header = (prop::collection::vec(prop::sample::select(PLY_LINES), 0..14), prop::collection::vec(any::<u8>(), 0..64))
        .prop_map(|(lines, payload)| {
            let mut bytes = format!("ply\n{}\n", lines.join("\n")).into_bytes();
            bytes.extend(payload);
            bytes
        });
    // Edits of the payload alone get past the header more often.
    let payload_edited = (0..3u8, prop::collection::vec(byte_edit(), 1..4)).prop_map(|(encoding, edits)| {
        let bytes = valid_ply(encoding);
        let end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let mut payload = bytes[end..].to_vec();
        edits.iter().for_each(|edit| apply_bytes(&mut payload, edit));
        [&bytes[..end], &payload].concat()
    });
    prop_oneof![3 => edited, 3 => payload_edited, 3 => header, 1 => prop::collection::vec(any::<u8>(), 0..64)]
}

/// The decompressed data of a `.serialized` shape (Mitsuba 3's `serialized` plugin): a
/// quad and a triangle with normals, texture coordinates and colours as `flags` says.
fn serialized_body(version: u16, flags: u32) -> Vec<u8> {
    let double = flags & 0x2000 != 0;
    let mut body = flags.to_le_bytes().to_vec();
    if version == 4 {
        body.extend(b"fuzz\0");
    }
    body.extend(5u64.to_le_bytes());
    body.extend(3u64.to_le_bytes());
    let positions = [0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0., 0.5, 0.5, 1.];
    let mut reals: Vec<f32> = positions.to_vec();
    for (flag, per_vertex) in [(0x1, 3), (0x2, 2), (0x8, 3)] {
        if flags & flag != 0 {
            reals.extend((0..5 * per_vertex).map(|i| (i % 3) as f32 * 0.5));
        }
    }
    for x in reals {
        if double {
            body.extend(f64::from(x).to_le_bytes());
        } else {
            body.extend(x.to_le_bytes());
        }
    }
    body.extend([0u32, 1, 2, 0, 2, 3, 0, 4, 1].iter().flat_map(|i| i.to_le_bytes()));
    body
}

/// A `.serialized` file of two shapes: edits of the decompressed data of each (so that
/// they reach past the decompressor), edits of the file's bytes, or random data behind a
/// valid header.
fn serialized_file_strategy() -> impl Strategy<Value = Vec<u8>> {
    let flags = prop_oneof![
        4 => (0..16u32).prop_map(|bits| (bits & 0xb) | if bits & 4 != 0 { 0x2000 } else { 0x1000 } | (bits & 1) << 4),
        1 => any::<u32>(),
    ];
    let version = prop_oneof![8 => prop::sample::select(vec![3u16, 4]), 1 => any::<u16>()];
    let edits = || prop::collection::vec(byte_edit(), 0..3);
    let edited = (version, flags.clone(), flags, edits(), edits(), edits()).prop_map(|(version, f0, f1, e0, e1, file)| {
        let mut bodies = [serialized_body(version, f0), serialized_body(version, f1)];
        for (body, edits) in bodies.iter_mut().zip([e0, e1]) {
            edits.iter().for_each(|edit| apply_bytes(body, edit));
        }
        let mut bytes = serialized_file(&bodies, version);
        file.iter().for_each(|edit| apply_bytes(&mut bytes, edit));
        bytes
    });
    let random = (prop::sample::select(vec![3u16, 4]), prop::collection::vec(any::<u8>(), 0..96), any::<bool>()).prop_map(
        |(version, data, compress)| {
            if compress {
                serialized_file(&[data], version)
            } else {
                [&0x041Cu16.to_le_bytes()[..], &version.to_le_bytes(), &data].concat()
            }
        },
    );
    prop_oneof![8 => edited, 2 => random, 1 => prop::collection::vec(any::<u8>(), 0..64)]
}

/// PLY files, edited valid ones and random ones: a scene or an error at the mesh's
/// `file` key, never a panic.
#[test]
fn random_ply_files_never_panic() {
    let dir = common::scratch("fuzz-random-ply");
    proptest!(config(), |(bytes in ply_file(), smooth in any::<bool>())| {
        let path = mesh_file_scene(&dir, "random.ply", &bytes, &format!("smooth = {smooth}\n"));
        check_mesh_file_scene(&path)?;
    });
}

/// Mitsuba `.serialized` files, edited valid ones and random ones, read at shape 0, 1
/// or 2: a scene or an error at the mesh's `file` key, never a panic.
#[test]
fn random_serialized_files_never_panic() {
    let dir = common::scratch("fuzz-random-serialized");
    proptest!(config(), |(
        bytes in serialized_file_strategy(),
        shape_index in 0..3u32,
        smooth in any::<bool>(),
    )| {
        let path = mesh_file_scene(&dir, "random.serialized", &bytes, &format!("smooth = {smooth}\nshape_index = {shape_index}\n"));
        check_mesh_file_scene(&path)?;
    });
}

// --- Mitsuba scene XML ---

/// A fresh folder holding the Mitsuba test scenes' meshes, textures and included fragment,
/// where mutated copies of the scenes are written (one file per case, under a name of its own).
fn mitsuba_dir() -> common::Scratch {
    let source = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/mitsuba"));
    let dir = common::scratch("fuzz-mitsuba");
    for folder in ["meshes", "textures"] {
        std::fs::create_dir_all(dir.join(folder)).unwrap();
        for entry in std::fs::read_dir(source.join(folder)).unwrap() {
            let path = entry.unwrap().path();
            std::fs::copy(&path, dir.join(folder).join(path.file_name().unwrap())).unwrap();
        }
    }
    std::fs::copy(source.join("legacy-walls.xml"), dir.join("legacy-walls.xml")).unwrap();
    dir
}

/// The Mitsuba test scenes' texts: every scene of scenes/mitsuba but the fragment
/// legacy-walls.xml.
fn mitsuba_scenes() -> Vec<String> {
    let source = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/mitsuba"));
    let mut names: Vec<PathBuf> = std::fs::read_dir(source)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml") && !p.ends_with("legacy-walls.xml"))
        .collect();
    names.sort();
    names.iter().map(|p| std::fs::read_to_string(p).unwrap()).collect()
}

/// Values an XML attribute is replaced with.
const ODD_ATTRIBUTES: &[&str] =
    &["", "nan", "1e39", "-1", "0", "$undefined", "$", "#zz0000", "1, 2", "1 2 3 4", "true", "x", "ggx", "none", "\u{1F600}"];

/// Mutated Mitsuba XML scenes (lines, numbers and attribute values): a scene or an error
/// that names a file of the scene and a line inside it, never a panic.
#[test]
fn mutated_mitsuba_scenes_never_panic() {
    let dir = mitsuba_dir();
    proptest!(config(), |(
        which in any::<Index>(),
        mutations in prop::collection::vec(mutation(), 0..3),
        attribute in any::<Index>(),
        value in any::<Index>(),
        edit_attribute in any::<bool>(),
        case in any::<u64>(),
    )| {
        let scenes = mitsuba_scenes();
        let mut text = mutations.iter().fold(which.get(&scenes).clone(), |text, m| apply(&text, m));
        if edit_attribute {
            // Replace the value of one attribute: the text between a `="` and the next `"`.
            let starts: Vec<usize> = text.match_indices("=\"").map(|(i, _)| i + 2).collect();
            if !starts.is_empty() {
                let start = starts[attribute.index(starts.len())];
                if let Some(len) = text[start..].find('"') {
                    text = format!("{}{}{}", &text[..start], value.get(ODD_ATTRIBUTES), &text[start + len..]);
                }
            }
        }
        let path = dir.join(format!("case-{case:016x}.xml"));
        std::fs::write(&path, &text).unwrap();
        let result = scene::load(&path);
        let _ = std::fs::remove_file(&path);
        match result {
            Ok(scene) => check_scene(&scene)?,
            Err(error) => {
                prop_assert!(error.file == path || error.file.starts_with(&dir), "{}", error);
                prop_assert!(error.to_string().starts_with(&error.file.display().to_string()), "{}", error);
                prop_assert!(!error.message.is_empty());
                if let (Some(line), true) = (error.line, error.file == path) {
                    prop_assert!(line >= 1 && line <= text.lines().count() + 1, "line {} of {}: {}", line, text.lines().count(), error);
                }
            }
        }
    });
}

/// Tokens that a token of a pbrt-v4 scene is replaced with.
const ODD_PBRT_TOKENS: &[&str] = &[
    "",
    "[",
    "]",
    "\"",
    "nan",
    "1e39",
    "-1",
    "0",
    "\"float\"",
    "\"float x\"",
    "Shape",
    "AttributeEnd",
    "WorldBegin",
    "\"texture reflectance\" \"x\"",
    "#",
    "\"spectrum eta\" \"glass-BK7\"",
    "\"blackbody L\" [ 0 ]",
    "ObjectInstance \"cube\"",
    "MediumInterface \"fog\" \"\"",
    "\"float power\" 2",
    "\"string materials\" [ \"red\" ]",
];

/// The pbrt-v4 scenes mutated: the Cornell box (includes, instances) and the files of
/// loopsubdiv, area-light power, mix and media.
const PBRT_SEEDS: &[&str] = &["cornell-box.pbrt", "loopsubdiv.pbrt", "area-power.pbrt", "mix.pbrt", "media.pbrt", "coated.pbrt"];

proptest! {
    #![proptest_config(Config { cases: 1024, ..config() })]

    /// Mutated pbrt-v4 scenes (lines, numbers, tokens) through the tokenizer and reader: a
    /// scene or an error that names the scene or its included file, and a line inside it,
    /// never a panic.
    #[test]
    fn mutated_pbrt_scenes_never_panic(
        seed in any::<Index>(),
        mutations in prop::collection::vec(mutation(), 0..3),
        token in any::<Index>(),
        value in any::<Index>(),
        edit_token in any::<bool>(),
    ) {
        let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/scenes/pbrt"));
        let path = dir.join(seed.get(PBRT_SEEDS));
        let original = std::fs::read_to_string(&path).unwrap();
        let mut text = mutations.iter().fold(original, |text, m| apply(&text, m));
        if edit_token {
            let starts: Vec<(usize, usize)> = text
                .split_whitespace()
                .map(|w| (w.as_ptr() as usize - text.as_ptr() as usize, w.len()))
                .collect();
            if !starts.is_empty() {
                let (at, len) = starts[token.index(starts.len())];
                text = format!("{}{}{}", &text[..at], value.get(ODD_PBRT_TOKENS), &text[at + len..]);
            }
        }
        let (result, _) = scene::pbrt::load_str(&text, &path);
        match result {
            Ok(scene) => check_scene(&scene)?,
            Err(error) => {
                prop_assert!(error.file.starts_with(dir), "{}", error);
                prop_assert!(!error.message.is_empty());
                if let (Some(line), true) = (error.line, error.file == path) {
                    prop_assert!(line >= 1 && line <= text.lines().count() + 1, "line {} of {}: {}", line, text.lines().count(), error);
                }
            }
        }
    }
}
