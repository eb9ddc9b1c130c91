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

#[cfg(test)]
impl IndexedMesh {
    /// What every mesh reader promises (the readers' tests check it): indices in range,
    /// normals and texture coordinates one per position and finite, finite positions, some
    /// triangles.
    pub(super) fn assert_valid(&self) {
        let n = self.positions.len();
        assert!(self.indices.iter().flatten().all(|&i| (i as usize) < n));
        assert!(self.normals.as_ref().is_none_or(|v| v.len() == n && v.iter().all(|x| x.is_finite())));
        assert!(self.uvs.as_ref().is_none_or(|v| v.len() == n && v.iter().all(|x| x.is_finite())));
        assert!(self.positions.iter().all(|p| p.is_finite()) && !self.indices.is_empty());
    }
}

/// An affine object-to-world transform `M p = A p + t`, with the normal matrix
/// `(A^-1)^T` for normals. [`Transform::new`] builds it from scale, then rotation about x, y
/// and z (in that order), then translation (`M = T * Rz * Ry * Rx * S`);
/// [`Transform::from_affine`] from any linear part and translation.
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
        Self::from_affine(linear, translation)
    }

    /// The general affine transform `p -> linear * p + translation`: the upper 3x3 block and
    /// the last column of a 4x4 matrix whose last row is `0 0 0 1` (Mitsuba's `<transform>`
    /// and `<matrix>`). Normals go through the inverse transpose of `linear`, so `linear`
    /// should be invertible: a singular one gives zero-area triangles, which are skipped.
    pub fn from_affine(linear: Mat3, translation: Vec3) -> Self {
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
    let bytes = super::files::read(path)?;
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

/// Which shading normals [`triangles`] gives a mesh's vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Normals {
    /// None: triangles are shaded with their geometric normals (`smooth = false` in a TOML
    /// scene; Mitsuba's `face_normals = true`).
    Flat,
    /// The file's normals, or else per position (so that texture seams do not split them)
    /// the area-weighted average of the normals of the faces around it (`smooth = true` in a
    /// TOML scene).
    Smooth,
    /// What Mitsuba 3 does for a mesh without `face_normals`: the file's normals, or else
    /// those of its `Mesh::recompute_vertex_normals` (src/render/mesh.cpp): per vertex index,
    /// not position, the sum over the faces that use the vertex of the face's unit normal
    /// times the face's interior angle at the vertex (Thürmer & Wüthrich 1998, "Computing
    /// vertex normals from polygonal facets", JGT 3(1)), normalized. Computed in world space,
    /// as Mitsuba does after applying `to_world`.
    MitsubaSmooth,
}

/// Host bytes a primitive costs while its scene is loaded and made ready for the device: the
/// scene's [`Triangle`], the device copies staged on the host (triangle, reference and BVH
/// node, normals and texture coordinates: 164 bytes, as `integrators::memory_need` counts
/// them) and the BVH build's box, centroid and reference (about 64).
pub(crate) const LOAD_BYTES_PER_PRIMITIVE: u64 = std::mem::size_of::<Triangle>() as u64 + 164 + 64;

/// The most primitives any scene may have: a primitive reference is a 31-bit index (its top
/// bit marks spheres).
const MAX_PRIMITIVES: u64 = (1 << 31) - 1;

/// How many triangles and spheres a scene may expand to here, fixed as loading starts:
/// what the host's available memory holds at [`LOAD_BYTES_PER_PRIMITIVE`] each. Every scene
/// reader (TOML, [`super::SceneBuilder`], Mitsuba XML with its instances) checks it before it
/// makes a shape's primitives, so that a scene too large is an error rather than an
/// allocation that fails or a process killed for memory.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PrimitiveBudget {
    /// The host's available memory in bytes, where known.
    available: Option<u64>,
}

impl PrimitiveBudget {
    pub fn new() -> Self {
        Self::with_memory(super::files::available_memory())
    }

    /// The budget of a host with `available` bytes (`None`: unknown, only the 31-bit cap).
    pub fn with_memory(available: Option<u64>) -> Self {
        PrimitiveBudget { available }
    }

    /// The most primitives a scene may have.
    pub fn max(&self) -> u64 {
        self.available.map_or(MAX_PRIMITIVES, |m| (m / LOAD_BYTES_PER_PRIMITIVE).min(MAX_PRIMITIVES))
    }

    /// Refuses adding `count` primitives to a scene of `have`; `what` (a parenthesis or
    /// empty) says where they come from.
    pub fn check(&self, have: u64, count: u64, what: &str) -> Result<(), String> {
        let total = have.saturating_add(count);
        let max = self.max();
        if total <= max {
            return Ok(());
        }
        let why = match self.available {
            Some(m) if max < MAX_PRIMITIVES => format!(
                "the {max} this machine's memory holds ({:.1} GiB available, about {LOAD_BYTES_PER_PRIMITIVE} bytes a \
                 primitive while loading)",
                m as f64 / (1u64 << 30) as f64
            ),
            _ => format!("the {MAX_PRIMITIVES} a scene may have (a primitive reference is a 31-bit index)"),
        };
        Err(format!("the scene expands to {total} triangles and spheres{what}: more than {why}"))
    }
}

/// The primitives a TOML shape of `kind` makes, checked before it is made; 0 for a mesh,
/// counted once its file is read.
pub(super) fn fixed_primitives(kind: super::ShapeKind) -> u64 {
    match kind {
        super::ShapeKind::Quad => 2,
        super::ShapeKind::Sphere => 1,
        super::ShapeKind::Cube => 12,
        super::ShapeKind::Mesh => 0,
    }
}

/// The world-space triangles of `mesh` under `transform`, and how many were skipped for
/// having zero area. `normals` says which shading normals the vertices get; a vertex whose
/// normal is zero (a zero normal in the file, or faces whose normals cancel) takes its
/// triangle's geometric normal. Errors when the transform takes a vertex out of the range
/// of 32-bit floats.
pub(super) fn triangles(
    mesh: &IndexedMesh,
    transform: &Transform,
    normals: Normals,
    shape: u32,
) -> Result<(Vec<Triangle>, usize), String> {
    let world: Vec<Vec3> = mesh.positions.iter().map(|&p| transform.point(p)).collect();
    if !world.iter().all(|p| p.is_finite()) {
        return Err(OUT_OF_RANGE.into());
    }
    let mut faces = Vec::with_capacity(mesh.indices.len());
    for &[a, b, c] in &mesh.indices {
        let face = if transform.flips_winding() { [a, c, b] } else { [a, b, c] }.map(|i| i as usize);
        let area2 = face_normal(&world, face).length_squared();
        // An area that overflows (infinite, or NaN from inf - inf) is a shape too large, not
        // one scaled to nothing.
        if !area2.is_finite() {
            return Err(OUT_OF_RANGE.into());
        }
        if area2 > 0.0 {
            faces.push(face);
        }
    }
    let skipped = mesh.indices.len() - faces.len();

    let file_normals = || mesh.normals.as_ref().map(|n| n.iter().map(|&n| transform.normal(n)).collect::<Vec<_>>());
    let normals = match normals {
        Normals::Flat => None,
        Normals::Smooth => Some(file_normals().unwrap_or_else(|| averaged_normals(&world, &faces))),
        Normals::MitsubaSmooth => Some(file_normals().unwrap_or_else(|| angle_weighted_normals(&world, &faces))),
    };
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

/// Per-vertex unit normals as Mitsuba 3's `Mesh::recompute_vertex_normals` computes them
/// (see [`Normals::MitsubaSmooth`]): for each vertex index, the sum of the unit normals of
/// the faces that use it, each weighted by the face's interior angle there; zero where they
/// cancel or no face uses the vertex. `faces` have nonzero area.
fn angle_weighted_normals(world: &[Vec3], faces: &[[usize; 3]]) -> Vec<Vec3> {
    let mut sums = vec![Vec3::ZERO; world.len()];
    for &face in faces {
        let n = face_normal(world, face).normalize_or_zero();
        for corner in 0..3 {
            let at = world[face[corner]];
            let to_next = (world[face[(corner + 1) % 3]] - at).normalize_or_zero();
            let to_previous = (world[face[(corner + 2) % 3]] - at).normalize_or_zero();
            sums[face[corner]] += n * unit_angle(to_next, to_previous);
        }
    }
    sums.into_iter().map(Vec3::normalize_or_zero).collect()
}

/// The angle between unit vectors `a` and `b`, accurate near 0 and pi as well (it uses the
/// half chord, `|a - b| / 2 = sin(angle / 2)`, rather than `acos` of the dot product).
fn unit_angle(a: Vec3, b: Vec3) -> f32 {
    let half_chord = |v: Vec3| (v.length() * 0.5).min(1.0).asin();
    if a.dot(b) < 0.0 {
        std::f32::consts::PI - 2.0 * half_chord(a + b)
    } else {
        2.0 * half_chord(a - b)
    }
}

/// Reads a TOML scene's `texture`: [`read_image`], filtered bilinearly with repeat, its t
/// running up the image (row 0 at t = 1).
pub(super) fn read_texture(path: &Path) -> Result<Texture, String> {
    let mut texture = read_image(path, false)?;
    texture.to_uv = glam::Affine2::from_cols(glam::Vec2::X, glam::Vec2::NEG_Y, glam::Vec2::Y);
    Ok(texture)
}

/// Reads an image (PNG, JPEG, OpenEXR, Radiance HDR, portable float map ([`read_pfm`]), or
/// Targa, which has no signature and is known by its `.tga` extension) into a texture of linear RGB, row 0 at
/// the top, sampled bilinearly with repeat and an identity `to_uv`. As Mitsuba 3's `bitmap`
/// decides it: integer images (8 or 16 bits) are sRGB-encoded and decoded here, floating-point
/// images (EXR, HDR) are linear; `raw` keeps every value as stored. Alpha is dropped, a grey
/// image gives grey texels.
pub(super) fn read_image(path: &Path, raw: bool) -> Result<Texture, String> {
    let bytes = super::files::read(path)?;
    if bytes.starts_with(b"PF") || bytes.starts_with(b"Pf") {
        let (width, height, texels) = read_pfm(&bytes)?;
        return Ok(Texture {
            path: path.to_path_buf(),
            width,
            height,
            texels: std::sync::Arc::new(texels),
            filter: super::TextureFilter::Bilinear,
            wrap: super::TextureWrap::Repeat,
            to_uv: glam::Affine2::IDENTITY,
        });
    }
    // Targa has no signature: known by its extension alone (other formats by their bytes).
    let format = image::guess_format(&bytes).or_else(|e| match image::ImageFormat::from_path(path) {
        Ok(f @ image::ImageFormat::Tga) => Ok(f),
        _ => Err(e),
    });
    let image = format.and_then(|f| image::load_from_memory_with_format(&bytes, f)).map_err(|e| e.to_string())?;
    let linear = raw || matches!(image, image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_));
    let image = image.into_rgb32f();
    let decode = |c: f32| if linear { c } else { srgb_to_linear(c) };
    let texels: Vec<Vec3> = image.pixels().map(|p| Vec3::from_array(p.0.map(decode))).collect();
    if !texels.iter().all(|t| t.is_finite()) {
        return Err("a texel is not a finite number".into());
    }
    Ok(Texture {
        path: path.to_path_buf(),
        width: image.width(),
        height: image.height(),
        texels: std::sync::Arc::new(texels),
        filter: super::TextureFilter::Bilinear,
        wrap: super::TextureWrap::Repeat,
        to_uv: glam::Affine2::IDENTITY,
    })
}

/// A portable float map (`PF`: RGB, `Pf`: grey), as pbrt-v4 reads it: a text header of the
/// kind, width, height and a scale whose sign is the byte order (negative: little-endian),
/// one whitespace byte, then 32-bit floats row by row from the bottom row up. Linear RGB
/// texels, row 0 at the top; the scale's magnitude is not applied (pbrt-v4 does not).
fn read_pfm(bytes: &[u8]) -> Result<(u32, u32, Vec<Vec3>), String> {
    // Four whitespace-separated header words, then the single whitespace byte.
    let mut words = Vec::new();
    let mut at = 0;
    while words.len() < 4 {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        if start == at || at - start > 32 {
            return Err("not a portable float map: its header is cut short or malformed".into());
        }
        words.push(std::str::from_utf8(&bytes[start..at]).map_err(|_| "a PFM header that is not text")?);
    }
    let channels = if words[0] == "PF" { 3 } else { 1 };
    let dim =
        |w: &str| w.parse::<u32>().ok().filter(|&n| n > 0).ok_or_else(|| format!("PFM size `{w}` is not a positive integer"));
    let (width, height) = (dim(words[1])?, dim(words[2])?);
    let scale: f32 = words[3].parse().map_err(|_| format!("PFM scale `{}` is not a number", words[3]))?;
    if scale == 0.0 || !scale.is_finite() {
        return Err(format!("PFM scale {scale} is neither positive nor negative"));
    }
    let data = bytes.get(at + 1..).unwrap_or_default();
    let count = (width as usize).checked_mul(height as usize).and_then(|n| n.checked_mul(channels));
    if count.is_none_or(|n| data.len() / 4 < n) {
        return Err(format!("the PFM holds {} floats, fewer than its {width} x {height} x {channels}", data.len() / 4));
    }
    let float = |k: usize| {
        let b = [data[4 * k], data[4 * k + 1], data[4 * k + 2], data[4 * k + 3]];
        if scale < 0.0 {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let (w, h) = (width as usize, height as usize);
    let mut texels = Vec::with_capacity(w * h);
    for y in 0..h {
        // Stored bottom row first.
        let row = (h - 1 - y) * w;
        for x in 0..w {
            let k = (row + x) * channels;
            texels.push(if channels == 3 { Vec3::new(float(k), float(k + 1), float(k + 2)) } else { Vec3::splat(float(k)) });
        }
    }
    if !texels.iter().all(|t| t.is_finite()) {
        return Err("a texel is not a finite number".into());
    }
    Ok((width, height, texels))
}

/// The sRGB electro-optical transfer function (IEC 61966-2-1), for values in [0, 1].
pub(super) fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pfm_rows_bottom_up_in_either_byte_order() {
        // 2 x 2 RGB, little-endian: bottom row (1, 2, 3) (4, 5, 6), top row (7, 8, 9) (10, 11, 12).
        let mut le = b"PF\n2 2\n-1.0\n".to_vec();
        le.extend((1..=12).flat_map(|v| (v as f32).to_le_bytes()));
        let (w, h, t) = read_pfm(&le).unwrap();
        assert_eq!((w, h), (2, 2));
        assert_eq!(
            t,
            [Vec3::new(7.0, 8.0, 9.0), Vec3::new(10.0, 11.0, 12.0), Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0)]
        );
        // Grey, big-endian, one row.
        let mut be = b"Pf 2 1 1\n".to_vec();
        be.extend([0.5f32, 2.0].iter().flat_map(|v| v.to_be_bytes()));
        assert_eq!(read_pfm(&be).unwrap().2, [Vec3::splat(0.5), Vec3::splat(2.0)]);
        // Cut short, or with no data at all: errors, not panics.
        assert!(read_pfm(&le[..le.len() - 1]).unwrap_err().contains("fewer"));
        assert!(read_pfm(b"PF\n2 2\n-1.0").is_err());
        assert!(read_pfm(b"PF\n4294967295 4294967295\n-1\n").is_err());
    }
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};

    fn identity() -> Transform {
        Transform::new(Vec3::ONE, Vec3::ZERO, Vec3::ZERO)
    }

    /// The shading normal `triangles` gives the vertex at `p`, the same in every triangle
    /// that has it.
    fn normal_at(triangles: &[Triangle], p: Vec3) -> Vec3 {
        let normals: Vec<Vec3> =
            triangles.iter().flat_map(|t| (0..3).filter(move |&k| t.p[k] == p).map(move |k| t.n.unwrap()[k])).collect();
        assert!(!normals.is_empty(), "no vertex at {p}");
        assert!(normals.iter().all(|&n| n == normals[0]), "the normals at {p} differ: {normals:?}");
        normals[0]
    }

    #[track_caller]
    fn assert_close(a: Vec3, b: Vec3) {
        assert!((a - b).length() < 1e-6, "{a} != {b}");
    }

    /// The tetrahedron O = 0, A = (2, 0, 0), B = (0, 1, 0), C = (0, 0, 1), wound outwards:
    /// faces OBA (-z), OCB (-x), OAC (-y) and ABC ((1, 2, 2) / 3).
    fn tetrahedron() -> IndexedMesh {
        IndexedMesh {
            positions: vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::Y, Vec3::Z],
            normals: None,
            uvs: None,
            indices: vec![[0, 2, 1], [0, 3, 2], [0, 1, 3], [1, 2, 3]],
        }
    }

    /// Mitsuba's recomputed vertex normals, against angle-weighted sums worked out by hand.
    #[test]
    fn mitsuba_smooth_weights_unit_face_normals_by_angle() {
        let (triangles, skipped) = triangles(&tetrahedron(), &identity(), Normals::MitsubaSmooth, 0).unwrap();
        assert_eq!((triangles.len(), skipped), (4, 0));
        let (minus_x, minus_y, minus_z, abc) = (-Vec3::X, -Vec3::Y, -Vec3::Z, Vec3::new(1.0, 2.0, 2.0) / 3.0);
        // O: a right angle in each of its three faces.
        let o = FRAC_PI_2 * (minus_x + minus_y + minus_z);
        // A: angle(AO, AB) = angle(AO, AC) = acos(2 / sqrt 5); angle(AB, AC) = acos(4 / 5).
        let a = (2.0 / 5f32.sqrt()).acos() * (minus_z + minus_y) + 0.8f32.acos() * abc;
        // B: angle(BO, BA) = acos(1 / sqrt 5), angle(BO, BC) = pi / 4, angle(BA, BC) =
        // acos(1 / sqrt 10); C is B with y and z swapped.
        let b = (1.0 / 5f32.sqrt()).acos() * minus_z + FRAC_PI_4 * minus_x + (0.1f32.sqrt()).acos() * abc;
        let c = (1.0 / 5f32.sqrt()).acos() * minus_y + FRAC_PI_4 * minus_x + (0.1f32.sqrt()).acos() * abc;
        let mesh = tetrahedron();
        for (p, expected) in mesh.positions.iter().zip([o, a, b, c]) {
            assert_close(normal_at(&triangles, *p), expected.normalize());
        }
        // Weighting by area instead (the `Smooth` normals) gives another normal at O.
        let (smooth, _) = super::triangles(&tetrahedron(), &identity(), Normals::Smooth, 0).unwrap();
        assert_close(normal_at(&smooth, Vec3::ZERO), -Vec3::new(0.5, 1.0, 1.0).normalize());
    }

    /// Mitsuba sums per vertex index: vertices that share a position but not an index (a
    /// seam) keep their own normals, where `Smooth` averages them.
    #[test]
    fn mitsuba_smooth_sums_per_vertex_index() {
        // Two triangles folded along the edge from 0 to (0, 1, 0), the edge's vertices
        // duplicated: one in the plane z = 0 facing +z, the other in x = 0 facing +x.
        let mesh = IndexedMesh {
            positions: vec![Vec3::ZERO, Vec3::Y, Vec3::X, Vec3::ZERO, Vec3::Y, Vec3::Z],
            normals: None,
            uvs: None,
            indices: vec![[0, 2, 1], [3, 4, 5]],
        };
        let (mitsuba, _) = triangles(&mesh, &identity(), Normals::MitsubaSmooth, 0).unwrap();
        assert_eq!(mitsuba[0].n.unwrap(), [Vec3::Z; 3]);
        assert_eq!(mitsuba[1].n.unwrap(), [Vec3::X; 3]);
        let (smooth, _) = triangles(&mesh, &identity(), Normals::Smooth, 0).unwrap();
        assert_close(smooth[0].n.unwrap()[0], Vec3::new(1.0, 0.0, 1.0).normalize());
    }

    /// With normals in the file, `MitsubaSmooth` uses them (transformed, unit length), as
    /// `Smooth` does; `Flat` gives none.
    #[test]
    fn file_normals_are_kept() {
        let mut mesh = tetrahedron();
        mesh.normals = Some(vec![Vec3::new(0.0, 0.0, 2.0); 4]);
        let transform = Transform::new(Vec3::new(1.0, 1.0, 4.0), Vec3::ZERO, Vec3::ZERO);
        let (mitsuba, _) = triangles(&mesh, &transform, Normals::MitsubaSmooth, 0).unwrap();
        let (smooth, _) = triangles(&mesh, &transform, Normals::Smooth, 0).unwrap();
        assert_eq!(mitsuba, smooth);
        assert!(mitsuba.iter().all(|t| t.n == Some([Vec3::Z; 3])));
        let (flat, _) = triangles(&mesh, &transform, Normals::Flat, 0).unwrap();
        assert!(flat.iter().all(|t| t.n.is_none()));
    }

    /// The budget: memory over bytes a primitive, the 31-bit cap, and the message.
    #[test]
    fn primitive_budget() {
        let budget = PrimitiveBudget::with_memory(Some(1000 * LOAD_BYTES_PER_PRIMITIVE));
        assert_eq!(budget.max(), 1000);
        assert!(budget.check(990, 10, "").is_ok());
        let e = budget.check(990, 11, " (here)").unwrap_err();
        assert!(
            e.starts_with(
                "the scene expands to 1001 triangles and spheres (here): more than the 1000 this machine's memory holds"
            ),
            "{e}"
        );
        assert!(budget.check(u64::MAX, u64::MAX, "").is_err());
        let unknown = PrimitiveBudget::with_memory(None);
        assert_eq!(unknown.max(), MAX_PRIMITIVES);
        assert!(unknown.check(MAX_PRIMITIVES, 1, "").unwrap_err().contains("31-bit"));
    }

    /// A transform that overflows an edge or an area is out of range, not zero area: the NaN
    /// of inf - inf in a cross product too.
    #[test]
    fn overflowing_areas_are_out_of_range() {
        let mesh = IndexedMesh {
            positions: vec![Vec3::ZERO, Vec3::new(1.0, 0.2, 0.0), Vec3::new(0.3, 1.0, 0.0)],
            normals: None,
            uvs: None,
            indices: vec![[0, 1, 2]],
        };
        let huge = Transform::new(Vec3::splat(1e30), Vec3::ZERO, Vec3::ZERO);
        assert_eq!(triangles(&mesh, &huge, Normals::Flat, 0).unwrap_err(), OUT_OF_RANGE);
        let tiny = Transform::new(Vec3::splat(1e-30), Vec3::ZERO, Vec3::ZERO);
        assert_eq!(triangles(&mesh, &tiny, Normals::Flat, 0).unwrap().1, 1);
    }

    /// A general affine transform: the same as `new` for a scale-rotate-translate, normals
    /// by the inverse transpose (perpendicular to transformed tangents under a shear), and
    /// mirrors detected.
    #[test]
    fn affine_transforms() {
        let (scale, rotate, translate) = (Vec3::new(2.0, 3.0, 0.5), Vec3::new(10.0, 20.0, 30.0), Vec3::new(1.0, -2.0, 3.0));
        let r = rotate * (std::f32::consts::PI / 180.0);
        let linear =
            Mat3::from_rotation_z(r.z) * Mat3::from_rotation_y(r.y) * Mat3::from_rotation_x(r.x) * Mat3::from_diagonal(scale);
        let (a, b) = (Transform::new(scale, rotate, translate), Transform::from_affine(linear, translate));
        let p = Vec3::new(0.3, -0.7, 1.1);
        assert_eq!(a.point(p), b.point(p));
        assert_eq!(a.normal(p), b.normal(p));

        // x' = x + y: the plane with normal (1, 1, 0) is spanned by (1, -1, 0) and z.
        let shear = Transform::from_affine(Mat3::from_cols(Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Z), Vec3::ONE);
        assert_eq!(shear.point(Vec3::new(1.0, 2.0, 3.0)), Vec3::new(4.0, 3.0, 4.0));
        let n = shear.normal(Vec3::new(1.0, 1.0, 0.0));
        assert!((n.length() - 1.0).abs() < 1e-6);
        for tangent in [Vec3::new(1.0, -1.0, 0.0), Vec3::Z] {
            let image = shear.point(tangent) - shear.point(Vec3::ZERO);
            assert!(n.dot(image).abs() < 1e-6, "{n} is not perpendicular to {image}");
        }
        assert!(!shear.flips_winding());
        assert!(Transform::from_affine(Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0)), Vec3::ZERO).flips_winding());
    }
}
