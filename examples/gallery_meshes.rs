//! Generates the procedural meshes of the gallery scenes (`scenes/gallery/*.toml`) as
//! Wavefront OBJ files with vertex normals, in `scenes/gallery/meshes/`:
//!
//! - `water.obj`: a water surface, a height field of a few sine waves over the floor of the
//!   Cornell box, with a vertical skirt that closes the water body at the open front;
//! - `ice_cream_bowl.obj`: a footed glass sundae bowl;
//! - `flower_pot.obj`: a tapered glass flower pot with a rolled rim band.
//!
//! ```text
//! cargo run --release --example gallery_meshes
//! ```
//!
//! Everything is in scene units: the gallery's Cornell box spans x, z in [-1, 1] and y in
//! [0, 2]. The water is generated in place. The bowl and the pot stand on y = 0 around the
//! y axis, so a scene places them with a translation in x and z (and a rotation about y or a
//! uniform scale if it likes) and they still stand on the floor.
//!
//! The bowl and the pot are surfaces of revolution of a closed profile with wall thickness
//! (outer wall, rim, inner wall), so that glass refracts correctly: the generator checks
//! that each is watertight (every edge shared by exactly two triangles, in opposite
//! directions), that every triangle faces out of the solid (positive enclosed volume) and
//! that every vertex normal lies on the front side of the triangles that use it.

use glam::{DVec2, DVec3};
use std::collections::HashMap;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

const OUTPUT_DIR: &str = "scenes/gallery/meshes";

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(OUTPUT_DIR);
    std::fs::create_dir_all(&dir).expect("cannot create the output folder");

    let water = water_surface();
    water.check(Closure::Open);
    water.write_obj(
        &dir.join("water.obj"),
        "Water surface for scenes/gallery/water.toml: a height field of three sine waves\n\
         over the floor of the Cornell box (x, z in [-1, 1]) at mean height 0.4, with a\n\
         vertical skirt at z = +1 that closes the water body at the box's open front.\n\
         Normals face up and out of the water.",
    );

    let bowl = revolve(&ice_cream_bowl_profile(), 40);
    bowl.check(Closure::Closed);
    bowl.write_obj(
        &dir.join("ice_cream_bowl.obj"),
        "Footed glass ice-cream bowl for scenes/gallery/glass-bowl.toml: a closed surface\n\
         of revolution about the y axis with wall thickness, standing on y = 0.\n\
         Watertight, triangles counter-clockwise seen from outside the glass.",
    );

    let pot = revolve(&flower_pot_profile(), 48);
    pot.check(Closure::Closed);
    pot.write_obj(
        &dir.join("flower_pot.obj"),
        "Glass flower pot for scenes/gallery/flower-pot.toml: a closed surface of\n\
         revolution about the y axis with wall thickness, standing on y = 0.\n\
         Watertight, triangles counter-clockwise seen from outside the glass.",
    );
}

// ---------------------------------------------------------------------------------------
// Water

/// One travelling-wave component of the water surface, frozen in time.
struct Wave {
    amplitude: f64,
    wavelength: f64,
    /// Direction of travel in the (x, z) plane, in degrees from +x towards +z.
    direction_degrees: f64,
    phase: f64,
}

/// Gentle waves: slopes stay below about 15 degrees, yet the crests curve enough to focus
/// light into a caustic network on the floor some 0.4 below.
const WAVES: [Wave; 3] = [
    Wave { amplitude: 0.008, wavelength: 0.62, direction_degrees: 20.0, phase: 0.3 },
    Wave { amplitude: 0.006, wavelength: 0.43, direction_degrees: 115.0, phase: 1.7 },
    Wave { amplitude: 0.004, wavelength: 0.31, direction_degrees: 245.0, phase: 4.1 },
];

/// Mean height of the water surface above the floor.
const WATER_LEVEL: f64 = 0.4;

/// The height of the water at (x, z) and its gradient (dh/dx, dh/dz).
fn water_height(x: f64, z: f64) -> (f64, DVec2) {
    let mut height = WATER_LEVEL;
    let mut gradient = DVec2::ZERO;
    for wave in &WAVES {
        let k = 2.0 * PI / wave.wavelength;
        let d = DVec2::from_angle(wave.direction_degrees.to_radians());
        let arg = k * d.dot(DVec2::new(x, z)) + wave.phase;
        height += wave.amplitude * arg.sin();
        gradient += wave.amplitude * k * arg.cos() * d;
    }
    (height, gradient)
}

/// The water surface as an N x N grid of quads over [-1, 1]^2 in x and z, with the exact
/// normals of the height field, plus the skirt down to the floor along the front edge.
fn water_surface() -> Mesh {
    const N: usize = 40;
    let mut mesh = Mesh::default();
    let coordinate = |i: usize| -1.0 + 2.0 * i as f64 / N as f64;

    // Surface vertices, row by row from the back (z = -1) to the front (z = +1). The
    // normal of the height field y = h(x, z) is (-dh/dx, 1, -dh/dz), normalised.
    let surface = |i: usize, j: usize| (j * (N + 1) + i) as u32;
    for j in 0..=N {
        for i in 0..=N {
            let (x, z) = (coordinate(i), coordinate(j));
            let (y, gradient) = water_height(x, z);
            mesh.positions.push(DVec3::new(x, y, z));
            mesh.normals.push(DVec3::new(-gradient.x, 1.0, -gradient.y).normalize());
        }
    }
    // Two triangles a cell, wound counter-clockwise seen from above.
    for j in 0..N {
        for i in 0..N {
            let [a, b, c, d] = [surface(i, j), surface(i + 1, j), surface(i + 1, j + 1), surface(i, j + 1)];
            mesh.triangles.push([a, d, c].map(Corner::smooth));
            mesh.triangles.push([a, c, b].map(Corner::smooth));
        }
    }

    // The skirt: a vertical strip under the front edge (z = +1), from the surface down to the
    // floor, facing +z. It shares its top positions with the surface but has its own normal,
    // so the edge stays sharp.
    let front = mesh.push_normal(DVec3::Z);
    let bottom = mesh.positions.len() as u32;
    for i in 0..=N {
        mesh.positions.push(DVec3::new(coordinate(i), 0.0, 1.0));
    }
    for i in 0..N as u32 {
        let [top0, top1] = [surface(i as usize, N), surface(i as usize + 1, N)];
        let [bottom0, bottom1] = [bottom + i, bottom + i + 1];
        mesh.triangles.push([bottom0, bottom1, top1].map(|p| Corner { p, n: front }));
        mesh.triangles.push([bottom0, top1, top0].map(|p| Corner { p, n: front }));
    }
    mesh
}

// ---------------------------------------------------------------------------------------
// Profiles and surfaces of revolution

/// A point of a profile curve with the outward normals of the pieces of curve on either side
/// of it: equal where the curve is smooth, different at a crease.
#[derive(Clone, Copy, Debug)]
struct ProfilePoint {
    p: DVec2,
    normal_before: DVec2,
    normal_after: DVec2,
}

impl ProfilePoint {
    fn is_crease(&self) -> bool {
        self.normal_before.angle_to(self.normal_after).abs() > 1e-3
    }
}

/// A cross-section of a solid of revolution: a curve in the half-plane (r, y), r >= 0, to be
/// revolved about the y axis. It runs from a point on the axis to another point on the axis,
/// anticlockwise around the solid (the solid is on its left), so its right-hand normal
/// points out of the solid. Built piece by piece, each piece starting where the last ended.
#[derive(Default)]
struct Profile {
    points: Vec<ProfilePoint>,
}

impl Profile {
    fn starting_at(p: DVec2) -> Self {
        let point = ProfilePoint { p, normal_before: DVec2::NAN, normal_after: DVec2::NAN };
        Profile { points: vec![point] }
    }

    fn end(&self) -> DVec2 {
        self.points.last().unwrap().p
    }

    /// Appends the curve `f(t)`, t in [0, 1], sampled at `steps` equal steps of t. It must
    /// start where the profile ends, and be defined a little beyond [0, 1]. Normals come
    /// from the curve's tangent (by central differences), so they are exact for any smooth
    /// `f`, and a kink where two pieces meet becomes a crease with a normal for each side.
    fn curve(&mut self, steps: usize, f: impl Fn(f64) -> DVec2) {
        assert!(steps > 0);
        assert!(f(0.0).distance(self.end()) < 1e-9, "a piece of profile must start where the last ended");
        let normal = |t: f64| {
            const H: f64 = 1e-6;
            let tangent = f(t + H) - f(t - H);
            DVec2::new(tangent.y, -tangent.x).normalize()
        };
        let last = self.points.last_mut().unwrap();
        last.normal_after = normal(0.0);
        if last.normal_before.is_nan() {
            last.normal_before = last.normal_after;
        }
        for step in 1..=steps {
            let t = step as f64 / steps as f64;
            let n = normal(t);
            self.points.push(ProfilePoint { p: f(t), normal_before: n, normal_after: n });
        }
    }

    /// A straight piece. One step is exact: revolved, a line is a cone, a cylinder or a disc,
    /// whose quads between two rings are planar.
    fn line_to(&mut self, to: DVec2) {
        let from = self.end();
        self.curve(1, |t| from.lerp(to, t));
    }

    /// A circular arc about `center` from angle `from` to angle `to` (radians; anticlockwise
    /// when `to > from`), in steps of at most `max_step` radians.
    fn arc(&mut self, center: DVec2, radius: f64, from: f64, to: f64, max_step: f64) {
        let steps = ((to - from).abs() / max_step).ceil().max(1.0) as usize;
        self.curve(steps, |t| center + radius * DVec2::from_angle(from + (to - from) * t));
    }

    /// A polyline from the current end through `corners` to `to`, each corner rounded by a
    /// circular arc of its radius that is tangent to both of its edges (a radius of zero
    /// leaves a sharp crease). Left turns round convex corners of the solid, right turns
    /// concave ones.
    fn rounded_path(&mut self, corners: &[(DVec2, f64)], to: DVec2, max_step: f64) {
        let vertices: Vec<DVec2> =
            std::iter::once(self.end()).chain(corners.iter().map(|c| c.0)).chain(std::iter::once(to)).collect();
        for (i, &(corner, radius)) in corners.iter().enumerate() {
            let incoming = (corner - vertices[i]).normalize();
            let outgoing = (vertices[i + 2] - corner).normalize();
            // Positive for a left turn. The arc touches each edge at `setback` from the corner.
            let turn = incoming.angle_to(outgoing);
            let setback = radius * (turn.abs() / 2.0).tan();
            assert!(
                setback <= (corner - vertices[i]).length() + 1e-12 && setback <= (vertices[i + 2] - corner).length() + 1e-12,
                "the fillet at {corner} does not fit its edges"
            );
            self.line_to_unless_there(corner - setback * incoming);
            if radius > 0.0 && turn != 0.0 {
                // The centre lies `radius` to the inside of the turn.
                let side = turn.signum() * incoming.perp();
                let center = self.end() + radius * side;
                let from = (-side).to_angle();
                self.arc(center, radius, from, from + turn, max_step);
            }
        }
        self.line_to_unless_there(to);
    }

    /// `line_to`, but no zero-length piece where two fillets meet.
    fn line_to_unless_there(&mut self, to: DVec2) {
        if self.end().distance(to) > 1e-9 {
            self.line_to(to);
        }
    }

    /// Checks that the profile makes a valid solid of revolution: it starts and ends on the
    /// axis, meeting it at a right angle (a smooth pole, not a cone tip), stays off the axis
    /// in between, and never crosses itself.
    fn validate(&self) {
        let (first, last) = (self.points[0], *self.points.last().unwrap());
        for pole in [first, last] {
            assert!(pole.p.x.abs() < 1e-12, "the profile must start and end on the axis");
            assert!(
                pole.normal_before.x.abs() < 1e-6 && pole.normal_after.x.abs() < 1e-6,
                "the profile must meet the axis at a right angle"
            );
        }
        let inner = &self.points[1..self.points.len() - 1];
        assert!(inner.iter().all(|q| q.p.x > 1e-9), "the profile must stay off the axis between its ends");
        let segments: Vec<(DVec2, DVec2)> = self.points.windows(2).map(|w| (w[0].p, w[1].p)).collect();
        for i in 0..segments.len() {
            for j in i + 2..segments.len() {
                assert!(!segments_cross(segments[i], segments[j]), "the profile crosses itself (pieces {i} and {j})");
            }
        }
        // Anticlockwise around the solid: the cross-section's signed area, closed along the
        // axis, is positive.
        let area: f64 = segments.iter().map(|(a, b)| a.perp_dot(*b)).sum::<f64>() / 2.0;
        assert!(area > 0.0, "the profile must run anticlockwise around the solid");
    }
}

/// Whether two closed segments share a point.
fn segments_cross((a, b): (DVec2, DVec2), (c, d): (DVec2, DVec2)) -> bool {
    let side = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let (d1, d2) = (side(c, d, a), side(c, d, b));
    let (d3, d4) = (side(a, b, c), side(a, b, d));
    if d1 == 0.0 && d2 == 0.0 {
        // On one line: they share a point if their extents along it overlap.
        let axis = b - a;
        let (s, t) = (axis.dot(c - a), axis.dot(d - a));
        return s.max(t) >= 0.0 && s.min(t) <= axis.length_squared();
    }
    (d1 * d2 <= 0.0) && (d3 * d4 <= 0.0)
}

/// Revolves `profile` about the y axis in `sectors` equal sectors. The ends of the profile
/// become the two poles, each closed by a fan of triangles; a crease in the profile becomes
/// a sharp ring, with the positions shared and a ring of normals for each side.
///
/// A profile point (r, y) at angle theta goes to (r cos theta, y, r sin theta). With s the
/// arc length along the profile, d/ds x d/dtheta = r (y' cos theta, -r', y' sin theta) is r
/// times the revolved right-hand normal (y', -r'): the quad (s0, theta0), (s1, theta0),
/// (s1, theta1), (s0, theta1) is anticlockwise seen from outside the solid.
fn revolve(profile: &Profile, sectors: usize) -> Mesh {
    profile.validate();
    let points = &profile.points;
    let last = points.len() - 1;
    let angle = |j: usize| 2.0 * PI * (j % sectors) as f64 / sectors as f64;
    let revolved = |v: DVec2, j: usize| DVec3::new(v.x * angle(j).cos(), v.y, v.x * angle(j).sin());

    let mut mesh = Mesh::default();
    // Position and normal indices of each profile point: one position for a pole, else a
    // ring of `sectors` positions; normals likewise, for each side of the point.
    let mut position_base = Vec::with_capacity(points.len());
    let mut normal_base = Vec::with_capacity(points.len()); // (before, after)
    for (k, point) in points.iter().enumerate() {
        position_base.push(mesh.positions.len() as u32);
        if k == 0 || k == last {
            mesh.positions.push(DVec3::new(0.0, point.p.y, 0.0));
            let n = mesh.push_normal(DVec3::new(0.0, point.normal_after.y.signum(), 0.0));
            normal_base.push((n, n));
            continue;
        }
        mesh.positions.extend((0..sectors).map(|j| revolved(point.p, j)));
        let mut ring = |n: DVec2| {
            let base = mesh.normals.len() as u32;
            mesh.normals.extend((0..sectors).map(|j| revolved(n, j)));
            base
        };
        let before = ring(point.normal_before);
        let after = if point.is_crease() { ring(point.normal_after) } else { before };
        normal_base.push((before, after));
    }

    // The corner of profile point k at sector j, on the side of the piece of profile that
    // leaves it (`after`) or arrives at it.
    let corner = |k: usize, j: usize, after: bool| {
        let offset = if k == 0 || k == last { 0 } else { (j % sectors) as u32 };
        let (before_n, after_n) = normal_base[k];
        Corner { p: position_base[k] + offset, n: if after { after_n } else { before_n } + offset }
    };
    for k in 0..last {
        for j in 0..sectors {
            let a = corner(k, j, true);
            let b = corner(k + 1, j, false);
            let c = corner(k + 1, j + 1, false);
            let d = corner(k, j + 1, true);
            if k == 0 {
                mesh.triangles.push([a, b, c]); // fan around the first pole (a = d)
            } else if k + 1 == last {
                mesh.triangles.push([a, b, d]); // fan around the last pole (b = c)
            } else {
                mesh.triangles.push([a, b, c]);
                mesh.triangles.push([a, c, d]);
            }
        }
    }
    mesh
}

/// The footed sundae bowl: a round foot with a rounded edge, a short stem, and a bowl whose
/// outer wall is a quarter of an ellipse (slightly short of vertical at the rim, so the bowl
/// opens a little), with an inner wall at constant thickness and a half-round rim.
fn ice_cream_bowl_profile() -> Profile {
    let foot_radius = 0.16;
    let foot_edge = 0.02; // height of the foot's rim
    let stem_radius = 0.032;
    let stem_base = 0.045; // where the stem meets the top of the foot
    let bowl_bottom = 0.10; // lowest point of the bowl's outer wall
    let (a, b) = (0.36, 0.27); // outer ellipse: radius at its widest, depth
    let rim_t = 0.47 * PI; // ellipse parameter of the rim (pi / 2 would be vertical)
    let wall = 0.016; // thickness of the glass

    // Outer wall of the bowl and its outward normal, for t in [0, pi / 2]; the inner wall
    // is offset inwards by `wall` along that normal.
    let outer = move |t: f64| DVec2::new(a * t.sin(), bowl_bottom + b * (1.0 - t.cos()));
    let normal = move |t: f64| DVec2::new(b * t.sin(), -a * t.cos()).normalize();
    let inner = move |t: f64| outer(t) - wall * normal(t);
    let stem_t = (stem_radius / a).asin(); // where the stem meets the outer wall

    let fine = 30f64.to_radians();
    let mut profile = Profile::starting_at(DVec2::ZERO);
    // Foot and stem: the flat underside, a rounded edge, the top of the foot sloping up to
    // the stem with a fillet, and the stem up to the bowl (a sharp, concave crease).
    profile.rounded_path(
        &[
            (DVec2::new(foot_radius, 0.0), 0.008),
            (DVec2::new(foot_radius, foot_edge), 0.008),
            (DVec2::new(stem_radius, stem_base), 0.02),
        ],
        outer(stem_t),
        fine,
    );
    // Outer wall up to the rim.
    profile.curve(12, |s| outer(stem_t + (rim_t - stem_t) * s));
    // The rim: a half circle from the outer to the inner wall, tangent to both.
    let rim_center = outer(rim_t) - 0.5 * wall * normal(rim_t);
    let from = normal(rim_t).to_angle();
    profile.arc(rim_center, 0.5 * wall, from, from + PI, fine);
    // Inner wall down to the axis, where it is horizontal.
    profile.curve(14, |s| inner(rim_t * (1.0 - s)));
    profile
}

/// The flower pot: a tapered wall on a flat bottom, a band around the top (a ledge stepping
/// out, then vertical), and an inner wall parallel to the outer one. Every corner is
/// rounded by a small fillet, as on moulded glass, so the whole surface is smooth.
fn flower_pot_profile() -> Profile {
    let bottom_radius = 0.20; // outer radius at the floor
    let wall_top = (0.27, 0.44); // (radius, height) where the tapered wall meets the band
    let band_radius = 0.30;
    let height = 0.53;
    let wall = 0.02; // thickness of the wall, square to it
    let floor = 0.03; // thickness of the bottom

    // The inner wall is the outer wall's line moved inwards by `wall`: at height y its
    // radius is r_outer(y) - wall / cos(taper).
    let slope = (wall_top.0 - bottom_radius) / wall_top.1; // dr / dy
    let inner_radius = |y: f64| bottom_radius + slope * y - wall * (1.0 + slope * slope).sqrt();

    let mut profile = Profile::starting_at(DVec2::ZERO);
    profile.rounded_path(
        &[
            (DVec2::new(bottom_radius, 0.0), 0.03),            // outer bottom edge
            (DVec2::new(wall_top.0, wall_top.1), 0.006),       // wall into the ledge (concave)
            (DVec2::new(band_radius, wall_top.1), 0.008),      // ledge to band
            (DVec2::new(band_radius, height), 0.008),          // top of the band, outside
            (DVec2::new(inner_radius(height), height), 0.008), // top of the band, inside
            (DVec2::new(inner_radius(floor), floor), 0.025),   // inner bottom edge (concave)
        ],
        DVec2::new(0.0, floor),
        20f64.to_radians(),
    );
    profile
}

// ---------------------------------------------------------------------------------------
// Indexed meshes, checks and OBJ output

/// A triangle corner: a position index and a normal index (OBJ's `v//vn`).
#[derive(Clone, Copy, Debug)]
struct Corner {
    p: u32,
    n: u32,
}

impl Corner {
    /// A corner whose normal has the same index as its position.
    fn smooth(i: u32) -> Self {
        Corner { p: i, n: i }
    }
}

/// A triangle mesh with separately indexed positions and normals, as in OBJ. Triangles are
/// anticlockwise seen from their front (outside) side.
#[derive(Default)]
struct Mesh {
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    triangles: Vec<[Corner; 3]>,
}

#[derive(Clone, Copy, PartialEq)]
enum Closure {
    /// A surface with a boundary (the water): edges may be used once.
    Open,
    /// The boundary of a solid: every edge used exactly twice, in opposite directions.
    Closed,
}

impl Mesh {
    fn push_normal(&mut self, n: DVec3) -> u32 {
        self.normals.push(n.normalize());
        self.normals.len() as u32 - 1
    }

    fn face_normal(&self, t: &[Corner; 3]) -> DVec3 {
        let [a, b, c] = t.map(|c| self.positions[c.p as usize]);
        (b - a).cross(c - a)
    }

    /// Panics unless the mesh is consistently oriented (no directed edge used twice), free
    /// of degenerate triangles, has vertex normals on the front side of every triangle, and,
    /// if `Closed`, is watertight and encloses a positive volume.
    fn check(&self, closure: Closure) {
        let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
        for t in &self.triangles {
            let n = self.face_normal(t);
            assert!(n.length() > 1e-12, "degenerate triangle {t:?}");
            for (i, c) in t.iter().enumerate() {
                *edges.entry((c.p, t[(i + 1) % 3].p)).or_default() += 1;
                let vn = self.normals[c.n as usize];
                assert!(vn.dot(n) > 0.0, "the vertex normal of {c:?} faces away from its triangle");
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "edge {a}-{b} is used twice in the same direction");
            if closure == Closure::Closed {
                assert!(edges.contains_key(&(b, a)), "edge {a}-{b} is a boundary: the mesh is not watertight");
            }
        }
        if closure == Closure::Closed {
            assert!(self.volume() > 0.0, "the triangles face inwards");
        }
    }

    /// Enclosed volume by the divergence theorem (meaningful for a closed mesh).
    fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|c| self.positions[c.p as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        let min = self.positions.iter().fold(DVec3::INFINITY, |m, &p| m.min(p));
        let max = self.positions.iter().fold(DVec3::NEG_INFINITY, |m, &p| m.max(p));
        (min, max)
    }

    /// Writes the mesh as OBJ (`v`, `vn`, `f v//vn`), with `description` as a comment.
    fn write_obj(&self, path: &Path, description: &str) {
        let (min, max) = self.bounds();
        let mut out = String::new();
        for line in description.lines() {
            writeln!(out, "# {}", line.trim()).unwrap();
        }
        writeln!(
            out,
            "# Written by examples/gallery_meshes.rs. {} vertices, {} triangles.",
            self.positions.len(),
            self.triangles.len()
        )
        .unwrap();
        writeln!(out, "# Bounds: [{:.4}, {:.4}, {:.4}] to [{:.4}, {:.4}, {:.4}].", min.x, min.y, min.z, max.x, max.y, max.z)
            .unwrap();
        for p in &self.positions {
            writeln!(out, "v {:.6} {:.6} {:.6}", p.x, p.y, p.z).unwrap();
        }
        for n in &self.normals {
            writeln!(out, "vn {:.6} {:.6} {:.6}", n.x, n.y, n.z).unwrap();
        }
        for t in &self.triangles {
            let [a, b, c] = t.map(|c| format!("{}//{}", c.p + 1, c.n + 1));
            writeln!(out, "f {a} {b} {c}").unwrap();
        }
        std::fs::write(path, out).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        println!(
            "{}: {} triangles, {} vertices, bounds [{:.3}, {:.3}, {:.3}] to [{:.3}, {:.3}, {:.3}]",
            path.display(),
            self.triangles.len(),
            self.positions.len(),
            min.x,
            min.y,
            min.z,
            max.x,
            max.y,
            max.z
        );
    }
}
