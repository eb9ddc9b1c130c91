//! The scene file reader. The TOML document is walked by hand so that every key and value
//! keeps its line for error messages: each table is checked for unknown keys, each value for
//! its type and range, and each shape is turned into world-space primitives.

use super::mesh::{self, Normals, Transform};
use super::param::{Bound, UNIT};
use super::toml_table::{Source, Table, Value};
use super::{
    emitter, material, medium, Camera, CropWindow, Medium, Phase, PixelFilter, RadiusRule, RadiusSchedule, RenderSettings, Scene,
    SceneError, Shape, ShapeKind, Sphere, Triangle,
};
use super::{ply, serialized};
use glam::{Vec2, Vec3};
use std::path::Path;
use toml::de::DeTable;

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
        table.entries().iter().map(|(name, m)| material::read_toml(name, m, &mut textures)).collect()
    })?;
    let lights = root.or("lights", Vec::new(), |v| {
        let mut lights = Vec::new();
        for entry in v.elements()? {
            let light = emitter::read_toml(&entry)?;
            if let Some(why) = emitter::second_environment(&lights, &light.kind) {
                return Err(entry.error(why));
            }
            lights.push(light);
        }
        Ok(lights)
    })?;
    let mut scene = Scene::new(path.to_path_buf(), render, camera, materials, textures, lights, media);
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
        "light_paths",
        "connect_share",
        "merge_share",
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
        light_paths: read_light_paths(t)?,
        connect_share: t.opt("connect_share", |v| v.f32_in(Bound::Closed(0.0, 1.0)))?,
        merge_share: t.opt("merge_share", |v| v.f32_in(Bound::Closed(0.0, 1.0)))?,
        radius_schedule: t.or("radius_schedule", d.radius_schedule, Value::named)?,
        radius_schedule_given: t.get("radius_schedule").is_some(),
        radius_rule: read_radius_rule(t)?,
        filter: read_filter(t)?,
        sampler: t.or("sampler", d.sampler, Value::named)?,
        work_given: super::WorkGiven { photons: t.get("photons").is_some(), spp: t.get("spp").is_some() },
        strategies: d.strategies,
        photon_mapping: d.photon_mapping,
        texture_palettes: d.texture_palettes,
    })
}

/// `light_paths`; 0 (vcm without light subpaths) leaves nothing to connect or merge with.
fn read_light_paths(t: &Table) -> Result<Option<u32>> {
    let paths = t.opt("light_paths", |v| v.u32_in(0, u32::MAX))?;
    if paths == Some(0) {
        for key in ["connect_share", "merge_share"] {
            if let Some(share) = t.opt(key, |v| v.f32_in(Bound::Closed(0.0, 1.0)))?.filter(|&s| s > 0.0) {
                return Err(t.error_at(
                    "light_paths",
                    format!("light_paths = 0 traces no light subpath to connect or merge with, but {key} = {share}"),
                ));
            }
        }
    }
    Ok(paths)
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
const SHAPE_KEYS: &[&str] = &["type", "material", "emission", "emission_two_sided", "velocity", "interior", "exterior"];

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
        material: t.req("material", |v| material::index(&scene.materials, v.string()?).map_err(|e| v.error(e)))?,
        emission: emitter::read_toml_emission(&t)?,
        emission_two_sided: t.or("emission_two_sided", false, Value::bool)?,
        velocity: t.opt("velocity", Value::vec3)?,
        line: entry.line,
        velocity_line: t.get("velocity").map(|v| v.line),
        sphere_frame: t.opt("uv_frame", read_uv_frame)?,
        interior: t.opt("interior", |v| v.medium(&scene.media))?,
        exterior: t.opt("exterior", |v| v.medium(&scene.media))?,
    };
    if shape.emission_two_sided && shape.emission.is_none() {
        return Err(t.error_at("emission_two_sided", "a shape without an emission has no side to emit from: give `emission`"));
    }
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
