//! The camera and how the image is made: pbrt-v4's `Camera`, `Film`, `PixelFilter`,
//! `Sampler` and `Integrator`, as our camera and render settings.
//!
//! - `Camera "perspective"`: `fov` (90 degrees) spans the image's shorter axis, as in pbrt;
//!   `lensradius` (0) and `focaldistance` (1e6) make a thin lens; `screenwindow` and
//!   `frameaspectratio` other than the film's are refused; `shutteropen`/`shutterclose` (0, 1)
//!   set how far a moving shape moves while it is open (shape.rs). Other cameras are refused.
//! - `Film "rgb"` (and `gbuffer`, `spectral`, read as rgb): `xresolution` (1280),
//!   `yresolution` (720), `cropwindow` (the image is the window); `filename` is not applied
//!   (warned: `--output` names the image); `iso` (100), `whitebalance` (0) and `sensor`
//!   (`cie1931`) other than pbrt's defaults are refused; `maxcomponentvalue` is warned.
//! - `PixelFilter`: `gaussian` (pbrt-v4's default: `sigma` 0.5) as ours (its radius 4 sigma
//!   where pbrt's `xradius` is 1.5), `box` (radius 0.5), `triangle` (`xradius` 2) as our tent;
//!   `mitchell` and `sinc` are rendered with the Gaussian, warned.
//! - `Sampler`: `pixelsamples` (16; `stratified`: `xsamples` x `ysamples`, 4 x 4) is our
//!   passes, `seed` our seed; `independent` is ours, every other kind our Sobol sampler.
//! - `Integrator` (default `volpath`): `path`, `volpath` as pt-nee; `bdpt` as bpt; `mlt`, `pssmlt`
//!   (which converge to the same image) as pt-nee, warned; `lightpath` as lt; `randomwalk`
//!   and `simplepath` without light samples as pt; `sppm` as SPPM: `photonsperiteration`
//!   (-1: one a pixel), `radius` (when given; else our automatic choice, as the radius
//!   changes only how the estimate converges), the sampler's `pixelsamples` its passes (or
//!   pbrt-v3's `iterations`). `maxdepth` (5) is ours: pbrt's depth 1 is direct light, as our
//!   `max_depth` 1. `ambientocclusion` and `aov` are refused.

use super::params::Params;
use super::{Reader, Result};
use crate::scene::{Camera, CropWindow, Method, PixelFilter, RenderSettings};
use glam::{Vec2, Vec3};

/// Our camera and render settings from the options read before `WorldBegin`.
pub(super) fn settings(r: &mut Reader) -> Result<(Camera, RenderSettings)> {
    let empty = |what: &str| Params::parse(&[], &mut 0, &Default::default(), &r.dir, what.into(), 0);
    let take = |o: &Option<(String, Params)>, default: &str, what: &str| -> Result<(String, Params)> {
        Ok(match o {
            Some((k, p)) => (k.clone(), p.clone()),
            None => (default.to_owned(), empty(&format!("{what} \"{default}\""))?),
        })
    };
    let (film_kind, film) = take(&r.options.film, "rgb", "Film")?;
    let (filter_kind, filter) = take(&r.options.filter, "gaussian", "PixelFilter")?;
    let (sampler_kind, sampler) = take(&r.options.sampler, "zsobol", "Sampler")?;
    let (integrator_kind, integrator) = take(&r.options.integrator, "volpath", "Integrator")?;
    let mut render = RenderSettings::default();

    // Film.
    if !matches!(film_kind.as_str(), "rgb" | "gbuffer" | "spectral") {
        return Err(film.directive_error(format!("the \"{film_kind}\" film is not read by sppm-gpu: rgb, gbuffer, spectral")));
    }
    let resolution = |name: &str, default: i64| -> Result<u32> {
        let v = film.int_or(name, default)?;
        let max = crate::scene::load::MAX_RESOLUTION as i64;
        if !(1..=max).contains(&v) {
            return Err(film.error(name, format!("{name} {v} is outside 1..={max}")));
        }
        Ok(v as u32)
    };
    let (xres, yres) = (resolution("xresolution", 1280)?, resolution("yresolution", 720)?);
    if let Some(name) = film.string("filename")? {
        let message = format!("filename \"{name}\" is not applied: sppm-gpu names its images after the scene (or --output)");
        r.warnings.push(film.error("filename", message));
    }
    let mut crop = None;
    let (mut width, mut height) = (xres, yres);
    if let Some(w) = film.numbers("cropwindow", "float")? {
        let [x0, x1, y0, y1] = w[..] else {
            return Err(film.error("cropwindow", "cropwindow is four numbers: x0 x1 y0 y1"));
        };
        // pbrt-v4's pixel bounds (FilmBaseParameters): each pair in either order, clamped to
        // [0, 1], times the resolution and rounded up, in single precision (0.55 of 800 is
        // 440 there, 441 in double precision).
        let px = |f: f64, n: u32| ((f as f32).clamp(0.0, 1.0) * n as f32).ceil() as u32;
        let (a, b, c, d) = (px(x0.min(x1), xres), px(x0.max(x1), xres), px(y0.min(y1), yres), px(y0.max(y1), yres));
        if b <= a || d <= c {
            return Err(film.error("cropwindow", "the crop window holds no pixel"));
        }
        if (a, b, c, d) != (0, xres, 0, yres) {
            let film_size = Vec2::new(xres as f32, yres as f32);
            crop = Some(CropWindow {
                min: Vec2::new(a as f32, c as f32) / film_size,
                max: Vec2::new(b as f32, d as f32) / film_size,
            });
            (width, height) = (b - a, d - c);
        }
    }
    if film.has("pixelbounds") {
        return Err(film.error("pixelbounds", "pixelbounds is not modelled by sppm-gpu: give a cropwindow"));
    }
    if film.float_or("iso", 100.0)? != 100.0 {
        return Err(film.error("iso", "an iso other than 100 (a scale of the image) is not modelled by sppm-gpu"));
    }
    if film.float_or("whitebalance", 0.0)? != 0.0 {
        return Err(film.error("whitebalance", "white balancing is not modelled by sppm-gpu"));
    }
    if let Some(s) = film.string("sensor")?.filter(|s| *s != "cie1931") {
        return Err(film.error("sensor", format!("the sensor \"{s}\" is not modelled by sppm-gpu: cie1931")));
    }
    if let Some(v) = film.float("maxcomponentvalue")?.filter(|v| v.is_finite()) {
        let message = format!("maxcomponentvalue {v} is not applied: sppm-gpu does not clamp samples");
        r.warnings.push(film.error("maxcomponentvalue", message));
    }
    film.pass_over(&["savefp16", "writefp16", "diagonal", "coordinatesystem", "nbuckets", "lambdamin", "lambdamax"]);
    film.finish()?;
    render.width = width;
    render.height = height;

    // Camera.
    let (camera_kind, camera, world_from_camera) = match &r.options.camera {
        Some((k, p, m)) => (k.clone(), p.clone(), *m),
        None => ("perspective".to_owned(), empty("Camera \"perspective\"")?, glam::Mat4::IDENTITY),
    };
    if camera_kind != "perspective" {
        return Err(camera.directive_error(format!("the \"{camera_kind}\" camera is not modelled by sppm-gpu: perspective")));
    }
    let fov = camera.float_or("fov", 90.0)?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(camera.error("fov", format!("fov {fov} is outside (0, 180)")));
    }
    // pbrt's fov spans the shorter axis; ours is vertical.
    let aspect = xres as f32 / yres as f32;
    let fov_y = if aspect >= 1.0 { fov } else { 2.0 * ((fov.to_radians() * 0.5).tan() / aspect).atan().to_degrees() };
    if let Some(v) = camera.numbers("screenwindow", "float")? {
        let default = if aspect > 1.0 { [-aspect, aspect, -1.0, 1.0] } else { [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect] };
        if v.len() != 4 || v.iter().zip(default).any(|(a, b)| (*a as f32 - b).abs() > 1e-4) {
            return Err(camera.error("screenwindow", "a screenwindow other than the film's is not modelled by sppm-gpu"));
        }
    }
    if let Some(f) = camera.float("frameaspectratio")? {
        if (f - aspect).abs() > 1e-4 {
            return Err(camera.error("frameaspectratio", "a frameaspectratio other than the film's is not modelled by sppm-gpu"));
        }
    }
    let lens = camera.float_or("lensradius", 0.0)?;
    let focus = camera.float_or("focaldistance", 1e6)?;
    if !(lens >= 0.0 && focus > 0.0) {
        return Err(camera.error("lensradius", "lensradius must be >= 0 and focaldistance > 0"));
    }
    camera.pass_over(&["shutteropen", "shutterclose"]);
    camera.finish()?;
    let position = world_from_camera.transform_point3(Vec3::ZERO);
    let forward = world_from_camera.transform_vector3(Vec3::Z).normalize_or_zero();
    let up = world_from_camera.transform_vector3(Vec3::Y).normalize_or_zero();
    if forward == Vec3::ZERO || up == Vec3::ZERO || forward.dot(up).abs() > 1e-3 {
        return Err(camera.directive_error("the camera's transform shears or collapses its axes"));
    }
    let camera = Camera {
        position,
        look_at: position + forward,
        up,
        fov: fov_y,
        aperture_radius: lens,
        focus_distance: if lens > 0.0 { focus } else { 1.0 },
        aperture_line: (lens > 0.0).then_some(camera.line),
        crop,
        medium: None,
    };
    crate::scene::validate_camera(&camera).map_err(|e| {
        r.options.camera.as_ref().map_or_else(|| film.directive_error(e.clone()), |c| c.1.directive_error(e.clone()))
    })?;

    // Pixel filter.
    render.filter = match filter_kind.as_str() {
        "box" => {
            let radius = filter.float_or("xradius", 0.5)?;
            filter.float("yradius")?;
            if radius != 0.5 {
                r.warnings.push(filter.error("xradius", "a box of a radius other than 0.5 pixels is rendered as one of 0.5"));
            }
            PixelFilter::Box
        }
        "triangle" => {
            let radius = filter.float_or("xradius", 2.0)?;
            filter.float("yradius")?;
            if !(radius > 0.0 && radius <= 16.0) {
                return Err(filter.error("xradius", format!("xradius {radius} is outside (0, 16] pixels")));
            }
            PixelFilter::Tent { radius }
        }
        "gaussian" => {
            let sigma = filter.float_or("sigma", 0.5)?;
            filter.pass_over(&["xradius", "yradius"]);
            if !(sigma > 0.0 && sigma <= 4.0) {
                return Err(filter.error("sigma", format!("sigma {sigma} is outside (0, 4] pixels")));
            }
            PixelFilter::Gaussian { stddev: sigma }
        }
        "mitchell" | "sinc" | "lanczos" => {
            filter.pass_over(&["xradius", "yradius", "B", "C", "tau"]);
            r.warnings.push(filter.directive_error(format!(
                "the \"{filter_kind}\" filter is not modelled by sppm-gpu: rendered with a Gaussian of sigma 0.5"
            )));
            PixelFilter::Gaussian { stddev: 0.5 }
        }
        other => return Err(filter.directive_error(format!("\"{other}\": unknown filter"))),
    };
    filter.finish()?;

    // Sampler.
    let spp = if sampler_kind == "stratified" {
        sampler.pass_over(&["jitter"]);
        sampler.int_or("xsamples", 4)? * sampler.int_or("ysamples", 4)?
    } else {
        sampler.int_or("pixelsamples", 16)?
    };
    if !(1..=u32::MAX as i64).contains(&spp) {
        return Err(sampler.directive_error(format!("{spp} samples a pixel: at least 1")));
    }
    render.iterations = spp as u32;
    let seed = sampler.int_or("seed", 0)?;
    render.seed = u32::try_from(seed).map_err(|_| sampler.error("seed", format!("seed {seed} is outside 0..2^32")))?;
    render.sampler = match sampler_kind.as_str() {
        "independent" => crate::sampler::Sampler::Independent,
        "zsobol" | "sobol" | "paddedsobol" | "halton" | "pmj02bn" | "stratified" => crate::sampler::Sampler::Sobol,
        other => return Err(sampler.directive_error(format!("\"{other}\": unknown sampler"))),
    };
    sampler.pass_over(&["randomization"]);
    sampler.finish()?;

    // Integrator.
    let depth = integrator.int_or("maxdepth", 5)?;
    if !(1..=1024).contains(&depth) {
        return Err(integrator.error("maxdepth", format!("maxdepth {depth}: sppm-gpu renders 1 to 1024 bounces")));
    }
    render.max_depth = depth as u32;
    integrator.pass_over(&["lightsampler", "regularize"]);
    if integrator.bool_or("regularize", false)? {
        r.warnings.push(integrator.error("regularize", "regularize is not applied: sppm-gpu does not regularize BSDFs"));
    }
    render.method = match integrator_kind.as_str() {
        "path" | "volpath" => Method::PtNee,
        "bdpt" => {
            for name in ["visualizestrategies", "visualizeweights"] {
                if integrator.bool_or(name, false)? {
                    return Err(
                        integrator.error(name, format!("{name} (an image of the strategies) is not modelled by sppm-gpu"))
                    );
                }
            }
            Method::Bpt
        }
        "mlt" | "pssmlt" => {
            integrator.pass_over(&["bootstrapsamples", "chains", "mutationsperpixel", "largestepprobability", "sigma"]);
            r.warnings.push(integrator.directive_error(format!(
                "the \"{integrator_kind}\" integrator is rendered by pt-nee, which converges to the same image"
            )));
            Method::PtNee
        }
        "lightpath" => Method::Lt,
        "randomwalk" => Method::Pt,
        "simplepath" => {
            let lights = integrator.bool_or("samplelights", true)?;
            integrator.bool_or("samplebsdf", true)?;
            if lights {
                Method::PtNee
            } else {
                Method::Pt
            }
        }
        "sppm" => {
            let photons = integrator.int_or("photonsperiteration", -1)?;
            render.photons = match photons {
                -1 => width.saturating_mul(height),
                n if (1..=u32::MAX as i64).contains(&n) => n as u32,
                n => return Err(integrator.error("photonsperiteration", format!("photonsperiteration {n}: -1 or at least 1"))),
            };
            render.work_given.photons = true;
            if let Some(radius) = integrator.float("radius")? {
                if radius <= 0.0 {
                    return Err(integrator.error("radius", format!("radius {radius} is not positive")));
                }
                render.radius = Some(radius);
            }
            if let Some(n) = integrator.int("iterations")? {
                if n < 1 {
                    return Err(integrator.error("iterations", format!("iterations {n}: at least 1")));
                }
                render.iterations = n.min(u32::MAX as i64) as u32;
            }
            integrator.pass_over(&["seed"]);
            Method::Sppm
        }
        "ambientocclusion" | "aov" => {
            return Err(integrator.directive_error(format!(
                "the \"{integrator_kind}\" integrator renders no light transport: not modelled by sppm-gpu"
            )))
        }
        other => return Err(integrator.directive_error(format!("\"{other}\": unknown integrator"))),
    };
    integrator.finish()?;
    Ok((camera, render))
}
