//! The camera and how the image is made: Mitsuba 3's sensors, film, reconstruction filters and
//! samplers (its plugin reference); the parameters of
//! Mitsuba 0.5/0.6's that Mitsuba 3 lacks are read as said here (mod.rs).
//!
//! - `perspective`: `fov` with `fov_axis` (`x`, `y`, `diagonal`, `smaller`, `larger`; default
//!   `x`) or `focal_length` (35 mm equivalent, a diagonal field of view of
//!   2 atan(43.27 mm / 2 f)); `to_world` with the camera looking along its +z, +y up and +x
//!   to the image's left. `thinlens`: also `aperture_radius` and `focus_distance` (in a 0.x
//!   scene by default `far_clip`, as Mitsuba 0.6 has it).
//! - `hdrfilm`/`ldrfilm` (and 0.6's `tiledhdrfilm`, an hdrfilm written in tiles): `width`
//!   (768), `height` (576); a crop window `crop_offset_x`, `crop_offset_y` (0), `crop_width`,
//!   `crop_height` (the rest of the film), which is then the image
//!   ([`crate::scene::Camera::crop`]); an `rfilter`: `box`, `tent` (`radius` 1) or `gaussian`
//!   (`stddev` 0.5, the default). What only the output file's encoding depends on (0.6's
//!   `channel_names` and `attach_log` among it) is passed over; an ldrfilm's tone mapping is
//!   warned. 0.6's `box` takes a `radius` (0.5): any other is refused.
//! - Any sampler: `sample_count` (4) becomes the number of passes; `seed` our seed.
//!   `independent` is our independent sampler; the low-discrepancy and stratified ones
//!   (`ldsampler`, `multijitter`, `stratified`, `orthogonal`, and Mitsuba 0.6's `sobol`,
//!   `halton`, `hammersley`) our Sobol sampler; any other kind, or none, our default.
//!   How a kind places its points (`scramble`, `dimension`, ...) changes only the noise.

use super::props::Props;
use super::xml::Node;
use super::Result;
use crate::scene::{Camera, PixelFilter};
use glam::{Mat4, Vec3};

/// What the sensor element says.
pub(super) struct SensorSettings {
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    pub filter: PixelFilter,
    /// The sampler's `sample_count` (Mitsuba's default 4).
    pub sample_count: u32,
    /// The sampler's `seed`.
    pub seed: u32,
    /// Ours for the sampler's kind.
    pub sampler: crate::sampler::Sampler,
}

/// Reads a `<sensor>`; `medium` gives the index of the medium a nested `<medium>` or `<ref>`
/// names (the medium the camera sits in).
pub(super) fn sensor<'a>(node: &'a Node, medium: &mut dyn FnMut(&'a Node) -> Result<u32>) -> Result<SensorSettings> {
    node.allow_attrs(&["type", "id", "name"])?;
    let kind = node.req_attr("type")?;
    if kind != "perspective" && kind != "thinlens" {
        return Err(node.error(Some("type"), format!("the `{kind}` sensor is not modelled by sppm-gpu: perspective or thinlens")));
    }
    let p = Props::new(node)?;
    let mut width = 768;
    let mut height = 576;
    let mut filter = PixelFilter::Gaussian { stddev: 0.5 };
    let mut crop = None;
    let mut sample_count = 4;
    let mut seed = 0;
    let mut kind_of_sampler = crate::sampler::Sampler::DEFAULT;
    let (mut films, mut samplers, mut media) = (0, 0, 0);
    let mut camera_medium = None;
    for object in p.all_objects() {
        match object.tag.as_str() {
            "film" => {
                films += 1;
                (width, height, filter, crop) = film(object)?;
            }
            "sampler" => {
                samplers += 1;
                (sample_count, seed, kind_of_sampler) = sampler(object)?;
            }
            // The medium around the camera (Mitsuba's endpoint takes one, by any name).
            "medium" | "ref" => {
                media += 1;
                if media > 1 {
                    return Err(object.error(None, "a second medium in the sensor: a camera sits in one medium"));
                }
                camera_medium = Some(medium(object)?);
            }
            _ => return Err(object.error(None, format!("{} inside a sensor", object.describe()))),
        }
        if films > 1 || samplers > 1 {
            return Err(object.error(None, format!("a second {} in the sensor", object.describe())));
        }
    }
    let aspect = width as f32 / height as f32;
    let fov = vertical_fov(&p, aspect)?;
    let to_world = p.transform("to_world")?.unwrap_or(Mat4::IDENTITY);
    let position = to_world.transform_point3(Vec3::ZERO);
    let forward = to_world.transform_vector3(Vec3::Z).normalize_or_zero();
    let up = to_world.transform_vector3(Vec3::Y).normalize_or_zero();
    let left = to_world.transform_vector3(Vec3::X).normalize_or_zero();
    let at = p.get("to_world").unwrap_or(node);
    if forward == Vec3::ZERO || up == Vec3::ZERO || forward.dot(up).abs() > 1e-3 || left.dot(forward).abs() > 1e-3 {
        return Err(at.error(Some("to_world"), "the sensor's to_world shears or collapses its axes"));
    }
    // Mitsuba's image runs from camera +x (left) to -x; a transform that mirrors x (a scale
    // of -1, common in exported scenes) mirrors the image, which our camera cannot.
    if left.dot(up.cross(forward)) < 0.0 {
        return Err(
            at.error(Some("to_world"), "the sensor's to_world mirrors the image (a negative scale): not modelled by sppm-gpu")
        );
    }
    let mut camera = Camera {
        position,
        look_at: position + forward,
        up,
        fov,
        aperture_radius: 0.0,
        focus_distance: 1.0,
        aperture_line: None,
        crop: None,
        medium: camera_medium,
    };
    // The image is the crop window: its pixels are the film's (fov and aspect stay the film's).
    if let Some([x, y, w, h]) = crop {
        let film = glam::Vec2::new(width as f32, height as f32);
        let (min, max) = (glam::Vec2::new(x as f32, y as f32), glam::Vec2::new((x + w) as f32, (y + h) as f32));
        camera.crop = Some(crate::scene::CropWindow { min: min / film, max: max / film });
        (width, height) = (w, h);
    }
    if kind == "thinlens" {
        let need = |name: &str| -> Result<f32> {
            p.float(name)?.ok_or_else(|| node.error(Some(name), format!("a thinlens sensor needs `{name}`")))
        };
        camera.aperture_radius = need("aperture_radius")?;
        camera.focus_distance = match node.legacy() {
            // Mitsuba 0.6 focuses at the far clipping plane unless told.
            true if !p.has("focus_distance") => p.float_or("far_clip", 1e4)?,
            _ => need("focus_distance")?,
        };
        camera.aperture_line = Some(node.line);
    } else {
        // A pinhole has no focal plane: Mitsuba's perspective camera takes and ignores it.
        p.float("focus_distance")?;
    }
    for name in ["near_clip", "far_clip"] {
        if let Some(v) = p.float(name)? {
            let default = if name == "near_clip" { 0.01 } else { 10000.0 };
            if v != default {
                p.get(name).unwrap().warn(Some(name), format!("{name} {v} is not applied (sppm-gpu has no clipping planes)"));
            }
        }
    }
    if p.float("shutter_open")?.unwrap_or(0.0) != 0.0 || p.float("shutter_close")?.unwrap_or(0.0) != 0.0 {
        return Err(node.error(Some("shutter_open"), "a shutter interval (motion blur) from Mitsuba is not modelled"));
    }
    for name in ["principal_point_offset_x", "principal_point_offset_y"] {
        if p.float(name)?.unwrap_or(0.0) != 0.0 {
            return Err(node.error(Some(name), format!("{name} (an off-centre image) is not modelled by sppm-gpu")));
        }
    }
    p.finish()?;
    crate::scene::validate_camera(&camera).map_err(|e| node.error(None, e))?;
    Ok(SensorSettings { camera, width, height, filter, sample_count, seed, sampler: kind_of_sampler })
}

/// The vertical field of view in degrees, from `fov` and `fov_axis` or `focal_length`.
fn vertical_fov(p: &Props, aspect: f32) -> Result<f32> {
    let tan_half = |deg: f32| (deg.to_radians() * 0.5).tan();
    let (fov, axis) = match (p.float("fov")?, p.string("focal_length")?) {
        (Some(_), Some(_)) => return Err(p.node.error(Some("fov"), "give `fov` or `focal_length`, not both")),
        (Some(fov), None) => {
            if !(fov > 0.0 && fov < 180.0) {
                return Err(p.get("fov").unwrap().error(Some("fov"), format!("fov {fov} is outside (0, 180)")));
            }
            (fov, p.string("fov_axis")?.unwrap_or("x"))
        }
        (None, focal) => {
            let text = focal.unwrap_or("50mm");
            let at = p.get("focal_length").unwrap_or(p.node);
            let mm: f32 =
                text.trim().trim_end_matches("mm").parse().ok().filter(|f: &f32| f.is_finite() && *f > 0.0).ok_or_else(|| {
                    at.error(Some("focal_length"), format!("\"{text}\" is not a focal length such as \"50mm\""))
                })?;
            if p.has("fov_axis") {
                p.string("fov_axis")?;
            }
            // The 35 mm frame's diagonal, 43.27 mm, over the image's diagonal.
            let diagonal = 2.0 * (36.0f32.hypot(24.0) / (2.0 * mm)).atan().to_degrees();
            (diagonal, "diagonal")
        }
    };
    let t = tan_half(fov);
    let tan_y = match axis {
        "x" => t / aspect,
        "y" => t,
        "diagonal" => t / (1.0 + aspect * aspect).sqrt(),
        "smaller" if aspect < 1.0 => t / aspect,
        "smaller" => t,
        "larger" if aspect > 1.0 => t / aspect,
        "larger" => t,
        other => {
            let at = p.get("fov_axis").unwrap_or(p.node);
            return Err(at.error(Some("fov_axis"), format!("\"{other}\" is not a fov_axis (x, y, diagonal, smaller, larger)")));
        }
    };
    Ok(2.0 * tan_y.atan().to_degrees())
}

/// A film's size and pixel filter.
/// A `<film>`: its width, height, pixel filter, and crop window (x, y, width, height) unless
/// that is the whole film.
fn film(node: &Node) -> Result<(u32, u32, PixelFilter, Option<[u32; 4]>)> {
    node.allow_attrs(&["type", "id", "name"])?;
    let kind = node.req_attr("type")?;
    if kind != "hdrfilm" && kind != "ldrfilm" && kind != "tiledhdrfilm" {
        return Err(node.error(
            Some("type"),
            format!("the `{kind}` film is not read by sppm-gpu: hdrfilm, ldrfilm (or 0.6's tiledhdrfilm)"),
        ));
    }
    let p = Props::new(node)?;
    let size = |name: &str, default: i64| -> Result<u32> {
        let v = p.integer(name)?.unwrap_or(default);
        if !(1..=crate::scene::load::MAX_RESOLUTION as i64).contains(&v) {
            let at = p.get(name).unwrap_or(node);
            return Err(at.error(Some(name), format!("{name} {v} is outside 1..={}", crate::scene::load::MAX_RESOLUTION)));
        }
        Ok(v as u32)
    };
    let width = size("width", 768)?;
    let height = size("height", 576)?;
    // The crop window (Mitsuba's defaults: the whole film), x, y, width, height in pixels.
    let crop_x = p.integer("crop_offset_x")?.unwrap_or(0);
    let crop_y = p.integer("crop_offset_y")?.unwrap_or(0);
    let crop_w = p.integer("crop_width")?.unwrap_or(width as i64 - crop_x);
    let crop_h = p.integer("crop_height")?.unwrap_or(height as i64 - crop_y);
    for (name, offset, size, whole) in
        [("crop_width", crop_x, crop_w, width as i64), ("crop_height", crop_y, crop_h, height as i64)]
    {
        if offset < 0 || size < 1 || offset + size > whole {
            let at = p.get(name).or(p.get(if name == "crop_width" { "crop_offset_x" } else { "crop_offset_y" })).unwrap_or(node);
            return Err(at.error(
                Some(name),
                format!("a crop window from {offset} of size {size} does not lie within the film's {whole} pixels"),
            ));
        }
    }
    let whole = (crop_x, crop_y, crop_w, crop_h) == (0, 0, width as i64, height as i64);
    let crop = (!whole).then_some([crop_x as u32, crop_y as u32, crop_w as u32, crop_h as u32]);
    // What only the output file's encoding depends on: read and passed over (`attach_log`:
    // Mitsuba 0.6 wrote its log into the EXR; `channel_names`: it named the EXR's channels).
    for name in [
        "file_format",
        "pixel_format",
        "component_format",
        "banner",
        "high_quality_edges",
        "sample_border",
        "compensate",
        "attach_log",
        "channel_names",
    ] {
        p.get(name);
    }
    // An LDR film's tone mapping: our PNG output applies its own (sRGB, clamped).
    for name in ["tonemap_method", "gamma", "exposure", "key", "burn"] {
        if let Some(at) = p.get(name) {
            at.warn(Some(name), format!("ldrfilm's {name} is not applied: sppm-gpu writes linear EXR or sRGB PNG"));
        }
    }
    let mut filter = PixelFilter::Gaussian { stddev: 0.5 };
    let filters = p.all_objects();
    if filters.len() > 1 {
        return Err(filters[1].error(None, "a second <rfilter> in the film"));
    }
    for f in filters {
        if f.tag != "rfilter" {
            return Err(f.error(None, format!("{} inside a film", f.describe())));
        }
        filter = rfilter(f)?;
    }
    p.finish()?;
    Ok((width, height, filter, crop))
}

/// A reconstruction filter.
fn rfilter(node: &Node) -> Result<PixelFilter> {
    node.allow_attrs(&["type", "id", "name"])?;
    let p = Props::new(node)?;
    let filter = match node.req_attr("type")? {
        "box" => {
            // Mitsuba 0.6's box takes a radius, 0.5 by default as Mitsuba 3's fixed one.
            if node.legacy() && p.float_or("radius", 0.5)? != 0.5 {
                let at = p.get("radius").unwrap();
                return Err(
                    at.error(Some("radius"), "a box filter of a radius other than 0.5 pixels is not modelled by sppm-gpu")
                );
            }
            PixelFilter::Box
        }
        "tent" => PixelFilter::Tent { radius: positive(&p, "radius", 1.0)? },
        "gaussian" => PixelFilter::Gaussian { stddev: positive(&p, "stddev", 0.5)? },
        other => {
            return Err(
                node.error(Some("type"), format!("the `{other}` filter is not modelled by sppm-gpu: box, tent or gaussian"))
            )
        }
    };
    p.finish()?;
    Ok(filter)
}

/// A positive `<float>` parameter (at most 16 pixels: filter sizes).
fn positive(p: &Props, name: &str, default: f32) -> Result<f32> {
    let v = p.float_or(name, default)?;
    if !(v > 0.0 && v <= 16.0) {
        return Err(p.get(name).unwrap_or(p.node).error(Some(name), format!("{name} {v} is outside (0, 16] pixels")));
    }
    Ok(v)
}

/// A sampler's sample count, seed and our sampler for its kind, which changes only the noise.
fn sampler(node: &Node) -> Result<(u32, u32, crate::sampler::Sampler)> {
    use crate::sampler::Sampler;
    node.allow_attrs(&["type", "id", "name"])?;
    let kind = match node.req_attr("type")? {
        "independent" => Sampler::Independent,
        "ldsampler" | "multijitter" | "stratified" | "orthogonal" | "sobol" | "halton" | "hammersley" => Sampler::Sobol,
        _ => Sampler::DEFAULT,
    };
    let p = Props::new(node)?;
    let count = p.integer("sample_count")?.unwrap_or(4);
    if !(1..=u32::MAX as i64).contains(&count) {
        return Err(p.get("sample_count").unwrap().error(Some("sample_count"), format!("sample_count {count} is not positive")));
    }
    let seed = p.integer("seed")?.unwrap_or(0);
    let seed =
        u32::try_from(seed).map_err(|_| p.get("seed").unwrap().error(Some("seed"), format!("seed {seed} is outside 0..2^32")))?;
    // How the kinds place their points: noise, not the image's expectation.
    for name in ["jitter", "scramble", "dimension", "strength", "randomize"] {
        p.get(name);
    }
    p.finish()?;
    Ok((count as u32, seed, kind))
}
