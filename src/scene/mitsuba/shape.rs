//! Mitsuba 3's shape plugins, as our shapes (its plugin reference, "Shapes"). Every shape
//! takes `to_world` (identity), `flip_normals` (false), a BSDF (nested or `<ref>`) and an
//! `area` emitter:
//!
//! - `obj`, `ply`, `serialized` (`shape_index`, 0): triangle meshes from a file (`filename`),
//!   smooth unless `face_normals` (false): the file's vertex normals, or else Mitsuba's
//!   angle-weighted ones. Faces keep the file's winding under a mirroring transform, as
//!   Mitsuba's face normals do.
//! - `rectangle`: `[-1, 1]^2` in the plane z = 0, facing +z. `cube`: `[-1, 1]^3`, facing out.
//! - `disk`: the unit disk in z = 0, facing +z, tessellated into 256 triangles (its area is
//!   0.01% short of the disk's).
//! - `sphere`: `center` (0), `radius` (1), analytic; `to_world` must scale it uniformly.
//! - `shapegroup` and `instance`: a group's shapes, copied under each instance's `to_world`.
//!   A group holds no instance, shapegroup or emitter, as Mitsuba refuses them (mod.rs,
//!   `References`); once an instance has made the first copy, the copies of every instance of
//!   the group are counted against the scene's primitive budget before another is made.
//!
//! `max_smooth_angle` (Mitsuba 0.6's meshes) is refused. In a 0.x scene, Mitsuba 0.6's mesh
//! parameters that Mitsuba 3 lacks are read as [`legacy_mesh`] says.
//!
//! Texture coordinates are Mitsuba 3's, v running down the image (texture.rs): a mesh's from
//! its file, OBJ's `vt` read as (u, 1 - v) unless `flip_tex_coords` is false (its default is
//! true), PLY's as stored unless `flip_tex_coords` (default false), `.serialized` ones as
//! stored; a mesh without them has, on each face, the barycentric coordinates (b1, b2) of its
//! second and third vertex, as Mitsuba gives it. `rectangle`: ((x + 1) / 2, (y + 1) / 2) of
//! the object-space point; `cube`: each face mapped onto [0, 1]^2 ([`CUBE_FACES`]); `disk`:
//! (r, phi / 2 pi), phi from +x towards +y in [0, 2 pi) (linear across each of the 256
//! triangles: v is off by at most 1/512 near the centre, where a turn is short); `sphere`:
//! (phi / 2 pi, theta / pi) of the object-space normal, theta from +z ([`Shape::sphere_frame`]).

use super::props::Props;
use super::xml::Node;
use super::{Result, SceneReader};
use crate::scene::mesh::{self, IndexedMesh, Normals, Transform};
use crate::scene::{ply, serialized, Shape, ShapeKind, Sphere, Triangle};
use glam::{Mat3, Mat4, Vec2, Vec3};
use std::path::{Path, PathBuf};

/// Segments of a tessellated `disk`.
const DISK_SEGMENTS: u32 = 256;

/// The faces of Mitsuba 3's `cube` and their texture coordinates: (n, a, b) is the face
/// through n facing along n, whose point n + s a + t b (s, t in [-1, 1]) has uv ((s + 1) / 2,
/// (t + 1) / 2), the layout of Mitsuba's cube (checked on its vertex table).
const CUBE_FACES: [(Vec3, Vec3, Vec3); 6] = [
    (Vec3::NEG_Y, Vec3::Z, Vec3::X),
    (Vec3::Y, Vec3::NEG_X, Vec3::NEG_Z),
    (Vec3::X, Vec3::Y, Vec3::NEG_Z),
    (Vec3::Z, Vec3::Y, Vec3::X),
    (Vec3::NEG_X, Vec3::Y, Vec3::Z),
    (Vec3::NEG_Z, Vec3::NEG_Y, Vec3::X),
];

impl<'a> SceneReader<'a> {
    /// Reads shape element `node` under the parent transform `parent` (an instance's).
    pub(super) fn shape(&mut self, node: &'a Node, parent: Mat4) -> Result<()> {
        node.allow_attrs(&["type", "id", "name"])?;
        let kind = node.req_attr("type")?;
        if kind == "shapegroup" {
            // Read through its instances (what it may hold was checked with the references).
            node.req_attr("id")?;
            return Ok(());
        }
        let p = Props::new(node)?;
        let to_world = parent * p.transform("to_world")?.unwrap_or(Mat4::IDENTITY);
        if kind == "instance" {
            let refs = p.all_objects();
            let [named] = refs.as_slice() else {
                return Err(node.error(None, "an instance refers to one shapegroup: <ref id=\"...\"/>"));
            };
            let group = self.deref(named, "shape")?;
            if group.attr("type") != Some("shapegroup") {
                return Err(node.error(None, format!("an instance of {}: it must refer to a shapegroup", group.describe())));
            }
            p.finish()?;
            // Once one copy is read its size is known: this copy was counted then.
            let key = group as *const Node;
            if let Some(&size) = self.copy_size.get(&key) {
                self.reserved = self.reserved.saturating_sub(size);
            }
            let before = self.primitives();
            let outer = self.instance.replace((node, group));
            for child in &group.children {
                if child.tag != "shape" {
                    return Err(child.error(None, format!("{} in a shapegroup: it holds shapes only", child.describe())));
                }
                self.shape(child, to_world)?;
            }
            self.instance = outer;
            if !self.copy_size.contains_key(&key) {
                // The first copy: the others, before any is made.
                let size = self.primitives() - before;
                let copies = self.instances.get(&key).copied().unwrap_or(1).max(1);
                let others = size.saturating_mul(copies - 1);
                let what = format!(
                    " ({copies} instances of shapegroup \"{}\" of line {}, {size} primitives each)",
                    group.attr("id").unwrap_or_default(),
                    group.line
                );
                let id = (named.tag == "ref").then_some("id");
                self.budget.check(self.primitives(), others, &what).map_err(|e| named.error(id, e))?;
                self.copy_size.insert(key, size);
                self.reserved += others;
            }
            return Ok(());
        }

        let mut bsdf = None;
        let mut emission = None;
        let (mut interior, mut exterior) = (None, None);
        for object in p.all_objects() {
            let target = self.deref(object, "")?;
            match target.tag.as_str() {
                "bsdf" if bsdf.is_none() => bsdf = Some(object),
                "emitter" if emission.is_none() => emission = Some(super::emitter::area(target)?),
                "bsdf" | "emitter" => return Err(object.error(None, format!("a second {} in one shape", target.describe()))),
                "medium" => {
                    // The name on the nested element or the <ref> says which side it fills.
                    let side = match object.attr("name") {
                        Some("interior") => &mut interior,
                        Some("exterior") => &mut exterior,
                        other => {
                            let named = other.map(|n| format!(" named \"{n}\"")).unwrap_or_default();
                            return Err(object.error(
                                Some("name"),
                                format!(
                                    "a medium{named} in a shape: name it \"interior\" (inside the shape) or \"exterior\" \
                                     (outside it)"
                                ),
                            ));
                        }
                    };
                    if side.is_some() {
                        let name = object.attr("name").unwrap();
                        return Err(object.error(Some(name), format!("a second {name} medium in one shape")));
                    }
                    *side = Some((object, self.medium(object)?));
                }
                _ => return Err(object.error(None, format!("{} inside a shape", target.describe()))),
            }
        }
        let flip = p.boolean_or("flip_normals", false)?;
        let index = self.shapes.len() as u32;
        let first = self.triangles.len();
        let mut sphere_frame = None;
        let linear = Mat3::from_mat4(to_world);
        let translation = to_world.w_axis.truncate();
        let transform = Transform::from_affine(linear, translation);
        let shape_kind = match kind {
            "obj" | "ply" | "serialized" => {
                let path = file_name(&p, node, &self.root)?;
                let face_normals = p.boolean_or("face_normals", false)?;
                if p.has("max_smooth_angle") {
                    return Err(p.get("max_smooth_angle").unwrap().error(
                        Some("max_smooth_angle"),
                        "max_smooth_angle (splitting vertices at creases) is not modelled by sppm-gpu",
                    ));
                }
                if node.legacy() {
                    legacy_mesh(&p, kind, &path, bsdf.is_some())?;
                }
                let mut indexed = match kind {
                    "obj" => read_mesh(&p, &path, mesh::read_obj)?,
                    "ply" => read_mesh(&p, &path, ply::read_ply)?,
                    _ => {
                        let shape_index = p.integer("shape_index")?.unwrap_or(0);
                        let shape_index = u32::try_from(shape_index).map_err(|_| {
                            p.get("shape_index")
                                .unwrap()
                                .error(Some("shape_index"), format!("shape_index {shape_index} is negative"))
                        })?;
                        // Mitsuba 3 reads the file's face-normal flag but shades by the
                        // plugin's `face_normals` alone.
                        read_mesh(&p, &path, |path| serialized::read_serialized(path, shape_index))?
                    }
                };
                // Mitsuba flips v of OBJ's `vt` unless told not to, of PLY's only when told.
                let flip_tex = kind != "serialized" && p.boolean_or("flip_tex_coords", kind == "obj")?;
                if flip_tex {
                    if let Some(uvs) = &mut indexed.uvs {
                        uvs.iter_mut().for_each(|uv| uv.y = 1.0 - uv.y);
                    }
                }
                let normals = if face_normals { Normals::Flat } else { Normals::MitsubaSmooth };
                self.add_mesh(node, indexed, &transform, normals, index, &path, emission.is_some())?;
                ShapeKind::Mesh
            }
            "rectangle" => {
                // An analytic shape's normal is transformed as a normal: it stays on the side
                // of M^-T z even when M mirrors, as mesh::triangles keeps it.
                let quad = IndexedMesh {
                    positions: vec![
                        Vec3::new(-1.0, -1.0, 0.0),
                        Vec3::new(1.0, -1.0, 0.0),
                        Vec3::new(1.0, 1.0, 0.0),
                        Vec3::new(-1.0, 1.0, 0.0),
                    ],
                    normals: None,
                    uvs: Some(vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)]),
                    indices: vec![[0, 1, 2], [0, 2, 3]],
                };
                self.add_flat(node, &quad, &transform, index)?;
                ShapeKind::Quad
            }
            "cube" => {
                self.add_mesh(node, cube(), &transform, Normals::Flat, index, Path::new("cube"), emission.is_some())?;
                ShapeKind::Cube
            }
            "disk" => {
                self.add_flat(node, &disk(), &transform, index)?;
                ShapeKind::Mesh
            }
            "sphere" => {
                let center = p.vec3("center")?.unwrap_or(Vec3::ZERO);
                let radius = p.float_or("radius", 1.0)?;
                if radius <= 0.0 {
                    return Err(p
                        .get("radius")
                        .unwrap_or(node)
                        .error(Some("radius"), format!("radius {radius} is not positive")));
                }
                let scale = uniform_scale(linear).ok_or_else(|| {
                    node.error(
                        Some("to_world"),
                        "a sphere's to_world scales it unevenly or shears it: an ellipsoid is not modelled",
                    )
                })?;
                if flip {
                    return Err(node.error(Some("flip_normals"), "a sphere facing inwards is not modelled by sppm-gpu"));
                }
                self.reserve(1, node, None)?;
                self.spheres.push(Sphere { center: to_world.transform_point3(center), radius: radius * scale, shape: index });
                sphere_frame = Some(linear / scale);
                ShapeKind::Sphere
            }
            "cylinder" | "bsplinecurve" | "linearcurve" | "sdfgrid" | "ellipsoids" | "ellipsoidsmesh" => {
                return Err(node.error(Some("type"), format!("the `{kind}` shape is not modelled by sppm-gpu")))
            }
            other => return Err(node.error(Some("type"), format!("`{other}` is not a Mitsuba 3 shape plugin"))),
        };
        if flip {
            self.triangles[first..].iter_mut().for_each(flip_triangle);
        }
        let material = self.material(bsdf, node, emission.is_some())?;
        if self.materials[material as usize].kind.texture().is_some() {
            // A textured mesh without texture coordinates: each face's barycentrics, in the
            // file's vertex order (flip_normals swapped its last two vertices).
            let barycentric = if flip { [Vec2::ZERO, Vec2::Y, Vec2::X] } else { [Vec2::ZERO, Vec2::X, Vec2::Y] };
            self.triangles[first..].iter_mut().filter(|t| t.uv.is_none()).for_each(|t| t.uv = Some(barycentric));
        }
        p.finish()?;
        if shape_kind != ShapeKind::Sphere && self.triangles.len() == first {
            // A mesh of no area (warned by add_mesh) adds no shape: `convert` would write it
            // as a mesh file of no faces.
            return Ok(());
        }
        let triangles = &self.triangles[first..];
        let spheres = if shape_kind == ShapeKind::Sphere { &self.spheres[self.spheres.len() - 1..] } else { &[] };
        mesh::check_extent(triangles, spheres, Vec3::ZERO).map_err(|e| node.error(Some("to_world"), e))?;
        let shape = Shape {
            kind: shape_kind,
            material,
            emission,
            emission_two_sided: false,
            velocity: None,
            line: node.line,
            velocity_line: None,
            sphere_frame,
            interior: interior.map(|(_, m)| m),
            exterior: exterior.map(|(_, m)| m),
        };
        self.shapes.push(shape);
        Ok(())
    }

    /// Appends a mesh's world-space triangles, keeping the file's winding under a mirroring
    /// transform (Mitsuba's face normals are the cross products of world-space edges). A
    /// mesh whose every triangle has no area adds nothing, with a warning, as Mitsuba loads
    /// it; an emitting one is refused (a light of no area has no density to sample).
    #[allow(clippy::too_many_arguments)]
    fn add_mesh(
        &mut self,
        node: &Node,
        mut indexed: IndexedMesh,
        transform: &Transform,
        normals: Normals,
        shape: u32,
        path: &Path,
        emits: bool,
    ) -> Result<()> {
        // Counted before the triangles are made.
        self.reserve(indexed.indices.len(), node, Some("filename"))?;
        if transform.flips_winding() {
            // mesh::triangles turns mirrored faces around; turn them first so they stay.
            indexed.indices.iter_mut().for_each(|t| t.swap(1, 2));
        }
        let (triangles, skipped) =
            mesh::triangles(&indexed, transform, normals, shape).map_err(|e| node.error(Some("to_world"), e))?;
        if triangles.is_empty() && emits {
            return Err(node.error(
                None,
                format!("all {skipped} triangles of {} have no area: the area light has nothing to emit from", path.display()),
            ));
        }
        if triangles.is_empty() {
            node.warn(None, format!("all {skipped} triangles of {} have no area: the shape adds nothing", path.display()));
        } else if skipped > 0 {
            node.warn(None, format!("{skipped} triangles of {} have no area and are skipped", path.display()));
        }
        self.triangles.extend(triangles);
        Ok(())
    }

    /// Appends a flat analytic shape given as triangles in object space: its normal follows
    /// the transformed normal, so mirrored faces are turned around (mesh::triangles does).
    fn add_flat(&mut self, node: &Node, indexed: &IndexedMesh, transform: &Transform, shape: u32) -> Result<()> {
        self.reserve(indexed.indices.len(), node, None)?;
        let (triangles, skipped) =
            mesh::triangles(indexed, transform, Normals::Flat, shape).map_err(|e| node.error(Some("to_world"), e))?;
        if skipped > 0 {
            return Err(node.error(Some("to_world"), "the shape has no area in 32-bit floats (to_world scales it to nothing)"));
        }
        self.triangles.extend(triangles);
        Ok(())
    }
}

/// Mitsuba 3's `cube`, `[-1, 1]^3` facing out, four vertices a face with its uv
/// ([`CUBE_FACES`]).
fn cube() -> IndexedMesh {
    let mut cube = IndexedMesh { uvs: Some(Vec::new()), ..IndexedMesh::default() };
    for (n, a, b) in CUBE_FACES {
        let first = cube.positions.len() as u32;
        for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            cube.positions.push(n + s * a + t * b);
            cube.uvs.as_mut().unwrap().push(Vec2::new(s + 1.0, t + 1.0) * 0.5);
        }
        // Corners in this order turn about a x b; wind them about n.
        let [i0, i1, i2, i3] = [0, 1, 2, 3].map(|i| first + i);
        if a.cross(b).dot(n) > 0.0 {
            cube.indices.extend([[i0, i1, i2], [i0, i2, i3]]);
        } else {
            cube.indices.extend([[i0, i2, i1], [i0, i3, i2]]);
        }
    }
    cube
}

/// Mitsuba 3's `disk` as [`DISK_SEGMENTS`] triangles about its centre, with uv (r, phi /
/// 2 pi): three vertices a triangle, so that the centre takes the middle of its triangle's
/// phi and the last rim vertex v = 1 rather than 0.
fn disk() -> IndexedMesh {
    let mut disk = IndexedMesh { uvs: Some(Vec::new()), ..IndexedMesh::default() };
    let n = DISK_SEGMENTS as f32;
    let rim = |i: u32| {
        let phi = 2.0 * std::f32::consts::PI * (i % DISK_SEGMENTS) as f32 / n;
        Vec3::new(phi.cos(), phi.sin(), 0.0)
    };
    for i in 0..DISK_SEGMENTS {
        let first = disk.positions.len() as u32;
        disk.positions.extend([Vec3::ZERO, rim(i), rim(i + 1)]);
        let v = i as f32 / n;
        disk.uvs.as_mut().unwrap().extend([Vec2::new(0.0, v + 0.5 / n), Vec2::new(1.0, v), Vec2::new(1.0, v + 1.0 / n)]);
        disk.indices.push([first, first + 1, first + 2]);
    }
    disk
}

/// The `filename` of a mesh shape, relative to the file that names it or one of the scene's
/// directories `root` ([`super::xml::resolve`]).
fn file_name(p: &Props, node: &Node, root: &[PathBuf]) -> Result<PathBuf> {
    let name =
        p.string("filename")?.ok_or_else(|| node.error(Some("filename"), format!("{} needs a `filename`", node.describe())))?;
    Ok(super::xml::resolve(name, &node.file, root))
}

/// The parameters of Mitsuba 0.6's mesh plugins that Mitsuba 3's lack, in a 0.x scene: OBJ's
/// `shape_index` (-1, every group; one group alone is refused), `collapse` (one shape of all
/// its groups: the speed, warned) and `load_materials` (true, refused for a shape without a
/// BSDF whose file names materials: Mitsuba 0.6 would build them from its `.mtl`); PLY's `srgb`
/// (how its vertex colours are decoded, which are not read: warned).
fn legacy_mesh(p: &Props, kind: &str, path: &Path, has_bsdf: bool) -> Result<()> {
    match kind {
        "obj" => {
            if let Some(index) = p.integer("shape_index")?.filter(|&i| i >= 0) {
                let at = p.get("shape_index").unwrap();
                return Err(at.error(
                    Some("shape_index"),
                    format!("shape_index {index} (one group of the OBJ file) is not modelled by sppm-gpu"),
                ));
            }
            p.legacy_ignored(&["collapse"], "it merges the OBJ's groups into one shape, which changes the speed, not the image");
            if p.boolean_or("load_materials", true)? && p.has("load_materials") && !has_bsdf {
                let names_materials = crate::scene::files::read_text(path)
                    .is_ok_and(|text| text.lines().any(|l| l.trim_start().starts_with("usemtl")));
                if names_materials {
                    let at = p.get("load_materials").unwrap();
                    return Err(at.error(
                        Some("load_materials"),
                        "load_materials: the OBJ file's .mtl materials, which Mitsuba 0.6 would use for a shape without a \
                         BSDF, are not read by sppm-gpu: give the shape a <bsdf>, or set load_materials false",
                    ));
                }
            }
        }
        "ply" => {
            p.legacy_ignored(&["srgb"], "it says how Mitsuba 0.6 decodes the PLY's vertex colours, which sppm-gpu does not read")
        }
        _ => {}
    }
    Ok(())
}

/// Reads a mesh file, with errors placed at the `filename` parameter.
fn read_mesh<T>(p: &Props, path: &Path, read: impl FnOnce(&Path) -> std::result::Result<T, String>) -> Result<T> {
    let at = p.get("filename").unwrap_or(p.node);
    read(path).map_err(|e| at.error(Some("filename"), format!("{}: {e}", path.display())))
}

/// The factor of a similarity transform's linear part (rotation times a uniform scale,
/// possibly mirrored), or `None` when it shears or scales unevenly.
fn uniform_scale(linear: Mat3) -> Option<f32> {
    // Measured on the matrix divided by its largest entry, so that squares neither overflow
    // nor underflow: a huge scale is then too large for the sphere's extent (check_extent),
    // not uneven.
    let largest = linear.to_cols_array().iter().fold(0f32, |m, x| m.max(x.abs()));
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let unit = linear * (1.0 / largest);
    let lengths = [unit.x_axis.length(), unit.y_axis.length(), unit.z_axis.length()];
    let s = lengths[0];
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * s;
    let orthogonal = close(unit.x_axis.dot(unit.y_axis) / s, 0.0)
        && close(unit.y_axis.dot(unit.z_axis) / s, 0.0)
        && close(unit.x_axis.dot(unit.z_axis) / s, 0.0);
    (s > 0.0 && close(lengths[1], s) && close(lengths[2], s) && orthogonal).then_some(s * largest)
}

/// `flip_normals`: the other side becomes the front.
fn flip_triangle(t: &mut Triangle) {
    t.p.swap(1, 2);
    if let Some(n) = &mut t.n {
        n.swap(1, 2);
        *n = n.map(|n| -n);
    }
    if let Some(uv) = &mut t.uv {
        uv.swap(1, 2);
    }
}
