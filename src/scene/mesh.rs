//! OBJ meshes, textures and shape tessellation: the files a scene names, and every shape
//! turned into world-space triangles. Knows nothing of TOML; errors are plain messages that
//! the loader places in the scene file.

use super::{Sphere, Texture, Triangle};
use glam::{Mat3, Vec2, Vec3};
use std::collections::HashMap;
use std::path::Path;

/// An indexed triangle mesh in object space. `normals` and `uvs`, when present, have one
/// entry per position.
#[derive(Clone, Debug, Default)]
pub(super) struct IndexedMesh {
    /// Vertex positions, object space.
    pub positions: Vec<Vec3>,
    /// Per-vertex normals (OBJ `vn`), object space, not necessarily unit length.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates (OBJ `vt`).
    pub uvs: Option<Vec<Vec2>>,
    /// Triangles as three indices into the vertex arrays, counter-clockwise seen from the
    /// front.
    pub indices: Vec<[u32; 3]>,
}

/// Scale, then rotation about x, y and z (in that order), then translation:
/// `M = T * Rz * Ry * Rx * S`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Transform {
    linear: Mat3,
    translation: Vec3,
    /// Inverse transpose of `linear`, for normals.
    normal_matrix: Mat3,
}

impl Transform {
    /// `rotate_degrees` holds the angles about x, y and z.
    pub fn new(scale: Vec3, rotate_degrees: Vec3, translation: Vec3) -> Self {
        let r = rotate_degrees * (std::f32::consts::PI / 180.0);
        let linear =
            Mat3::from_rotation_z(r.z) * Mat3::from_rotation_y(r.y) * Mat3::from_rotation_x(r.x) * Mat3::from_diagonal(scale);
        Transform { linear, translation, normal_matrix: linear.inverse().transpose() }
    }

    /// A transformed point: `M p`.
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.linear * p + self.translation
    }

    /// A transformed normal, unit length, or zero when `n` is zero.
    pub fn normal(&self, n: Vec3) -> Vec3 {
        (self.normal_matrix * n).normalize_or_zero()
    }

    /// Whether the transform mirrors space, so that triangle winding must be reversed to
    /// keep the front side in front.
    pub fn flips_winding(&self) -> bool {
        self.linear.determinant() < 0.0
    }
}

/// The two triangles of the parallelogram `corner, corner+u, corner+u+v, corner+v`, with
/// geometric normals along `cross(u, v)` and texture coordinates `uv_scale * (a, b)`.
pub(super) fn quad(corner: Vec3, u: Vec3, v: Vec3, uv_scale: Vec2, shape: u32) -> [Triangle; 2] {
    let vertex = |a: f32, b: f32| (corner + a * u + b * v, uv_scale * Vec2::new(a, b));
    let triangle = |corners: [(f32, f32); 3]| {
        let vertices = corners.map(|(a, b)| vertex(a, b));
        Triangle { p: vertices.map(|x| x.0), n: None, uv: Some(vertices.map(|x| x.1)), shape }
    };
    [triangle([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]), triangle([(0.0, 0.0), (1.0, 1.0), (0.0, 1.0)])]
}

/// The cube `[-1, 1]^3`, wound so that every face's normal points outwards.
pub(super) fn unit_cube() -> IndexedMesh {
    // Corner i has x, y, z = +1 where bits 0, 1, 2 of i are set, -1 elsewhere.
    let positions = (0..8).map(|i| Vec3::new(sign(i & 1), sign(i & 2), sign(i & 4))).collect();
    // Each face counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    let faces: [[u32; 4]; 6] = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];
    let indices = faces.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
    IndexedMesh { positions, normals: None, uvs: None, indices }
}

fn sign(bit: u32) -> f32 {
    if bit != 0 {
        1.0
    } else {
        -1.0
    }
}

/// Reads a Wavefront OBJ file, triangulated, all its objects in one mesh. Normals and
/// texture coordinates are kept only when every vertex has them. Materials are ignored.
/// Errors name the OBJ line where there is one (see `check_obj_text`).
pub(super) fn read_obj(path: &Path) -> Result<IndexedMesh, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
        format!("line {line}: not UTF-8 text")
    })?;
    check_obj_text(text)?;
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
    let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| Ok(Default::default()))
        .map_err(|e| format!("not a valid OBJ file: {e}"))?;

    let mut mesh = IndexedMesh::default();
    let mut normals = Some(Vec::new());
    let mut uvs = Some(Vec::new());
    for model in &models {
        let m = &model.mesh;
        let count = m.positions.len() / 3;
        let base = mesh.positions.len() as u32;
        if m.indices.iter().any(|&i| i as usize >= count) {
            return Err("a face refers to a vertex that does not exist".into());
        }
        mesh.positions.extend(m.positions.chunks_exact(3).map(Vec3::from_slice));
        mesh.indices.extend(m.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]].map(|i| base + i)));
        append_if_complete(&mut normals, &m.normals, count, 3, Vec3::from_slice);
        append_if_complete(&mut uvs, &m.texcoords, count, 2, Vec2::from_slice);
    }
    if mesh.indices.is_empty() {
        return Err("the file has no triangles".into());
    }
    // `check_obj_text` found every number finite; this guards the reader's arithmetic.
    if !mesh.positions.iter().all(|p| p.is_finite())
        || !normals.iter().flatten().all(|n| n.is_finite())
        || !uvs.iter().flatten().all(|t| t.is_finite())
    {
        return Err("a vertex, normal or texture coordinate is not a finite number".into());
    }
    mesh.normals = normals;
    mesh.uvs = uvs;
    Ok(mesh)
}

/// Checks the lines of an OBJ file before the OBJ reader sees them, so that errors name the
/// line, and catches what the reader would take without a word: `v`, `vt` and `vn` lines
/// with too few numbers, numbers that are not finite (or overflow to infinity), a weight
/// `w` that does not give finite coordinates, a `v` with 5 or more than 6 numbers, faces
/// with fewer than 3 vertices or a malformed vertex, and indices of 0 or beyond what the
/// file defines (relative ones count back from their line; positive ones may refer
/// forward). The message starts with the 1-based line.
fn check_obj_text(text: &str) -> Result<(), String> {
    // How many positions, texture coordinates and normals the file defines so far.
    let mut counts = [0usize; 3];
    const NAMES: [(&str, &str); 3] =
        [("vertex", "vertices"), ("texture coordinate", "texture coordinates"), ("normal", "normals")];
    // Positive indices may refer forward: the largest of each kind, and its line, is checked
    // against the totals at the end.
    let mut largest = [(0usize, 0usize); 3];
    for (i, line) in text.lines().enumerate() {
        let number = i + 1;
        let mut words = line.split_whitespace();
        let (kind, width) = match words.next() {
            Some("v") => (0, 3),
            Some("vt") => (1, 2),
            Some("vn") => (2, 3),
            Some("f") => {
                let words: Vec<&str> = words.collect();
                if words.len() < 3 {
                    return Err(format!("line {number}: a face needs at least 3 vertices, found {}", words.len()));
                }
                for word in words {
                    if word.split('/').count() > 3 || word.starts_with('/') {
                        return Err(format!("line {number}: `{word}` is not a face vertex"));
                    }
                    for (slot, part) in word.split('/').enumerate() {
                        if part.is_empty() {
                            continue;
                        }
                        let Ok(index) = part.parse::<i64>() else {
                            return Err(format!("line {number}: `{word}` is not a face vertex"));
                        };
                        let (what, whats) = NAMES[slot];
                        if index == 0 {
                            return Err(format!("line {number}: {what} index 0 in `{word}` (OBJ indices start at 1)"));
                        }
                        if index < 0 && index.unsigned_abs() > counts[slot] as u64 {
                            return Err(format!(
                                "line {number}: {what} index {index} in `{word}` reaches back past the {} {whats} defined before it",
                                counts[slot]
                            ));
                        }
                        if index > 0 && index as u64 > largest[slot].0 as u64 {
                            largest[slot] = (index as usize, number);
                        }
                    }
                }
                continue;
            }
            _ => continue,
        };
        let values: Vec<&str> = words.collect();
        let mut numbers = [0.0f32; 3];
        for (x, word) in numbers.iter_mut().zip(&values).take(width) {
            *x = word.parse().map_err(|_| format!("line {number}: `{word}` is not a number"))?;
            if !x.is_finite() {
                return Err(format!("line {number}: `{word}` is not a finite number"));
            }
        }
        if values.len() < width {
            return Err(format!("line {number}: a {} needs {width} numbers, found {}", NAMES[kind].0, values.len()));
        }
        if kind == 0 && ![3, 4, 6].contains(&values.len()) {
            return Err(format!(
                "line {number}: a vertex has 3 numbers, 4 (with a weight w) or 6 (with a colour), found {}",
                values.len()
            ));
        }
        if kind == 0 && values.len() == 4 {
            let w: f32 = values[3].parse().map_err(|_| format!("line {number}: `{}` is not a number", values[3]))?;
            if w == 0.0 || !numbers.iter().all(|x| (x / w).is_finite()) {
                return Err(format!("line {number}: the weight w = {} does not give finite coordinates", values[3]));
            }
        }
        counts[kind] += 1;
    }
    for (slot, &(index, number)) in largest.iter().enumerate() {
        // A file without texture coordinates or normals may still name them; the reader
        // ignores those, but an index past what the file has is a broken file either way.
        if index > counts[slot] {
            let (what, whats) = NAMES[slot];
            return Err(format!("line {number}: {what} index {index} does not exist (the file has {} {whats})", counts[slot]));
        }
    }
    Ok(())
}

/// Appends one model's per-vertex attribute (flattened, `width` floats a vertex) to `all`,
/// or drops `all` when the model does not have it for each of its `count` vertices.
fn append_if_complete<T>(all: &mut Option<Vec<T>>, flat: &[f32], count: usize, width: usize, convert: fn(&[f32]) -> T) {
    if flat.len() != count * width {
        *all = None;
    }
    if let Some(all) = all {
        all.extend(flat.chunks_exact(width).map(convert));
    }
}

/// The world-space triangles of `mesh` under `transform`, and how many were skipped for
/// having zero area. With `smooth`, each vertex gets a shading normal: the file's, or else
/// the area-weighted average of the normals of the faces around its position. Errors when
/// the transform takes a vertex out of the range of 32-bit floats.
pub(super) fn triangles(
    mesh: &IndexedMesh,
    transform: &Transform,
    smooth: bool,
    shape: u32,
) -> Result<(Vec<Triangle>, usize), String> {
    let world: Vec<Vec3> = mesh.positions.iter().map(|&p| transform.point(p)).collect();
    if !world.iter().all(|p| p.is_finite()) {
        return Err(OUT_OF_RANGE.into());
    }
    let mut faces = Vec::with_capacity(mesh.indices.len());
    for &[a, b, c] in &mesh.indices {
        let face = if transform.flips_winding() { [a, c, b] } else { [a, b, c] }.map(|i| i as usize);
        if face_normal(&world, face).length_squared() > 0.0 {
            faces.push(face);
        }
    }
    let skipped = mesh.indices.len() - faces.len();

    let normals = smooth.then(|| match &mesh.normals {
        Some(file_normals) => file_normals.iter().map(|&n| transform.normal(n)).collect(),
        None => averaged_normals(&world, &faces),
    });
    let triangles = faces
        .iter()
        .map(|&face| Triangle {
            p: face.map(|i| world[i]),
            n: normals.as_ref().map(|n| {
                let geometric = face_normal(&world, face).normalize_or_zero();
                face.map(|i| if n[i] == Vec3::ZERO { geometric } else { n[i] })
            }),
            uv: mesh.uvs.as_ref().map(|uv| face.map(|i| uv[i])),
            shape,
        })
        .collect();
    Ok((triangles, skipped))
}

/// Why a shape is refused when its world-space geometry overflows 32-bit floats.
const OUT_OF_RANGE: &str = "the shape lies beyond the range of 32-bit floats: a vertex, an edge or an area overflows \
     (position, size or scale too large)";

/// Whether a triangle has no area in 32-bit floats: the renderer could not give it a normal.
pub(super) fn is_degenerate(t: &Triangle) -> bool {
    let area2 = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).length_squared();
    area2.is_nan() || area2 <= 0.0
}

/// Checks that a shape's world-space primitives, displaced by `offset` (zero for the shape
/// at rest, its velocity for the end of the shutter), stay within 32-bit floats: every
/// vertex, edge and twice-area of a triangle and its squared length, and every sphere's
/// bounds and area. The renderer computes all of these; an infinity among them would give
/// NaN normals, light powers or bounding boxes.
pub(super) fn check_extent(triangles: &[Triangle], spheres: &[Sphere], offset: Vec3) -> Result<(), String> {
    let triangle_fits = |t: &Triangle| {
        let p = t.p.map(|p| p + offset);
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let n = e1.cross(e2);
        p.iter().all(|p| p.is_finite()) && e1.is_finite() && e2.is_finite() && n.length_squared().is_finite()
    };
    let sphere_fits = |s: &Sphere| {
        let c = s.center + offset;
        (c + s.radius).is_finite() && (c - s.radius).is_finite() && (4.0 * std::f32::consts::PI * s.radius * s.radius).is_finite()
    };
    if triangles.iter().all(triangle_fits) && spheres.iter().all(sphere_fits) {
        Ok(())
    } else {
        Err(OUT_OF_RANGE.into())
    }
}

/// `cross(p1 - p0, p2 - p0)`: along the front side, twice the triangle's area long.
fn face_normal(world: &[Vec3], [a, b, c]: [usize; 3]) -> Vec3 {
    (world[b] - world[a]).cross(world[c] - world[a])
}

/// Per-vertex unit normals averaged over the faces that share the vertex's position
/// (so that texture seams do not split them), weighted by area; zero where they cancel.
fn averaged_normals(world: &[Vec3], faces: &[[usize; 3]]) -> Vec<Vec3> {
    // Adding 0.0 turns -0.0 into 0.0, so that both give the same key.
    let key = |p: Vec3| p.to_array().map(|c| (c + 0.0).to_bits());
    let mut sums: HashMap<[u32; 3], Vec3> = HashMap::new();
    for &face in faces {
        let n = face_normal(world, face);
        for i in face {
            *sums.entry(key(world[i])).or_default() += n;
        }
    }
    world.iter().map(|&p| sums.get(&key(p)).copied().unwrap_or_default().normalize_or_zero()).collect()
}

/// Reads an sRGB image (PNG) and decodes it to linear RGB, row 0 at the top.
pub(super) fn read_texture(path: &Path) -> Result<Texture, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let image = image::load_from_memory(&bytes).map_err(|e| e.to_string())?.into_rgb32f();
    let texels = image.pixels().map(|p| Vec3::from_array(p.0.map(srgb_to_linear))).collect();
    Ok(Texture { path: path.to_path_buf(), width: image.width(), height: image.height(), texels })
}

/// The sRGB electro-optical transfer function (IEC 61966-2-1), for values in [0, 1].
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
