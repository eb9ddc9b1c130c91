//! Point lights (`point` in TOML and Mitsuba 3; pbrt-v4's PointLight): radiant intensity I
//! (W/sr) from a point, the same in every direction; power 4 pi I.
//!
//! Parameters: `position`; `intensity`, linear RGB >= 0 (Mitsuba's default 1). Mitsuba gives
//! the position as `position` or as `to_world`'s origin, not both.
//! Kernel: `shaders/shared/emitter/point.wgsl`.

use super::{average, given_or_to_world, LightKind, MitsubaEmitter, MitsubaPlugin, Result, TomlType};
use crate::layout::{Emitter, Features};
use crate::scene::param::{self, Bound, Invalid};
use crate::scene::toml_table::{put_str, put_vec3, Table, Value};
use glam::Vec3;

/// [`Emitter::kind`] of a point light.
pub const EMITTER_POINT: u32 = 1;

/// How its power comes about, for messages.
pub(super) const POWER: &str = "its intensity times 4 pi";

pub(super) const TOML: TomlType = TomlType { name: "point", keys: &["position", "intensity"], read: read_toml };

fn read_toml(t: &Table) -> Result<LightKind> {
    Ok(LightKind::Point { position: t.req("position", Value::vec3)?, intensity: t.req("intensity", |v| v.rgb(Bound::Any))? })
}

pub(super) const MITSUBA: MitsubaPlugin = MitsubaPlugin { name: "point", read: from_mitsuba, params: &[] };

fn from_mitsuba(p: &dyn MitsubaEmitter) -> Result<LightKind> {
    let intensity = p.colour("intensity")?.unwrap_or(Vec3::ONE);
    let position = given_or_to_world(p, "position", |m| m.transform_point3(Vec3::ZERO))?;
    Ok(LightKind::Point { position, intensity })
}

pub(super) fn check(position: Vec3, intensity: Vec3) -> std::result::Result<(), Invalid> {
    param::rgb("position", position, Bound::Any)?;
    param::rgb("intensity", intensity, Bound::NonNegative)?;
    Ok(())
}

pub(super) fn toml_keys(t: &mut toml::Table, position: Vec3, intensity: Vec3) {
    put_str(t, "type", "point");
    put_vec3(t, "position", position);
    put_vec3(t, "intensity", intensity);
}

/// On the GPU: its position and intensity; power 4 pi average(I).
pub(super) fn pack(position: Vec3, intensity: Vec3) -> (Emitter, f64) {
    let e = Emitter { kind: EMITTER_POINT, position: position.into(), radiance: intensity.into(), ..Emitter::default() };
    (e, average(intensity) * 4.0 * std::f64::consts::PI)
}

/// `USES_POINT_LIGHTS`.
pub(super) fn turn_on(_e: &Emitter, f: &mut Features) {
    f.point_lights = true;
}
