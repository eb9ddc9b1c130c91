//! Directional lights (`directional` in TOML and Mitsuba 3; pbrt-v4's DistantLight): parallel
//! light travelling along a direction, irradiance E on a surface facing it. Its photons leave a
//! disk facing it that covers the scene's bounding sphere (radius R, moving shapes included),
//! outside it; power E pi R^2.
//!
//! Parameters: `direction` of travel (nonzero; made unit length); `irradiance`, linear RGB >= 0
//! (Mitsuba's default 1). Mitsuba gives the direction as `direction` or as `to_world`'s +z,
//! not both.
//! Kernel: `shaders/shared/emitter/directional.wgsl`.

use super::{average, given_or_to_world, LightKind, MitsubaEmitter, MitsubaPlugin, Result, TomlType};
use crate::layout::{Emitter, Features};
use crate::scene::param::{self, Bound, Invalid};
use crate::scene::toml_table::{put_str, put_vec3, Table, Value};
use glam::Vec3;

/// [`Emitter::kind`] of a directional light.
pub const EMITTER_DIRECTIONAL: u32 = 2;

/// How its power comes about, for messages (followed by the disk).
pub(super) const POWER: &str = "its irradiance times";

pub(super) const TOML: TomlType = TomlType { name: "directional", keys: &["direction", "irradiance"], read: read_toml };

fn read_toml(t: &Table) -> Result<LightKind> {
    Ok(LightKind::Directional {
        direction: t.req("direction", Value::vec3)?,
        irradiance: t.req("irradiance", |v| v.rgb(Bound::Any))?,
    })
}

pub(super) const MITSUBA: MitsubaPlugin = MitsubaPlugin { name: "directional", read: from_mitsuba, params: &[] };

fn from_mitsuba(p: &dyn MitsubaEmitter) -> Result<LightKind> {
    let irradiance = p.colour("irradiance")?.unwrap_or(Vec3::ONE);
    let direction = given_or_to_world(p, "direction", |m| m.transform_vector3(Vec3::Z))?;
    let direction = direction.try_normalize().ok_or_else(|| p.error("direction", "the light's direction is zero".into()))?;
    Ok(LightKind::Directional { direction, irradiance })
}

pub(super) fn check(direction: Vec3, irradiance: Vec3) -> std::result::Result<(), Invalid> {
    param::direction("direction", direction)?;
    param::rgb("irradiance", irradiance, Bound::NonNegative)?;
    Ok(())
}

pub(super) fn toml_keys(t: &mut toml::Table, direction: Vec3, irradiance: Vec3) {
    put_str(t, "type", "directional");
    put_vec3(t, "direction", direction);
    put_vec3(t, "irradiance", irradiance);
}

/// On the GPU: the disk of radius `radius` about `center` that covers the scene, placed
/// outside it upstream; power average(E) pi R^2.
pub(super) fn pack(direction: Vec3, irradiance: Vec3, center: Vec3, radius: f32) -> (Emitter, f64) {
    let d = direction.normalize();
    let area = std::f32::consts::PI * radius * radius;
    let e = Emitter {
        kind: EMITTER_DIRECTIONAL,
        position: (center - 1.01 * radius * d).into(),
        area,
        radiance: irradiance.into(),
        radius,
        direction: d.into(),
        ..Emitter::default()
    };
    (e, average(irradiance) * area as f64)
}

/// `USES_DIRECTIONAL_LIGHTS`.
pub(super) fn turn_on(_e: &Emitter, f: &mut Features) {
    f.directional_lights = true;
}
