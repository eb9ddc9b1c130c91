//! Area lights (a shape's `emission` in TOML; Mitsuba 3's `area` emitter inside a shape;
//! pbrt-v4's DiffuseAreaLight): radiance Le leaving the front of each of the shape's triangles
//! and spheres alike in every direction (a quad's, a mesh's: the side its winding faces; a
//! sphere's: outside), or both sides (`emission_two_sided`; pbrt-v4's `twosided`). Each
//! primitive is an emitter of power average(Le) area pi, twice that from both sides.
//!
//! Parameters: `emission` (Mitsuba's `radiance`, required), linear RGB >= 0;
//! `emission_two_sided` (false).
//! Kernel: `shaders/shared/emitter/area.wgsl`.

use super::{average, MitsubaEmitter, Packing, Result, Source};
use crate::layout::{Emitter, Features, SPHERE_BIT};
use crate::scene::param::{self, Bound, Invalid};
use crate::scene::toml_table::{put_vec3, Table};
use crate::scene::Scene;
use glam::Vec3;

/// [`Emitter::kind`] of an emitting triangle or sphere (its `prim_ref`).
pub const EMITTER_AREA: u32 = 0;

/// The kind as `info` names it.
pub(super) const NAME: &str = "area";

/// How its power comes about, for messages.
pub(super) const POWER: &str = "its emission times its area times pi";

/// A `[[shapes]]` entry's `emission`, checked.
pub(super) fn read_toml(t: &Table) -> Result<Option<Vec3>> {
    let emission = t.opt("emission", |v| v.rgb(Bound::Any))?;
    emission.map(|e| check(e).map_err(|e| t.invalid(e))).transpose()
}

pub(super) fn from_mitsuba(p: &dyn MitsubaEmitter) -> Result<Vec3> {
    p.colour("radiance")?.ok_or_else(|| p.error("radiance", "an area emitter needs a `radiance`".into()))
}

pub(super) fn toml_keys(t: &mut toml::Table, emission: Vec3) {
    put_vec3(t, "emission", emission);
}

pub(super) fn check(emission: Vec3) -> std::result::Result<Vec3, Invalid> {
    param::rgb("emission", emission, Bound::NonNegative)
}

/// On the GPU: every triangle, then every sphere, of a shape that emits, each of positive
/// power.
pub(super) fn pack(scene: &Scene, p: &mut Packing) {
    // Le, times 2 where it leaves both sides (the power's factor).
    let emission = |shape: u32| {
        let s = &scene.shapes[shape as usize];
        s.emission.unwrap_or(Vec3::ZERO) * if s.emission_two_sided { 2.0 } else { 1.0 }
    };
    let pi = std::f32::consts::PI;
    for (i, t) in scene.triangles.iter().enumerate() {
        let area = 0.5 * (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).length();
        let power = average(emission(t.shape)) * (area * pi) as f64;
        if power > 0.0 {
            let e = Emitter { kind: EMITTER_AREA, prim_ref: i as u32, area, ..Emitter::default() };
            p.push(e, power, Source::Shape(t.shape as usize));
        }
    }
    for (i, s) in scene.spheres.iter().enumerate() {
        let area = 4.0 * pi * s.radius * s.radius;
        let power = average(emission(s.shape)) * (area * pi) as f64;
        if power > 0.0 {
            let e = Emitter { kind: EMITTER_AREA, prim_ref: i as u32 | SPHERE_BIT, area, ..Emitter::default() };
            p.push(e, power, Source::Shape(s.shape as usize));
        }
    }
}

/// `USES_TRIANGLE_LIGHTS` or `USES_SPHERE_LIGHTS`.
pub(super) fn turn_on(e: &Emitter, f: &mut Features) {
    if e.prim_ref & SPHERE_BIT != 0 {
        f.sphere_lights = true;
    } else {
        f.triangle_lights = true;
    }
}
