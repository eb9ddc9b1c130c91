//! Emitters: the lights a scene can have, one file a kind, as Mitsuba 3 keeps one plugin a
//! file and pbrt-v4 keeps a light's `Create` beside its sampling. A kind's file documents its
//! model and parameters at the top and owns what the host does with it: its TOML type and
//! keys, its Mitsuba plugin (through `MitsubaEmitter`), the checks of its parameters
//! (written once, for every reader and [`super::SceneBuilder`]), its name in `info`, its keys
//! in a converted TOML scene, its `EMITTER_*` kind, its GPU packing ([`Emitter`]) and power,
//! and the kernel features it turns on ([`Features`]). Its kernel is
//! `shaders/shared/emitter/<kind>.wgsl`, called through the dispatcher
//! `shaders/shared/lights.wgsl`.
//!
//! The kinds: `area` (the shapes with an `emission`), `point`, `spot`, `directional` and
//! `environment` (`constant` and `envmap`); every kind but the area lights is a [`Light`], a
//! `[[lights]]` entry. This file dispatches to them: a new kind is its variant, an arm in each
//! `match` (the compiler lists those that lack it) and its entries in `TOML_TYPES` and
//! `MITSUBA_PLUGINS` (`tests/suite/dispatch.rs` checks that every kind is in each
//! dispatcher).

mod area;
mod directional;
mod environment;
mod point;
mod spot;

pub use area::EMITTER_AREA;
pub use directional::EMITTER_DIRECTIONAL;
pub use environment::EMITTER_ENVIRONMENT;
pub use point::EMITTER_POINT;
pub use spot::{spot_falloff, spot_solid_angle, EMITTER_SPOT};

use super::envmap::Envmap;
use super::param::{number, Invalid};
use super::toml_table::{Table, Value};
use super::{Scene, SceneError};
use crate::layout::{Emitter, Features};
use glam::{Mat4, Vec3};
use std::sync::Arc;

type Result<T> = std::result::Result<T, SceneError>;

/// `[[lights]]` entries: the emitters that are not surfaces.
#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    /// Radiant intensity (W/sr) from a point.
    Point {
        /// World-space position.
        position: Vec3,
        /// Radiant intensity I, linear RGB (W/sr); power 4 pi I.
        intensity: Vec3,
    },
    /// Parallel light travelling along `direction` (unit), `irradiance` on a facing surface.
    Directional {
        /// Unit direction the light travels in.
        direction: Vec3,
        /// Irradiance E on a surface facing the light, linear RGB.
        irradiance: Vec3,
    },
    /// A spot light as Mitsuba 3's `spot`: a point that emits `intensity` (W/sr) within
    /// `beam_width` of its axis, falls off linearly in the angle from there to zero at
    /// `cutoff_angle`, and is dark beyond ([`spot_falloff`]). Angles in degrees, as Mitsuba's
    /// and pbrt's scene files give them.
    Spot {
        /// World-space position.
        position: Vec3,
        /// Unit direction of the cone's axis.
        direction: Vec3,
        /// Radiant intensity I on the axis, linear RGB (W/sr); power I [`spot_solid_angle`].
        intensity: Vec3,
        /// Half-angle of the lit cone, degrees, in (0, 180].
        cutoff_angle: f32,
        /// Half-angle of the cone of full intensity, degrees, >= 0; at or past
        /// `cutoff_angle` the cone's edge is hard.
        beam_width: f32,
    },
    /// Mitsuba 3's `constant` environment: the same radiance from every direction, at
    /// infinity. A scene has at most one environment.
    Constant {
        /// Radiance L, linear RGB; power average(L) pi R^2 4 pi through the disk of radius R
        /// that covers the scene's bounding sphere.
        radiance: Vec3,
    },
    /// Mitsuba 3's `envmap`: radiance from an equirectangular image ([`Envmap`]), at infinity;
    /// the scene's one environment.
    Envmap(Arc<Envmap>),
}

/// One `[[lights]]` entry (a point, directional, spot or environment light; area lights are
/// shapes with `emission`).
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// The light's type and parameters.
    pub kind: LightKind,
    /// Line of the `[[lights]]` header.
    pub line: usize,
}

impl LightKind {
    /// Whether the light is an environment (at infinity, around the whole scene).
    pub fn is_environment(&self) -> bool {
        matches!(self, LightKind::Constant { .. } | LightKind::Envmap(_))
    }

    /// Whether the light gives light: some channel of its brightness above zero.
    pub fn gives_light(&self) -> bool {
        match self {
            LightKind::Point { intensity: e, .. }
            | LightKind::Directional { irradiance: e, .. }
            | LightKind::Spot { intensity: e, .. }
            | LightKind::Constant { radiance: e } => e.max_element() > 0.0,
            LightKind::Envmap(m) => environment::envmap_gives_light(m),
        }
    }

    /// The kind as `info` names it.
    pub fn describe(&self) -> &'static str {
        match self {
            LightKind::Point { .. } => point::TOML.name,
            LightKind::Directional { .. } => directional::TOML.name,
            LightKind::Spot { .. } => spot::TOML.name,
            LightKind::Constant { .. } => environment::CONSTANT.name,
            LightKind::Envmap(_) => environment::ENVMAP.name,
        }
    }

    /// The light's keys in a TOML `[[lights]]` entry, or why TOML cannot say it.
    pub fn toml_keys(&self, t: &mut toml::Table) -> std::result::Result<(), String> {
        match self {
            &LightKind::Point { position, intensity } => point::toml_keys(t, position, intensity),
            &LightKind::Directional { direction, irradiance } => directional::toml_keys(t, direction, irradiance),
            &LightKind::Spot { position, direction, intensity, cutoff_angle, beam_width } => {
                spot::toml_keys(t, position, direction, intensity, cutoff_angle, beam_width)
            }
            &LightKind::Constant { radiance } => environment::constant_toml_keys(t, radiance),
            LightKind::Envmap(m) => return environment::envmap_toml_keys(t, m),
        }
        Ok(())
    }

    /// The light's parameters checked against their ranges, whichever reader gave them: the
    /// first that is out, named as a TOML scene names it.
    pub(crate) fn check(&self) -> std::result::Result<(), Invalid> {
        match *self {
            LightKind::Point { position, intensity } => point::check(position, intensity),
            LightKind::Directional { direction, irradiance } => directional::check(direction, irradiance),
            LightKind::Spot { position, direction, intensity, cutoff_angle, beam_width } => {
                spot::check(position, direction, intensity, cutoff_angle, beam_width)
            }
            LightKind::Constant { radiance } => environment::check_constant(radiance),
            LightKind::Envmap(_) => Ok(()),
        }
    }

    /// The light with its direction, if it has one, made unit length (in f64, so that no
    /// finite direction over- or underflows to zero): as the TOML reader and the builder give
    /// it, after [`LightKind::check`].
    pub(crate) fn with_unit_direction(&self) -> LightKind {
        let unit = |d: Vec3| d.as_dvec3().normalize_or_zero().as_vec3();
        match self.clone() {
            LightKind::Directional { direction, irradiance } => LightKind::Directional { direction: unit(direction), irradiance },
            LightKind::Spot { position, direction, intensity, cutoff_angle, beam_width } => {
                LightKind::Spot { position, direction: unit(direction), intensity, cutoff_angle, beam_width }
            }
            other => other,
        }
    }

    /// The parameter that sets the light's brightness, for messages and keys.
    pub(crate) fn brightness_key(&self) -> &'static str {
        match self {
            LightKind::Point { .. } | LightKind::Spot { .. } => "intensity",
            LightKind::Directional { .. } => "irradiance",
            LightKind::Constant { .. } => "radiance",
            LightKind::Envmap(_) => "scale",
        }
    }
}

/// Whether shape emission `emission` gives light (an area light).
pub(crate) fn emission_gives_light(emission: Option<Vec3>) -> bool {
    emission.is_some_and(|e| e.max_element() > 0.0)
}

/// The check of a shape's `emission`, radiance leaving its front (an area light).
pub(crate) fn check_emission(emission: Vec3) -> std::result::Result<Vec3, Invalid> {
    area::check(emission)
}

/// A shape's `emission` in a written TOML `[[shapes]]` entry (`convert`).
pub fn emission_toml_keys(t: &mut toml::Table, emission: Vec3) {
    area::toml_keys(t, emission);
}

/// A shape's `emission` in a TOML `[[shapes]]` entry, checked, if it has one.
pub(super) fn read_toml_emission(t: &Table) -> Result<Option<Vec3>> {
    area::read_toml(t)
}

/// Every emitter of `scene` as `info` names it: `area` for each shape that gives light, then
/// each light's kind.
pub fn names(scene: &Scene) -> Vec<&'static str> {
    let area = scene.shapes.iter().filter(|s| emission_gives_light(s.emission)).map(|_| area::NAME);
    area.chain(scene.lights.iter().map(|l| l.kind.describe())).collect()
}

/// A `type` of a TOML `[[lights]]` entry: its name, its keys besides `type`, and its kind's
/// reader of them.
pub(super) struct TomlType {
    name: &'static str,
    keys: &'static [&'static str],
    read: fn(&Table) -> Result<LightKind>,
}

/// Every TOML light type, in the order messages list them.
const TOML_TYPES: &[TomlType] = &[point::TOML, directional::TOML, spot::TOML, environment::CONSTANT, environment::ENVMAP];

/// The names of the TOML light types.
pub fn toml_types() -> Vec<&'static str> {
    TOML_TYPES.iter().map(|t| t.name).collect()
}

/// Reads one `[[lights]]` entry: its kind reads its keys, its check refuses a parameter out of
/// range at the parameter's line; directions are made unit length.
pub(super) fn read_toml(entry: &Value) -> Result<Light> {
    let t = entry.table()?;
    let types: Vec<_> = TOML_TYPES.iter().map(|k| (k.name, k.read, k.keys)).collect();
    let read = t.typed("light type", &types, &["type"])?;
    let kind = read(&t)?;
    kind.check().map_err(|e| t.invalid(e))?;
    Ok(Light { kind: kind.with_unit_direction(), line: entry.line })
}

/// Why `kind` cannot join `lights`: a scene has at most one environment. The message names
/// the other by its line.
pub(crate) fn second_environment(lights: &[Light], kind: &LightKind) -> Option<String> {
    let first = lights.iter().find(|l| l.kind.is_environment()).filter(|_| kind.is_environment())?;
    let at = if first.line > 0 { format!("; another is at line {}", first.line) } else { String::new() };
    Some(format!("a scene has at most one environment light{at}"))
}

/// What a kind's Mitsuba mapping reads an emitter plugin's parameters through, with Mitsuba
/// 3's types and names (`scene/mitsuba/emitter.rs` implements it over the plugin's element).
/// Every parameter must be read, or the plugin is refused for it.
pub(crate) trait MitsubaEmitter {
    /// A colour parameter (`intensity`, `irradiance`, `radiance`) as Mitsuba's RGB variants
    /// read an emitter's: linear RGB >= 0, not textured.
    fn colour(&self, name: &str) -> Result<Option<Vec3>>;
    /// A `<float>` with its default.
    fn float_or(&self, name: &str, default: f32) -> Result<f32>;
    /// A `<point>` or `<vector>`.
    fn vec3(&self, name: &str) -> Result<Option<Vec3>>;
    /// The plugin's `to_world`, read for every plugin.
    fn to_world(&self) -> Option<Mat4>;
    /// Whether the plugin gives `name`.
    fn has(&self, name: &str) -> bool;
    /// An `envmap`'s image, scale and frame.
    fn envmap(&self) -> Result<Envmap>;
    /// An error about parameter `name`, at the plugin's element.
    fn error(&self, name: &str, message: String) -> SceneError;
    /// An error about parameter `name`, at its line where it is given.
    fn error_at(&self, name: &str, message: String) -> SceneError;
}

/// A point or direction that Mitsuba gives as parameter `name` or through `to_world` (`of`
/// takes it from the matrix, the identity when neither is given), not both.
fn given_or_to_world(p: &dyn MitsubaEmitter, name: &'static str, of: fn(Mat4) -> Vec3) -> Result<Vec3> {
    match (p.vec3(name)?, p.to_world()) {
        (Some(_), Some(_)) => Err(p.error(name, format!("give `{name}` or `to_world`, not both"))),
        (Some(v), None) => Ok(v),
        (None, m) => Ok(of(m.unwrap_or(Mat4::IDENTITY))),
    }
}

/// A kind's Mitsuba plugin: its name, the mapping that reads it, and the names Mitsuba gives
/// the parameters that the kind's check names as TOML does.
pub(super) struct MitsubaPlugin {
    name: &'static str,
    read: fn(&dyn MitsubaEmitter) -> Result<LightKind>,
    params: &'static [(&'static str, &'static str)],
}

/// Every Mitsuba emitter plugin modelled here but `area`, which belongs inside a shape.
const MITSUBA_PLUGINS: &[MitsubaPlugin] =
    &[point::MITSUBA, directional::MITSUBA, spot::MITSUBA, environment::MITSUBA_CONSTANT, environment::MITSUBA_ENVMAP];

/// The light of Mitsuba emitter plugin `plugin`, read through `p` by its kind and checked as
/// every reader's; `None` for a plugin no kind models.
pub(crate) fn from_mitsuba(plugin: &str, p: &dyn MitsubaEmitter) -> Option<Result<LightKind>> {
    let kind = MITSUBA_PLUGINS.iter().find(|k| k.name == plugin)?;
    Some((kind.read)(p).and_then(|light| {
        let name = |key: &str| kind.params.iter().find(|(k, _)| *k == key).map_or(key, |(_, m)| m).to_owned();
        light.check().map_err(|e| p.error_at(&name(e.key), e.message))?;
        Ok(light)
    }))
}

/// An area emitter inside a Mitsuba shape: its `radiance`.
pub(crate) fn area_from_mitsuba(p: &dyn MitsubaEmitter) -> Result<Vec3> {
    let radiance = area::from_mitsuba(p)?;
    area::check(radiance).map_err(|e| p.error_at("radiance", e.message))
}

/// The most radiance, intensity or irradiance a light may have in a channel (for an
/// environment map, its brightest texel times its scale). The kernels sum such values over a
/// path's vertices and a pixel's passes in f32, and guard the sums by zeroing what overflows:
/// at 1e18, the sum of 3.4e20 passes, or a value's square, still fits under f32's 3.4e38.
/// Brighter lights are refused rather than rendered black.
pub const MAX_EMISSION: f64 = 1e18;

/// The most power the lights may emit together. Photon flux is kept relative to it (the f32
/// `Frame::power_total`), SPPM's estimate multiplies it by a point's gathered flux tau
/// (shared/estimate.wgsl), and a next-event estimate of a light of small pmf is about
/// power_total / (pi d^2) (shared/lights.wgsl): 1e28 leaves ten orders of magnitude below
/// f32's 3.4e38.
pub const MAX_LIGHT_POWER: f64 = 1e28;

/// What gives light: a shape with `emission`, or a `[[lights]]` entry (indices into
/// [`Scene::shapes`] and [`Scene::lights`]).
#[derive(Clone, Copy, PartialEq)]
enum Source {
    Shape(usize),
    Light(usize),
}

/// The emitters of a scene on the GPU, with their distribution by power.
pub struct Packed {
    /// Emitting triangles, then emitting spheres, then the lights, the environment last, each
    /// with its `pmf` and `cdf`.
    pub emitters: Vec<Emitter>,
    /// Sum of the emitters' power (average over RGB).
    pub power_total: f32,
}

/// The emitters being packed: each one's record, power and light.
struct Packing {
    emitters: Vec<Emitter>,
    powers: Vec<f64>,
    sources: Vec<Source>,
}

impl Packing {
    fn push(&mut self, emitter: Emitter, power: f64, source: Source) {
        self.emitters.push(emitter);
        self.powers.push(power);
        self.sources.push(source);
    }
}

/// The average over RGB, summed in f64: three channels near f32's largest overflow its sum.
fn average(v: Vec3) -> f64 {
    (v.x as f64 + v.y as f64 + v.z as f64) / 3.0
}

/// Every emitter of `scene` on the GPU, chosen in proportion to power (each kind gives its
/// own); `center` and `radius` are those of the sphere around the scene over the shutter,
/// which directional lights and the environment cover with a disk. An envmap's image and
/// distribution go at the end of `texels`.
///
/// Errors when the scene has no light with positive power or lights more powerful than
/// [`MAX_LIGHT_POWER`], or an environment map too large for a storage buffer.
pub fn pack(scene: &Scene, center: Vec3, radius: f32, texels: &mut Vec<[f32; 4]>) -> Result<Packed> {
    let mut p = Packing { emitters: Vec::new(), powers: Vec::new(), sources: Vec::new() };
    area::pack(scene, &mut p);
    for (i, light) in scene.lights.iter().enumerate() {
        let source = Source::Light(i);
        match light.kind {
            LightKind::Point { position, intensity } => {
                let (e, power) = point::pack(position, intensity);
                p.push(e, power, source);
            }
            LightKind::Directional { direction, irradiance } => {
                let (e, power) = directional::pack(direction, irradiance, center, radius);
                p.push(e, power, source);
            }
            LightKind::Spot { position, direction, intensity, cutoff_angle, beam_width } => {
                let (e, power) = spot::pack(position, direction, intensity, cutoff_angle, beam_width);
                p.push(e, power, source);
            }
            // Last, after the loop.
            LightKind::Constant { .. } | LightKind::Envmap(_) => {}
        }
    }
    // The environment is the last emitter, where the kernels find it.
    if let Some((i, light)) = scene.lights.iter().enumerate().find(|(_, l)| l.kind.is_environment()) {
        let (e, power) = environment::pack(light, center, radius, texels)?;
        p.push(e, power, Source::Light(i));
    }
    let power_total: f64 = p.powers.iter().sum();
    if power_total.is_nan() || power_total > MAX_LIGHT_POWER {
        return Err(power_error(scene, &p, power_total, radius));
    }
    if !power_total.is_finite() || power_total <= 0.0 {
        return Err(no_light_error(scene));
    }
    let mut running = 0.0;
    for (e, power) in p.emitters.iter_mut().zip(&p.powers) {
        running += power;
        e.pmf = (power / power_total) as f32;
        e.cdf = (running / power_total) as f32;
    }
    // The last interval must hold every u < 1, whatever the rounding.
    if let Some(last) = p.emitters.last_mut() {
        last.cdf = f32::INFINITY;
    }
    Ok(Packed { emitters: p.emitters, power_total: power_total as f32 })
}

/// Turn on the kernel features ([`Features`]) that emitter `e`, as on the GPU, needs: its
/// kind's `USES_*` overrides.
pub fn turn_on_features(e: &Emitter, f: &mut Features) {
    match e.kind {
        EMITTER_AREA => area::turn_on(e, f),
        EMITTER_POINT => point::turn_on(e, f),
        EMITTER_DIRECTIONAL => directional::turn_on(e, f),
        EMITTER_SPOT => spot::turn_on(e, f),
        EMITTER_ENVIRONMENT => environment::turn_on(e, f),
        _ => {}
    }
}

/// Why a light's values are refused.
fn beyond(bound: f64) -> String {
    format!("beyond what the renderer's 32-bit arithmetic holds: at most {bound:e}")
}

/// A computed value for a message, to four digits (`3.142e29`), more where four would show
/// `bound` for a value past it.
fn rounded(x: f64, bound: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let s = format!("{x:.3e}");
    let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
    let s = format!("{}e{exponent}", mantissa.trim_end_matches('0').trim_end_matches('.'));
    if x != bound && s.parse::<f64>() == Ok(bound) {
        format!("{x:e}")
    } else {
        s
    }
}

/// An error at a light's record: its line (none for the builder's records, line 0) and the
/// key of `name`, its value to blame, as TOML and the builder spell it (`lights[2].intensity`,
/// `shapes[0].emission`), or as a Mitsuba XML parameter (`intensity`; an area emitter's
/// `radiance`, at its shape's line).
fn light_error(scene: &Scene, source: Source, name: &str, message: String) -> SceneError {
    let xml = super::is_mitsuba_xml(&scene.path);
    let (line, key) = match source {
        Source::Shape(i) => (scene.shapes[i].line, if xml { "radiance".into() } else { format!("shapes[{i}].{name}") }),
        Source::Light(i) => {
            let name = if xml && name == "file" { "filename" } else { name };
            (scene.lights[i].line, if xml { name.to_owned() } else { format!("lights[{i}].{name}") })
        }
    };
    SceneError { file: scene.path.clone(), line: (line > 0).then_some(line), key: Some(key), message }
}

/// A scene that gives no light: at the first emission or light in the file, all of them
/// zero (its line and key), or, with none, at the file and the `lights` a light goes in.
fn no_light_error(scene: &Scene) -> SceneError {
    let message = "the scene has no light: give a shape an `emission` greater than zero, or add a [[lights]] entry \
                   with positive intensity or irradiance";
    let shape =
        scene.shapes.iter().position(|s| s.emission.is_some()).map(|i| (scene.shapes[i].line, Source::Shape(i), "emission"));
    let light = scene.lights.first().map(|l| (l.line, Source::Light(0), l.kind.brightness_key()));
    match shape.into_iter().chain(light).min_by_key(|&(line, ..)| line) {
        Some((_, source, name)) => light_error(scene, source, name, message.into()),
        None => SceneError { file: scene.path.clone(), line: None, key: Some("lights".into()), message: message.into() },
    }
}

/// Refuses a light brighter than [`MAX_EMISSION`] in some channel, naming it.
pub fn check_brightness(scene: &Scene) -> Result<()> {
    let too_bright = |v: Vec3| v.is_nan() || v.max_element() as f64 > MAX_EMISSION;
    for (i, s) in scene.shapes.iter().enumerate() {
        if let Some(e) = s.emission.filter(|&e| too_bright(e)) {
            let message = format!("emission {} is {} in each channel", number(e.max_element()), beyond(MAX_EMISSION));
            return Err(light_error(scene, Source::Shape(i), "emission", message));
        }
    }
    for (i, light) in scene.lights.iter().enumerate() {
        let name = light.kind.brightness_key();
        let at = Source::Light(i);
        match &light.kind {
            LightKind::Point { intensity: v, .. }
            | LightKind::Spot { intensity: v, .. }
            | LightKind::Directional { irradiance: v, .. }
            | LightKind::Constant { radiance: v } => {
                if too_bright(*v) {
                    let message = format!("{name} {} is {} in each channel", number(v.max_element()), beyond(MAX_EMISSION));
                    return Err(light_error(scene, at, name, message));
                }
            }
            LightKind::Envmap(map) => {
                if let Some((key, message)) = environment::too_bright(map) {
                    return Err(light_error(scene, at, key, message));
                }
            }
        }
    }
    Ok(())
}

/// The error for lights whose power sums past [`MAX_LIGHT_POWER`]: at the light that gives
/// the most, with how its power comes about (`radius`, that of the disk covering the scene,
/// for a directional light and the environment).
fn power_error(scene: &Scene, p: &Packing, total: f64, radius: f32) -> SceneError {
    let mut by_source: Vec<(Source, f64)> = Vec::new();
    for (&source, &power) in p.sources.iter().zip(&p.powers) {
        match by_source.iter_mut().find(|(s, _)| *s == source) {
            Some((_, sum)) => *sum += power,
            None => by_source.push((source, power)),
        }
    }
    let (source, power) = by_source.into_iter().max_by(|a, b| a.1.total_cmp(&b.1)).expect("a sum needs a term");
    let disk = format!("the area of the disk of radius {} that covers the scene", number(radius));
    let (name, how) = match source {
        Source::Shape(_) => ("emission", area::POWER.to_owned()),
        Source::Light(i) => {
            let kind = &scene.lights[i].kind;
            let how = match kind {
                LightKind::Point { .. } => point::POWER.to_owned(),
                LightKind::Spot { .. } => spot::POWER.to_owned(),
                LightKind::Directional { .. } => format!("{} {disk}", directional::POWER),
                LightKind::Constant { .. } | LightKind::Envmap(_) => environment::power(kind, &disk),
            };
            (kind.brightness_key(), how)
        }
    };
    let message = format!(
        "the lights' power is {}, {} of it from this light ({how}): {}; dim the lights (the image scales with them)",
        rounded(total, MAX_LIGHT_POWER),
        rounded(power, MAX_LIGHT_POWER),
        beyond(MAX_LIGHT_POWER)
    );
    light_error(scene, source, name, message)
}
