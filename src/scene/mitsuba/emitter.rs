//! Mitsuba 3's emitter plugins, as our lights: each plugin's parameters are read by its kind
//! in [`crate::scene::emitter`], whose file documents them and their defaults (Mitsuba 3's
//! plugin reference, "Emitters"); this file gives the kinds Mitsuba's types
//! ([`MitsubaEmitter`]): an emitter's colours (linear RGB >= 0, as Mitsuba 3's RGB variants read
//! an emitter's spectra; never textured), its `to_world`, and an `envmap`'s image. Every emitter
//! (and `area` inside a shape, shape.rs) takes `sampling_weight`, which changes only Mitsuba's
//! noise ([`Props::emitter_sampling_weight`]). At most one environment surrounds the scene, as
//! in Mitsuba 3.
//!
//! `envmap`: `filename` (required; an equirectangular EXR or HDR, linear, or an 8- or 16-bit
//! image, sRGB-decoded, as Mitsuba 3's `Bitmap` reads them), `scale` (1), `to_world` (a
//! rotation; its translation is ignored, as the map lies at infinity), and `mis_compensation`,
//! which changes Mitsuba's sampling only. In a 0.x scene also Mitsuba 0.6's `gamma`
//! ([`Props::legacy_gamma`]), `cache` (whether it kept its MIP map in a file: warned) and
//! `intensity_scale` (refused there too: renamed `scale`).

use super::props::{Props, Spectrum};
use super::xml::Node;
use super::{Result, SceneError};
use crate::scene::emitter::{self, MitsubaEmitter};
use crate::scene::envmap::Envmap;
use crate::scene::Light;
use glam::{Mat4, Vec3};
use std::path::PathBuf;

/// An emitter plugin's parameters, as its kind reads them.
struct EmitterProps<'r, 'a> {
    p: &'r Props<'a>,
    to_world: Option<Mat4>,
    /// The directories a file name is looked for in, after the file's own ([`super::xml::resolve`]).
    root: &'r [PathBuf],
}

impl MitsubaEmitter for EmitterProps<'_, '_> {
    fn colour(&self, name: &str) -> Result<Option<Vec3>> {
        match self.p.emitter_spectrum(name)? {
            None => Ok(None),
            Some(Spectrum::Rgb(v)) if v.min_element() >= 0.0 => Ok(Some(v)),
            Some(Spectrum::Rgb(_)) => Err(self.error_at(name, format!("{name} is negative"))),
            Some(Spectrum::Texture(_)) => {
                Err(self.error_at(name, format!("textured emission is not modelled by sppm-gpu (a textured `{name}`)")))
            }
        }
    }

    fn float_or(&self, name: &str, default: f32) -> Result<f32> {
        self.p.float_or(name, default)
    }

    fn vec3(&self, name: &str) -> Result<Option<Vec3>> {
        self.p.vec3(name)
    }

    fn to_world(&self) -> Option<Mat4> {
        self.to_world
    }

    fn has(&self, name: &str) -> bool {
        self.p.has(name)
    }

    fn envmap(&self) -> Result<Envmap> {
        envmap(self.p, self.to_world, self.root)
    }

    fn error(&self, name: &str, message: String) -> SceneError {
        self.p.node.error(Some(name), message)
    }

    fn error_at(&self, name: &str, message: String) -> SceneError {
        self.p.get(name).unwrap_or(self.p.node).error(Some(name), message)
    }
}

/// A top-level `<emitter>`, read by its kind into `lights` (an envmap's `filename` resolved
/// against the file's directory, then `root`).
pub(super) fn light(node: &Node, lights: &mut Vec<Light>, root: &[PathBuf]) -> Result<()> {
    node.allow_attrs(&["type", "id", "name"])?;
    let kind = node.req_attr("type")?;
    let p = Props::new(node)?;
    let props = EmitterProps { p: &p, to_world: p.transform("to_world")?, root };
    let light = match emitter::from_mitsuba(kind, &props) {
        Some(light) => light?,
        None => {
            let why = match kind {
                "area" => "an area emitter belongs inside the <shape> that emits".to_owned(),
                "sunsky" | "skysun" | "sky" | "sun" => {
                    format!("the `{kind}` environment emitter is not modelled by sppm-gpu yet")
                }
                "projector" => format!("the `{kind}` emitter is not modelled by sppm-gpu yet"),
                other => format!("`{other}` is not a Mitsuba 3 emitter plugin"),
            };
            return Err(node.error(Some("type"), why));
        }
    };
    if let Some(why) = emitter::second_environment(lights, &light) {
        return Err(node.error(Some("type"), why));
    }
    p.emitter_sampling_weight()?;
    p.finish()?;
    lights.push(Light { kind: light, line: node.line });
    Ok(())
}

/// An `<emitter type="area">` inside a shape: its `radiance`.
pub(super) fn area(node: &Node) -> Result<Vec3> {
    node.allow_attrs(&["type", "id", "name"])?;
    let kind = node.req_attr("type")?;
    if kind != "area" {
        return Err(node.error(Some("type"), format!("a `{kind}` emitter inside a shape: only `area` emitters belong there")));
    }
    let p = Props::new(node)?;
    let radiance = emitter::area_from_mitsuba(&EmitterProps { p: &p, to_world: None, root: &[] })?;
    p.emitter_sampling_weight()?;
    p.finish()?;
    Ok(radiance)
}

/// An `envmap` emitter's map (see the module's notes). Errors name the parameter.
fn envmap(p: &Props, to_world: Option<Mat4>, root: &[PathBuf]) -> Result<Envmap> {
    let name = p.string("filename")?.ok_or_else(|| p.node.error(Some("filename"), "an envmap needs a `filename`"))?;
    let at = p.get("filename").unwrap();
    let path = super::xml::resolve(name, &p.node.file, root);
    let scale = p.float_or("scale", 1.0)?;
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(p.get("scale").unwrap().error(Some("scale"), format!("scale {scale}: an envmap's scale is at least 0")));
    }
    p.boolean_or("mis_compensation", false)?;
    if p.node.legacy() && p.has("intensity_scale") {
        let at = p.get("intensity_scale").unwrap();
        return Err(at.error(Some("intensity_scale"), "intensity_scale is now `scale` (Mitsuba 0.6 refuses it too)"));
    }
    p.legacy_ignored(&["cache"], "it says whether Mitsuba 0.6 keeps the map's MIP map in a file, which changes the speed");
    let raw = p.legacy_gamma(&path)?.unwrap_or(false);
    let linear = glam::Mat3::from_mat4(to_world.unwrap_or(Mat4::IDENTITY));
    let image =
        crate::scene::mesh::read_image(&path, raw).map_err(|e| at.error(Some("filename"), format!("{}: {e}", path.display())))?;
    Envmap::new(path, image.width, image.height, std::sync::Arc::unwrap_or_clone(image.texels), scale, linear).map_err(|e| {
        let (node, key) = if e.contains("to_world") {
            (p.get("to_world").unwrap_or(p.node), "to_world")
        } else if e.starts_with("scale") {
            (p.get("scale").unwrap_or(p.node), "scale")
        } else {
            (at, "filename")
        };
        node.error(Some(key), e)
    })
}
