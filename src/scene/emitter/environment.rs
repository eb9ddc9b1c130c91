//! The environment (`constant` and `envmap` in TOML and Mitsuba 3; pbrt-v4's
//! UniformInfiniteLight and ImageInfiniteLight): radiance L(w) from every direction at
//! infinity, the same everywhere or from an equirectangular image ([`Envmap`]). A scene has at
//! most one. Its photons cross the disk of radius R that covers the scene's bounding sphere,
//! from every direction; power pi R^2 times the integral of average(L) over the sphere of
//! directions (average(L) 4 pi pi R^2 for a constant one).
//!
//! Parameters: `constant`: `radiance`, linear RGB >= 0 (Mitsuba's default 1). `envmap`: `file`
//! (Mitsuba's `filename`: EXR or HDR linear, PNG sRGB), `scale` >= 0 (1) and `rotate` (degrees
//! about x, y and z, as a shape's; Mitsuba's `to_world`, a rotation), which turns the map's
//! frame (+y up) into the world.
//! Kernel: `shaders/shared/emitter/environment.wgsl` (and `shaders/shared/envmap.wgsl`).

use super::{average, beyond, rounded, Light, LightKind, MitsubaEmitter, MitsubaPlugin, Result, TomlType, MAX_EMISSION};
use crate::layout::{Emitter, Features, NO_TEXTURE};
use crate::scene::envmap::{rotation_degrees, Envmap, EnvmapDistribution};
use crate::scene::param::{self, number, Bound, Invalid};
use crate::scene::toml_table::{put_float, put_str, put_vec3, Table, Value};
use crate::scene::SceneError;
use glam::Vec3;
use std::sync::Arc;

/// [`Emitter::kind`] of the environment, constant or an image, always the last emitter.
pub const EMITTER_ENVIRONMENT: u32 = 4;

/// Most `texels` entries with an environment map: 128 MiB, lavapipe's (and WebGPU's
/// default) largest storage buffer binding.
const ENVMAP_MAX_ENTRIES: usize = (128 << 20) / 16;

pub(super) const CONSTANT: TomlType = TomlType { name: "constant", keys: &["radiance"], read: read_constant };

pub(super) const ENVMAP: TomlType = TomlType { name: "envmap", keys: &["file", "scale", "rotate"], read: read_envmap };

fn read_constant(t: &Table) -> Result<LightKind> {
    Ok(LightKind::Constant { radiance: t.req("radiance", |v| v.rgb(Bound::Any))? })
}

/// The image is read here and checked by [`Envmap::new`], at `file`.
fn read_envmap(t: &Table) -> Result<LightKind> {
    let scale = t.or("scale", 1.0, |v| v.f32_in(Bound::NonNegative))?;
    let to_world = rotation_degrees(t.or("rotate", Vec3::ZERO, Value::vec3)?);
    let file = t.require("file")?;
    let path = file.path()?;
    let image = file.read_file("environment map", &path, |p| crate::scene::mesh::read_image(p, false))?;
    let map = Envmap::new(path, image.width, image.height, std::sync::Arc::unwrap_or_clone(image.texels), scale, to_world)
        .map_err(|e| file.error(e))?;
    Ok(LightKind::Envmap(Arc::new(map)))
}

pub(super) const MITSUBA_CONSTANT: MitsubaPlugin = MitsubaPlugin { name: "constant", read: constant_from_mitsuba, params: &[] };

pub(super) const MITSUBA_ENVMAP: MitsubaPlugin = MitsubaPlugin { name: "envmap", read: envmap_from_mitsuba, params: &[] };

fn constant_from_mitsuba(p: &dyn MitsubaEmitter) -> Result<LightKind> {
    Ok(LightKind::Constant { radiance: p.colour("radiance")?.unwrap_or(Vec3::ONE) })
}

fn envmap_from_mitsuba(p: &dyn MitsubaEmitter) -> Result<LightKind> {
    Ok(LightKind::Envmap(Arc::new(p.envmap()?)))
}

pub(super) fn check_constant(radiance: Vec3) -> std::result::Result<(), Invalid> {
    param::rgb("radiance", radiance, Bound::NonNegative).map(drop)
}

pub(super) fn envmap_gives_light(m: &Envmap) -> bool {
    m.scale > 0.0 && m.texels.iter().any(|t| t.max_element() > 0.0)
}

pub(super) fn constant_toml_keys(t: &mut toml::Table, radiance: Vec3) {
    put_str(t, "type", "constant");
    put_vec3(t, "radiance", radiance);
}

/// The image stays where it is, named by its absolute path; `to_world` as the angles of
/// `rotate` (R = Rz Ry Rx, degrees). A mirroring `to_world` has none.
pub(super) fn envmap_toml_keys(t: &mut toml::Table, m: &Envmap) -> std::result::Result<(), String> {
    let r = m.to_world;
    if r.determinant() < 0.0 {
        return Err("an environment map mirrored by its to_world cannot be written in TOML".into());
    }
    let b = (-r.x_axis.z).clamp(-1.0, 1.0).asin();
    let (a, c) = if r.x_axis.z.abs() < 0.9999 {
        (r.y_axis.z.atan2(r.z_axis.z), r.x_axis.y.atan2(r.x_axis.x))
    } else {
        (0.0, (-r.y_axis.x).atan2(r.y_axis.y))
    };
    let file = std::path::absolute(&m.path).unwrap_or_else(|_| m.path.clone());
    put_str(t, "type", "envmap");
    put_str(t, "file", &file.to_string_lossy());
    put_float(t, "scale", m.scale);
    put_vec3(t, "rotate", Vec3::new(a, b, c) * (180.0 / std::f32::consts::PI));
    Ok(())
}

/// Why an environment map is too bright, and the key to blame (the image alone, or the scale
/// that brightens it), if it is.
pub(super) fn too_bright(map: &Envmap) -> Option<(&'static str, String)> {
    let (texel, radiance) = (map.brightest_texel(), map.max_radiance());
    if !(radiance.is_nan() || radiance > MAX_EMISSION) {
        return None;
    }
    let key = if texel as f64 > MAX_EMISSION { "file" } else { "scale" };
    let message = format!(
        "the environment's radiance reaches {} (its brightest texel {} times scale {}), {} in each channel",
        rounded(radiance, MAX_EMISSION),
        number(texel),
        number(map.scale),
        beyond(MAX_EMISSION)
    );
    Some((key, message))
}

/// How its power comes about, for messages, with `disk` the disk that covers the scene.
pub(super) fn power(kind: &LightKind, disk: &str) -> String {
    match kind {
        LightKind::Envmap(_) => format!("its radiance over the sphere of directions times {disk}"),
        _ => format!("its radiance times 4 pi times {disk}"),
    }
}

/// On the GPU: the centre and radius R of the sphere its photons' disk covers, pi R^2; an
/// envmap's image and distribution at the end of `texels`, its `prim_ref` their header and its
/// `radiance` the scale (a constant one's [`NO_TEXTURE`] and its radiance).
pub(super) fn pack(light: &Light, center: Vec3, radius: f32, texels: &mut Vec<[f32; 4]>) -> Result<(Emitter, f64)> {
    let area = std::f32::consts::PI * radius * radius;
    let mut e =
        Emitter { kind: EMITTER_ENVIRONMENT, prim_ref: NO_TEXTURE, position: center.into(), area, radius, ..Emitter::default() };
    let integral = match &light.kind {
        LightKind::Envmap(map) => {
            let needed = texels.len() + EnvmapDistribution::packed_len(map);
            if needed > ENVMAP_MAX_ENTRIES {
                return Err(SceneError {
                    file: map.path.clone(),
                    line: Some(light.line),
                    key: None,
                    message: format!(
                        "the environment map of {}x{} texels, with the textures, needs {} MiB, over the {} MiB of a storage buffer",
                        map.width,
                        map.height,
                        (needed * 16) >> 20,
                        (ENVMAP_MAX_ENTRIES * 16) >> 20
                    ),
                });
            }
            let distribution = EnvmapDistribution::new(map);
            e.prim_ref = distribution.pack(map, texels);
            e.radiance = [map.scale; 3];
            map.integral().iter().sum::<f64>() / 3.0
        }
        LightKind::Constant { radiance } => {
            e.radiance = (*radiance).into();
            average(*radiance) * 4.0 * std::f64::consts::PI
        }
        _ => unreachable!("an environment"),
    };
    Ok((e, integral * area as f64))
}

/// `USES_ENVIRONMENT`, and `USES_ENVMAP` for an image.
pub(super) fn turn_on(e: &Emitter, f: &mut Features) {
    f.environment = true;
    f.envmap |= e.prim_ref != NO_TEXTURE;
}
