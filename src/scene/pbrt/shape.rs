//! pbrt-v4's shapes, as our triangles and spheres, under the CTM (and the world's mirror,
//! mod.rs). A triangle's front (where an area light emits, and a dielectric's outside) is
//! pbrt's: the side of its normals `N` where given, else of its winding, turned by
//! `ReverseOrientation` and by a transform that mirrors.
//!
//! - `trianglemesh`: `P`, `indices` (optional for one triangle), `N`, `uv`; `S` and
//!   `faceIndices` are read (tangents, face ids).
//! - `plymesh`: `filename` (our PLY reader); `displacement` is refused, `edgelength` read.
//! - `bilinearmesh`: `P`, `indices` (four a patch: p00 p10 p01 p11; optional for one
//!   patch), `N`, `uv`: two triangles a patch (exact for the planar patches of exported
//!   quads; a curved patch is approximated).
//! - `sphere`: `radius` (1), analytic; partial spheres (`zmin`, `zmax`, `phimax`) are refused,
//!   and so is a sphere that emits inwards (`ReverseOrientation`) or a CTM that scales it
//!   unevenly.
//! - `disk`: `height` (0), `radius` (1), `innerradius` (0), tessellated into 256 segments,
//!   facing +z; `phimax` other than 360 is refused.
//! - `loopsubdiv`: `P`, `indices`, `levels` (3): subdivided on load as pbrt-v4 does
//!   (subdiv.rs), a mesh with the limit surface's normals.
//! - `alpha` other than 1 is refused. Every other shape (`cylinder`, `curve`, ...) is
//!   refused.
//!
//! A shape whose CTMs at `TransformTimes`' start and end differ by a translation moves (our
//! `velocity`, [`Reader::motion`]); one that rotates or scales between them is refused.
//!
//! Texture coordinates are pbrt's: a mesh's `uv`, else (0, 0), (1, 0), (1, 1) on each
//! triangle; a sphere's (phi / 2 pi, 1 - theta / pi); a disk's (phi / 2 pi, (rmax - r) /
//! (rmax - rinner)).

use super::params::Params;
use super::{subdiv, Reader, Result, State};
use crate::scene::mesh::{self, IndexedMesh, Normals, Transform};
use crate::scene::{ply, Shape, ShapeKind, Sphere};
use glam::{Mat3, Vec2, Vec3};

/// Segments of a tessellated disk.
const DISK_SEGMENTS: u32 = 256;

impl Reader {
    /// `Shape "kind"` under `state`.
    pub(super) fn shape(&mut self, kind: &str, p: &Params, state: &State) -> Result<()> {
        let (ctm, velocity) = self.motion(p, state)?;
        let m = self.mirror * ctm;
        let linear = Mat3::from_mat4(m);
        let transform = Transform::from_affine(linear, m.w_axis.truncate());
        if p.float_or("alpha", 1.0)? != 1.0 || p.list.iter().any(|x| x.name == "alpha" && x.ty == "texture") {
            return Err(p.error("alpha", "alpha (cut-out) textures are not modelled by sppm-gpu"));
        }
        let mut emission = state.area.as_ref().map(|a| a.radiance);
        let index = self.shapes.len() as u32;
        let first = self.triangles.len();
        let material = self.material_index(state.material);
        let mut sphere_frame = None;
        let shape_kind = match kind {
            "trianglemesh" | "bilinearmesh" => {
                let (mesh, normals) = self.inline_mesh(kind, p)?;
                self.add_mesh(p, mesh, &transform, normals, state.reverse, index, emission.is_some())?;
                ShapeKind::Mesh
            }
            "plymesh" => {
                if p.has("displacement") {
                    return Err(p.error("displacement", "displacement of a plymesh is not modelled by sppm-gpu"));
                }
                p.pass_over(&["edgelength"]);
                let name = p.string("filename")?.ok_or_else(|| p.error("filename", "a plymesh needs a \"filename\""))?;
                let path = p.resolve(name);
                let mesh = ply::read_ply(&path).map_err(|e| p.error("filename", format!("{}: {e}", path.display())))?;
                let has_normals = mesh.normals.is_some();
                self.add_mesh(p, mesh, &transform, has_normals, state.reverse, index, emission.is_some())?;
                ShapeKind::Mesh
            }
            "sphere" => {
                let radius = p.float_or("radius", 1.0)?;
                if !(radius > 0.0 && radius.is_finite()) {
                    return Err(p.error("radius", format!("radius {radius} is not positive")));
                }
                let partial = p.float("zmin")?.is_some_and(|z| z > -radius)
                    || p.float("zmax")?.is_some_and(|z| z < radius)
                    || p.float("phimax")?.is_some_and(|x| x < 360.0);
                if partial {
                    let key = ["zmin", "zmax", "phimax"].into_iter().find(|k| p.has(k)).unwrap_or("zmin");
                    return Err(p.error(key, "a partial sphere is not modelled by sppm-gpu"));
                }
                let scale = uniform_scale(linear).ok_or_else(|| {
                    p.directive_error("the CTM scales the sphere unevenly or shears it: an ellipsoid is not modelled")
                })?;
                if emission.is_some() && state.reverse {
                    return Err(p.directive_error("a sphere emitting inwards (ReverseOrientation) is not modelled by sppm-gpu"));
                }
                self.reserve(p, 1)?;
                self.spheres.push(Sphere { center: m.transform_point3(Vec3::ZERO), radius: radius * scale, shape: index });
                // uv = (phi / 2 pi, 1 - theta / pi): theta from -z.
                sphere_frame = Some(Mat3::from_cols(linear.x_axis, linear.y_axis, -linear.z_axis) / scale);
                ShapeKind::Sphere
            }
            "disk" => {
                let height = p.float_or("height", 0.0)?;
                let radius = p.float_or("radius", 1.0)?;
                let inner = p.float_or("innerradius", 0.0)?;
                if p.float("phimax")?.is_some_and(|x| x < 360.0) {
                    return Err(p.error("phimax", "a partial disk is not modelled by sppm-gpu"));
                }
                if !(radius > 0.0 && inner >= 0.0 && inner < radius) {
                    return Err(p.error("radius", "a disk's radius is more than its innerradius, which is >= 0"));
                }
                self.add_mesh(p, disk(height, radius, inner), &transform, false, state.reverse, index, emission.is_some())?;
                ShapeKind::Mesh
            }
            "loopsubdiv" => {
                let mesh = self.loop_subdiv(p)?;
                self.add_mesh(p, mesh, &transform, true, state.reverse, index, emission.is_some())?;
                ShapeKind::Mesh
            }
            "cylinder" | "cone" | "paraboloid" | "hyperboloid" | "curve" | "heightfield" | "nurbs" => {
                return Err(p.directive_error(format!("the \"{kind}\" shape is not modelled by sppm-gpu")))
            }
            other => return Err(p.directive_error(format!("\"{other}\": unknown shape"))),
        };
        let two_sided = emission.is_some() && state.area.as_ref().is_some_and(|a| a.two_sided);
        if let (Some(l), Some(power)) = (emission, state.area.as_ref().and_then(|a| a.power)) {
            // pbrt-v4's DiffuseAreaLight: scale *= power / (pi area), and by half again where
            // it is two-sided.
            let sides = if two_sided { 2.0 } else { 1.0 };
            emission = Some(l * power / (sides * std::f32::consts::PI * self.pbrt_shape_area(kind, p, first)?));
        }
        p.finish()?;
        if shape_kind != ShapeKind::Sphere && self.triangles.len() == first {
            // A mesh of no area (warned by add_mesh) adds no shape: `convert` would write it
            // as a mesh file of no faces.
            return Ok(());
        }
        if self.materials[material as usize].kind.texture().is_some() {
            // pbrt's default uv on a triangle without them.
            let uv = [Vec2::ZERO, Vec2::X, Vec2::ONE];
            self.triangles[first..].iter_mut().filter(|t| t.uv.is_none()).for_each(|t| t.uv = Some(uv));
        }
        let spheres = if shape_kind == ShapeKind::Sphere { &self.spheres[self.spheres.len() - 1..] } else { &[] };
        mesh::check_extent(&self.triangles[first..], spheres, velocity.unwrap_or(Vec3::ZERO))
            .map_err(|e| p.directive_error(e))?;
        self.shapes.push(Shape {
            kind: shape_kind,
            material,
            emission,
            emission_two_sided: two_sided,
            velocity,
            line: p.line,
            velocity_line: None,
            sphere_frame,
            interior: None,
            exterior: None,
        });
        // A MediumInterface of two different media is a transition (medium.rs); a sphere's
        // outside is ours whatever ReverseOrientation says, so its names swap.
        let (inside, outside) = &state.media;
        if inside != outside {
            let names = if shape_kind == ShapeKind::Sphere && state.reverse {
                (outside.clone(), inside.clone())
            } else {
                (inside.clone(), outside.clone())
            };
            self.shape_media.push((index, names, p.directive_error(String::new())));
        }
        Ok(())
    }

    /// The CTM of a shape under `state` at the shutter's opening, and its velocity (our
    /// world's displacement over the shutter) where the CTMs at `TransformTimes`' start and end
    /// differ. pbrt-v4 interpolates between them over those times (its AnimatedTransform, held
    /// at either end outside them) and the camera samples times over its shutter
    /// (`shutteropen`, `shutterclose`: 0, 1); a shape that only translates moves at one
    /// velocity while the shutter lies within the times, which our motion blur renders (the
    /// shape at its position + velocity t, t in [0, 1) over the shutter). A CTM that also
    /// rotates or scales, or a shutter open outside the times, is refused.
    fn motion(&self, p: &Params, state: &State) -> Result<(glam::Mat4, Option<Vec3>)> {
        if state.ctm == state.ctm_end {
            return Ok((state.ctm, None));
        }
        let (start, end) = (state.ctm, state.ctm_end);
        let linear = |m: glam::Mat4| Mat3::from_mat4(m).to_cols_array();
        let scale = linear(start).iter().chain(&linear(end)).fold(0.0f32, |a, x| a.max(x.abs())).max(1e-30);
        if linear(start).iter().zip(&linear(end)).any(|(a, b)| (a - b).abs() > 1e-5 * scale) {
            return Err(p.directive_error(
                "the shape's transform rotates or scales between TransformTimes' start and end (ActiveTransform): \
                 motion that does not only translate is not modelled by sppm-gpu",
            ));
        }
        let camera = self.options.camera.as_ref().map(|(_, params, _)| params);
        let shutter = |key: &str, default: f32| camera.map_or(Ok(Some(default)), |c| c.float(key)).map(|x| x.unwrap_or(default));
        let (open, close) = (shutter("shutteropen", 0.0)?, shutter("shutterclose", 1.0)?);
        let (t0, t1) = self.transform_times;
        if open < t0 || close > t1 || close <= open {
            return Err(p.directive_error(format!(
                "the camera's shutter [{open}, {close}] is not within TransformTimes [{t0}, {t1}]: a shape held still for \
                 part of the shutter is not modelled by sppm-gpu"
            )));
        }
        let displacement = (end.w_axis - start.w_axis).truncate();
        let mut at_open = start;
        at_open.w_axis += (displacement * (open - t0) / (t1 - t0)).extend(0.0);
        let velocity = self.mirror.transform_vector3(displacement * (close - open) / (t1 - t0));
        Ok((at_open, Some(velocity)))
    }

    /// The area pbrt-v4's `power` divides by: its `Shape::Area()` of one shape, where a mesh
    /// is a shape per triangle (per patch of a `bilinearmesh`), in world space, and a sphere or
    /// disk one shape whose area is its object-space one (pbrt-v4 leaves out the CTM's
    /// scale). A mesh whose shapes differ in area would emit a radiance of its own from each,
    /// which one emission a shape cannot say: refused. `first` is the shape's first triangle.
    fn pbrt_shape_area(&self, kind: &str, p: &Params, first: usize) -> Result<f32> {
        use std::f32::consts::PI;
        let area = match kind {
            // Partial spheres and disks are refused above.
            "sphere" => 4.0 * PI * p.float_or("radius", 1.0)?.powi(2),
            "disk" => PI * (p.float_or("radius", 1.0)?.powi(2) - p.float_or("innerradius", 0.0)?.powi(2)),
            _ => {
                let tri = |t: &crate::scene::Triangle| 0.5 * (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).length();
                let triangles = &self.triangles[first..];
                let areas: Vec<f32> = if kind == "bilinearmesh" {
                    let patches = p.numbers("indices", "integer")?.map_or(1, |v| v.len() / 4);
                    if triangles.len() != 2 * patches {
                        return Err(p.error("power", "power on a bilinearmesh with a patch of no area is not modelled"));
                    }
                    triangles.chunks(2).map(|c| tri(&c[0]) + tri(&c[1])).collect()
                } else {
                    triangles.iter().map(tri).collect()
                };
                let (lo, hi) = areas.iter().fold((f32::INFINITY, 0.0f32), |(lo, hi), &a| (lo.min(a), hi.max(a)));
                if hi > lo * (1.0 + 1e-3) {
                    return Err(p.error(
                        "power",
                        format!(
                            "pbrt-v4 gives each {} of the mesh this power, so their radiances differ (areas {lo:.4e} to \
                             {hi:.4e}): one radiance a shape is modelled by sppm-gpu, not one a triangle",
                            if kind == "bilinearmesh" { "patch" } else { "triangle" }
                        ),
                    ));
                }
                hi
            }
        };
        if !(area > 0.0 && area.is_finite()) {
            return Err(p.error("power", format!("the shape's area {area} is not positive")));
        }
        Ok(area)
    }

    /// A `loopsubdiv`: `P`, `indices`, `levels` (3), subdivided (subdiv.rs) into a mesh with
    /// the limit surface's normals.
    fn loop_subdiv(&self, p: &Params) -> Result<IndexedMesh> {
        let positions: Vec<Vec3> = p
            .points::<3>("P", "point3")?
            .ok_or_else(|| p.error("P", "vertex positions \"P\" not provided with LoopSubdiv shape"))?
            .into_iter()
            .map(Vec3::from)
            .collect();
        let indices = p
            .numbers("indices", "integer")?
            .ok_or_else(|| p.error("indices", "vertex indices \"indices\" not provided with LoopSubdiv shape"))?;
        if indices.is_empty() || indices.len() % 3 != 0 {
            return Err(p.error("indices", format!("{} indices is not a whole number of triangles", indices.len())));
        }
        let n = positions.len();
        if let Some(bad) = indices.iter().find(|&&i| !(i >= 0.0 && (i as usize) < n && i.fract() == 0.0)) {
            return Err(p.error("indices", format!("index {bad} is out of range (the mesh has {n} vertices)")));
        }
        let levels = p.int_or("levels", 3)?;
        let faces: Vec<[u32; 3]> = indices.chunks(3).map(|c| [c[0] as u32, c[1] as u32, c[2] as u32]).collect();
        // Each level makes four faces of one.
        let count = u32::try_from(levels).ok().and_then(|l| 4usize.checked_pow(l)).and_then(|k| k.checked_mul(faces.len()));
        let Some(count) = count else {
            return Err(p.error("levels", format!("levels {levels} is negative or makes too many triangles")));
        };
        self.reserve(p, count)?;
        p.pass_over(&["uv", "N", "S", "faceIndices"]);
        let (m, normals) = subdiv::loop_subdivide(subdiv::LoopMesh { positions, faces }, levels as u32)
            .map_err(|e| p.error("indices", format!("Loop subdivision: {e}")))?;
        Ok(IndexedMesh { positions: m.positions, normals: Some(normals), uvs: None, indices: m.faces })
    }

    /// A `trianglemesh` or `bilinearmesh` given inline, and whether it has normals.
    fn inline_mesh(&self, kind: &str, p: &Params) -> Result<(IndexedMesh, bool)> {
        let positions: Vec<Vec3> = p
            .points::<3>("P", "point3")?
            .ok_or_else(|| p.error("P", "a mesh needs \"P\""))?
            .into_iter()
            .map(Vec3::from)
            .collect();
        let corners = if kind == "trianglemesh" { 3 } else { 4 };
        let indices = match p.numbers("indices", "integer")? {
            Some(v) => v,
            None if positions.len() == corners => (0..corners).map(|i| i as f64).collect(),
            None => return Err(p.error("indices", format!("\"indices\" is needed for more than {corners} vertices"))),
        };
        if indices.is_empty() || indices.len() % corners != 0 {
            return Err(p.error("indices", format!("{} indices is not a whole number of {corners}-vertex faces", indices.len())));
        }
        let n = positions.len();
        if let Some(bad) = indices.iter().find(|&&i| !(i >= 0.0 && (i as usize) < n && i.fract() == 0.0)) {
            return Err(p.error("indices", format!("index {bad} is out of range (the mesh has {n} vertices)")));
        }
        let indices: Vec<u32> = indices.iter().map(|&i| i as u32).collect();
        let normals = p.points::<3>("N", "normal")?.map(|v| v.into_iter().map(Vec3::from).collect::<Vec<_>>());
        let uvs = p.points::<2>("uv", "point2")?.map(|v| v.into_iter().map(Vec2::from).collect::<Vec<_>>());
        for (name, len) in [("N", normals.as_ref().map(Vec::len)), ("uv", uvs.as_ref().map(Vec::len))] {
            if len.is_some_and(|l| l != n) {
                return Err(p.error(name, format!("\"{name}\" has {} values for {n} vertices", len.unwrap())));
            }
        }
        p.pass_over(&["S", "faceIndices"]);
        let faces = if corners == 3 {
            indices.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
        } else {
            // p00 p10 p01 p11: (p00, p10, p11) and (p00, p11, p01), both facing dpdu x dpdv.
            indices.chunks(4).flat_map(|c| [[c[0], c[1], c[3]], [c[0], c[3], c[2]]]).collect()
        };
        let uvs = match uvs {
            Some(uvs) => Some(uvs),
            // A bilinear patch's own (u, v) at its corners, where each vertex has one place.
            None if corners == 4 => {
                let mut uv = vec![None; n];
                let mut consistent = true;
                for c in indices.chunks(4) {
                    for (k, corner) in [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE].into_iter().enumerate() {
                        let slot = &mut uv[c[k] as usize];
                        consistent &= slot.is_none_or(|s| s == corner);
                        *slot = Some(corner);
                    }
                }
                consistent.then(|| uv.into_iter().map(|u| u.unwrap_or_default()).collect())
            }
            None => None,
        };
        let has_normals = normals.is_some();
        Ok((IndexedMesh { positions, normals, uvs, indices: faces }, has_normals))
    }

    /// Appends a mesh's triangles, fronts as pbrt's (see the module's notes). A mesh whose
    /// every triangle has no area adds nothing, with a warning (pbrt-v4 loads it and never
    /// hits it); an emitting one is refused (a light of no area has no density to sample).
    #[allow(clippy::too_many_arguments)]
    fn add_mesh(
        &mut self,
        p: &Params,
        mesh: IndexedMesh,
        transform: &Transform,
        normals: bool,
        reverse: bool,
        shape: u32,
        emits: bool,
    ) -> Result<()> {
        self.reserve(p, mesh.indices.len())?;
        let how = if normals { Normals::Smooth } else { Normals::Flat };
        let (mut triangles, skipped) = mesh::triangles(&mesh, transform, how, shape).map_err(|e| p.directive_error(e))?;
        if triangles.is_empty() && emits {
            return Err(p.directive_error(format!(
                "all {skipped} triangles of the shape have no area: the area light has nothing to emit from"
            )));
        }
        if triangles.is_empty() {
            self.warnings.push(p.directive_error(format!("all {skipped} triangles of the shape have no area: it adds nothing")));
        } else if skipped > 0 {
            self.warnings.push(p.directive_error(format!("{skipped} triangles have no area and are skipped")));
        }
        for t in &mut triangles {
            let face = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]);
            // With normals, the side they face; else the winding, turned by ReverseOrientation.
            let flip = match t.n {
                Some(n) => face.dot(n[0] + n[1] + n[2]) < 0.0,
                None => reverse,
            };
            if flip {
                t.p.swap(1, 2);
                if let Some(n) = &mut t.n {
                    n.swap(1, 2);
                }
                if let Some(uv) = &mut t.uv {
                    uv.swap(1, 2);
                }
            }
        }
        self.triangles.extend(triangles);
        Ok(())
    }

    /// Refuses `count` more primitives where the scene would outgrow the machine's memory.
    fn reserve(&self, p: &Params, count: usize) -> Result<()> {
        let have = (self.triangles.len() + self.spheres.len()) as u64;
        self.budget.check(have, count as u64, "").map_err(|e| p.directive_error(e))
    }
}

/// pbrt's disk (an annulus when `inner` > 0) at z = `height`, facing +z, with its uv.
fn disk(height: f32, radius: f32, inner: f32) -> IndexedMesh {
    let mut m = IndexedMesh { uvs: Some(Vec::new()), ..IndexedMesh::default() };
    let n = DISK_SEGMENTS;
    for i in 0..=n {
        let phi = 2.0 * std::f32::consts::PI * i as f32 / n as f32;
        let (s, c) = phi.sin_cos();
        let u = i as f32 / n as f32;
        m.positions.extend([Vec3::new(radius * c, radius * s, height), Vec3::new(inner * c, inner * s, height)]);
        m.uvs.as_mut().unwrap().extend([Vec2::new(u, 0.0), Vec2::new(u, 1.0)]);
    }
    for i in 0..n {
        let (o0, i0, o1, i1) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
        // Counter-clockwise seen from +z.
        m.indices.push([o0, o1, i1]);
        if inner > 0.0 {
            m.indices.push([o0, i1, i0]);
        }
    }
    m
}

/// The factor of a similarity transform's linear part, or `None` when it shears or scales
/// unevenly.
fn uniform_scale(linear: Mat3) -> Option<f32> {
    let s = linear.x_axis.length();
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * s;
    let ok = s > 0.0
        && s.is_finite()
        && close(linear.y_axis.length(), s)
        && close(linear.z_axis.length(), s)
        && close(linear.x_axis.dot(linear.y_axis) / s, 0.0)
        && close(linear.y_axis.dot(linear.z_axis) / s, 0.0)
        && close(linear.x_axis.dot(linear.z_axis) / s, 0.0);
    ok.then_some(s)
}
