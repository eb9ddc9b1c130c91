//! pbrt-v4's lights, as our emitters ([`crate::scene::emitter`]). Every light's spectrum is
//! read as pbrt-v4 scales it (spectra.rs: an `rgb` as given, others to luminance 1), times
//! `scale` (1); its position and direction go through the CTM.
//!
//! - `AreaLightSource "diffuse"`: `L` (white), `scale`, for the shapes that follow, on the
//!   side their normals face; `power` as pbrt-v4 reads it, per pbrt shape (shape.rs):
//!   L scale power / (pi area), each triangle of a mesh a shape of its own; `twosided` (false:
//!   the radiance leaves both sides, and `power` is shared between them as pbrt-v4 shares it).
//!   `filename` (an image on the surface) is refused.
//! - `point`: `I`, `from` (0 0 0), `power` (when given, `scale` times power / 4 pi).
//! - `spot`: `I`, `from` (0 0 0), `to` (0 0 1), `coneangle` (30), `conedelta` (5), `power`
//!   (over the cone's solid angle as pbrt-v4 counts it). pbrt's falloff is a smoothstep in
//!   the cosine between the two cones, ours linear in the angle: the same cones, a slightly
//!   different penumbra (warned where conedelta > 0).
//! - `distant`: `L`, `from` (0 0 0), `to` (0 0 1): light travels from `from` to `to`;
//!   `illuminance` (when given, scale times it).
//! - `infinite`: `L` (a constant environment) or `filename` (pbrt-v4's equal-area octahedral
//!   map, square, resampled into our equirectangular one through the light's transform);
//!   `illuminance` and `portal` are refused.
//! - `goniometric` and `projection` are refused.

use super::params::{Params, Spectrum};
use super::spectra::SpectrumUse;
use super::{AreaLight, Reader, Result};
use crate::scene::envmap::Envmap;
use crate::scene::{Light, LightKind};
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::Arc;

impl Reader {
    /// An emitted spectrum (`L`, `I`) as RGB, white when not given; never a texture.
    fn emission(&self, p: &Params, name: &str) -> Result<Vec3> {
        match p.spectrum(name, SpectrumUse::Illuminant)? {
            None => Ok(Vec3::ONE),
            Some(Spectrum::Rgb(c)) => Ok(c),
            Some(Spectrum::Texture(_)) => Err(p.error(name, format!("a texture as {name} is not modelled by sppm-gpu"))),
        }
    }

    /// `scale` (1), finite and >= 0.
    fn light_scale(&self, p: &Params) -> Result<f32> {
        let s = p.float_or("scale", 1.0)?;
        if !(s.is_finite() && s >= 0.0) {
            return Err(p.error("scale", format!("scale {s} is negative")));
        }
        Ok(s)
    }

    /// `AreaLightSource "kind"`.
    pub(super) fn area_light(&mut self, kind: &str, p: &Params) -> Result<()> {
        if kind != "diffuse" {
            return Err(p.directive_error(format!("\"{kind}\": unknown area light (pbrt-v4 has \"diffuse\")")));
        }
        let radiance = self.emission(p, "L")? * self.light_scale(p)?;
        let two_sided = p.bool_or("twosided", false)?;
        if p.has("filename") {
            return Err(p.error("filename", "an area light's image (filename) is not modelled by sppm-gpu"));
        }
        // pbrt-v4 applies power only where it is positive.
        let power = p.float("power")?.filter(|&w| w > 0.0);
        if power.is_some_and(|w| !w.is_finite()) {
            return Err(p.error("power", "power is not a finite number"));
        }
        p.finish()?;
        self.state.area = Some(AreaLight { radiance, power, two_sided });
        Ok(())
    }

    /// `LightSource "kind"`.
    pub(super) fn light(&mut self, kind: &str, p: &Params) -> Result<()> {
        if self.moving() {
            return Err(p.directive_error("a light that moves (ActiveTransform) is not modelled by sppm-gpu"));
        }
        let m = self.mirror * self.state.ctm;
        let scale = self.light_scale(p)?;
        let power = p.float("power")?;
        if power.is_some_and(|w| !(w.is_finite() && w >= 0.0)) {
            return Err(p.error("power", "power is negative"));
        }
        let light = match kind {
            "point" => {
                let i = self.emission(p, "I")?;
                let from = p.point3("from", "point3")?.unwrap_or(Vec3::ZERO);
                let k = power.map_or(1.0, |w| w / (4.0 * PI));
                LightKind::Point { position: m.transform_point3(from), intensity: i * scale * k }
            }
            "spot" => {
                let i = self.emission(p, "I")?;
                let from = p.point3("from", "point3")?.unwrap_or(Vec3::ZERO);
                let to = p.point3("to", "point3")?.unwrap_or(Vec3::Z);
                let cone = p.float_or("coneangle", 30.0)?;
                let delta = p.float_or("conedelta", 5.0)?;
                if !(cone > 0.0 && cone <= 180.0 && delta >= 0.0) {
                    return Err(p.error("coneangle", "coneangle is in (0, 180] and conedelta >= 0"));
                }
                let start = (cone - delta).max(0.0);
                let k = power.map_or(1.0, |w| {
                    let (cos_end, cos_start) = (cone.to_radians().cos(), start.to_radians().cos());
                    w / (2.0 * PI * ((1.0 - cos_start) + (cos_start - cos_end) / 2.0))
                });
                let direction = m.transform_vector3(to - from).normalize_or_zero();
                if direction == Vec3::ZERO {
                    return Err(p.error("to", "a spot light's from and to are the same point"));
                }
                if delta > 0.0 {
                    self.warnings.push(p.error(
                        "conedelta",
                        "pbrt's spot light falls off smoothly in the cosine within conedelta, sppm-gpu's linearly in the \
                         angle: the same cones, a slightly different penumbra",
                    ));
                }
                LightKind::Spot {
                    position: m.transform_point3(from),
                    direction,
                    intensity: i * scale * k,
                    cutoff_angle: cone,
                    beam_width: start,
                }
            }
            "distant" => {
                let l = self.emission(p, "L")?;
                let from = p.point3("from", "point3")?.unwrap_or(Vec3::ZERO);
                let to = p.point3("to", "point3")?.unwrap_or(Vec3::Z);
                let e = p.float("illuminance")?.unwrap_or(1.0);
                let direction = m.transform_vector3(to - from).normalize_or_zero();
                if direction == Vec3::ZERO {
                    return Err(p.error("to", "a distant light's from and to are the same point"));
                }
                LightKind::Directional { direction, irradiance: l * scale * e }
            }
            "infinite" => {
                for key in ["illuminance", "portal"] {
                    if p.has(key) {
                        return Err(p.error(key, format!("an infinite light's {key} is not modelled by sppm-gpu")));
                    }
                }
                match p.string("filename")? {
                    Some(name) => {
                        if p.has("L") {
                            return Err(p.error("L", "an infinite light takes L or a filename, not both"));
                        }
                        let map = octahedral_envmap(p, name, Mat3::from_mat4(m), scale)?;
                        LightKind::Envmap(Arc::new(map))
                    }
                    None => LightKind::Constant { radiance: self.emission(p, "L")? * scale },
                }
            }
            "goniometric" | "projection" => {
                return Err(p.directive_error(format!("the \"{kind}\" light is not modelled by sppm-gpu")))
            }
            other => return Err(p.directive_error(format!("\"{other}\": unknown light"))),
        };
        if power.is_some() && !matches!(kind, "point" | "spot") {
            return Err(p.error("power", format!("a {kind} light's power is not modelled by sppm-gpu")));
        }
        p.finish()?;
        light.check().map_err(|e| p.error(e.key, e.message))?;
        if let Some(why) = crate::scene::emitter::second_environment(&self.lights, &light) {
            return Err(p.directive_error(why));
        }
        self.lights.push(Light { kind: light.with_unit_direction(), line: p.line });
        Ok(())
    }
}

/// pbrt-v4's equal-area octahedral environment map `name`, resampled into an equirectangular
/// map of twice its width by its width, through `to_world` (the light's transform, with the
/// world's mirror), times `scale`.
fn octahedral_envmap(p: &Params, name: &str, to_world: Mat3, scale: f32) -> Result<Envmap> {
    let path = p.resolve(name);
    let image =
        crate::scene::mesh::read_image(&path, true).map_err(|e| p.error("filename", format!("{}: {e}", path.display())))?;
    let n = image.width;
    if n == 0 || image.height != n {
        return Err(p.error(
            "filename",
            format!("{}: {}x{}: an infinite light's image is square (equal-area octahedral)", path.display(), n, image.height),
        ));
    }
    let light_from_world = to_world.inverse();
    if !light_from_world.is_finite() {
        return Err(p.error("filename", "the light's transform cannot be inverted"));
    }
    let n = n.min(2048);
    let (w, h) = (2 * n, n);
    let lookup = |uv: Vec2| {
        // Bilinear, texel centres at half-integers, clamped at the edges.
        let s = image.width as f32;
        let x = (uv.x * s - 0.5).clamp(0.0, s - 1.0);
        let y = (uv.y * s - 0.5).clamp(0.0, s - 1.0);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(image.width as usize - 1), (y0 + 1).min(image.width as usize - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let t = |x: usize, y: usize| image.texels[y * image.width as usize + x];
        (t(x0, y0) * (1.0 - fx) + t(x1, y0) * fx) * (1.0 - fy) + (t(x0, y1) * (1.0 - fx) + t(x1, y1) * fx) * fy
    };
    let mut texels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let (theta, phi) = ((y as f32 + 0.5) / h as f32 * PI, (x as f32 + 0.5) / w as f32 * 2.0 * PI);
            // Our envmap's direction at (u, v), to_world identity.
            let d = Vec3::new(phi.sin() * theta.sin(), theta.cos(), -phi.cos() * theta.sin());
            let l = (light_from_world * d).normalize_or_zero();
            texels.push(lookup(equal_area_sphere_to_square(l)).max(Vec3::ZERO));
        }
    }
    Envmap::new(path, w, h, texels, scale, Mat3::IDENTITY).map_err(|e| p.error("filename", e))
}

/// The equal-area octahedral map of the sphere onto the unit square (Clarberg, "Fast
/// equal-area mapping of the (hemi)sphere using SIMD", 2008), as pbrt-v4 lays out its maps.
fn equal_area_sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let (a, b) = (x.max(y), x.min(y));
    let b = if a == 0.0 { 0.0 } else { b / a };
    let mut phi = b.atan() * 2.0 / PI;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    let (u, v) = (u.copysign(d.x), v.copysign(d.y));
    Vec2::new((u + 1.0) * 0.5, (v + 1.0) * 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octahedral_corners_and_centre() {
        assert!((equal_area_sphere_to_square(Vec3::Z) - Vec2::splat(0.5)).length() < 1e-6);
        let down = equal_area_sphere_to_square(Vec3::NEG_Z);
        assert!(down.x.min(1.0 - down.x) < 1e-6 && down.y.min(1.0 - down.y) < 1e-6);
        assert!((equal_area_sphere_to_square(Vec3::X) - Vec2::new(1.0, 0.5)).length() < 1e-6);
    }
}
