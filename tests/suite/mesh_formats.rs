//! Mesh files behind a TOML `mesh` shape: PLY (ASCII, binary little and big endian) and
//! Mitsuba `.serialized` (versions 3 and 4) load to the same triangles as the same mesh in
//! OBJ, keep their normals and texture coordinates, `shape_index` picks a shape, and broken
//! files give an error at the shape's `file` key naming the mesh file, never a panic. The
//! files are written here, by small writers that follow the formats' descriptions.
//!
//! Also: the canonical and gallery scenes (OBJ meshes, flat and smooth) load to the very
//! triangles they did before PLY and `.serialized` support (hashes of every bit).

use crate::common;
use crate::common::serialized_writer;
use serialized_writer::serialized_file;
use sppm_gpu::scene::{self, Scene, SceneError};
use std::path::{Path, PathBuf};

// --- Meshes and writers ---

/// A polygon mesh to write in every format: faces are fans (serialized files get them as
/// triangles).
#[derive(Clone, Debug)]
struct TestMesh {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Option<Vec<[f32; 2]>>,
    faces: Vec<Vec<u32>>,
}

impl TestMesh {
    fn without_attributes(&self) -> TestMesh {
        TestMesh { normals: None, uvs: None, ..self.clone() }
    }

    fn triangles(&self) -> Vec<[u32; 3]> {
        self.faces.iter().flat_map(|f| (1..f.len() - 1).map(|k| [f[0], f[k], f[k + 1]])).collect()
    }
}

/// A tetrahedron, wound outwards, with (not unit) normals and texture coordinates.
fn tetrahedron() -> TestMesh {
    TestMesh {
        positions: vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        normals: Some(vec![[-1.0, -1.0, -1.0], [1.0, 0.1, 0.1], [0.1, 1.0, 0.1], [0.1, 0.1, 2.0]]),
        uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.25]]),
        faces: vec![vec![0, 2, 1], vec![0, 3, 2], vec![0, 1, 3], vec![1, 2, 3]],
    }
}

/// A planar quad as one four-sided face.
fn quad() -> TestMesh {
    TestMesh {
        positions: vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
        normals: Some(vec![[0.0, 0.0, 1.0], [0.0, 0.6, 0.8], [0.0, 0.0, 3.0], [0.6, 0.0, 0.8]]),
        uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
        faces: vec![vec![0, 1, 2, 3]],
    }
}

fn obj(mesh: &TestMesh) -> Vec<u8> {
    let mut text = String::new();
    for p in &mesh.positions {
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for uv in mesh.uvs.iter().flatten() {
        text += &format!("vt {} {}\n", uv[0], uv[1]);
    }
    for n in mesh.normals.iter().flatten() {
        text += &format!("vn {} {} {}\n", n[0], n[1], n[2]);
    }
    for face in &mesh.faces {
        let corner = |i: &u32| match (&mesh.uvs, &mesh.normals) {
            (None, None) => format!("{}", i + 1),
            (Some(_), None) => format!("{0}/{0}", i + 1),
            (None, Some(_)) => format!("{0}//{0}", i + 1),
            (Some(_), Some(_)) => format!("{0}/{0}/{0}", i + 1),
        };
        text += &format!("f {}\n", face.iter().map(corner).collect::<Vec<_>>().join(" "));
    }
    text.into_bytes()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// How a PLY file is written: its encoding and the types and names of its properties.
#[derive(Clone, Copy, Debug)]
struct PlyStyle {
    encoding: Encoding,
    position: &'static str,
    normal: &'static str,
    uv_names: (&'static str, &'static str),
    uv: &'static str,
    list_count: &'static str,
    list_index: &'static str,
    list_name: &'static str,
    /// An element of its own before `vertex`, a colour among the vertex properties and one
    /// after the list in each face, and an `edge` element after `face`: all skipped.
    extras: bool,
}

const ASCII: PlyStyle = PlyStyle {
    encoding: Encoding::Ascii,
    position: "float",
    normal: "float",
    uv_names: ("u", "v"),
    uv: "float",
    list_count: "uchar",
    list_index: "int",
    list_name: "vertex_indices",
    extras: true,
};
const LITTLE: PlyStyle = PlyStyle {
    encoding: Encoding::Little,
    position: "double",
    normal: "float32",
    uv_names: ("s", "t"),
    uv: "double",
    list_count: "uint8",
    list_index: "uint32",
    list_name: "vertex_index",
    extras: true,
};
const BIG: PlyStyle = PlyStyle {
    encoding: Encoding::Big,
    position: "short",
    normal: "double",
    uv_names: ("texture_u", "texture_v"),
    uv: "float",
    list_count: "int",
    list_index: "ushort",
    list_name: "vertex_indices",
    extras: false,
};

/// One number of PLY type `ty` in `encoding`.
fn put(out: &mut Vec<u8>, encoding: Encoding, ty: &str, x: f64) {
    if encoding == Encoding::Ascii {
        let word = match ty {
            "float" | "float32" => format!("{}", x as f32),
            "double" | "float64" => format!("{x}"),
            _ => format!("{}", x as i64),
        };
        out.extend(word.as_bytes());
        out.push(b' ');
        return;
    }
    let bytes: Vec<u8> = match ty {
        "char" | "int8" => vec![x as i8 as u8],
        "uchar" | "uint8" => vec![x as u8],
        "short" | "int16" => (x as i16).to_le_bytes().to_vec(),
        "ushort" | "uint16" => (x as u16).to_le_bytes().to_vec(),
        "int" | "int32" => (x as i32).to_le_bytes().to_vec(),
        "uint" | "uint32" => (x as u32).to_le_bytes().to_vec(),
        "float" | "float32" => (x as f32).to_le_bytes().to_vec(),
        "double" | "float64" => x.to_le_bytes().to_vec(),
        _ => panic!("type {ty}"),
    };
    match encoding {
        Encoding::Big => out.extend(bytes.iter().rev()),
        _ => out.extend(bytes),
    }
}

fn ply(mesh: &TestMesh, style: PlyStyle) -> Vec<u8> {
    let format = match style.encoding {
        Encoding::Ascii => "ascii",
        Encoding::Little => "binary_little_endian",
        Encoding::Big => "binary_big_endian",
    };
    let mut header = format!("ply\nformat {format} 1.0\ncomment written by tests/suite/mesh_formats.rs\n");
    if style.extras {
        header += "element material 2\nproperty float shininess\nproperty list uchar float spectrum\n";
    }
    header += &format!("element vertex {}\n", mesh.positions.len());
    for axis in ["x", "y", "z"] {
        header += &format!("property {} {axis}\n", style.position);
    }
    if mesh.normals.is_some() {
        for axis in ["nx", "ny", "nz"] {
            header += &format!("property {} {axis}\n", style.normal);
        }
    }
    if style.extras {
        header += "property uchar red\n";
    }
    if mesh.uvs.is_some() {
        header += &format!("property {} {}\nproperty {} {}\n", style.uv, style.uv_names.0, style.uv, style.uv_names.1);
    }
    header += &format!("element face {}\n", mesh.faces.len());
    header += &format!("property list {} {} {}\n", style.list_count, style.list_index, style.list_name);
    if style.extras {
        header += "property float area\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n";
    }
    header += "end_header\n";

    let mut out = header.into_bytes();
    let e = style.encoding;
    let end_line = |out: &mut Vec<u8>| {
        if e == Encoding::Ascii {
            out.pop();
            out.push(b'\n');
        }
    };
    if style.extras {
        for _ in 0..2 {
            put(&mut out, e, "float", 0.5);
            put(&mut out, e, "uchar", 2.0);
            put(&mut out, e, "float", 1.0);
            put(&mut out, e, "float", 2.0);
            end_line(&mut out);
        }
    }
    for (i, p) in mesh.positions.iter().enumerate() {
        p.iter().for_each(|&x| put(&mut out, e, style.position, x.into()));
        if let Some(normals) = &mesh.normals {
            normals[i].iter().for_each(|&x| put(&mut out, e, style.normal, x.into()));
        }
        if style.extras {
            put(&mut out, e, "uchar", 200.0);
        }
        if let Some(uvs) = &mesh.uvs {
            uvs[i].iter().for_each(|&x| put(&mut out, e, style.uv, x.into()));
        }
        end_line(&mut out);
    }
    for face in &mesh.faces {
        put(&mut out, e, style.list_count, face.len() as f64);
        face.iter().for_each(|&i| put(&mut out, e, style.list_index, i.into()));
        if style.extras {
            put(&mut out, e, "float", 1.5);
        }
        end_line(&mut out);
    }
    if style.extras {
        put(&mut out, e, "int", 0.0);
        put(&mut out, e, "int", 1.0);
        end_line(&mut out);
    }
    out
}

/// How a shape is written in a `.serialized` file.
#[derive(Clone, Copy, Debug)]
struct SerialStyle {
    double: bool,
    /// Vertex colours, which the reader skips.
    colors: bool,
    face_normals: bool,
}

const SINGLE: SerialStyle = SerialStyle { double: false, colors: false, face_normals: false };
const DOUBLE: SerialStyle = SerialStyle { double: true, colors: true, face_normals: true };

/// The decompressed data of one shape (Mitsuba 3's documentation of the `serialized` plugin).
fn serialized_body(mesh: &TestMesh, style: SerialStyle, version: u16) -> Vec<u8> {
    let flags = u32::from(mesh.normals.is_some())
        | if mesh.uvs.is_some() { 0x2 } else { 0 }
        | if style.colors { 0x8 } else { 0 }
        | if style.face_normals { 0x10 } else { 0 }
        | if style.double { 0x2000 } else { 0x1000 };
    let mut body = flags.to_le_bytes().to_vec();
    if version == 4 {
        body.extend(b"test shape\0");
    }
    let triangles = mesh.triangles();
    body.extend((mesh.positions.len() as u64).to_le_bytes());
    body.extend((triangles.len() as u64).to_le_bytes());
    let mut reals = |values: &mut dyn Iterator<Item = f32>| {
        for x in values {
            if style.double {
                body.extend(f64::from(x).to_le_bytes());
            } else {
                body.extend(x.to_le_bytes());
            }
        }
    };
    reals(&mut mesh.positions.iter().flatten().copied());
    reals(&mut mesh.normals.iter().flatten().flatten().copied());
    reals(&mut mesh.uvs.iter().flatten().flatten().copied());
    if style.colors {
        reals(&mut std::iter::repeat_n(0.25, 3 * mesh.positions.len()));
    }
    body.extend(triangles.iter().flatten().flat_map(|i| i.to_le_bytes()));
    body
}

fn serialized(meshes: &[(&TestMesh, SerialStyle)], version: u16) -> Vec<u8> {
    let bodies: Vec<Vec<u8>> = meshes.iter().map(|(mesh, style)| serialized_body(mesh, *style, version)).collect();
    serialized_file(&bodies, version)
}

// --- Scenes ---

/// The line of the mesh shape's `file` key in [`mesh_scene`].
const FILE_LINE: usize = 17;

/// Writes `bytes` as `dir/file` and a scene `dir/scene.toml` with it as its one mesh (with
/// `extra` keys), and loads the scene.
fn load_mesh(dir: &Path, file: &str, bytes: &[u8], extra: &str) -> (PathBuf, Result<Scene, SceneError>) {
    std::fs::write(dir.join(file), bytes).unwrap();
    let text = format!(
        "[render]\nwidth = 8\nheight = 8\niterations = 1\n\n[camera]\nposition = [0, 0, 5]\n\
         look_at = [0, 0, 0]\nfov = 40\n\n[materials]\n\
         white = {{ type = \"diffuse\", albedo = [0.5, 0.5, 0.5] }}\n\n\
         [[shapes]]\ntype = \"mesh\"\nmaterial = \"white\"\nfile = \"{file}\"\n{extra}\n"
    );
    assert_eq!(text.lines().nth(FILE_LINE - 1), Some(format!("file = \"{file}\"").as_str()));
    let path = dir.join("scene.toml");
    std::fs::write(&path, &text).unwrap();
    let result = scene::load(&path);
    (path, result)
}

#[track_caller]
fn load_ok(dir: &Path, file: &str, bytes: &[u8], extra: &str) -> Scene {
    load_mesh(dir, file, bytes, extra).1.unwrap_or_else(|e| panic!("{e}"))
}

/// Loading `bytes` as mesh `file` fails at the `file` key, naming the mesh file, with a
/// message holding each of `words`.
#[track_caller]
fn assert_mesh_error(dir: &Path, file: &str, bytes: &[u8], extra: &str, words: &[&str]) {
    let (path, result) = load_mesh(dir, file, bytes, extra);
    let error = match result {
        Ok(_) => panic!("{file} loaded without error"),
        Err(error) => error,
    };
    assert_eq!(error.file, path, "{error}");
    assert_eq!((error.line, error.key.as_deref()), (Some(FILE_LINE), Some("shapes[0].file")), "{error}");
    assert!(error.message.contains(file), "the message does not name {file}: {error}");
    for word in words {
        assert!(error.message.contains(word), "{word:?} is not in the message of: {error}");
    }
}

// --- Tests ---

/// The same mesh as OBJ, ASCII PLY, binary PLY in both byte orders, `.serialized` v3 in
/// single precision and v4 in double: the same triangles, flat and smooth, with and
/// without normals and texture coordinates, under a transform.
#[test]
fn every_format_gives_the_same_triangles() {
    let dir = common::scratch("mesh-formats-same");
    let transform = "scale = [1, 2, 3]\nrotate = [10, 30, 0]\ntranslate = [1, 0, -1]\n";
    for (name, full) in [("tetrahedron", tetrahedron()), ("quad", quad())] {
        for mesh in [full.clone(), full.without_attributes()] {
            for smooth in [false, true] {
                let extra = format!("smooth = {smooth}\n{transform}");
                let expected = load_ok(&dir, "mesh.obj", &obj(&mesh), &extra).triangles;
                assert_eq!(expected.len(), mesh.triangles().len());
                assert!(expected.iter().all(|t| t.uv.is_some() == mesh.uvs.is_some() && t.n.is_some() == smooth));
                let files = [
                    ("ascii.ply", ply(&mesh, ASCII)),
                    ("little.ply", ply(&mesh, LITTLE)),
                    ("big.ply", ply(&mesh, BIG)),
                    ("v3.serialized", serialized(&[(&mesh, SINGLE)], 3)),
                    ("v4.serialized", serialized(&[(&mesh, DOUBLE)], 4)),
                ];
                for (file, bytes) in files {
                    let triangles = load_ok(&dir, file, &bytes, &extra).triangles;
                    assert_eq!(triangles, expected, "{name} as {file}, smooth = {smooth}, normals {:?}", mesh.normals.is_some());
                }
            }
        }
    }
}

/// Normals and texture coordinates come through as the file has them (normals made unit
/// length); the extension's case does not matter.
#[test]
fn normals_and_texture_coordinates_are_kept() {
    let dir = common::scratch("mesh-formats-attributes");
    let mesh = tetrahedron();
    let normals = mesh.normals.clone().unwrap();
    let uvs = mesh.uvs.clone().unwrap();
    for (file, bytes) in [("a.PLY", ply(&mesh, LITTLE)), ("b.Serialized", serialized(&[(&mesh, SINGLE)], 4))] {
        let scene = load_ok(&dir, file, &bytes, "smooth = true");
        assert_eq!(scene.triangles.len(), 4);
        for (t, face) in scene.triangles.iter().zip(mesh.triangles()) {
            for (k, &i) in face.iter().enumerate() {
                let i = i as usize;
                assert_eq!(t.p[k].to_array(), mesh.positions[i]);
                assert_eq!(t.uv.unwrap()[k].to_array(), uvs[i]);
                let n = glam::Vec3::from_array(normals[i]).normalize();
                assert!((t.n.unwrap()[k] - n).length() < 1e-6, "{file}: {} != {n}", t.n.unwrap()[k]);
            }
        }
    }
}

/// `shape_index` picks one shape of a `.serialized` file with several, in both versions;
/// one past the last is an error that says how many there are.
#[test]
fn shape_index_picks_the_shape() {
    let dir = common::scratch("mesh-formats-shape-index");
    let (first, second) = (tetrahedron(), quad());
    let first_triangles = load_ok(&dir, "first.obj", &obj(&first), "smooth = true").triangles;
    let second_triangles = load_ok(&dir, "second.obj", &obj(&second), "smooth = true").triangles;
    for version in [3, 4] {
        let bytes = serialized(&[(&first, SINGLE), (&second, DOUBLE)], version);
        let file = format!("two-v{version}.serialized");
        assert_eq!(load_ok(&dir, &file, &bytes, "smooth = true").triangles, first_triangles);
        assert_eq!(load_ok(&dir, &file, &bytes, "smooth = true\nshape_index = 0").triangles, first_triangles);
        assert_eq!(load_ok(&dir, &file, &bytes, "smooth = true\nshape_index = 1").triangles, second_triangles);
        assert_mesh_error(&dir, &file, &bytes, "shape_index = 2", &["shape_index 2", "2 shapes"]);
    }
    let one = serialized(&[(&first, SINGLE)], 4);
    assert_mesh_error(&dir, "one.serialized", &one, "shape_index = 7", &["1 shape"]);
}

/// File types: an unknown extension is an error at `file`; `shape_index` only goes with
/// `.serialized` files, and must be a non-negative integer.
#[test]
fn file_types_and_shape_index_key() {
    let dir = common::scratch("mesh-formats-types");
    let mesh = tetrahedron();
    assert_mesh_error(&dir, "mesh.stl", b"solid", "", &["unknown mesh file type", ".obj, .ply or .serialized"]);
    assert_mesh_error(&dir, "mesh", &obj(&mesh), "", &["unknown mesh file type"]);
    for (file, bytes) in [("mesh.obj", obj(&mesh)), ("mesh.ply", ply(&mesh, ASCII))] {
        let (path, result) = load_mesh(&dir, file, &bytes, "shape_index = 0");
        let error = result.expect_err("shape_index on an OBJ or PLY file");
        assert_eq!(error.file, path);
        assert_eq!((error.line, error.key.as_deref()), (Some(FILE_LINE + 1), Some("shapes[0].shape_index")), "{error}");
        assert!(error.message.contains(".serialized"), "{error}");
    }
    let bytes = serialized(&[(&mesh, SINGLE)], 4);
    for bad in ["-1", "1.5", "\"1\"", "4294967296"] {
        let (_, result) = load_mesh(&dir, "mesh.serialized", &bytes, &format!("shape_index = {bad}"));
        let error = result.expect_err("a bad shape_index");
        assert_eq!(error.key.as_deref(), Some("shapes[0].shape_index"), "{error}");
    }
}

/// PLY files that are wrong in each way the reader checks.
#[test]
fn broken_ply_files_are_errors() {
    let dir = common::scratch("mesh-formats-ply-errors");
    let mesh = tetrahedron();
    let ascii = String::from_utf8(ply(&mesh, ASCII)).unwrap();
    let edit = |from: &str, to: &str| {
        assert!(ascii.contains(from), "{from:?}");
        ascii.replacen(from, to, 1).into_bytes()
    };
    let cases: Vec<(&str, Vec<u8>, &[&str])> = vec![
        ("not PLY", b"OFF\n4 4 0\n".to_vec(), &["not a PLY file"]),
        ("empty", Vec::new(), &["not a PLY file"]),
        ("no format", edit("format ascii 1.0\n", ""), &["header"]),
        ("bad header line", edit("element face", "elephant face"), &["header"]),
        ("no end_header", ascii.split("end_header").next().unwrap().as_bytes().to_vec(), &["header"]),
        ("no vertex element", edit("element vertex", "element vertices"), &["no `vertex` element"]),
        ("no z", edit("property float z\n", ""), &["`z`"]),
        ("list x", edit("property float x\n", "property list uchar float x\n"), &["`x`", "list"]),
        ("no face element", edit("element face 4\n", "element facet 4\n"), &["no `face` element"]),
        ("no index list", edit("vertex_indices", "corners"), &["vertex_indices"]),
        ("float indices", edit("list uchar int vertex_indices", "list uchar float vertex_indices"), &["integers"]),
        ("index out of range", edit("\n3 1 2 3", "\n3 1 2 4"), &["face 3", "vertex 4", "4 vertices"]),
        ("negative index", edit("\n3 1 2 3", "\n3 1 2 -1"), &["face 3", "negative"]),
        ("two-vertex face", edit("\n3 1 2 3 1.5", "\n2 1 2 1.5"), &["face 3", "at least 3"]),
        // The grammar has no `nan` or `inf`; these overflow 32-bit floats.
        ("infinite position", edit("\n2 0 0 ", "\n1e39 0 0 "), &["vertex 1", "position", "finite"]),
        ("infinite normal", edit(" 0.1 0.1 2 ", " 0.1 0.1 -1e39 "), &["vertex 3", "normal", "finite"]),
        ("infinite uv", edit(" 200 0.5 0.25", " 200 0.5 4e38"), &["vertex 3", "texture", "finite"]),
        ("no faces", edit("element face 4\n", "element face 0\n"), &["no faces"]),
        // Without the edge element's line and the last face's.
        ("truncated", ascii.as_bytes()[..ascii.len() - "3 1 2 3 1.5\n0 1\n".len()].to_vec(), &["ends after 3 of its 4 `face`"]),
        ("garbled number", edit("\n2 0 0 ", "\n2 zero 0 "), &["line"]),
        ("not text", edit("\n2 0 0 ", "\n2 \u{1} 0 ").iter().map(|&b| if b == 1 { 0xff } else { b }).collect(), &["not ASCII"]),
    ];
    for (what, bytes, words) in cases {
        eprintln!("{what}");
        assert_mesh_error(&dir, "broken.ply", &bytes, "", words);
    }

    // Binary: numbers beyond 32-bit floats, an index out of range, truncation, a huge count.
    let mut double = ply(&mesh, LITTLE);
    let header_end = double.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    // The material element (2 x 13 bytes) comes first; then vertex 0's x, a double.
    double[header_end + 26..header_end + 34].copy_from_slice(&1e300f64.to_le_bytes());
    assert_mesh_error(&dir, "double.ply", &double, "", &["vertex 0", "finite"]);
    let mut big = ply(&mesh, BIG);
    let last_index = big.len() - 2;
    big[last_index..].copy_from_slice(&9u16.to_be_bytes());
    assert_mesh_error(&dir, "big.ply", &big, "", &["face 3", "vertex 9"]);
    let little = ply(&mesh, LITTLE);
    assert_mesh_error(&dir, "short.ply", &little[..little.len() - 3], "", &["ends after"]);
    let count = |n: &str| {
        [&little[..header_end], &little[header_end..]]
            .map(<[u8]>::to_vec)
            .map(|mut part| {
                if part.starts_with(b"ply") {
                    part = String::from_utf8(part)
                        .unwrap()
                        .replacen("element vertex 4\n", &format!("element vertex {n}\n"), 1)
                        .into_bytes();
                }
                part
            })
            .concat()
    };
    assert_mesh_error(&dir, "huge.ply", &count("4000000000"), "", &["ends after"]);
    assert_mesh_error(&dir, "huger.ply", &count("4294967296"), "", &["4294967296 vertices"]);
}

/// `.serialized` files that are wrong in each way the reader checks.
#[test]
fn broken_serialized_files_are_errors() {
    let dir = common::scratch("mesh-formats-serialized-errors");
    let mesh = tetrahedron();
    let good = serialized(&[(&mesh, SINGLE)], 4);
    let body = serialized_body(&mesh, SINGLE, 4);
    // The counts follow the flags and the name "test shape\0".
    let counts = 4 + 11;
    let with_counts = |vertices: u64, triangles: u64| {
        let mut body = body.clone();
        body[counts..counts + 8].copy_from_slice(&vertices.to_le_bytes());
        body[counts + 8..counts + 16].copy_from_slice(&triangles.to_le_bytes());
        serialized_file(&[body], 4)
    };
    let with_body = |edit: &dyn Fn(&mut Vec<u8>)| {
        let mut body = body.clone();
        edit(&mut body);
        serialized_file(&[body], 4)
    };
    let positions = counts + 16;
    let indices = body.len() - 4 * 3 * 4;
    // The zlib header's compression method is not DEFLATE.
    let mut corrupt = good.clone();
    corrupt[4] ^= 0xff;
    // Incompressible data, far less than a million vertices need but more than the counts
    // check allows to be ruled out at once.
    let mut noise = body[..positions].to_vec();
    noise[counts..counts + 8].copy_from_slice(&1_000_000u64.to_le_bytes());
    let mut state = 1u32;
    noise.extend((0..100_000).map(|_| {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 24) as u8
    }));
    let cases: Vec<(&str, Vec<u8>, &[&str])> = vec![
        ("empty", Vec::new(), &["not a Mitsuba .serialized file"]),
        ("bad magic", [&[0x1D, 0x04], &good[2..]].concat(), &["not a Mitsuba .serialized file"]),
        ("version 2", [&good[..2], &[2, 0], &good[4..]].concat(), &["version 2"]),
        ("version 5", [&good[..2], &[5, 0], &good[4..]].concat(), &["version 5"]),
        ("truncated", good[..good.len() / 2].to_vec(), &["ends early"]),
        ("header only", good[..4].to_vec(), &["ends early"]),
        ("corrupt", corrupt, &["corrupt compressed data"]),
        ("huge counts", with_counts(1 << 31, 1 << 40), &["more than its"]),
        ("more vertices than data", with_counts(u32::MAX.into(), 4), &["more than its"]),
        ("too many vertices", with_counts(u64::MAX, 4), &["vertices", "at most"]),
        ("counts beyond the data", serialized_file(&[noise], 4), &["ends early"]),
        ("no triangles", with_counts(4, 0), &["no triangles"]),
        (
            "index out of range",
            with_body(&|b| b[indices..indices + 4].copy_from_slice(&4u32.to_le_bytes())),
            &["triangle 0", "vertex 4"],
        ),
        (
            "nan position",
            with_body(&|b| b[positions..positions + 4].copy_from_slice(&f32::NAN.to_le_bytes())),
            &["vertex 0", "finite"],
        ),
        (
            "infinite normal",
            with_body(&|b| b[positions + 48..positions + 52].copy_from_slice(&f32::INFINITY.to_le_bytes())),
            &["vertex 0", "normal"],
        ),
        ("no name end", serialized_file(&[[&body[..4], &vec![b'x'; 70_000][..]].concat()], 4), &["NUL"]),
    ];
    for (what, bytes, words) in cases {
        eprintln!("{what}");
        assert_mesh_error(&dir, "broken.serialized", &bytes, "", words);
    }

    // A double beyond 32-bit floats.
    let mut double = serialized_body(&mesh, DOUBLE, 3);
    let at = 4 + 16;
    double[at..at + 8].copy_from_slice(&1e300f64.to_le_bytes());
    assert_mesh_error(&dir, "double.serialized", &serialized_file(&[double], 3), "", &["vertex 0", "finite"]);

    // A broken dictionary, read only for shapes past the first.
    let two = serialized(&[(&mesh, SINGLE), (&quad(), SINGLE)], 4);
    let mut bad_offset = two.clone();
    let at = two.len() - 4 - 8;
    bad_offset[at..at + 8].copy_from_slice(&5u64.to_le_bytes());
    assert_mesh_error(&dir, "offset.serialized", &bad_offset, "shape_index = 1", &["offset 5"]);
    bad_offset[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
    assert_mesh_error(&dir, "offset.serialized", &bad_offset, "shape_index = 1", &["offset"]);
    let mut bad_count = two.clone();
    let end = two.len() - 4;
    bad_count[end..].copy_from_slice(&u32::MAX.to_le_bytes());
    assert_mesh_error(&dir, "count.serialized", &bad_count, "shape_index = 1", &["dictionary"]);
    load_ok(&dir, "count.serialized", &bad_count, "");
}

/// A sample of the prefixes of valid files, and of the files with one byte garbled, through
/// the loader: a scene or an error naming the scene file, never a panic (the test would fail
/// on one). The readers' unit tests try every prefix and many more garbled bytes, without
/// files, which are slow to write.
#[test]
fn truncated_and_garbled_files_never_panic() {
    let dir = common::scratch("mesh-formats-garbled");
    let (tetra, quad) = (tetrahedron(), quad());
    let files = [
        ("a.ply", ply(&tetra, ASCII)),
        ("l.ply", ply(&tetra, LITTLE)),
        ("b.ply", ply(&quad, BIG)),
        ("s.serialized", serialized(&[(&tetra, SINGLE), (&quad, DOUBLE)], 4)),
        ("t.serialized", serialized(&[(&quad, DOUBLE), (&tetra, SINGLE)], 3)),
    ];
    let (mut loaded, mut refused) = (0, 0);
    for (file, bytes) in &files {
        let mut variants: Vec<Vec<u8>> = (0..bytes.len()).step_by(11).map(|n| bytes[..n].to_vec()).collect();
        for i in (0..bytes.len()).step_by(7) {
            let mut garbled = bytes.clone();
            garbled[i] ^= [0x01, 0x80, 0xff][i % 3];
            variants.push(garbled);
        }
        let extra = if file.ends_with(".serialized") { "smooth = true\nshape_index = 1" } else { "smooth = true" };
        let (path, _) = load_mesh(&dir, file, bytes, extra);
        for variant in variants {
            std::fs::write(dir.join(file), &variant).unwrap();
            match scene::load(&path) {
                Ok(scene) => {
                    loaded += 1;
                    assert!(scene.triangles.iter().all(|t| t.p.iter().all(|p| p.is_finite())));
                }
                Err(error) => {
                    refused += 1;
                    assert_eq!(error.file, path);
                    assert!(!error.message.is_empty());
                }
            }
        }
    }
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
}

/// Files from Mitsuba's own data (<https://github.com/mitsuba-renderer/mitsuba-data>), when
/// `SPPM_MITSUBA_DATA` names a copy of it; skipped otherwise. `matpreview.serialized` is a
/// version 3 file of three shapes; the rectangles exist as PLY and as version 4
/// `.serialized` files with the same vertices; the PLY files have extra vertex and face
/// properties, `texture_u`/`texture_v` and `vertex_index` lists, ASCII and binary.
#[test]
fn mitsuba_data_files() {
    let Some(root) = std::env::var_os("SPPM_MITSUBA_DATA").map(PathBuf::from) else {
        eprintln!("skipped: SPPM_MITSUBA_DATA does not name a copy of mitsuba-data");
        return;
    };
    let dir = common::scratch("mesh-formats-mitsuba-data");
    let load = |relative: &str, extra: &str| {
        let bytes = std::fs::read(root.join(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"));
        let file = Path::new(relative).file_name().unwrap().to_str().unwrap();
        load_ok(&dir, file, &bytes, extra)
    };
    // Shape: triangles in the file (some may be degenerate and skipped).
    for (shape, count) in [(0, 512), (1, 3936), (2, 57152)] {
        let scene = load("common/meshes/matpreview.serialized", &format!("smooth = true\nshape_index = {shape}"));
        assert!(
            scene.triangles.len() <= count && scene.triangles.len() * 100 >= count * 99,
            "{shape}: {}",
            scene.triangles.len()
        );
        assert!(scene.triangles.iter().all(|t| t.n.is_some() && t.uv.is_some()));
    }
    for name in ["rectangle_normals", "rectangle_normals_uv", "rectangle_uv"] {
        let ply = load(&format!("tests/ply/{name}.ply"), "smooth = true").triangles;
        let serialized = load(&format!("tests/serialized/{name}.serialized"), "smooth = true").triangles;
        assert_eq!(ply.len(), 2);
        assert_eq!(ply.len(), serialized.len());
        for (a, b) in ply.iter().zip(&serialized) {
            for k in 0..3 {
                assert!((a.p[k] - b.p[k]).length() < 1e-5, "{name}: {} != {}", a.p[k], b.p[k]);
                assert!((a.n.unwrap()[k] - b.n.unwrap()[k]).length() < 1e-5, "{name}");
                assert_eq!(a.uv.is_some(), b.uv.is_some(), "{name}");
                // These .serialized files store 1 - v where the PLY files store v: both are
                // read as stored.
                if let (Some(u), Some(v)) = (a.uv, b.uv) {
                    let flipped = glam::Vec2::new(v[k].x, 1.0 - v[k].y);
                    assert!((u[k] - flipped).length() < 1e-5, "{name}: {} != {flipped}", u[k]);
                }
            }
        }
    }
    for (file, count) in [
        ("common/meshes/bunny.ply", 69451),
        ("common/meshes/bunny_lowres.ply", 948),
        ("common/meshes/teapot.ply", 2256),
        ("docs/scenes/meshes/bunny_attribute_color.ply", 12000),
        ("tests/ply/cbox_smallbox.ply", 12),
        ("tests/ply/triangle.ply", 1),
        ("tests/ply/triangle_face_colors.ply", 1),
    ] {
        let scene = load(file, "smooth = true");
        assert!(scene.triangles.len() <= count && scene.triangles.len() * 100 >= count * 99, "{file}: {}", scene.triangles.len());
    }
}

// --- OBJ scenes are unchanged ---

fn fnv(hash: &mut u64, word: u32) {
    for byte in word.to_le_bytes() {
        *hash ^= u64::from(byte);
        *hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
}

/// A hash of every bit of a scene's triangles.
fn triangle_hash(scene: &Scene) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325;
    for t in &scene.triangles {
        t.p.iter().flat_map(|p| p.to_array()).for_each(|c| fnv(&mut h, c.to_bits()));
        match t.n {
            Some(n) => n.iter().flat_map(|n| n.to_array()).for_each(|c| fnv(&mut h, c.to_bits())),
            None => fnv(&mut h, 0xffff_ffff),
        }
        match t.uv {
            Some(uv) => uv.iter().flat_map(|uv| uv.to_array()).for_each(|c| fnv(&mut h, c.to_bits())),
            None => fnv(&mut h, 0xffff_fffe),
        }
        fnv(&mut h, t.shape);
    }
    h
}

/// The canonical and gallery scenes, as written (smooth meshes: the bunny and dragon
/// without normals in their files, the others with) and with every `smooth = true` made
/// false, load to the triangles they gave before the loader read PLY and `.serialized`
/// files: hashes of every bit, taken then.
#[test]
fn obj_scenes_give_the_same_triangles_as_before() {
    const BEFORE: &[(&str, bool, usize, u64)] = &[
        ("cornell-box.toml", true, 36, 0x9cc715bdf19301b5),
        ("cornell-glossy.toml", true, 24, 0x51166f2a740d4e79),
        ("cornell-spheres.toml", true, 12, 0x7e6b5286bada8a15),
        ("depth-of-field.toml", true, 12, 0x7e6b5286bada8a15),
        ("furnace.toml", true, 12, 0xbf371f2b263a5615),
        ("gallery/bunny-cube.toml", true, 3698, 0xcdaa0f9476f2ec3f),
        ("gallery/bunny-cube.toml", false, 3698, 0x9fbc8d71d848a672),
        ("gallery/coloured-lights.toml", true, 28, 0xee2af7ed2ef262b1),
        ("gallery/flower-pot.toml", true, 3480, 0x41ca68d799aeff7f),
        ("gallery/flower-pot.toml", false, 3480, 0x942f7c3a741458bf),
        ("gallery/glass-bowl.toml", true, 3532, 0x4200af60a92998db),
        ("gallery/glass-bowl.toml", false, 3532, 0x932f192858a22adb),
        ("gallery/glass-dragon.toml", true, 11114, 0xa3abc478d3c1a015),
        ("gallery/glass-dragon.toml", false, 11114, 0x62dc2151aefeb57a),
        ("gallery/glossy-cube.toml", true, 24, 0xd9e8663f9bd97d95),
        ("gallery/ice-dragon.toml", true, 11114, 0x5b1ab8771480674f),
        ("gallery/ice-dragon.toml", false, 11114, 0xdd0c625d399cbbce),
        ("gallery/water.toml", true, 3292, 0x1e1b7e43db4b0012),
        ("gallery/water.toml", false, 3292, 0x3cb6fab25a04231a),
        ("motion-blur.toml", true, 24, 0x51166f2a740d4e79),
        ("point-light.toml", true, 34, 0x1cf2d3639097bda1),
        ("textured.toml", true, 24, 0x423f0183b25b82c1),
    ];
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for &(name, as_written, count, hash) in BEFORE {
        let path = root.join(name);
        let text = std::fs::read_to_string(&path).unwrap();
        let text = if as_written { text } else { text.replace("smooth = true", "smooth = false") };
        let scene = scene::load_str(&text, &path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((scene.triangles.len(), triangle_hash(&scene)), (count, hash), "{name}, as written: {as_written}");
    }
}
