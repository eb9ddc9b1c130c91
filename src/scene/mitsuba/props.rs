//! A plugin's parameters, as Mitsuba's `Properties`: the named children of an object element
//! (`<float name=".." value=".."/>`, `<rgb ..>`, `<transform ..>`, a nested `<bsdf>` or
//! `<ref>`), read by type. Every parameter must be read by the plugin that owns it:
//! [`Props::finish`] refuses any left over in a scene of version 2/3, as Mitsuba 3 does, so a
//! parameter we do not model is an error rather than a silently different scene. In a 0.x
//! scene it warns instead, as Mitsuba 0.5/0.6 warn about a parameter their plugin does not
//! query and render: so each plugin here reads every parameter its Mitsuba 0.6 counterpart
//! queries, mapping it, passing it over with a warning ([`Props::legacy_ignored`]: it changes
//! only the noise, the speed or the scheduling) or refusing it (it would change the image).

use super::super::SceneError;
use super::spectra::{spectrum_to_srgb, SpectrumUse, XYZ_TO_SRGB};
use super::xml::Node;
use glam::{Mat3, Mat4, Vec3, Vec4};
use std::cell::Cell;

type Result<T> = std::result::Result<T, SceneError>;

/// Tags of property elements (as opposed to nested objects).
pub const PROPERTY_TAGS: &[&str] =
    &["float", "integer", "boolean", "string", "rgb", "srgb", "spectrum", "point", "vector", "transform"];

/// Tags of nested objects.
pub const OBJECT_TAGS: &[&str] =
    &["bsdf", "texture", "emitter", "shape", "sensor", "film", "rfilter", "sampler", "integrator", "medium", "phase", "volume"];

/// One object element's parameters and nested objects.
pub struct Props<'a> {
    /// The object element.
    pub node: &'a Node,
    /// `(name, element, read)` for each named property and nested object.
    named: Vec<(&'a str, &'a Node, Cell<bool>)>,
    /// Nested objects without a name, and whether each was taken.
    unnamed: Vec<(&'a Node, Cell<bool>)>,
}

/// A spectrum-valued parameter: a constant colour or a texture element.
pub enum Spectrum<'a> {
    /// Linear RGB.
    Rgb(Vec3),
    /// A `<texture>` element (or the one a `<ref>` names, resolved by the caller).
    Texture(&'a Node),
}

impl<'a> Props<'a> {
    /// The parameters of object element `node`.
    pub fn new(node: &'a Node) -> Result<Self> {
        let mut named: Vec<(&str, &Node, Cell<bool>)> = Vec::new();
        let mut unnamed = Vec::new();
        for child in &node.children {
            let is_object = OBJECT_TAGS.contains(&child.tag.as_str()) || child.tag == "ref";
            if !is_object && !PROPERTY_TAGS.contains(&child.tag.as_str()) {
                return Err(child.error(None, format!("<{}> is not an element of Mitsuba's scene format", child.tag)));
            }
            // A nested object's name only labels it (Mitsuba's plugins take nested BSDFs,
            // emitters, films, filters and samplers by type), but for a texture, whose name is
            // the parameter it sets. A named <ref> may be either: it stays named, and
            // all_objects takes it too.
            let label_only = is_object && child.tag != "ref" && child.tag != "texture";
            match child.attr("name").filter(|_| !label_only) {
                Some(name) => {
                    if named.iter().any(|(n, _, _)| *n == name) {
                        return Err(child.error(Some(name), format!("{} sets `{name}` twice", node.describe())));
                    }
                    named.push((name, child, Cell::new(false)));
                }
                None if is_object => unnamed.push((child, Cell::new(false))),
                None => return Err(child.error(None, format!("<{}> needs a `name` attribute", child.tag))),
            }
        }
        Ok(Props { node, named, unnamed })
    }

    /// The element of parameter `name`, marked read.
    pub fn get(&self, name: &str) -> Option<&'a Node> {
        self.named.iter().find(|(n, _, _)| *n == name).map(|(_, node, read)| {
            read.set(true);
            *node
        })
    }

    /// Parameters of this plugin in Mitsuba 0.5/0.6 that sppm-gpu does not apply and that
    /// change only the noise, the speed or the scheduling: in a 0.x scene each one given is
    /// read and passed over with a warning naming it and `why`; in a 2/3 scene they are left
    /// unread, for [`Props::finish`] to refuse, as Mitsuba 3 does.
    pub fn legacy_ignored(&self, names: &[&str], why: &str) {
        if !self.node.legacy() {
            return;
        }
        for name in names {
            if let Some(node) = self.get(name) {
                let value = node.attr("value").map(|v| format!(" {v}")).unwrap_or_default();
                node.warn(Some(name), format!("{name}{value} is not applied: {why}"));
            }
        }
    }

    /// Mitsuba 0.5/0.6's `gamma` of a `bitmap` texture or an `envmap` reading image `path`, in
    /// a 0.x scene: whether it asks for the image's values as stored (our `raw`). 0, the
    /// default, is as the file says, and so is -1 (sRGB) on an 8- or 16-bit image; 1 (linear)
    /// is `raw`. Any other (a power law, or sRGB decoding of a floating-point image) would
    /// change the image, and is refused. `None` where not given, and in a 2/3 scene, whose
    /// Mitsuba 3 has no `gamma` ([`Props::finish`] refuses it there).
    pub fn legacy_gamma(&self, path: &std::path::Path) -> Result<Option<bool>> {
        if !self.node.legacy() || !self.has("gamma") {
            return Ok(None);
        }
        let gamma = self.float("gamma")?.unwrap();
        let floating = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| ["exr", "hdr", "rgbe", "pfm"].contains(&e.to_ascii_lowercase().as_str()));
        match gamma {
            0.0 => Ok(None),
            1.0 => Ok(Some(true)),
            -1.0 if !floating => Ok(Some(false)),
            _ => Err(self.get("gamma").unwrap().error(
                Some("gamma"),
                format!(
                    "gamma {gamma} is not modelled by sppm-gpu: 0 (as the file says), 1 (linear) or -1 (sRGB, of an \
                     8- or 16-bit image)"
                ),
            )),
        }
    }

    /// Whether parameter `name` is given (without reading it).
    pub fn has(&self, name: &str) -> bool {
        self.named.iter().any(|(n, _, _)| *n == name)
    }

    /// Unnamed nested objects and `<ref>`s, and named `<ref>`s not read as parameters, every
    /// one, marked read (the caller sorts them).
    pub fn all_objects(&self) -> Vec<&'a Node> {
        let named_refs = self.named.iter().filter(|(_, node, read)| node.tag == "ref" && !read.get());
        self.unnamed
            .iter()
            .map(|(node, read)| (*node, read))
            .chain(named_refs.map(|(_, node, read)| (*node, read)))
            .map(|(node, read)| {
                read.set(true);
                node
            })
            .collect()
    }

    /// Refuses any parameter or nested object not read; in a 0.x scene a parameter not read
    /// is one the plugin's Mitsuba 0.6 counterpart does not query either, and a warning.
    pub fn finish(&self) -> Result<()> {
        for (name, node, _) in self.named.iter().filter(|(_, _, read)| !read.get()) {
            if !self.node.legacy() {
                return Err(node.error(
                    Some(name),
                    format!(
                        "{} has no parameter `{name}` that sppm-gpu reads (not in Mitsuba 3, or not modelled here)",
                        self.node.describe()
                    ),
                ));
            }
            node.warn(
                Some(name),
                format!(
                    "{} has no parameter `{name}` in Mitsuba 0.5/0.6: ignored, as they ignore it (with a warning)",
                    self.node.describe()
                ),
            );
        }
        if let Some((node, _)) = self.unnamed.iter().find(|(_, read)| !read.get()) {
            return Err(node.error(None, format!("{} inside {} is not read by sppm-gpu", node.describe(), self.node.describe())));
        }
        Ok(())
    }

    /// A `<float>` (or `<integer>`) parameter.
    pub fn float(&self, name: &str) -> Result<Option<f32>> {
        let Some(node) = self.get(name) else { return Ok(None) };
        if node.tag != "float" && node.tag != "integer" {
            return Err(node.error(Some(name), format!("`{name}` is a number: <float name=\"{name}\" value=\"...\"/>")));
        }
        node.allow_attrs(&["name", "value"])?;
        parse_f32(node, node.req_attr("value")?, name).map(Some)
    }

    /// An emitter's `sampling_weight` (1), read and checked: how often Mitsuba 3 picks the
    /// emitter for next-event estimation, which changes the noise and not the image. Ours
    /// picks lights by power.
    pub fn emitter_sampling_weight(&self) -> Result<()> {
        match self.float("sampling_weight")? {
            Some(w) if !(w >= 0.0 && w.is_finite()) => Err(self.get("sampling_weight").unwrap().error(
                Some("sampling_weight"),
                format!("sampling_weight {w}: a light's sampling weight is a number at least 0"),
            )),
            _ => Ok(()),
        }
    }

    /// A `<float>` with a default.
    pub fn float_or(&self, name: &str, default: f32) -> Result<f32> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    /// An `<integer>` parameter.
    pub fn integer(&self, name: &str) -> Result<Option<i64>> {
        let Some(node) = self.get(name) else { return Ok(None) };
        if node.tag != "integer" {
            return Err(node.error(Some(name), format!("`{name}` is an integer: <integer name=\"{name}\" value=\"...\"/>")));
        }
        node.allow_attrs(&["name", "value"])?;
        let text = node.req_attr("value")?;
        text.trim().parse::<i64>().map(Some).map_err(|_| node.error(Some(name), format!("\"{text}\" is not an integer")))
    }

    /// A `<boolean>` parameter with a default.
    pub fn boolean_or(&self, name: &str, default: bool) -> Result<bool> {
        let Some(node) = self.get(name) else { return Ok(default) };
        if node.tag != "boolean" {
            return Err(node.error(Some(name), format!("`{name}` is a boolean: <boolean name=\"{name}\" value=\"true\"/>")));
        }
        node.allow_attrs(&["name", "value"])?;
        match node.req_attr("value")?.trim() {
            "true" => Ok(true),
            "false" => Ok(false),
            other => Err(node.error(Some(name), format!("\"{other}\" is not a boolean (true or false)"))),
        }
    }

    /// A `<string>` parameter.
    pub fn string(&self, name: &str) -> Result<Option<&'a str>> {
        let Some(node) = self.get(name) else { return Ok(None) };
        if node.tag != "string" {
            return Err(node.error(Some(name), format!("`{name}` is a string: <string name=\"{name}\" value=\"...\"/>")));
        }
        node.allow_attrs(&["name", "value"])?;
        node.req_attr("value").map(Some)
    }

    /// A `<point>` or `<vector>` parameter: `value="x, y, z"` or `x=".." y=".." z=".."`.
    pub fn vec3(&self, name: &str) -> Result<Option<Vec3>> {
        let Some(node) = self.get(name) else { return Ok(None) };
        if node.tag != "point" && node.tag != "vector" {
            return Err(node.error(Some(name), format!("`{name}` is a <point> or <vector>")));
        }
        xyz(node, 0.0).map(Some)
    }

    /// A spectrum parameter: `<rgb>`, `<srgb>` (decoded to linear), a constant `<spectrum>`
    /// or `<float>`, or a nested `<texture>` / `<ref>` (returned as the element).
    pub fn spectrum(&self, name: &str) -> Result<Option<Spectrum<'a>>> {
        let Some(node) = self.get(name) else { return Ok(None) };
        spectrum_of(node, name, SpectrumUse::Reflectance).map(Some)
    }

    /// An unbounded non-emissive spectrum parameter (a conductor's `eta` and `k`): as
    /// [`Props::spectrum`], but a spectrum given by wavelengths is not clamped to 1.
    pub fn unbounded_spectrum(&self, name: &str) -> Result<Option<Spectrum<'a>>> {
        let Some(node) = self.get(name) else { return Ok(None) };
        spectrum_of(node, name, SpectrumUse::Unbounded).map(Some)
    }

    /// An emitter's spectrum parameter (`radiance`, `intensity`, `irradiance`), as Mitsuba 3's
    /// RGB variants read it (`Properties::get_emissive_texture`): as [`Props::spectrum`], but
    /// a constant `<spectrum>` is the colour of that flat spectrum in linear sRGB, its
    /// CIE XYZ (1, 1, 1) times the value: XYZ_TO_SRGB's rows summed, a purple-ish
    /// (1.205, 0.948, 0.909), so that RGB renders match spectral ones; one given by
    /// wavelengths is integrated without an illuminant. In a 0.x scene a constant is grey, as
    /// Mitsuba 0.5/0.6 read it ([`legacy_spectrum`]).
    pub fn emitter_spectrum(&self, name: &str) -> Result<Option<Spectrum<'a>>> {
        let Some(node) = self.get(name) else { return Ok(None) };
        spectrum_of(node, name, SpectrumUse::Emitter).map(Some)
    }

    /// A `<transform>` parameter as a 4x4 matrix.
    pub fn transform(&self, name: &str) -> Result<Option<Mat4>> {
        let Some(node) = self.get(name) else { return Ok(None) };
        if node.tag != "transform" {
            return Err(node.error(Some(name), format!("`{name}` is a <transform>")));
        }
        transform(node).map(Some)
    }
}

/// The colour or texture of a spectrum element, read as a parameter of kind `used`.
pub fn spectrum_of<'a>(node: &'a Node, name: &str, used: SpectrumUse) -> Result<Spectrum<'a>> {
    match node.tag.as_str() {
        "rgb" | "srgb" => {
            node.allow_attrs(&["name", "value"])?;
            let text = node.req_attr("value")?;
            let rgb = if let Some(hex) = text.trim().strip_prefix('#') {
                let bytes = (hex.len() == 6)
                    .then(|| (0..3).map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).ok()).collect::<Option<Vec<u8>>>())
                    .flatten()
                    .ok_or_else(|| node.error(Some(name), format!("\"{text}\" is not a colour #rrggbb")))?;
                Vec3::new(bytes[0] as f32, bytes[1] as f32, bytes[2] as f32) / 255.0
            } else {
                let v = numbers(node, text, name)?;
                match v.len() {
                    1 => Vec3::splat(v[0]),
                    3 => Vec3::new(v[0], v[1], v[2]),
                    n => return Err(node.error(Some(name), format!("an RGB value has 1 or 3 numbers, not {n}"))),
                }
            };
            // <srgb> is sRGB-encoded (Mitsuba 0.x); Mitsuba 3's <rgb> is linear.
            Ok(Spectrum::Rgb(if node.tag == "srgb" { rgb.map(crate::scene::mesh::srgb_to_linear) } else { rgb }))
        }
        "spectrum" => {
            let legacy = node.legacy();
            node.allow_attrs(if legacy { &["name", "value", "intent"] } else { &["name", "value"] })?;
            let text = node.req_attr("value")?;
            if text.contains(':') {
                if node.attr("intent").is_some() {
                    return Err(node.error(Some(name), "a <spectrum>'s `intent` goes with a single value only (Mitsuba 0.6)"));
                }
                return wavelengths(node, text, name, used).map(Spectrum::Rgb);
            }
            let v = numbers(node, text, name)?;
            if legacy {
                return legacy_spectrum(node, &v, name).map(Spectrum::Rgb);
            }
            if v.len() != 1 {
                return Err(node.error(Some(name), "a <spectrum> without wavelengths is one number"));
            }
            // On an emitter, the colour of a flat spectrum: its CIE XYZ (1, 1, 1) in sRGB, a
            // purple-ish (1.205, 0.948, 0.909), so that RGB renders match spectral ones.
            let flat = if used == SpectrumUse::Emitter { XYZ_TO_SRGB * Vec3::ONE } else { Vec3::ONE };
            Ok(Spectrum::Rgb(flat * v[0]))
        }
        "float" => {
            node.allow_attrs(&["name", "value"])?;
            Ok(Spectrum::Rgb(Vec3::splat(parse_f32(node, node.req_attr("value")?, name)?)))
        }
        "texture" | "ref" => Ok(Spectrum::Texture(node)),
        "blackbody" => Err(node.error(Some(name), "<blackbody> spectra are not read by sppm-gpu: give <rgb> values")),
        _ => Err(node.error(Some(name), format!("`{name}` is a colour (<rgb>, <spectrum>, <float>) or a <texture>"))),
    }
}

/// A `<spectrum>` of numbers `v` in a 0.x scene, as Mitsuba 0.5/0.6's RGB build (the default:
/// three spectral samples, the linear RGB values) reads it: one number is grey, on an emitter
/// too (Mitsuba 0.6 makes it D65 times the value, and D65 is 1 in its RGB build; Mitsuba 3 makes
/// it the colour of a flat spectrum, 1.2, 0.95, 0.91 per unit), and so whatever its `intent`;
/// three are the RGB values themselves. Any other count is refused, as Mitsuba 0.6 refuses it.
fn legacy_spectrum(node: &Node, v: &[f32], name: &str) -> Result<Vec3> {
    match node.attr("intent") {
        None => {}
        Some(intent) if v.len() == 1 && ["reflectance", "illuminant"].contains(&intent.to_ascii_lowercase().as_str()) => {}
        Some(intent) if v.len() == 1 => {
            return Err(node.error(Some(name), format!("intent \"{intent}\": \"reflectance\" or \"illuminant\"")))
        }
        Some(_) => return Err(node.error(Some(name), "a <spectrum>'s `intent` goes with a single value only (Mitsuba 0.6)")),
    }
    match *v {
        [x] => Ok(Vec3::splat(x)),
        [r, g, b] => Ok(Vec3::new(r, g, b)),
        _ => Err(node.error(
            Some(name),
            format!(
                "a <spectrum> without wavelengths has one number or three (Mitsuba 0.5/0.6's RGB build reads three as \
                 its spectral samples, the RGB values), not {}",
                v.len()
            ),
        )),
    }
}

/// A `<spectrum>` of `wavelength:value` pairs (nm, increasing) as linear sRGB
/// ([`spectrum_to_srgb`]; in a 0.x scene as Mitsuba 0.5/0.6 read it, without an illuminant).
fn wavelengths(node: &Node, text: &str, name: &str, used: SpectrumUse) -> Result<Vec3> {
    let bad = |why: String| node.error(Some(name), why);
    let mut points: Vec<(f32, f32)> = Vec::new();
    for pair in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (w, v) = pair.split_once(':').ok_or_else(|| bad(format!("\"{pair}\" is not a wavelength:value pair")))?;
        let (w, v) = (parse_f32(node, w.trim(), name)?, parse_f32(node, v.trim(), name)?);
        if points.last().is_some_and(|&(last, _)| w <= last) {
            return Err(bad(format!("wavelength {w} after {}: wavelengths increase", points.last().unwrap().0)));
        }
        points.push((w, v));
    }
    if points.len() < 2 {
        return Err(bad("a spectrum given by wavelengths needs two wavelength:value pairs or more".into()));
    }
    let legacy = node.legacy();
    let (rgb, clamped) = spectrum_to_srgb(&points, used, legacy);
    if clamped && legacy {
        node.warn(
            Some(name),
            format!(
                "the spectrum of `{name}` lies outside the sRGB gamut: clamped to {rgb} (Mitsuba 0.5/0.6 clamp only \
                 negative values, and keep a reflectance above 1)"
            ),
        );
    } else if clamped {
        node.warn(Some(name), format!("the spectrum of `{name}` lies outside the sRGB gamut: clamped to {rgb}, as Mitsuba does"));
    }
    Ok(rgb)
}

/// Rodrigues' rotation about `a` by `theta`, R = cos I + (1 - cos) a a^T + sin [a]x, with `a`
/// as written, not normalized: Mitsuba 3 (Dr.Jit's `rotate`) does not normalize it either, so
/// an axis such as (0, 1, 1) also scales and shears, and scenes are rendered with that.
fn rotation(a: Vec3, theta: f32) -> Mat3 {
    let (s, c) = theta.sin_cos();
    let outer = Mat3::from_cols(a * a.x, a * a.y, a * a.z);
    let cross = Mat3::from_cols(Vec3::new(0.0, a.z, -a.y), Vec3::new(-a.z, 0.0, a.x), Vec3::new(a.y, -a.x, 0.0));
    Mat3::from_diagonal(Vec3::splat(c)) + outer * (1.0 - c) + cross * s
}

/// One finite number.
pub fn parse_f32(node: &Node, text: &str, key: &str) -> Result<f32> {
    let v = numbers(node, text, key)?;
    if v.len() != 1 {
        return Err(node.error(Some(key), format!("\"{text}\" is not one number")));
    }
    Ok(v[0])
}

/// Finite numbers separated by commas and/or white space.
pub fn numbers(node: &Node, text: &str, key: &str) -> Result<Vec<f32>> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| match s.parse::<f32>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(_) => Err(node.error(Some(key), format!("{s} is not a finite 32-bit number"))),
            Err(_) => Err(node.error(Some(key), format!("\"{s}\" is not a number"))),
        })
        .collect()
}

/// A vector given as `value="x y z"` or by `x`, `y`, `z` attributes (each `missing` when left
/// out).
fn xyz(node: &Node, missing: f32) -> Result<Vec3> {
    node.allow_attrs(&["name", "value", "x", "y", "z"])?;
    if let Some(text) = node.attr("value") {
        if node.attr("x").is_some() || node.attr("y").is_some() || node.attr("z").is_some() {
            return Err(node.error(Some("value"), "give either `value` or `x`, `y`, `z`, not both"));
        }
        let v = numbers(node, text, "value")?;
        return match v.len() {
            3 => Ok(Vec3::new(v[0], v[1], v[2])),
            1 => Ok(Vec3::splat(v[0])),
            n => Err(node.error(Some("value"), format!("a vector has 3 numbers, not {n}"))),
        };
    }
    let mut out = [missing; 3];
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        if let Some(text) = node.attr(axis) {
            out[i] = parse_f32(node, text, axis)?;
        }
    }
    Ok(Vec3::from_array(out))
}

/// A `<transform>` element's matrix: its operations in order, each applied after (to the
/// left of) the ones before it, as Mitsuba composes them.
pub fn transform(node: &Node) -> Result<Mat4> {
    node.allow_attrs(&["name"])?;
    let mut m = Mat4::IDENTITY;
    for op in &node.children {
        let step = match op.tag.as_str() {
            "translate" => Mat4::from_translation(xyz(op, 0.0)?),
            "scale" => {
                // A single `value` scales uniformly; x, y, z left out keep that axis.
                let s = xyz(op, 1.0)?;
                Mat4::from_scale(s)
            }
            "rotate" => {
                op.allow_attrs(&["value", "x", "y", "z", "angle", "axis"])?;
                let angle = parse_f32(op, op.req_attr("angle")?, "angle")?;
                let axis = match (op.attr("axis"), op.attr("value")) {
                    (Some(text), _) | (None, Some(text)) => {
                        let v = numbers(op, text, "axis")?;
                        if v.len() != 3 {
                            return Err(op.error(Some("axis"), "a rotation axis has 3 numbers"));
                        }
                        Vec3::new(v[0], v[1], v[2])
                    }
                    (None, None) => {
                        let mut a = [0.0; 3];
                        for (i, k) in ["x", "y", "z"].iter().enumerate() {
                            if let Some(text) = op.attr(k) {
                                a[i] = parse_f32(op, text, k)?;
                            }
                        }
                        Vec3::from_array(a)
                    }
                };
                if axis == Vec3::ZERO {
                    return Err(op.error(Some("axis"), "the rotation axis is zero"));
                }
                Mat4::from_mat3(rotation(axis, angle.to_radians()))
            }
            "matrix" => {
                op.allow_attrs(&["value"])?;
                let v = numbers(op, op.req_attr("value")?, "value")?;
                match v.len() {
                    // Row-major, as written.
                    16 => {
                        projective_row(op, [v[12], v[13], v[14], v[15]])?;
                        Mat4::from_cols_array(&[
                            v[0], v[4], v[8], v[12], v[1], v[5], v[9], v[13], v[2], v[6], v[10], v[14], v[3], v[7], v[11], v[15],
                        ])
                    }
                    9 => Mat4::from_mat3(Mat3::from_cols_array(&[v[0], v[3], v[6], v[1], v[4], v[7], v[2], v[5], v[8]])),
                    n => return Err(op.error(Some("value"), format!("a matrix has 16 (or 9) numbers, not {n}"))),
                }
            }
            "lookat" | "lookAt" => {
                op.allow_attrs(&["origin", "target", "up"])?;
                let point = |k: &str| -> Result<Vec3> {
                    let v = numbers(op, op.req_attr(k)?, k)?;
                    if v.len() != 3 {
                        return Err(op.error(Some(k), format!("`{k}` has 3 numbers")));
                    }
                    Ok(Vec3::new(v[0], v[1], v[2]))
                };
                let origin = point("origin")?;
                let target = point("target")?;
                let up = match op.attr("up") {
                    Some(_) => point("up")?,
                    None => default_up(target - origin),
                };
                look_at(op, origin, target, up)?
            }
            other => {
                return Err(
                    op.error(None, format!("<{other}> is not a transform operation (translate, rotate, scale, matrix, lookat)"))
                )
            }
        };
        m = step * m;
    }
    if !m.is_finite() {
        return Err(node.error(node.attr("name"), "the transform overflows 32-bit floats"));
    }
    // Applied as affine, as Mitsuba 3's transform_affine: the top three rows.
    m = Mat4::from_cols(m.x_axis.with_w(0.0), m.y_axis.with_w(0.0), m.z_axis.with_w(0.0), m.w_axis.with_w(1.0));
    Ok(m)
}

/// A `<matrix>` whose bottom row is not `0 0 0 1`, a projective transform. Mitsuba 3 applies
/// a shape's, sensor's or emitter's `to_world` as an affine transform (`transform_affine`,
/// the top three rows: the mesh plugins transform their vertices so), so the row is ignored
/// with a warning. Mitsuba 0.5/0.6 divide each transformed point by its w (`Transform`'s
/// point operator), which sppm-gpu does not model: refused in a 0.x scene.
fn projective_row(op: &Node, bottom: [f32; 4]) -> Result<()> {
    if bottom == [0.0, 0.0, 0.0, 1.0] {
        return Ok(());
    }
    let row = bottom.map(|x| x.to_string()).join(" ");
    if op.legacy() {
        return Err(op.error(
            Some("value"),
            format!(
                "the bottom row {row} makes the matrix projective: Mitsuba 0.5/0.6 divide each transformed point by its w, \
                 which sppm-gpu does not model (give 0 0 0 1)"
            ),
        ));
    }
    op.warn(
        Some("value"),
        format!(
            "the bottom row {row} is ignored: Mitsuba 3 applies the transform as affine (its top three rows), and so does \
             sppm-gpu"
        ),
    );
    Ok(())
}

/// The `up` of a `lookat` that gives none, as Mitsuba 3 picks it: the first tangent of
/// `coordinate_system(dir)`, the branchless orthonormal basis of Duff et al. 2017 ("Building
/// an orthonormal basis, revisited", JCGT 6(1)).
fn default_up(dir: Vec3) -> Vec3 {
    let n = dir.normalize_or_zero();
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x)
}

/// Mitsuba's look-at: columns left = up x dir, up' = dir x left, dir, origin; the camera
/// looks along its local +z.
fn look_at(op: &Node, origin: Vec3, target: Vec3, up: Vec3) -> Result<Mat4> {
    let dir = (target - origin).try_normalize().ok_or_else(|| op.error(Some("target"), "target equals origin"))?;
    let left =
        up.cross(dir).try_normalize().ok_or_else(|| op.error(Some("up"), "`up` is zero or parallel to the view direction"))?;
    let new_up = dir.cross(left);
    Ok(Mat4::from_cols(left.extend(0.0), new_up.extend(0.0), dir.extend(0.0), Vec4::new(origin.x, origin.y, origin.z, 1.0)))
}
