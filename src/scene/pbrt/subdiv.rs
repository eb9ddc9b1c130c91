//! pbrt-v4's `loopsubdiv` shape: Loop subdivision (Loop 1987) of a triangle mesh, `levels`
//! times, then every vertex pushed to the limit surface with the limit surface's normal, as
//! pbrt-v4's `LoopSubdivide` does (pbrt-v3 book, section 3.8). The result is a triangle mesh
//! with normals `N`, read as a `trianglemesh`.
//!
//! Rules, for a vertex of valence n (neighbours p_j) and an edge (a, b):
//! - even (old) vertices: interior (1 - n beta) v + beta sum p_j, beta = 3/16 for n = 3
//!   and 3 / (8 n) otherwise; boundary 3/4 v + 1/8 (the two boundary neighbours);
//! - odd (edge) vertices: interior 3/8 (a + b) + 1/8 (the two opposite vertices); boundary
//!   1/2 (a + b);
//! - limit positions: interior (1 - n gamma) v + gamma sum p_j, gamma = 1 / (n + 3 / (8
//!   beta)); boundary 3/5 v + 1/5 (the two boundary neighbours);
//! - limit normals: cross(S, T) of the tangents over the one-ring in pbrt's order (interior:
//!   S = sum cos(2 pi j / n) p_j, T = sum sin(2 pi j / n) p_j; boundary: pbrt's closed forms).
//!   pbrt's walk (next vertex, then the face across the edge to it) turns clockwise seen from
//!   the side a counter-clockwise winding faces, so these normals point against the winding,
//!   and the mesh's front with them (the reader's triangles face `N`), as in pbrt-v4.

use glam::Vec3;
use std::collections::HashMap;
use std::f32::consts::PI;

/// A triangle mesh being subdivided: faces counter-clockwise as given.
#[derive(Debug)]
pub(super) struct LoopMesh {
    pub positions: Vec<Vec3>,
    pub faces: Vec<[u32; 3]>,
}

/// The faces around each edge: `(min, max)` vertex pair to the faces holding it.
type EdgeFaces = HashMap<(u32, u32), Vec<u32>>;

fn edge(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The mesh's edges, refusing an edge of more than two faces or two faces that run an edge
/// the same way (pbrt's one-ring walk needs a consistently oriented manifold).
fn edges(m: &LoopMesh) -> Result<EdgeFaces, String> {
    let mut e: EdgeFaces = HashMap::new();
    let mut directed = HashMap::new();
    for (f, face) in m.faces.iter().enumerate() {
        if face[0] == face[1] || face[1] == face[2] || face[0] == face[2] {
            return Err(format!("face {f} repeats a vertex"));
        }
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            if directed.insert((a, b), f).is_some() {
                return Err(format!(
                    "the edge {a}-{b} is used the same way by two faces: the mesh is not consistently oriented, or not manifold"
                ));
            }
            let list = e.entry(edge(a, b)).or_default();
            list.push(f as u32);
            if list.len() > 2 {
                return Err(format!("the edge {a}-{b} is shared by more than two faces"));
            }
        }
    }
    Ok(e)
}

/// Position of `v` in `face`.
fn slot(face: &[u32; 3], v: u32) -> usize {
    face.iter().position(|&x| x == v).unwrap()
}

/// The face across the edge (a, b) from `f`, if any.
fn across(e: &EdgeFaces, f: u32, a: u32, b: u32) -> Option<u32> {
    e[&edge(a, b)].iter().copied().find(|&g| g != f)
}

/// Vertex `v`'s one-ring in pbrt's order (SDVertex::oneRing) and whether it is on a boundary.
/// `start` is a face holding `v`.
fn one_ring(m: &LoopMesh, e: &EdgeFaces, v: u32, start: u32) -> (Vec<u32>, bool) {
    let next = |f: u32| m.faces[f as usize][(slot(&m.faces[f as usize], v) + 1) % 3];
    let prev = |f: u32| m.faces[f as usize][(slot(&m.faces[f as usize], v) + 2) % 3];
    // Interior: nextVert, then nextFace (across the edge to nextVert) round to the start.
    let mut ring = Vec::new();
    let mut f = start;
    loop {
        ring.push(next(f));
        match across(e, f, v, next(f)) {
            Some(g) if g == start => return (ring, false),
            Some(g) => f = g,
            None => break,
        }
        if ring.len() > m.faces.len() {
            break;
        }
    }
    // Boundary: from the last face nextFace reaches, its nextVert, then prevVerts back
    // through prevFace.
    let mut ring = vec![next(f)];
    let mut g = Some(f);
    while let Some(face) = g {
        ring.push(prev(face));
        g = across(e, face, prev(face), v);
        if ring.len() > m.faces.len() + 2 {
            break;
        }
    }
    (ring, true)
}

/// beta of Loop's even-vertex rule for valence `n`.
fn beta(n: usize) -> f32 {
    if n == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * n as f32)
    }
}

/// A face holding each vertex (`None` for a vertex no face uses).
fn vertex_faces(m: &LoopMesh) -> Vec<Option<u32>> {
    let mut vf = vec![None; m.positions.len()];
    for (f, face) in m.faces.iter().enumerate() {
        for &v in face {
            vf[v as usize].get_or_insert(f as u32);
        }
    }
    vf
}

/// One level of subdivision: each face becomes four, winding kept.
fn subdivide_once(m: &LoopMesh) -> Result<LoopMesh, String> {
    let e = edges(m)?;
    let vf = vertex_faces(m);
    let mut positions: Vec<Vec3> = m
        .positions
        .iter()
        .enumerate()
        .map(|(v, &p)| {
            let Some(f) = vf[v] else { return p };
            let (ring, boundary) = one_ring(m, &e, v as u32, f);
            let q = |i: u32| m.positions[i as usize];
            if boundary {
                // weightBoundary(v, 1/8): the ring's ends are the boundary neighbours.
                0.75 * p + 0.125 * (q(ring[0]) + q(*ring.last().unwrap()))
            } else {
                let b = beta(ring.len());
                (1.0 - ring.len() as f32 * b) * p + b * ring.iter().map(|&i| q(i)).sum::<Vec3>()
            }
        })
        .collect();
    // Odd vertices, one an edge.
    let mut odd: HashMap<(u32, u32), u32> = HashMap::with_capacity(e.len());
    let mut keys: Vec<_> = e.keys().copied().collect();
    keys.sort_unstable();
    for (a, b) in keys {
        let faces = &e[&(a, b)];
        let (pa, pb) = (m.positions[a as usize], m.positions[b as usize]);
        let p = if faces.len() == 1 {
            0.5 * (pa + pb)
        } else {
            let other = |f: u32| {
                let face = m.faces[f as usize];
                m.positions[face.into_iter().find(|&x| x != a && x != b).unwrap() as usize]
            };
            0.375 * (pa + pb) + 0.125 * (other(faces[0]) + other(faces[1]))
        };
        odd.insert((a, b), positions.len() as u32);
        positions.push(p);
    }
    let mut faces = Vec::with_capacity(4 * m.faces.len());
    for &[v0, v1, v2] in &m.faces {
        let (e01, e12, e20) = (odd[&edge(v0, v1)], odd[&edge(v1, v2)], odd[&edge(v2, v0)]);
        faces.extend([[v0, e01, e20], [v1, e12, e01], [v2, e20, e12], [e01, e12, e20]]);
    }
    Ok(LoopMesh { positions, faces })
}

/// `levels` subdivisions of `m`, then its vertices on the limit surface with their normals.
/// Vertices no face uses are kept where they are, with a zero normal (the triangles do not
/// refer to them).
pub(super) fn loop_subdivide(mut m: LoopMesh, levels: u32) -> Result<(LoopMesh, Vec<Vec3>), String> {
    for _ in 0..levels {
        m = subdivide_once(&m)?;
    }
    let e = edges(&m)?;
    let vf = vertex_faces(&m);
    let q = |i: u32| m.positions[i as usize];
    let mut limit = m.positions.clone();
    let mut rings = Vec::with_capacity(m.positions.len());
    for (v, p) in m.positions.iter().enumerate() {
        let Some(f) = vf[v] else {
            rings.push(None);
            continue;
        };
        let (ring, boundary) = one_ring(&m, &e, v as u32, f);
        limit[v] = if boundary {
            0.6 * *p + 0.2 * (q(ring[0]) + q(*ring.last().unwrap()))
        } else {
            let n = ring.len();
            let gamma = 1.0 / (n as f32 + 3.0 / (8.0 * beta(n)));
            (1.0 - n as f32 * gamma) * *p + gamma * ring.iter().map(|&i| q(i)).sum::<Vec3>()
        };
        rings.push(Some((ring, boundary)));
    }
    let normals = rings
        .iter()
        .enumerate()
        .map(|(v, r)| {
            let Some((ring, boundary)) = r else { return Vec3::ZERO };
            let p = |k: usize| limit[ring[k] as usize];
            let n = ring.len();
            let (s, t) = if !boundary {
                (0..n).fold((Vec3::ZERO, Vec3::ZERO), |(s, t), j| {
                    let th = 2.0 * PI * j as f32 / n as f32;
                    (s + th.cos() * p(j), t + th.sin() * p(j))
                })
            } else {
                let s = p(n - 1) - p(0);
                let c = limit[v];
                let t = match n {
                    2 => p(0) + p(1) - 2.0 * c,
                    3 => p(1) - c,
                    4 => -p(0) + 2.0 * p(1) + 2.0 * p(2) - p(3) - 2.0 * c,
                    _ => {
                        let th = PI / (n - 1) as f32;
                        let t = th.sin() * (p(0) + p(n - 1))
                            + (1..n - 1).map(|k| (2.0 * th.cos() - 2.0) * (k as f32 * th).sin() * p(k)).sum::<Vec3>();
                        -t
                    }
                };
                (s, t)
            };
            s.cross(t)
        })
        .collect();
    m.positions = limit;
    Ok((m, normals))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A regular octahedron, faces counter-clockwise seen from outside.
    fn octahedron() -> LoopMesh {
        let positions = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        let faces = vec![[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
        LoopMesh { positions, faces }
    }

    #[test]
    fn octahedron_subdivides_towards_a_rounded_surface() {
        let (m, normals) = loop_subdivide(octahedron(), 2).unwrap();
        // 6 + 12 + 48 vertices, 8 * 16 faces, still closed and oriented.
        assert_eq!((m.positions.len(), m.faces.len()), (66, 128));
        edges(&m).unwrap();
        // The original vertices, of valence 4 (beta 3/32, gamma 1/8), by hand: level 1 takes
        // X to 0.625 X (its ring sums to 0) and makes edge points 0.375 (X + Y); level 2 takes
        // it to 0.625^2 X + 3/32 (1.5 X) = 0.53125 X, its new ring summing to 1.875 X; the
        // limit is (1 - 4/8) 0.53125 X + 1/8 (1.875 X) = 0.5 X.
        for v in 0..6 {
            assert!((m.positions[v] - 0.5 * octahedron().positions[v]).length() < 1e-6, "{}", m.positions[v]);
        }
        // Limit normals point along the vertex of a symmetric position, one way for all.
        let sign = normals[0].normalize().dot(m.positions[0].normalize());
        assert!((sign.abs() - 1.0).abs() < 1e-4, "{sign}");
        for (p, n) in m.positions.iter().zip(&normals) {
            let d = n.normalize().dot(p.normalize());
            assert!(d * sign > 0.8, "{p} {n}");
        }
    }

    #[test]
    fn open_and_inconsistent_meshes() {
        // One triangle: every vertex and edge on the boundary, the limit its own corners
        // moved 1/5 of the way towards the other two each.
        let m = LoopMesh { positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y], faces: vec![[0, 1, 2]] };
        let (l, normals) = loop_subdivide(m, 0).unwrap();
        assert!((l.positions[0] - Vec3::new(0.2, 0.2, 0.0)).length() < 1e-6);
        assert!(normals.iter().all(|n| n.normalize().z.abs() > 0.999));
        let flipped = LoopMesh { positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z], faces: vec![[0, 1, 2], [0, 1, 3]] };
        assert!(loop_subdivide(flipped, 1).unwrap_err().contains("not consistently oriented"));
    }
}
