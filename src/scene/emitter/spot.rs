//! Spot lights (`spot` in TOML and Mitsuba 3, whose model this is; pbrt-v4's SpotLight, with
//! its smoothstep falloff instead): a point that emits intensity I (W/sr) within the beam width
//! b of its axis, falls off linearly in the angle from there to zero at the cutoff angle c
//! ([`spot_falloff`]), and is dark beyond; power I times [`spot_solid_angle`].
//!
//! Parameters: `position`; `direction` of the axis (nonzero; made unit length); `intensity` on
//! the axis, linear RGB >= 0 (Mitsuba's default 1); `cutoff_angle` c in (0, 180] degrees
//! (default 20); `beam_width` b >= 0 degrees (default 3/4 of the cutoff; at or past it the edge
//! is hard). Mitsuba places it at `to_world`'s origin looking along its +z; a `to_world` that
//! scales unevenly or shears (an elliptical cone) and a projected `texture` are refused.
//! Kernel: `shaders/shared/emitter/spot.wgsl`.

use super::{average, LightKind, MitsubaEmitter, MitsubaPlugin, Result, TomlType};
use crate::layout::{Emitter, Features};
use crate::scene::param::{self, Bound, Invalid};
use crate::scene::toml_table::{put_float, put_str, put_vec3, Table, Value};
use glam::{Mat4, Vec3};

/// [`Emitter::kind`] of a spot light.
pub const EMITTER_SPOT: u32 = 3;

/// How its power comes about, for messages.
pub(super) const POWER: &str = "its intensity times its cone's solid angle";

pub(super) const TOML: TomlType =
    TomlType { name: "spot", keys: &["position", "direction", "intensity", "cutoff_angle", "beam_width"], read: read_toml };

fn read_toml(t: &Table) -> Result<LightKind> {
    let direction = t.req("direction", Value::vec3)?;
    let cutoff_angle = t.or("cutoff_angle", 20.0, |v| v.f32_in(Bound::Any))?;
    Ok(LightKind::Spot {
        position: t.req("position", Value::vec3)?,
        direction,
        intensity: t.req("intensity", |v| v.rgb(Bound::Any))?,
        cutoff_angle,
        beam_width: t.or("beam_width", 0.75 * cutoff_angle, |v| v.f32_in(Bound::Any))?,
    })
}

pub(super) const MITSUBA: MitsubaPlugin = MitsubaPlugin { name: "spot", read: from_mitsuba, params: &[] };

fn from_mitsuba(p: &dyn MitsubaEmitter) -> Result<LightKind> {
    if p.has("texture") {
        return Err(p.error_at("texture", "a spot light's `texture` (a projected image) is not modelled by sppm-gpu".into()));
    }
    let intensity = p.colour("intensity")?.unwrap_or(Vec3::ONE);
    let cutoff_angle = p.float_or("cutoff_angle", 20.0)?;
    // Mitsuba 3's default beam width.
    let beam_width = p.float_or("beam_width", cutoff_angle * 3.0 / 4.0)?;
    // Mitsuba 3 takes the falloff of the direction carried back into the light's frame,
    // normalized: the same cone under a rotation and a uniform scale, an elliptical one under
    // any other linear map, which is not modelled.
    let m = p.to_world().unwrap_or(Mat4::IDENTITY);
    let linear = glam::Mat3::from_mat4(m);
    let gram = linear.transpose() * linear;
    let scale2 = (gram.x_axis.x + gram.y_axis.y + gram.z_axis.z) / 3.0;
    let conformal = (0..3).all(|i| (0..3).all(|j| (gram.col(i)[j] - if i == j { scale2 } else { 0.0 }).abs() <= 1e-4 * scale2));
    if !(scale2 > 0.0 && conformal) {
        return Err(p.error_at(
            "to_world",
            "a spot light's to_world that scales unevenly or shears (an elliptical cone) is not modelled by sppm-gpu".into(),
        ));
    }
    let position = m.transform_point3(Vec3::ZERO);
    let direction = linear.mul_vec3(Vec3::Z).normalize();
    Ok(LightKind::Spot { position, direction, intensity, cutoff_angle, beam_width })
}

pub(super) fn check(
    position: Vec3,
    direction: Vec3,
    intensity: Vec3,
    cutoff_angle: f32,
    beam_width: f32,
) -> std::result::Result<(), Invalid> {
    param::rgb("position", position, Bound::Any)?;
    param::direction("direction", direction)?;
    param::rgb("intensity", intensity, Bound::NonNegative)?;
    if !(cutoff_angle > 0.0 && cutoff_angle <= 180.0) {
        return Err(Invalid::new("cutoff_angle", format!("must be more than 0 and at most 180 degrees, found {cutoff_angle}")));
    }
    if param::float("beam_width", beam_width, Bound::Any)? < 0.0 {
        return Err(Invalid::new("beam_width", format!("must be at least 0 degrees, found {beam_width}")));
    }
    Ok(())
}

pub(super) fn toml_keys(t: &mut toml::Table, position: Vec3, direction: Vec3, intensity: Vec3, cutoff: f32, beam: f32) {
    put_str(t, "type", "spot");
    put_vec3(t, "position", position);
    put_vec3(t, "direction", direction);
    put_vec3(t, "intensity", intensity);
    put_float(t, "cutoff_angle", cutoff);
    put_float(t, "beam_width", beam);
}

/// On the GPU: the angles in radians, the beam clamped to the cutoff, their difference the
/// falloff's width; power average(I) Omega.
pub(super) fn pack(position: Vec3, direction: Vec3, intensity: Vec3, cutoff_angle: f32, beam_width: f32) -> (Emitter, f64) {
    let cutoff = (cutoff_angle as f64).to_radians();
    let beam = (beam_width as f64).to_radians().min(cutoff);
    let omega = spot_solid_angle(cutoff, beam);
    let e = Emitter {
        kind: EMITTER_SPOT,
        position: position.into(),
        area: omega as f32,
        radiance: intensity.into(),
        radius: cutoff as f32,
        direction: direction.normalize().into(),
        width: (cutoff - beam) as f32,
        ..Emitter::default()
    };
    (e, average(intensity) * omega)
}

/// `USES_SPOT_LIGHTS`.
pub(super) fn turn_on(_e: &Emitter, f: &mut Features) {
    f.spot_lights = true;
}

/// Mitsuba 3's spot falloff (its `spot` plugin's `falloff_curve`, checked against Mitsuba
/// 3.9.1): 1 for `theta` <= `beam`, (`cutoff` - `theta`) / (`cutoff` - `beam`) between,
/// 0 from `cutoff` on. Angles in radians; `theta` from the axis.
pub fn spot_falloff(theta: f64, cutoff: f64, beam: f64) -> f64 {
    if theta >= cutoff {
        0.0
    } else if theta <= beam {
        1.0
    } else {
        (cutoff - theta) / (cutoff - beam)
    }
}

/// The integral of [`spot_falloff`] over the sphere of directions (steradians): a spot
/// light's power is its intensity times this. With c the cutoff, b the beam width (at most
/// c) and w = c - b, the cone of full intensity gives 2 pi (1 - cos b) and the ring of
/// falloff 2 pi / w integral_b^c (c - theta) sin(theta) d theta = 2 pi (cos b - (sin c -
/// sin b) / w), since (c - theta) sin(theta) has the antiderivative -(c - theta) cos(theta) -
/// sin(theta). Angles in radians; the ring's term is summed by its series where w is small,
/// where the closed form cancels.
pub fn spot_solid_angle(cutoff: f64, beam: f64) -> f64 {
    let b = beam.clamp(0.0, cutoff);
    let w = cutoff - b;
    let inner = 4.0 * std::f64::consts::PI * (0.5 * b).sin().powi(2);
    // cos b - (sin c - sin b) / w = cos b - (sin(b + w) - sin b) / w
    //   = cos b (1 - sin(w) / w) + sin b (1 - cos w) / w.
    let (s, t) = if w < 1e-3 {
        // 1 - sin(w) / w and (1 - cos w) / w by their Taylor series.
        (w * w / 6.0 - w.powi(4) / 120.0, w / 2.0 - w.powi(3) / 24.0)
    } else {
        (1.0 - w.sin() / w, (1.0 - w.cos()) / w)
    };
    inner + 2.0 * std::f64::consts::PI * (b.cos() * s + b.sin() * t)
}
