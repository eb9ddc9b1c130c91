//! The scene file reader. The TOML document is walked by hand so that every key and value
//! keeps its line for error messages: each table is checked for unknown keys, each value for
//! its type and range, and each shape is turned into world-space primitives.

use super::mesh::{self, Normals, Transform};
use super::{
    medium, Camera, ComplexIor, CropWindow, Light, LightKind, Material, MaterialKind, Medium, Microfacet, Phase, PixelFilter,
    RadiusRule, RadiusSchedule, RenderSettings, Scene, SceneError, Shape, ShapeKind, Sphere, Texture, TextureFilter, TextureWrap,
    Triangle,
};
use super::{ply, serialized};
use glam::{Vec2, Vec3};
use std::fmt;
use std::path::{Path, PathBuf};
use toml::de::{DeInteger, DeString, DeTable, DeValue};
use toml::Spanned;

type Result<T> = std::result::Result<T, SceneError>;

/// Largest accepted image width or height, in pixels.
pub(super) const MAX_RESOLUTION: u32 = 16384;
/// Most camera paths per visible point per pass that `direct_samples` may ask for.
pub const MAX_DIRECT_SAMPLES: u32 = 1024;

/// Reads a scene file and loads it.
pub fn load(path: &Path) -> Result<Scene> {
    let bytes =
        super::files::read(path).map_err(|e| SceneError::new(path, None, None, format!("cannot read the scene file: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = valid.iter().filter(|&&b| b == b'\n').count() + 1;
        SceneError::new(path, Some(line), None, "the scene file is not UTF-8 text")
    })?;
    load_str(&text, path)
}

/// Loads a scene from its text. `path` names the file in errors, and relative mesh and
/// texture file names are resolved against its directory.
pub fn load_str(text: &str, path: &Path) -> Result<Scene> {
    let source = Source::new(text, path);
    let document = DeTable::parse(text).map_err(|e| {
        let line = e.span().map(|span| source.line(span.start));
        let key = line.and_then(|line| key_on_line(text, line));
        source.error(line, key.as_deref(), e.message().trim())
    })?;
    let root = Table { source: &source, table: document.get_ref(), key: String::new(), line: None };
    root.allow_keys(&["render", "camera", "materials", "shapes", "lights", "media"])?;

    let render = root.req("render", |v| read_render(&v.table()?))?;
    // Participating media (`[media.<name>]`), which the camera and shapes name.
    let media = root.or("media", Vec::new(), |v| {
        let table = v.table()?;
        table.entries().iter().map(|(name, m)| read_medium(name, m)).collect()
    })?;
    let camera = root.req("camera", |v| read_camera(&v.table()?, &media))?;
    let mut textures = Vec::new();
    let materials = root.or("materials", Vec::new(), |v| {
        let table = v.table()?;
        table.entries().iter().map(|(name, m)| read_material(name, m, &mut textures)).collect()
    })?;
    let lights = root.or("lights", Vec::new(), |v| v.elements()?.iter().map(read_light).collect())?;
    // At most one environment surrounds the scene.
    let mut environments = lights.iter().enumerate().filter(|(_, l)| l.kind.is_environment());
    if let (Some((_, first)), Some((i, second))) = (environments.next(), environments.next()) {
        let message = format!("a scene has at most one environment light; another is at line {}", first.line);
        return Err(source.error(Some(second.line), Some(&format!("lights[{i}]")), message));
    }
    let mut scene = Scene {
        path: path.to_path_buf(),
        render,
        camera,
        materials,
        textures,
        shapes: Vec::new(),
        triangles: Vec::new(),
        spheres: Vec::new(),
        lights,
        media,
        inputs: Vec::new(),
    };
    let budget = mesh::PrimitiveBudget::new();
    for (index, entry) in root.or("shapes", Vec::new(), Value::elements)?.iter().enumerate() {
        let shape = read_shape(entry, index as u32, &mut scene, &budget)?;
        scene.shapes.push(shape);
    }
    Ok(scene)
}

/// The dotted key that line `line` (1-based) of a scene assigns, for placing a TOML syntax
/// error: the last table header above it (`[[shapes]]` counted, as `shapes[2]`) and the
/// key before the line's `=` (or its first word when it has none). A line inside an array or
/// inline table opened on an earlier line belongs to the key that opened it. `None` when the
/// line is a header, or its key is not plain (quoted keys and keys with spaces are left out).
fn key_on_line(text: &str, line: usize) -> Option<String> {
    let mut table = String::new();
    let mut arrays: Vec<(String, usize)> = Vec::new();
    // Brackets and braces still open, and the key whose value opened them.
    let mut depth = 0;
    let mut open_key = None;
    for (i, l) in text.lines().enumerate() {
        let here = i + 1 == line;
        if depth > 0 {
            if here {
                return open_key;
            }
            depth = bracket_depth(l, depth);
            continue;
        }
        let l = l.trim();
        if let Some(name) = l.strip_prefix("[[").and_then(|l| l.split("]]").next()) {
            let name = name.trim().to_owned();
            let count = match arrays.iter_mut().find(|(n, _)| *n == name) {
                Some((_, count)) => {
                    *count += 1;
                    *count
                }
                None => {
                    arrays.push((name.clone(), 0));
                    0
                }
            };
            table = format!("{name}[{count}]");
        } else if let Some(name) = l.strip_prefix('[').and_then(|l| l.split(']').next()) {
            table = name.trim().to_owned();
        } else {
            let (key, value) = l.split_once('=').unwrap_or((l.split_whitespace().next().unwrap_or(""), ""));
            let key = key.trim();
            let plain = |c: char| c.is_ascii_alphanumeric() || "_-.".contains(c);
            let key = (!key.is_empty() && !key.starts_with('#') && key.chars().all(plain)).then(|| {
                if table.is_empty() {
                    key.to_owned()
                } else {
                    format!("{table}.{key}")
                }
            });
            if here {
                return key;
            }
            depth = bracket_depth(value, 0);
            open_key = key;
            continue;
        }
        if here {
            return None;
        }
    }
    None
}

/// How many brackets and braces are open after `text`, starting with `depth` open; strings
/// and comments are skipped (roughly: multi-line strings are not followed).
fn bracket_depth(text: &str, mut depth: usize) -> usize {
    let mut quote = None;
    let mut escaped = false;
    for c in text.chars() {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if c == '\\' && q == '"' {
                    escaped = true;
                } else if c == q {
                    quote = None;
                }
            }
            None => match c {
                '"' | '\'' => quote = Some(c),
                '#' => break,
                '[' | '{' => depth += 1,
                ']' | '}' => depth = depth.saturating_sub(1),
                _ => {}
            },
        }
    }
    depth
}

/// The `[render]` table, with defaults.
fn read_render(t: &Table) -> Result<RenderSettings> {
    t.allow_keys(&[
        "width",
        "height",
        "method",
        "iterations",
        "spp",
        "photons",
        "radius",
        "alpha",
        "max_depth",
        "seed",
        "time_limit",
        "direct",
        "direct_samples",
        "radius_schedule",
        "radius_rule",
        "filter",
        "filter_radius",
        "filter_stddev",
        "sampler",
    ])?;
    let d = RenderSettings::default();
    Ok(RenderSettings {
        width: t.req("width", |v| v.u32_in(1, MAX_RESOLUTION))?,
        height: t.req("height", |v| v.u32_in(1, MAX_RESOLUTION))?,
        method: t.or("method", d.method, Value::named)?,
        iterations: t.req("iterations", Value::count)?,
        spp: t.or("spp", d.spp, Value::count)?,
        photons: t.or("photons", d.photons, Value::count)?,
        radius: t.opt("radius", |v| v.f32_in(Bound::Positive))?,
        alpha: t.or("alpha", d.alpha, |v| v.f32_in(Bound::Open(0.0, 1.0)))?,
        max_depth: t.or("max_depth", d.max_depth, Value::count)?,
        seed: t.or("seed", d.seed, |v| v.u32_in(0, u32::MAX))?,
        time_limit: t.opt("time_limit", |v| v.f64_in(Bound::Positive))?,
        direct: t.or("direct", d.direct, Value::named)?,
        direct_samples: t.opt("direct_samples", |v| v.u32_in(1, MAX_DIRECT_SAMPLES))?,
        radius_schedule: t.or("radius_schedule", d.radius_schedule, Value::named)?,
        radius_rule: read_radius_rule(t)?,
        filter: read_filter(t)?,
        sampler: t.or("sampler", d.sampler, Value::named)?,
        work_given: super::WorkGiven { photons: t.get("photons").is_some(), spp: t.get("spp").is_some() },
    })
}

/// `radius_rule`; `"adaptive"` belongs to the per-point radius schedule.
fn read_radius_rule(t: &Table) -> Result<RadiusRule> {
    let rule = t.or("radius_rule", RadiusRule::Shrink, Value::named)?;
    let schedule = t.or("radius_schedule", RadiusSchedule::PerPoint, Value::named)?;
    if rule == RadiusRule::Adaptive && schedule == RadiusSchedule::Global {
        return Err(t.error_at("radius_rule", "radius_rule = \"adaptive\" needs radius_schedule = \"per-point\""));
    }
    Ok(rule)
}

/// The pixel filter: `filter` = `"box"` (default), `"tent"` (`filter_radius` in pixels,
/// default 1) or `"gaussian"` (`filter_stddev` in pixels, default 0.5), as Mitsuba's.
fn read_filter(t: &Table) -> Result<PixelFilter> {
    let kinds = [("box", 0), ("tent", 1), ("gaussian", 2)];
    let kind = t.or("filter", 0, |v| v.choice("filter", &kinds))?;
    let size = Bound::Open(0.0, 16.0);
    for (key, wanted) in [("filter_radius", 1), ("filter_stddev", 2)] {
        if t.get(key).is_some() && kind != wanted {
            return Err(t.error_at(key, format!("`{key}` belongs to filter = \"{}\"", kinds[wanted].0)));
        }
    }
    Ok(match kind {
        1 => PixelFilter::Tent { radius: t.or("filter_radius", 1.0, |v| v.f32_in(size))? },
        2 => PixelFilter::Gaussian { stddev: t.or("filter_stddev", 0.5, |v| v.f32_in(size))? },
        _ => PixelFilter::Box,
    })
}

/// The `[camera]` table; `focus_distance` defaults to the distance to `look_at`; `medium`
/// names one of `media`, the medium the camera sits in.
fn read_camera(t: &Table, media: &[Medium]) -> Result<Camera> {
    t.allow_keys(&["position", "look_at", "up", "fov", "aperture_radius", "focus_distance", "crop", "medium"])?;
    let position = t.req("position", Value::vec3)?;
    let look_at = t.req("look_at", Value::vec3)?;
    let up = t.or("up", Vec3::Y, Value::vec3)?;
    if !(look_at - position).length_squared().is_finite() {
        return Err(t.error_at("look_at", VIEW_OUT_OF_RANGE));
    }
    let view = (look_at - position).normalize_or_zero();
    if view == Vec3::ZERO {
        return Err(t.error_at("look_at", "look_at equals position: the camera has no view direction"));
    }
    if view.cross(up.normalize_or_zero()).length() < 1e-6 {
        return Err(t.error_at("up", "up is zero or parallel to the view direction"));
    }
    Ok(Camera {
        position,
        look_at,
        up,
        fov: t.req("fov", |v| v.f32_in(Bound::Open(0.0, 180.0)))?,
        aperture_radius: t.or("aperture_radius", 0.0, |v| v.f32_in(Bound::NonNegative))?,
        focus_distance: t.or("focus_distance", look_at.distance(position), |v| v.f32_in(Bound::Positive))?,
        aperture_line: t.get("aperture_radius").map(|v| v.line),
        crop: t.opt("crop", read_crop)?,
        medium: t.opt("medium", |v| v.medium(media))?,
    })
}

/// Keys of a `[media.<name>]` table.
const MEDIUM_KEYS: &[&str] = &["type", "sigma_a", "sigma_s", "sigma_t", "albedo", "scale", "phase", "g"];

/// Reads the `[media.<name>]` table of a homogeneous medium (see [`super::medium`]):
/// `sigma_a` and `sigma_s`, or `sigma_t` and `albedo` (each one number or `[r, g, b]`, in
/// inverse scene units; albedo in [0, 1]), times `scale` (1); `phase` = "isotropic" (the
/// default) or "hg" with `g` in (-1, 1). `type` = "homogeneous", the only type, may be given.
fn read_medium(name: &str, entry: &Value) -> Result<Medium> {
    let t = entry.table()?;
    t.allow_keys(MEDIUM_KEYS)?;
    t.opt("type", |v| v.choice("medium type", &[("homogeneous", ())]))?;
    let scale = t.or("scale", 1.0, |v| v.f32_in(Bound::NonNegative))?;
    let given = |keys: [&'static str; 2]| keys.into_iter().find(|k| t.get(k).is_some());
    let (sigma_a, sigma_s) = match (given(["sigma_a", "sigma_s"]), given(["sigma_t", "albedo"])) {
        (Some(_), Some(other)) => {
            return Err(t.error_at(other, "give sigma_a and sigma_s, or sigma_t and albedo: not keys of both forms"))
        }
        (Some(_), None) => {
            let a = t.req("sigma_a", |v| v.rgb(Bound::NonNegative))?;
            let s = t.req("sigma_s", |v| v.rgb(Bound::NonNegative))?;
            (a * scale, s * scale)
        }
        (None, Some(_)) => {
            let sigma_t = t.req("sigma_t", |v| v.rgb(Bound::NonNegative))?;
            let albedo = t.req("albedo", |v| v.rgb(UNIT))?;
            medium::from_extinction(sigma_t, albedo, scale)
        }
        (None, None) => return Err(t.error_here("a medium needs its coefficients: sigma_a and sigma_s, or sigma_t and albedo")),
    };
    for (key, value) in [("sigma_a", sigma_a), ("sigma_s", sigma_s)] {
        if let Some(why) = medium::check_coefficient(key, value) {
            return Err(t.error_at("scale", why));
        }
    }
    let phase = match t.or("phase", "isotropic", |v| v.choice("phase type", &[("isotropic", "isotropic"), ("hg", "hg")]))? {
        "hg" => Phase::HenyeyGreenstein { g: t.req("g", |v| v.f32_in(Bound::Open(-1.0, 1.0)))? },
        _ if t.get("g").is_some() => return Err(t.error_at("g", "`g` belongs to phase = \"hg\"")),
        _ => Phase::Isotropic,
    };
    Ok(Medium { name: name.to_owned(), sigma_a, sigma_s, phase, line: entry.line })
}

/// `crop` = [x0, y0, x1, y1]: the part of the film the image is, in fractions of its width
/// and height from its top-left corner (the render's width and height are the window's).
fn read_crop(v: &Value) -> Result<CropWindow> {
    let [x0, y0, x1, y1] = v.floats::<4>(Bound::Closed(0.0, 1.0))?;
    if x0 >= x1 || y0 >= y1 {
        return Err(v.error("a crop window [x0, y0, x1, y1] needs x0 < x1 and y0 < y1"));
    }
    Ok(CropWindow { min: Vec2::new(x0, y0), max: Vec2::new(x1, y1) })
}

/// Why a camera is refused when `look_at - position` overflows 32-bit floats.
pub(super) const VIEW_OUT_OF_RANGE: &str = "look_at is too far from position: their distance overflows 32-bit floats";

/// Reads one material type's keys; diffuse materials may load a texture.
type MaterialReader = fn(&Table, &mut Vec<Texture>) -> Result<MaterialKind>;

/// Material types: name, reader, and the keys allowed besides `type`.
const MATERIAL_TYPES: &[(&str, MaterialReader, &[&str])] = &[
    ("diffuse", read_diffuse, &["albedo", "texture"]),
    ("mirror", read_mirror, &["albedo", "texture", "eta", "k"]),
    ("glossy", read_glossy, &["albedo", "texture", "roughness", "distribution", "eta", "k"]),
    ("dielectric", read_dielectric, &["ior", "roughness", "distribution", "reflectance", "transmittance"]),
    ("plastic", read_plastic, &["albedo", "texture", "specular", "ior", "roughness", "distribution", "nonlinear"]),
    ("thin_dielectric", read_thin_dielectric, &["ior", "reflectance", "transmittance"]),
    ("null", read_null, &[]),
];

/// Reflectances and roughnesses lie in [0, 1].
const UNIT: Bound = Bound::Closed(0.0, 1.0);

/// Reads the `[materials]` entry `name = { type = ..., ... }`.
fn read_material(name: &str, entry: &Value, textures: &mut Vec<Texture>) -> Result<Material> {
    let t = entry.table()?;
    let read = t.typed("material type", MATERIAL_TYPES, &["type", "one_sided"])?;
    let kind = read(&t, textures)?;
    // Black seen from behind, as Mitsuba's BSDFs unless wrapped in `twosided`.
    let one_sided = t.or("one_sided", false, Value::bool)?;
    if one_sided && matches!(kind, MaterialKind::Dielectric { .. } | MaterialKind::ThinDielectric { .. } | MaterialKind::Null) {
        return Err(t.error_at("one_sided", "a dielectric or null surface is the same from both sides: one_sided does not apply"));
    }
    Ok(Material { name: name.to_owned(), kind, one_sided, line: entry.line })
}

/// Lambertian: `albedo`, or `texture` in its place.
fn read_diffuse(t: &Table, textures: &mut Vec<Texture>) -> Result<MaterialKind> {
    let (albedo, texture) = read_albedo(t, textures)?;
    Ok(MaterialKind::Diffuse { albedo, texture })
}

/// `albedo` in [0, 1], or a `texture` in its place (then the albedo is white).
fn read_albedo(t: &Table, textures: &mut Vec<Texture>) -> Result<(Vec3, Option<u32>)> {
    let albedo = t.opt("albedo", |v| v.rgb(UNIT))?;
    if albedo.is_some() && t.get("texture").is_some() {
        return Err(t.error_at("texture", "give either `albedo` or `texture`, not both"));
    }
    let texture = t.opt("texture", |v| texture_index(v, textures))?;
    if albedo.is_none() && texture.is_none() {
        return Err(t.error_at("albedo", "missing required key `albedo` (or `texture`)"));
    }
    Ok((albedo.unwrap_or(Vec3::ONE), texture))
}

/// A conductor's complex index of refraction: `eta` and `k` together (each >= 0 per
/// channel), or neither (no Fresnel term: the albedo alone).
fn read_fresnel(t: &Table) -> Result<Option<ComplexIor>> {
    let eta = t.opt("eta", |v| v.rgb(Bound::NonNegative))?;
    let k = t.opt("k", |v| v.rgb(Bound::NonNegative))?;
    match (eta, k) {
        (Some(eta), Some(k)) => Ok(Some(ComplexIor { eta, k })),
        (None, None) => Ok(None),
        (Some(_), None) => Err(t.error_at("eta", "a conductor's `eta` needs its `k`")),
        (None, Some(_)) => Err(t.error_at("k", "a conductor's `k` needs its `eta`")),
    }
}

/// `distribution` of microfacet normals: "ggx" (default) or "beckmann".
fn read_distribution(t: &Table) -> Result<Microfacet> {
    t.or("distribution", Microfacet::Ggx, Value::named)
}

/// A specular lobe's tint in [0, 1] (Mitsuba's `specular_reflectance` and
/// `specular_transmittance`), white unless given.
fn read_tint(t: &Table, key: &str) -> Result<Vec3> {
    t.or(key, Vec3::ONE, |v| v.rgb(UNIT))
}

fn read_mirror(t: &Table, textures: &mut Vec<Texture>) -> Result<MaterialKind> {
    let (albedo, texture) = read_albedo(t, textures)?;
    Ok(MaterialKind::Mirror { albedo, texture, fresnel: read_fresnel(t)? })
}

fn read_glossy(t: &Table, textures: &mut Vec<Texture>) -> Result<MaterialKind> {
    let (albedo, texture) = read_albedo(t, textures)?;
    Ok(MaterialKind::Glossy {
        albedo,
        texture,
        roughness: t.req("roughness", |v| v.f32_in(UNIT))?,
        distribution: read_distribution(t)?,
        fresnel: read_fresnel(t)?,
    })
}

fn read_dielectric(t: &Table, _: &mut Vec<Texture>) -> Result<MaterialKind> {
    Ok(MaterialKind::Dielectric {
        ior: t.req("ior", |v| v.f32_in(Bound::Positive))?,
        roughness: t.or("roughness", 0.0, |v| v.f32_in(UNIT))?,
        distribution: read_distribution(t)?,
        reflectance: read_tint(t, "reflectance")?,
        transmittance: read_tint(t, "transmittance")?,
    })
}

/// Mitsuba's plastic: a diffuse base (`albedo` or `texture`) under a dielectric coating of
/// index `ior`, smooth or of `roughness` (alpha), tinted by `specular`.
fn read_plastic(t: &Table, textures: &mut Vec<Texture>) -> Result<MaterialKind> {
    let (albedo, texture) = read_albedo(t, textures)?;
    let ior = t.req("ior", |v| v.f32_in(Bound::Positive))?;
    let roughness = t.or("roughness", 0.0, |v| v.f32_in(UNIT))?;
    if ior == 1.0 && roughness > 0.0 {
        return Err(t.error_at("ior", "a rough coating needs an index other than 1"));
    }
    Ok(MaterialKind::Plastic {
        albedo,
        texture,
        specular: read_tint(t, "specular")?,
        ior,
        roughness,
        distribution: read_distribution(t)?,
        nonlinear: t.or("nonlinear", false, Value::bool)?,
    })
}

fn read_thin_dielectric(t: &Table, _: &mut Vec<Texture>) -> Result<MaterialKind> {
    Ok(MaterialKind::ThinDielectric {
        ior: t.req("ior", |v| v.f32_in(Bound::Positive))?,
        reflectance: read_tint(t, "reflectance")?,
        transmittance: read_tint(t, "transmittance")?,
    })
}

fn read_null(_: &Table, _: &mut Vec<Texture>) -> Result<MaterialKind> {
    Ok(MaterialKind::Null)
}

/// Index of the texture a `texture` value names, loaded once per distinct file and settings:
/// a file name, or a table `{ file, filter, wrap, uv_transform }` with `filter` "bilinear"
/// (default) or "nearest", `wrap` "repeat" (default), "mirror" or "clamp", and
/// `uv_transform` = [[a, b, tx], [c, d, ty]], the image point (x right, y down, in [0, 1]) of
/// texture coordinates (u, v): x = a u + b v + tx, y = c u + d v + ty; by default
/// [[1, 0, 0], [0, -1, 1]], v up the image.
fn texture_index(v: &Value, textures: &mut Vec<Texture>) -> Result<u32> {
    let (file, settings) = match v.value {
        DeValue::Table(_) => {
            let t = v.table()?;
            t.allow_keys(&["file", "filter", "wrap", "uv_transform"])?;
            (t.require("file")?, Some(t))
        }
        _ => (Value { source: v.source, value: v.value, key: v.key.clone(), line: v.line }, None),
    };
    let path = file.path()?;
    let mut texture = file.read_file("texture", &path, mesh::read_texture)?;
    if let Some(t) = settings {
        let filters = [("bilinear", TextureFilter::Bilinear), ("nearest", TextureFilter::Nearest)];
        let wraps = [("repeat", TextureWrap::Repeat), ("mirror", TextureWrap::Mirror), ("clamp", TextureWrap::Clamp)];
        texture.filter = t.or("filter", texture.filter, |v| v.choice("filter", &filters))?;
        texture.wrap = t.or("wrap", texture.wrap, |v| v.choice("wrap", &wraps))?;
        if let Some(rows) = t.opt("uv_transform", |v| {
            let rows = v.elements()?;
            if rows.len() != 2 {
                return Err(v.error(format!("expected two rows of three numbers, found {} rows", rows.len())));
            }
            Ok([rows[0].floats::<3>(Bound::Any)?, rows[1].floats::<3>(Bound::Any)?])
        })? {
            let [[a, b, tx], [c, d, ty]] = rows;
            texture.to_uv = glam::Affine2::from_cols_array(&[a, c, b, d, tx, ty]);
        }
    }
    let same =
        |u: &Texture| u.path == texture.path && u.filter == texture.filter && u.wrap == texture.wrap && u.to_uv == texture.to_uv;
    if let Some(index) = textures.iter().position(same) {
        return Ok(index as u32);
    }
    textures.push(texture);
    Ok(textures.len() as u32 - 1)
}

/// A `[[shapes]]` type: one of the scene's [`ShapeKind`]s, or a disk, whose triangles make a
/// [`ShapeKind::Mesh`] (as Mitsuba's `disk` does).
#[derive(Clone, Copy, PartialEq)]
enum ShapeType {
    Kind(ShapeKind),
    Disk,
}

/// Shape types: name, type, and the keys allowed besides [`SHAPE_KEYS`].
const SHAPE_TYPES: &[(&str, ShapeType, &[&str])] = &[
    ("quad", ShapeType::Kind(ShapeKind::Quad), &["corner", "u", "v", "uv_scale"]),
    ("sphere", ShapeType::Kind(ShapeKind::Sphere), &["center", "radius", "uv_frame"]),
    ("cube", ShapeType::Kind(ShapeKind::Cube), &["scale", "rotate", "translate"]),
    ("mesh", ShapeType::Kind(ShapeKind::Mesh), &["file", "smooth", "shape_index", "scale", "rotate", "translate"]),
    ("disk", ShapeType::Disk, &["center", "normal", "radius"]),
];

/// Segments of a `disk`: triangles about its centre, as many as Mitsuba's `disk` has (their
/// area is 0.01% short of the circle's).
const DISK_SEGMENTS: u32 = 256;

/// Keys every shape allows.
const SHAPE_KEYS: &[&str] = &["type", "material", "emission", "velocity", "interior", "exterior"];

/// A sphere's `uv_frame` = [x, y, z]: the axes its texture coordinates are taken in (see
/// [`Shape::sphere_frame`]; by default [`super::TOML_SPHERE_FRAME`]), orthonormal to within
/// 1e-4 and used as written, so that a converted Mitsuba sphere keeps its frame bit for bit.
fn read_uv_frame(v: &Value) -> Result<glam::Mat3> {
    let items = v.elements().map_err(|_| v.expected("an array of 3 axes [x, y, z]"))?;
    if items.len() != 3 {
        return Err(v.error(format!("expected 3 axes [x, y, z], found {} items", items.len())));
    }
    let mut axes = [Vec3::ZERO; 3];
    for (axis, item) in axes.iter_mut().zip(items) {
        *axis = Value { key: v.key.clone(), ..item }.vec3()?;
    }
    let [x, y, z] = axes.map(|a| a.as_dvec3());
    let unit = |a: glam::DVec3| (a.length() - 1.0).abs() <= 1e-4;
    let orthogonal = x.dot(y).abs() <= 1e-4 && y.dot(z).abs() <= 1e-4 && z.dot(x).abs() <= 1e-4;
    if !(unit(x) && unit(y) && unit(z) && orthogonal) {
        return Err(v.error("the axes of a uv_frame are unit length and at right angles to each other"));
    }
    Ok(glam::Mat3::from_cols_array_2d(&axes.map(|a| a.to_array())))
}

/// Reads `shapes[index]` and appends its primitives to the scene, within `budget`.
fn read_shape(entry: &Value, index: u32, scene: &mut Scene, budget: &mesh::PrimitiveBudget) -> Result<Shape> {
    let t = entry.table()?;
    let shape_type = t.typed("shape type", SHAPE_TYPES, SHAPE_KEYS)?;
    let kind = match shape_type {
        ShapeType::Kind(kind) => kind,
        ShapeType::Disk => ShapeKind::Mesh,
    };
    let shape = Shape {
        kind,
        material: t.req("material", |v| v.material(&scene.materials))?,
        emission: t.opt("emission", |v| v.rgb(Bound::NonNegative))?,
        velocity: t.opt("velocity", Value::vec3)?,
        line: entry.line,
        velocity_line: t.get("velocity").map(|v| v.line),
        sphere_frame: t.opt("uv_frame", read_uv_frame)?,
        interior: t.opt("interior", |v| v.medium(&scene.media))?,
        exterior: t.opt("exterior", |v| v.medium(&scene.media))?,
    };
    let first_triangle = scene.triangles.len();
    let first_sphere = scene.spheres.len();
    // A warning for skipped degenerate triangles, printed once the shape is accepted.
    let mut warning = None;
    let fixed = if shape_type == ShapeType::Disk { DISK_SEGMENTS.into() } else { mesh::fixed_primitives(kind) };
    budget.check(primitives(scene), fixed, "").map_err(|e| t.error_here(e))?;
    match kind {
        ShapeKind::Quad => {
            let corner = t.req("corner", Value::vec3)?;
            let u = t.req("u", Value::vec3)?;
            let v = t.req("v", Value::vec3)?;
            if u.cross(v).length_squared() == 0.0 {
                return Err(t.error_at("v", "u and v are parallel or zero: the quad has no area"));
            }
            let uv_scale = t.or("uv_scale", Vec2::ONE, |v| v.vec2_in(Bound::Any))?;
            scene.triangles.extend(mesh::quad(corner, u, v, uv_scale, index));
        }
        ShapeKind::Sphere => scene.spheres.push(Sphere {
            center: t.req("center", Value::vec3)?,
            radius: t.req("radius", |v| v.f32_in(Bound::Positive))?,
            shape: index,
        }),
        ShapeKind::Cube => {
            let (triangles, skipped) =
                mesh::triangles(&mesh::unit_cube(), &read_transform(&t)?, Normals::Flat, index).map_err(|e| t.error_here(e))?;
            if triangles.is_empty() {
                return Err(t.error_at(
                    "scale",
                    "all 12 triangles of the cube have no area in 32-bit floats (scale too small \
                     for its size, or too small for its distance from the origin)",
                ));
            }
            if skipped > 0 {
                warning = Some(t.error_at("scale", format!("{skipped} of the cube's 12 triangles have no area and are skipped")));
            }
            scene.triangles.extend(triangles);
        }
        ShapeKind::Mesh if shape_type == ShapeType::Disk => scene.triangles.extend(read_disk(&t, index)?),
        ShapeKind::Mesh => warning = read_mesh(&t, index, scene, budget)?,
    }
    let triangles = &scene.triangles[first_triangle..];
    let spheres = &scene.spheres[first_sphere..];
    mesh::check_extent(triangles, spheres, Vec3::ZERO).map_err(|e| t.error_here(e))?;
    if let Some(velocity) = shape.velocity {
        mesh::check_extent(triangles, spheres, velocity)
            .map_err(|e| t.error_at("velocity", format!("moved by its velocity, {e}")))?;
    }
    if kind == ShapeKind::Quad && triangles.iter().any(mesh::is_degenerate) {
        return Err(t.error_at(
            "corner",
            "the quad has no area in 32-bit floats: u and v are too small for its distance \
             from the origin",
        ));
    }
    if shape.interior.is_some() {
        if let Some(why) = medium::check_closed(triangles, &shape, index) {
            return Err(t.error_at("interior", why));
        }
    }
    if let Some(warning) = warning {
        eprintln!("warning: {warning}");
    }
    Ok(shape)
}

/// A `disk` shape's triangles: `center`, `normal` (its front side, which emission leaves) and
/// `radius`, as [`DISK_SEGMENTS`] triangles about the centre. Texture coordinates are those of
/// Mitsuba's `disk`, (r / radius, phi / 2 pi), phi turning about the normal from the direction
/// that the shortest rotation of +z onto the normal takes +x to.
fn read_disk(t: &Table, index: u32) -> Result<Vec<Triangle>> {
    let center = t.req("center", Value::vec3)?;
    // Normalized in f64, so that no finite normal over- or underflows to zero.
    let normal = t.req("normal", Value::vec3)?.as_dvec3().normalize_or_zero().as_vec3();
    if normal == Vec3::ZERO {
        return Err(t.error_at("normal", "the normal must not be zero"));
    }
    let radius = t.req("radius", |v| v.f32_in(Bound::Positive))?;
    let frame = glam::Quat::from_rotation_arc(Vec3::Z, normal);
    let (x, y) = (frame * Vec3::X * radius, frame * Vec3::Y * radius);
    let n = DISK_SEGMENTS as f32;
    let rim = |i: u32| {
        let phi = std::f32::consts::TAU * (i % DISK_SEGMENTS) as f32 / n;
        center + phi.cos() * x + phi.sin() * y
    };
    let triangle = |i: u32| {
        let v = i as f32 / n;
        let uv = [Vec2::new(0.0, v + 0.5 / n), Vec2::new(1.0, v), Vec2::new(1.0, v + 1.0 / n)];
        Triangle { p: [center, rim(i), rim(i + 1)], n: None, uv: Some(uv), shape: index }
    };
    let triangles: Vec<Triangle> = (0..DISK_SEGMENTS).map(triangle).collect();
    mesh::check_extent(&triangles, &[], Vec3::ZERO).map_err(|e| t.error_here(e))?;
    if triangles.iter().any(mesh::is_degenerate) {
        return Err(t.error_at(
            "radius",
            "the disk has no area in 32-bit floats: its radius is too small for its distance from the origin",
        ));
    }
    Ok(triangles)
}

/// Reads a `mesh` shape's file (OBJ, PLY or Mitsuba `.serialized`, by its extension, in
/// any case; `shape_index` picks a `.serialized` file's shape) and appends its world-space
/// triangles; gives the warning to print when some of its triangles are degenerate and
/// skipped. A `.serialized` file's face-normals flag is ignored: `smooth` decides.
fn read_mesh(t: &Table, index: u32, scene: &mut Scene, budget: &mesh::PrimitiveBudget) -> Result<Option<SceneError>> {
    let transform = read_transform(t)?;
    let smooth = t.or("smooth", false, Value::bool)?;
    let file = t.require("file")?;
    let path = file.path()?;
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if extension.as_deref() != Some("serialized") && t.get("shape_index").is_some() {
        return Err(t.error_at("shape_index", "shape_index applies only to a .serialized mesh file"));
    }
    let mesh = match extension.as_deref() {
        Some("obj") => file.read_file("mesh", &path, mesh::read_obj)?,
        Some("ply") => file.read_file("mesh", &path, ply::read_ply)?,
        Some("serialized") => {
            let shape_index = t.or("shape_index", 0, |v| v.u32_in(0, u32::MAX))?;
            serialized::read_serialized(&path, shape_index)
                .map_err(|e| file.error(format!("cannot read mesh {}: {e}", path.display())))?
        }
        _ => {
            return Err(
                file.error(format!("unknown mesh file type {}: expected a .obj, .ply or .serialized file", path.display()))
            )
        }
    };
    budget.check(primitives(scene), mesh.indices.len() as u64, "").map_err(|e| file.error(e))?;
    let normals = if smooth { Normals::Smooth } else { Normals::Flat };
    let (triangles, skipped) = mesh::triangles(&mesh, &transform, normals, index).map_err(|e| t.error_here(e))?;
    if triangles.is_empty() {
        return Err(file.error(format!("all {skipped} triangles of mesh {} are degenerate", path.display())));
    }
    scene.triangles.extend(triangles);
    Ok((skipped > 0).then(|| {
        let s = if skipped == 1 { "" } else { "s" };
        file.error(format!("{skipped} degenerate triangle{s} (zero area) skipped in mesh {}", path.display()))
    }))
}

/// The triangles and spheres of `scene` so far.
pub(super) fn primitives(scene: &Scene) -> u64 {
    (scene.triangles.len() + scene.spheres.len()) as u64
}

/// A shape's `scale`, `rotate` and `translate`.
fn read_transform(t: &Table) -> Result<Transform> {
    Ok(Transform::new(
        t.or("scale", Vec3::ONE, Value::scale)?,
        t.or("rotate", Vec3::ZERO, Value::vec3)?,
        t.or("translate", Vec3::ZERO, Value::vec3)?,
    ))
}

/// Reads one light type's keys.
type LightReader = fn(&Table) -> Result<LightKind>;

/// Light types: name, reader, and the keys allowed besides `type`.
const LIGHT_TYPES: &[(&str, LightReader, &[&str])] = &[
    ("point", read_point_light, &["position", "intensity"]),
    ("directional", read_directional_light, &["direction", "irradiance"]),
    ("spot", read_spot_light, &["position", "direction", "intensity", "cutoff_angle", "beam_width"]),
    ("constant", read_constant_light, &["radiance"]),
    ("envmap", read_envmap_light, &["file", "scale", "rotate"]),
];

/// Reads one `[[lights]]` entry.
fn read_light(entry: &Value) -> Result<Light> {
    let t = entry.table()?;
    let read = t.typed("light type", LIGHT_TYPES, &["type"])?;
    Ok(Light { kind: read(&t)?, line: entry.line })
}

fn read_point_light(t: &Table) -> Result<LightKind> {
    Ok(LightKind::Point {
        position: t.req("position", Value::vec3)?,
        intensity: t.req("intensity", |v| v.rgb(Bound::NonNegative))?,
    })
}

/// A spot light (Mitsuba 3's): at `position`, its axis along `direction`, `intensity` on the
/// axis, lighting the cone of half-angle `cutoff_angle` (degrees, default 20), at full
/// intensity within `beam_width` (degrees, default 3/4 of the cutoff) and falling off
/// linearly in the angle beyond.
fn read_spot_light(t: &Table) -> Result<LightKind> {
    let direction = t.req("direction", Value::vec3)?;
    let direction = direction.as_dvec3().normalize_or_zero().as_vec3();
    if direction == Vec3::ZERO {
        return Err(t.error_at("direction", "the direction must not be zero"));
    }
    let cutoff_angle = t.or("cutoff_angle", 20.0, |v| v.f32_in(Bound::Positive))?;
    if cutoff_angle > 180.0 {
        return Err(t.error_at("cutoff_angle", format!("a spot's cutoff is at most 180 degrees, found {cutoff_angle}")));
    }
    Ok(LightKind::Spot {
        position: t.req("position", Value::vec3)?,
        direction,
        intensity: t.req("intensity", |v| v.rgb(Bound::NonNegative))?,
        cutoff_angle,
        beam_width: t.or("beam_width", 0.75 * cutoff_angle, |v| v.f32_in(Bound::NonNegative))?,
    })
}

/// A constant environment: `radiance` from every direction.
fn read_constant_light(t: &Table) -> Result<LightKind> {
    Ok(LightKind::Constant { radiance: t.req("radiance", |v| v.rgb(Bound::NonNegative))? })
}

/// An environment map: `file` (an equirectangular image, EXR or HDR linear, PNG sRGB),
/// `scale` (default 1) and `rotate` (degrees about x, y and z, as a shape's; default none),
/// which turns the map's frame (+y up, see [`super::envmap`]) into the world.
fn read_envmap_light(t: &Table) -> Result<LightKind> {
    let scale = t.or("scale", 1.0, |v| v.f32_in(Bound::NonNegative))?;
    let to_world = super::envmap::rotation_degrees(t.or("rotate", Vec3::ZERO, Value::vec3)?);
    let file = t.require("file")?;
    let path = file.path()?;
    let image = file.read_file("environment map", &path, |p| mesh::read_image(p, false))?;
    let map =
        super::envmap::Envmap::new(path, image.width, image.height, image.texels, scale, to_world).map_err(|e| file.error(e))?;
    Ok(LightKind::Envmap(std::sync::Arc::new(map)))
}

/// A directional light; its direction is normalized.
fn read_directional_light(t: &Table) -> Result<LightKind> {
    // Normalized in f64, so that no finite direction over- or underflows to zero.
    let direction = t.req("direction", Value::vec3)?;
    let direction = direction.as_dvec3().normalize_or_zero().as_vec3();
    if direction == Vec3::ZERO {
        return Err(t.error_at("direction", "the direction must not be zero"));
    }
    Ok(LightKind::Directional { direction, irradiance: t.req("irradiance", |v| v.rgb(Bound::NonNegative))? })
}

/// The scene file: its name and where its lines start.
struct Source<'a> {
    path: &'a Path,
    /// Byte offset of the start of each line.
    line_starts: Vec<usize>,
}

impl<'a> Source<'a> {
    fn new(text: &str, path: &'a Path) -> Self {
        let line_starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
        Source { path, line_starts }
    }

    /// The 1-based line holding byte `offset`.
    fn line(&self, offset: usize) -> usize {
        self.line_starts.partition_point(|&start| start <= offset)
    }

    fn error(&self, line: Option<usize>, key: Option<&str>, message: impl Into<String>) -> SceneError {
        SceneError::new(self.path, line, key, message)
    }
}

/// A TOML table of the scene, with its dotted key (empty for the document) and the line of
/// its header or inline table (none for the document).
struct Table<'a, 'i> {
    source: &'a Source<'a>,
    table: &'a DeTable<'i>,
    key: String,
    line: Option<usize>,
}

impl<'a, 'i> Table<'a, 'i> {
    fn child_key(&self, name: &str) -> String {
        if self.key.is_empty() {
            name.to_owned()
        } else {
            format!("{}.{name}", self.key)
        }
    }

    /// The entries with their names, in file order.
    fn entries(&self) -> Vec<(&'a str, Value<'a, 'i>)> {
        let mut entries: Vec<_> = self.table.iter().collect();
        entries.sort_by_key(|(name, _)| name.span().start);
        entries.into_iter().map(|(name, value)| self.entry(name, value)).collect()
    }

    fn get(&self, name: &str) -> Option<Value<'a, 'i>> {
        let (name, value) = self.table.get_key_value(name)?;
        Some(self.entry(name, value).1)
    }

    /// An entry's name, and its value at the line of its key.
    fn entry(&self, name: &'a Spanned<DeString<'i>>, value: &'a Spanned<DeValue<'i>>) -> (&'a str, Value<'a, 'i>) {
        let value = Value {
            source: self.source,
            value: value.get_ref(),
            key: self.child_key(name.get_ref()),
            line: self.source.line(name.span().start),
        };
        (name.get_ref().as_ref(), value)
    }

    /// An error about the table itself, at its header's line.
    fn error_here(&self, message: impl Into<String>) -> SceneError {
        self.source.error(self.line, Some(&self.key), message)
    }

    /// An error about key `name`: at its line when it is present, else at the header's.
    fn error_at(&self, name: &str, message: impl Into<String>) -> SceneError {
        let line = self.get(name).map(|v| v.line).or(self.line);
        self.source.error(line, Some(&self.child_key(name)), message)
    }

    fn require(&self, name: &str) -> Result<Value<'a, 'i>> {
        self.get(name).ok_or_else(|| self.error_at(name, format!("missing required key `{name}`")))
    }

    /// Reads the required key `name` with `read`.
    fn req<T>(&self, name: &str, read: impl FnOnce(&Value<'a, 'i>) -> Result<T>) -> Result<T> {
        read(&self.require(name)?)
    }

    /// Reads the key `name` with `read` when it is present.
    fn opt<T>(&self, name: &str, read: impl FnOnce(&Value<'a, 'i>) -> Result<T>) -> Result<Option<T>> {
        self.get(name).map(|v| read(&v)).transpose()
    }

    /// Reads the key `name` with `read`, or gives `default` when it is absent.
    fn or<T>(&self, name: &str, default: T, read: impl FnOnce(&Value<'a, 'i>) -> Result<T>) -> Result<T> {
        Ok(self.opt(name, read)?.unwrap_or(default))
    }

    /// Fails on the first key (in file order) that is not in `allowed`.
    fn allow_keys(&self, allowed: &[&str]) -> Result<()> {
        match self.entries().into_iter().find(|(name, _)| !allowed.contains(name)) {
            Some((name, value)) => Err(value.error(format!("unknown key `{name}`; allowed keys: {}", allowed.join(", ")))),
            None => Ok(()),
        }
    }

    /// Reads `type` as one of `types` (`what` names them in errors), then allows only the
    /// `common` keys and that type's own.
    fn typed<T: Copy>(&self, what: &str, types: &[(&str, T, &[&str])], common: &[&str]) -> Result<T> {
        let names: Vec<(&str, usize)> = types.iter().enumerate().map(|(i, t)| (t.0, i)).collect();
        let (_, kind, keys) = types[self.req("type", |v| v.choice(what, &names))?];
        self.allow_keys(&[common, keys].concat())?;
        Ok(kind)
    }
}

/// A TOML value of the scene with its dotted key and line.
struct Value<'a, 'i> {
    source: &'a Source<'a>,
    value: &'a DeValue<'i>,
    key: String,
    line: usize,
}

impl<'a, 'i> Value<'a, 'i> {
    fn error(&self, message: impl Into<String>) -> SceneError {
        self.source.error(Some(self.line), Some(&self.key), message)
    }

    /// A type error: `what` was expected.
    fn expected(&self, what: &str) -> SceneError {
        let found = match self.value {
            DeValue::String(_) => "a string",
            DeValue::Integer(_) => "an integer",
            DeValue::Float(_) => "a float",
            DeValue::Boolean(_) => "a boolean",
            DeValue::Datetime(_) => "a date-time",
            DeValue::Array(_) => "an array",
            DeValue::Table(_) => "a table",
        };
        self.error(format!("expected {what}, found {found}"))
    }

    fn table(&self) -> Result<Table<'a, 'i>> {
        match self.value {
            DeValue::Table(table) => Ok(Table { source: self.source, table, key: self.key.clone(), line: Some(self.line) }),
            _ => Err(self.expected("a table")),
        }
    }

    /// The items of an array, keyed `key[i]`, each at its own line.
    fn elements(&self) -> Result<Vec<Value<'a, 'i>>> {
        let DeValue::Array(items) = self.value else {
            return Err(self.expected("an array"));
        };
        let element = |(i, item): (usize, &'a Spanned<DeValue<'i>>)| Value {
            source: self.source,
            value: item.get_ref(),
            key: format!("{}[{i}]", self.key),
            line: self.source.line(item.span().start),
        };
        Ok(items.iter().enumerate().map(element).collect())
    }

    fn string(&self) -> Result<&'a str> {
        self.value.as_str().ok_or_else(|| self.expected("a string"))
    }

    fn bool(&self) -> Result<bool> {
        self.value.as_bool().ok_or_else(|| self.expected("a boolean (true or false)"))
    }

    /// A setting's name, from its [`Named`] table.
    fn named<T: super::Named>(&self) -> Result<T> {
        T::from_name(self.string()?).map_err(|e| self.error(e))
    }

    /// A string that must name one of `options`; `what` names it in errors.
    fn choice<T: Copy>(&self, what: &str, options: &[(&str, T)]) -> Result<T> {
        let name = self.string()?;
        match options.iter().find(|(option, _)| *option == name) {
            Some(&(_, value)) => Ok(value),
            None => {
                let names: Vec<&str> = options.iter().map(|(option, _)| *option).collect();
                Err(self.error(format!("unknown {what} `{name}`; expected one of: {}", names.join(", "))))
            }
        }
    }

    /// An integer in `min..=max`.
    fn u32_in(&self, min: u32, max: u32) -> Result<u32> {
        let integer = match self.value {
            DeValue::Integer(integer) => integer,
            DeValue::Float(float) => return Err(self.error(format!("expected an integer, found the float {float}"))),
            _ => return Err(self.expected("an integer")),
        };
        if !has_digits(integer) {
            return Err(self.error(format!("`{integer}` is not a valid integer: it has no digits")));
        }
        parse_integer(integer)
            .and_then(|n| u32::try_from(n).ok())
            .filter(|n| (min..=max).contains(n))
            .ok_or_else(|| self.error(format!("must be between {min} and {max}, found {integer}")))
    }

    /// A count of at least 1.
    fn count(&self) -> Result<u32> {
        self.u32_in(1, u32::MAX)
    }

    /// A number, integer or float, unchecked.
    fn number(&self) -> Result<f64> {
        let number = match self.value {
            DeValue::Integer(integer) if !has_digits(integer) => {
                return Err(self.error(format!("`{integer}` is not a valid integer: it has no digits")))
            }
            DeValue::Integer(integer) => parse_integer(integer).map(|n| n as f64),
            DeValue::Float(float) => float.as_str().parse().ok(),
            _ => return Err(self.expected("a number")),
        };
        number.ok_or_else(|| match self.value {
            DeValue::Integer(integer) => {
                self.error(format!("{integer} is beyond the range of 64-bit integers; write it as a float"))
            }
            _ => self.error(format!("`{}` is not a valid number", self.literal())),
        })
    }

    /// A number as written in the file, for messages.
    fn literal(&self) -> String {
        match self.value {
            DeValue::Integer(integer) => integer.to_string(),
            DeValue::Float(float) => float.to_string(),
            other => other.type_str().to_owned(),
        }
    }

    fn f64_in(&self, bound: Bound) -> Result<f64> {
        let x = self.number()?;
        if !x.is_finite() {
            Err(self.error(format!("must be a finite number, found {}", self.literal())))
        } else if !bound.contains(x) {
            Err(self.error(format!("must be {bound}, found {}", self.literal())))
        } else {
            Ok(x)
        }
    }

    fn f32_in(&self, bound: Bound) -> Result<f32> {
        let x = self.f64_in(bound)? as f32;
        // Rounding may overflow, or underflow to a zero that `bound` rejects.
        if x.is_infinite() || !bound.contains(x.into()) {
            let message = format!("{} is out of the range of 32-bit floats", self.literal());
            return Err(self.error(message));
        }
        Ok(x)
    }

    /// An array of `N` numbers, each finite and within `bound`.
    fn floats<const N: usize>(&self, bound: Bound) -> Result<[f32; N]> {
        let what = format!("an array of {N} numbers");
        let items = self.elements().map_err(|_| self.expected(&what))?;
        if items.len() != N {
            return Err(self.error(format!("expected {what}, found {} items", items.len())));
        }
        let mut out = [0.0; N];
        for (x, item) in out.iter_mut().zip(items) {
            // Errors name the array's key, at the item's line.
            *x = Value { key: self.key.clone(), ..item }.f32_in(bound)?;
        }
        Ok(out)
    }

    fn vec2_in(&self, bound: Bound) -> Result<Vec2> {
        self.floats(bound).map(Vec2::from_array)
    }

    fn vec3_in(&self, bound: Bound) -> Result<Vec3> {
        self.floats(bound).map(Vec3::from_array)
    }

    fn vec3(&self) -> Result<Vec3> {
        self.vec3_in(Bound::Any)
    }

    /// A colour (every colour-valued key): one number (grey) or `[r, g, b]`, each within
    /// `bound`.
    fn rgb(&self, bound: Bound) -> Result<Vec3> {
        match self.value {
            DeValue::Array(_) => self.vec3_in(bound),
            DeValue::Integer(_) | DeValue::Float(_) => self.f32_in(bound).map(Vec3::splat),
            _ => Err(self.expected("one number or an array of 3 numbers")),
        }
    }

    /// The index of the medium this value names (`[media.<name>]`).
    fn medium(&self, media: &[Medium]) -> Result<u32> {
        let name = self.string()?;
        if let Some(index) = media.iter().position(|m| m.name == name) {
            return Ok(index as u32);
        }
        let names: Vec<&str> = media.iter().map(|m| m.name.as_str()).collect();
        let defined = if names.is_empty() {
            "no media are defined (a [media.<name>] table defines one)".to_owned()
        } else {
            format!("defined media: {}", names.join(", "))
        };
        Err(self.error(format!("unknown medium `{name}`; {defined}")))
    }

    /// A scale: one number or three, each nonzero.
    fn scale(&self) -> Result<Vec3> {
        match self.value {
            DeValue::Array(_) => self.vec3_in(Bound::NonZero),
            _ => self.f32_in(Bound::NonZero).map(Vec3::splat),
        }
    }

    /// A path relative to the scene file's directory.
    fn path(&self) -> Result<PathBuf> {
        let directory = self.source.path.parent().unwrap_or(Path::new(""));
        Ok(directory.join(self.string()?))
    }

    /// Reads the `what` file at `path` (which this value names) with `read`.
    fn read_file<T>(&self, what: &str, path: &Path, read: fn(&Path) -> std::result::Result<T, String>) -> Result<T> {
        read(path).map_err(|e| self.error(format!("cannot read {what} {}: {e}", path.display())))
    }

    /// The index of the material this value names.
    fn material(&self, materials: &[Material]) -> Result<u32> {
        let name = self.string()?;
        if let Some(index) = materials.iter().position(|m| m.name == name) {
            return Ok(index as u32);
        }
        let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
        let defined = if names.is_empty() {
            "no materials are defined".to_owned()
        } else {
            format!("defined materials: {}", names.join(", "))
        };
        Err(self.error(format!("unknown material `{name}`; {defined}")))
    }
}

/// A TOML integer (any radix), when it fits in an `i64`.
fn parse_integer(integer: &DeInteger) -> Option<i64> {
    i64::from_str_radix(integer.as_str(), integer.radix()).ok()
}

/// Whether a TOML integer has digits at all (`0x` alone has none); one that has them and
/// still does not parse is beyond the 64-bit range.
fn has_digits(integer: &DeInteger) -> bool {
    integer.as_str().trim_start_matches(['+', '-']).chars().any(|c| c.is_digit(integer.radix()))
}

/// A range that a number must lie in.
#[derive(Clone, Copy, Debug)]
pub(super) enum Bound {
    Any,
    Positive,
    NonNegative,
    NonZero,
    /// Strictly between the two.
    Open(f64, f64),
    /// Between the two, inclusive.
    Closed(f64, f64),
}

impl Bound {
    pub(super) fn contains(self, x: f64) -> bool {
        match self {
            Bound::Any => true,
            Bound::Positive => x > 0.0,
            Bound::NonNegative => x >= 0.0,
            Bound::NonZero => x != 0.0,
            Bound::Open(low, high) => low < x && x < high,
            Bound::Closed(low, high) => low <= x && x <= high,
        }
    }
}

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Bound::Any => write!(f, "a number"),
            Bound::Positive => write!(f, "greater than 0"),
            Bound::NonNegative => write!(f, "at least 0"),
            Bound::NonZero => write!(f, "nonzero"),
            Bound::Open(low, high) => write!(f, "greater than {low} and less than {high}"),
            Bound::Closed(low, high) => write!(f, "between {low} and {high}"),
        }
    }
}
