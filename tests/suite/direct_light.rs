//! Direct light against analytic irradiance. A diffuse receiver (the plane z = 0, albedo 0.5,
//! facing +z) lit by one light whose own material is black gets no indirect light at all, so
//! its radiance is exactly albedo / pi * E, with E in closed form: Lambert's formula for quad
//! and triangle lights, pi L (r / D)^2 cos(theta) for a sphere, I cos(theta) / d^2 for a point
//! light, E0 cos(theta) for a directional one, I f(theta_s) cos(theta) / d^2 for a spot light
//! (f its falloff at angle theta_s from its axis). Blocks of pixels are compared with the formula
//! averaged over the same pixels' squares (the camera's box filter), from normal incidence to
//! grazing (cos(theta) 0.1 to 0.2), next to an area light's plane, and in the ring just outside
//! a sphere light's silhouette, where shadow rays aimed from the un-offset point once made the
//! wall 10 to 14% too dark. Each block must be within 1% and its Monte Carlo standard error,
//! from independent batches of samples, well below that.

use crate::common;

use glam::{DVec3, Vec3};
use sppm_gpu::gpu::GpuContext;
use sppm_gpu::integrators::{self, camera_frame_for};
use sppm_gpu::scene::{DirectLight, Method, RadiusSchedule, Scene, SceneBuilder};
use std::f64::consts::PI;
use std::time::Instant;

/// The receiver's reflectance.
const ALBEDO: f64 = 0.5;
/// The receiver is the square [-2, 2]^2 in the plane z = 0 (the repro's wall, [-1, 1]^2).
const RECEIVER_HALF: f32 = 2.0;
/// Midpoint-rule points per pixel side for the analytic pixel average.
const SUPER: u32 = 8;

/// A light as the analytic side sees it.
#[derive(Clone, Debug)]
enum Light {
    /// A planar polygon of uniform radiance, emitting on the side its winding faces.
    Polygon { vertices: Vec<DVec3>, radiance: f64 },
    /// A sphere of uniform radiance.
    Sphere { center: DVec3, radius: f64, radiance: f64 },
    /// Radiant intensity from a point.
    Point { position: DVec3, intensity: f64 },
    /// Parallel light travelling along `direction` (unit), `irradiance` on a surface facing it.
    Directional { direction: DVec3, irradiance: f64 },
    /// Radiant intensity from a point, times Mitsuba 3's spot falloff about `axis` (unit):
    /// 1 within `beam` radians, linear in the angle down to 0 at `cutoff`, 0 beyond.
    Spot { position: DVec3, axis: DVec3, intensity: f64, cutoff: f64, beam: f64 },
}

/// Mitsuba 3's spot falloff at angle theta from the axis (as its `spot` plugin evaluates it,
/// measured with Mitsuba 3.9.1): written out here apart from the renderer's.
fn falloff(theta: f64, cutoff: f64, beam: f64) -> f64 {
    if theta >= cutoff {
        0.0
    } else if theta <= beam {
        1.0
    } else {
        (cutoff - theta) / (cutoff - beam)
    }
}

/// The angle between unit vectors a and b, accurate at every angle.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

impl Light {
    /// Irradiance at p on a surface of unit normal n, nothing in between.
    fn irradiance(&self, p: DVec3, n: DVec3) -> f64 {
        match self {
            Light::Polygon { vertices, radiance } => polygon_irradiance(vertices, *radiance, p, n),
            Light::Sphere { center, radius, radiance } => sphere_irradiance(*center, *radiance, *radius, p, n),
            // E = I cos(theta) / d^2.
            Light::Point { position, intensity } => {
                let to = *position - p;
                intensity * n.dot(to.normalize()).max(0.0) / to.length_squared()
            }
            // E = E0 cos(theta).
            Light::Directional { direction, irradiance } => irradiance * n.dot(-*direction).max(0.0),
            // E = I f(theta_s) cos(theta) / d^2.
            Light::Spot { position, axis, intensity, cutoff, beam } => {
                let to = *position - p;
                let f = falloff(angle(-to.normalize(), *axis), *cutoff, *beam);
                intensity * f * n.dot(to.normalize()).max(0.0) / to.length_squared()
            }
        }
    }

    /// Distance along the ray (o, unit d) to the light's surface, if it has one there.
    fn hit(&self, o: DVec3, d: DVec3) -> Option<f64> {
        match self {
            Light::Polygon { vertices, .. } => (1..vertices.len() - 1)
                .filter_map(|i| hit_triangle(o, d, [vertices[0], vertices[i], vertices[i + 1]]))
                .reduce(f64::min),
            Light::Sphere { center, radius, .. } => {
                let oc = o - *center;
                let b = oc.dot(d);
                let disc = b * b - (oc.length_squared() - radius * radius);
                (disc >= 0.0).then(|| -b - disc.sqrt()).filter(|t| *t > 0.0)
            }
            Light::Point { .. } | Light::Directional { .. } | Light::Spot { .. } => None,
        }
    }

    /// The direction the light mostly arrives from at p: towards its centre, or against its
    /// travel.
    fn towards(&self, p: DVec3) -> DVec3 {
        match self {
            Light::Polygon { vertices, .. } => {
                let centroid = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
                (centroid - p).normalize()
            }
            Light::Sphere { center, .. } => (*center - p).normalize(),
            Light::Point { position, .. } | Light::Spot { position, .. } => (*position - p).normalize(),
            Light::Directional { direction, .. } => -*direction,
        }
    }

    /// For the report: the cosine at p (normal +z) of the direction towards the light, and for a
    /// polygon the cosine at its centroid between its front and the direction back to p.
    fn cosines(&self, p: DVec3) -> (f64, Option<f64>) {
        let w = self.towards(p);
        match self {
            Light::Polygon { vertices, .. } => {
                let front = (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]).normalize();
                (w.z, Some(-w.dot(front)))
            }
            _ => (w.z, None),
        }
    }
}

/// Lambert's formula (Lambert 1760; Arvo 1994, "The irradiance Jacobian for partially occluded
/// polyhedral sources"): E = L / 2 * sum_i Theta_i n . unit(R_{i+1} x R_i), R_i the vertices
/// relative to p, Theta_i the angle between R_i and R_{i+1}. In this order of the cross product
/// the sum is positive when the polygon's front (its winding's normal) faces p, which
/// `formulas_match_monte_carlo` checks; behind its plane p gets no light. The polygon
/// must be wholly above p's horizon (there is no clipping here).
fn polygon_irradiance(vertices: &[DVec3], radiance: f64, p: DVec3, n: DVec3) -> f64 {
    let front = (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]);
    if front.dot(p - vertices[0]) <= 0.0 {
        return 0.0;
    }
    assert!(vertices.iter().all(|v| n.dot(*v - p) > 0.0), "the polygon crosses the horizon of {p}");
    let mut sum = 0.0;
    for (i, v) in vertices.iter().enumerate() {
        let (a, b) = (*v - p, vertices[(i + 1) % vertices.len()] - p);
        let c = b.cross(a);
        sum += c.length().atan2(a.dot(b)) * n.dot(c.normalize());
    }
    0.5 * radiance * sum
}

/// A uniform sphere wholly above the horizon subtends a cap of half-angle alpha, sin(alpha) =
/// r / D, whose projected solid angle is pi sin^2(alpha) cos(theta): E = pi L (r / D)^2
/// cos(theta), theta between n and the direction to the centre.
fn sphere_irradiance(center: DVec3, radiance: f64, radius: f64, p: DVec3, n: DVec3) -> f64 {
    let to = center - p;
    assert!(n.dot(to) > radius, "the sphere crosses the horizon of {p}");
    PI * radiance * radius * radius / to.length_squared() * n.dot(to.normalize())
}

/// Möller-Trumbore: distance to triangle `t` along the ray (o, d), either side.
fn hit_triangle(o: DVec3, d: DVec3, t: [DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let q = d.cross(e2);
    let det = e1.dot(q);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = o - t[0];
    let u = s.dot(q) / det;
    let r = s.cross(e1);
    let v = d.dot(r) / det;
    let dist = e2.dot(r) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && dist > 0.0).then_some(dist)
}

/// The pinhole camera as shaders/shared/camera.wgsl traces it: raster point (x, y), row 0 at
/// the top, goes along forward + sx right + sy up with sx = 2 x / W - 1, sy = 1 - 2 y / H
/// (right and up from `camera_frame_for`, spanning half the image).
struct Pinhole {
    origin: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    width: u32,
    height: u32,
    /// The receiver is the square [-receiver_half, receiver_half]^2 at z = 0.
    receiver_half: f64,
}

impl Pinhole {
    fn new(scene: &Scene) -> Self {
        let f = camera_frame_for(&scene.camera, scene.render.width, scene.render.height);
        let v = |a: [f32; 3]| Vec3::from(a).as_dvec3();
        Pinhole {
            origin: v(f.cam_position),
            forward: v(f.cam_forward),
            right: v(f.cam_right),
            up: v(f.cam_up),
            width: f.width,
            height: f.height,
            // The receiver is the scene's first shape.
            receiver_half: scene.triangles[0].p.iter().map(|p| p.x.abs() as f64).fold(0.0, f64::max),
        }
    }

    fn ray(&self, x: f64, y: f64) -> DVec3 {
        let sx = 2.0 * x / self.width as f64 - 1.0;
        let sy = 1.0 - 2.0 * y / self.height as f64;
        (self.forward + sx * self.right + sy * self.up).normalize()
    }

    /// Where the ray through raster point (x, y) meets the receiver, unless it meets a light
    /// first or misses.
    fn receiver_point(&self, x: f64, y: f64, lights: &[Light]) -> Option<DVec3> {
        let d = self.ray(x, y);
        let t = -self.origin.z / d.z;
        let p = self.origin + t * d;
        let on_receiver = t > 0.0 && p.x.abs() < self.receiver_half && p.y.abs() < self.receiver_half;
        let blocked = lights.iter().any(|l| l.hit(self.origin, d).is_some_and(|s| s < t));
        (on_receiver && !blocked).then_some(DVec3::new(p.x, p.y, 0.0))
    }
}

/// Each pixel's radiance albedo / pi * E averaged over its square (midpoint rule on SUPER^2
/// points), row-major; `None` where one of those rays meets a light or misses the receiver.
fn analytic_image(scene: &Scene, lights: &[Light]) -> Vec<Option<f64>> {
    let camera = Pinhole::new(scene);
    let mut out = Vec::with_capacity((camera.width * camera.height) as usize);
    for py in 0..camera.height {
        for px in 0..camera.width {
            let mut sum = 0.0;
            let mut whole = true;
            for j in 0..SUPER * SUPER {
                let x = px as f64 + ((j % SUPER) as f64 + 0.5) / SUPER as f64;
                let y = py as f64 + ((j / SUPER) as f64 + 0.5) / SUPER as f64;
                match camera.receiver_point(x, y, lights) {
                    Some(p) => sum += lights.iter().map(|l| l.irradiance(p, DVec3::Z)).sum::<f64>(),
                    None => whole = false,
                }
            }
            out.push(whole.then(|| ALBEDO / PI * sum / (SUPER * SUPER) as f64));
        }
    }
    out
}

/// Per-pixel values (mean over RGB) of `batches` independent batches of `passes` passes each,
/// recovered from the running mean: the image after k batches averages k equal batches, so
/// batch k is k M_k - (k - 1) M_{k-1}. For SPPM this holds where no photon lands, as on a
/// receiver whose only other surface is a black light, and under the global radius schedule,
/// whose image is the mean of its passes' estimates.
fn render_batches(gpu: &GpuContext, scene: &Scene, batches: u32, passes: u32) -> Vec<Vec<f64>> {
    let mut integrator = integrators::create(&gpu.device, &gpu.queue, scene).unwrap_or_else(|e| panic!("{e}"));
    let mut previous = vec![0.0; (scene.render.width * scene.render.height) as usize];
    let mut out = Vec::new();
    for k in 1..=batches {
        let image = common::run_passes(&mut *integrator, passes);
        let sums: Vec<f64> = image.pixels.iter().map(|p| p.iter().map(|c| *c as f64).sum::<f64>() / 3.0 * k as f64).collect();
        out.push(sums.iter().zip(&previous).map(|(s, p)| s - p).collect());
        previous = sums;
    }
    out
}

/// A named set of pixels compared as one receiver point.
struct Region {
    name: String,
    pixels: Vec<usize>,
}

/// Independent batches per render, for the standard error.
const BATCHES: u32 = 16;
/// SPPM's camera samples per pixel per pass.
const SPPM_SPP: u32 = 16;

/// Within 1% of the analytic radiance, with a standard error below 0.3%.
const TOLERANCE: f64 = 0.01;
const MAX_SE: f64 = 0.003;

/// Photons per pass and their initial radius where SPPM takes direct light from photons.
const PHOTONS: u32 = 1_000_000;
const PHOTON_RADIUS: f32 = 0.002;
/// Camera samples per pixel per pass where SPPM takes direct light from photons.
const PHOTON_SPP: u32 = 1;

/// How a render estimates the light at the receiver: a method as the scene would run it (SPPM
/// and pt-nee sample direct light at each visible point or path vertex), or SPPM with direct
/// light from photons alone.
#[derive(Clone, Copy, PartialEq)]
enum Estimator {
    Method(Method),
    SppmPhotons,
}

impl From<Method> for Estimator {
    fn from(method: Method) -> Self {
        Estimator::Method(method)
    }
}

impl std::fmt::Debug for Estimator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Estimator::Method(m) => write!(f, "{m:?}"),
            Estimator::SppmPhotons => write!(f, "Sppm (photons)"),
        }
    }
}

/// `scene` set up for `method` with `samples` camera samples per pixel in all (SPPM with
/// photons: the passes of as many, with fewer samples a pass), and the passes of one of the
/// BATCHES batches.
fn for_method(scene: &Scene, estimator: Estimator, samples: u32, photons: u32) -> (Scene, u32) {
    let mut scene = scene.clone();
    let method = match estimator {
        Estimator::Method(m) => m,
        Estimator::SppmPhotons => Method::Sppm,
    };
    scene.render.method = method;
    let per_pass = if method == Method::Sppm { SPPM_SPP } else { 1 };
    assert_eq!(samples % (BATCHES * per_pass), 0, "{samples} samples do not split into batches");
    if estimator == Estimator::SppmPhotons {
        // Photons straight from the light are the estimate: each pass one of its own under the
        // global radius schedule, so that batches of passes are independent. The radius is
        // small against the probe and against the light's variation, and every probe lies at
        // least 2 radii from where that variation has a kink. The passes are those of
        // `samples` at SPPM_SPP a pass, but the camera's samples only place the visible points,
        // PHOTON_SPP a pixel: each takes the photons within the radius (1.6 pixels), so one a
        // pixel still covers the probe, and the noise is the photons'. Measured 2026-11-28 on
        // the spot lights' probes: standard errors 0.06 to 0.15% at 16 a pixel, 0.06 to 0.16%
        // at 1 (the same within their own noise), while a photon landing in view deposits to
        // 16 times fewer points: spot_light_sppm_photons 62.7 CPU-s -> 41.6 on lavapipe.
        scene.render.spp = PHOTON_SPP;
        scene.render.direct = DirectLight::Photons;
        scene.render.radius_schedule = RadiusSchedule::Global;
        scene.render.photons = photons;
        scene.render.radius = Some(PHOTON_RADIUS);
    } else if method == Method::Sppm {
        // The receiver gets no photons (they leave it, or stop on the black light), so their
        // number and radius only cost time.
        scene.render.spp = SPPM_SPP;
        scene.render.photons = 1000;
        scene.render.radius = Some(0.01);
    }
    (scene, samples / (BATCHES * per_pass))
}

/// One region's comparison: the report's line, and the line again if it failed.
struct Outcome {
    line: String,
    failure: Option<String>,
}

/// Renders `scene` with `method` (`samples` per pixel; `photons` a pass for SPPM with direct
/// light from photons) and compares each region with the
/// analytic radiance: within `tolerance` (relative) with a standard error below `max_se`
/// (relative), or black, as the analytic value is, where the light cannot be seen. Every
/// region must lie wholly on the receiver.
#[allow(clippy::too_many_arguments)]
fn measure(
    gpu: &GpuContext,
    label: &str,
    scene: &Scene,
    lights: &[Light],
    regions: &[Region],
    method: Estimator,
    samples: u32,
    photons: u32,
    (tolerance, max_se): (f64, f64),
) -> Vec<Outcome> {
    let (scene, passes) = for_method(scene, method, samples, photons);
    let analytic = analytic_image(&scene, lights);
    let start = Instant::now();
    let batches = render_batches(gpu, &scene, BATCHES, passes);
    let seconds = start.elapsed().as_secs_f64();
    let camera = Pinhole::new(&scene);
    let k = BATCHES as f64;
    let mut outcomes = Vec::new();
    for region in regions {
        let n = region.pixels.len() as f64;
        let expected = region
            .pixels
            .iter()
            .map(|&i| analytic[i])
            .sum::<Option<f64>>()
            .unwrap_or_else(|| panic!("{label}, {}: the camera sees a light there, or misses the receiver", region.name))
            / n;
        let means: Vec<f64> = batches.iter().map(|b| region.pixels.iter().map(|&i| b[i]).sum::<f64>() / n).collect();
        let mean = means.iter().sum::<f64>() / k;
        let se = (means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (k - 1.0) / k).sqrt();
        // Where the region lies and how the light arrives there, averaged over its pixels.
        let centres: Vec<DVec3> = region
            .pixels
            .iter()
            .map(|&i| {
                let (x, y) = ((i as u32 % camera.width) as f64 + 0.5, (i as u32 / camera.width) as f64 + 0.5);
                camera.receiver_point(x, y, lights).unwrap()
            })
            .collect();
        let centre = centres.iter().sum::<DVec3>() / n;
        let cosines: Vec<String> = lights
            .iter()
            .map(|l| {
                let (r, s) =
                    centres.iter().map(|p| l.cosines(*p)).fold((0.0, 0.0), |(a, b), (c, d)| (a + c, b + d.unwrap_or(0.0)));
                match l {
                    Light::Polygon { .. } => format!("cos_r {:.3} cos_l {:+.3}", r / n, s / n),
                    _ => format!("cos_r {:.3}", r / n),
                }
            })
            .collect();
        let at = format!("{label} {method:?} {} at ({:.3}, {:.3}), {}", region.name, centre.x, centre.y, cosines.join(", "));
        let (line, failed) = if expected > 0.0 {
            let (error, rel_se) = (mean / expected - 1.0, se / expected);
            let line = format!(
                "{at}: analytic {expected:.5e} rendered {mean:.5e} error {:+.2}% se {:.2}%",
                error * 100.0,
                rel_se * 100.0
            );
            (line, !(error.abs() < tolerance && rel_se < max_se))
        } else {
            // Behind a one-sided light nothing arrives, exactly.
            (format!("{at}: analytic 0 rendered {mean:.3e}"), mean != 0.0)
        };
        outcomes.push(Outcome { failure: failed.then(|| line.clone()), line });
    }
    let per_pixel = if scene.render.method == Method::Sppm { scene.render.spp * passes * BATCHES } else { samples };
    let photons = if method == Estimator::SppmPhotons { format!(" of {photons} photons") } else { String::new() };
    eprintln!(
        "{label} {method:?}: {}x{}, {per_pixel} samples per pixel in {} passes{photons}, {seconds:.2} s",
        scene.render.width,
        scene.render.height,
        passes * BATCHES
    );
    outcomes
}

/// Prints every outcome and fails listing those off.
fn report(what: &str, outcomes: &[Outcome], (tolerance, max_se): (f64, f64)) {
    for o in outcomes {
        eprintln!("  {}", o.line);
    }
    let failures: Vec<&str> = outcomes.iter().filter_map(|o| o.failure.as_deref()).collect();
    assert!(
        failures.is_empty(),
        "{what}: {} of {} regions off the analytic radiance by {}% or more (or with a standard error of {}% or more):\n{}",
        failures.len(),
        outcomes.len(),
        tolerance * 100.0,
        max_se * 100.0,
        failures.join("\n")
    );
}

/// The probes' cameras look straight down from this height ...
const CAMERA_HEIGHT: f64 = 5.0;
/// ... at a square of the receiver this wide, in this many pixels a side.
const PROBE_SIDE: f64 = 0.04;
const PROBE_PIXELS: u32 = 32;

/// The receiver, the square [-s, s]^2 at z = 0, and a black material for the lights.
fn receiver(s: f32) -> SceneBuilder {
    SceneBuilder::new(PROBE_PIXELS, PROBE_PIXELS).diffuse("receiver", [ALBEDO as f32; 3]).diffuse("black", [0.0; 3]).quad(
        [-s, -s, 0.0],
        [2.0 * s, 0.0, 0.0],
        [0.0, 2.0 * s, 0.0],
        "receiver",
    )
}

/// A receiver point: the PROBE_SIDE square centred at `at`, rendered with `samples` per pixel.
struct Probe {
    name: &'static str,
    at: [f64; 2],
    samples: u32,
}

/// Samples per pixel at a probe of an area light. Area lights are sampled uniformly by area (a
/// sphere over its whole surface), so one sample's relative deviation is about 0.5 to 1 for a
/// polygon and 1.5 to 2 for a sphere or a polygon seen nearly edge-on: 1024 pixels of 512 or
/// 1024 samples leave a standard error of 0.1 to 0.2%.
const AREA_SAMPLES: u32 = 512;
const HARD_SAMPLES: u32 = 1024;
/// Samples per pixel where every sample gives the same value but for where it falls in the
/// pixel (point and directional lights) or nothing (behind a light).
const FEW_SAMPLES: u32 = 256;
/// Samples per pixel (and SPPM passes: two per batch) at the probes of the wide spot light,
/// for its photons' standard error: at 1024 samples (2026-11-28) the photons' relative
/// standard errors there read 0.11% (in the beam) and 0.08% (in the falloff); at 512 they are
/// sqrt(2) larger, about 0.16% and 0.11%: under MAX_SE (0.3%) by a factor of about 2, with the
/// 1% tolerance 6 standard errors away. Point-like lights' pt-nee and next-event SPPM
/// estimates, which use it too, vary only with where a sample falls in its pixel.
const WIDE_SPOT_SAMPLES: u32 = 512;

/// The light kinds: each scene is the receiver and one light; what the analytic side knows of
/// the light; and where to look.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// A 0.6 x 0.2 quad standing in the plane x = 0 at heights 0.05 to 0.25, facing +x.
    Quad,
    /// One triangle (tests/scenes/direct/triangle.obj) in the plane x + z = 0.2, tilted 45
    /// degrees, facing -x and down; the camera sees its black back over x = -0.1 to 0.1.
    Triangle,
    /// A sphere of radius 0.1 centred 0.15 above the origin (the camera sees it over x^2 + y^2
    /// < 0.103^2).
    Sphere,
    /// A point light 0.15 above the origin.
    Point,
    /// Directional light at normal incidence, and at cos(theta) = 0.15.
    Directional,
    /// Spot lights (cutoff 30 degrees, beam width 10) 0.2 above the origin looking straight
    /// down and 0.25 above it tilted 20 degrees towards +x, and one 0.1 above the origin
    /// looking along +x (cutoff 110, beam width 60), whose cone holds more than a hemisphere:
    /// in the beam, in the falloff (90 degrees from the axis, for the wide one) and outside
    /// the cutoff of each.
    Spot,
}

/// Area lights' radiance.
const RADIANCE: f32 = 10.0;

fn kind(kind: Kind) -> Vec<(SceneBuilder, Vec<Light>, Vec<Probe>)> {
    let l = RADIANCE as f64;
    let probe = |name, x, y, samples| Probe { name, at: [x, y], samples };
    match kind {
        Kind::Quad => {
            let (corner, u, v) = (DVec3::new(0.0, -0.3, 0.05), DVec3::new(0.0, 0.6, 0.0), DVec3::new(0.0, 0.0, 0.2));
            let b = receiver(RECEIVER_HALF).quad(corner.as_vec3(), u.as_vec3(), v.as_vec3(), "black").emission([RADIANCE; 3]);
            let light = Light::Polygon { vertices: vec![corner, corner + u, corner + u + v, corner + v], radiance: l };
            let probes = vec![
                probe("in front", 0.15, 0.0, AREA_SAMPLES),
                probe("0.005 to 0.045 from its plane", 0.025, 0.0, HARD_SAMPLES),
                probe("past its side", 0.3, 0.5, AREA_SAMPLES),
                probe("grazing", 1.0, 0.0, AREA_SAMPLES),
                probe("grazing", 1.5, 0.0, AREA_SAMPLES),
                probe("behind", -0.2, 0.0, FEW_SAMPLES),
            ];
            vec![(b, vec![light], probes)]
        }
        Kind::Triangle => {
            let file = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/scenes/direct/triangle.obj");
            let b = receiver(RECEIVER_HALF).mesh(file, [1.0; 3], [0.0; 3], [0.0; 3], "black").emission([RADIANCE; 3]);
            // Built for its triangles (any camera).
            let built =
                b.clone().camera([0.0, 0.0, 1.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0).build().unwrap_or_else(|e| panic!("{e}"));
            let vertices = built.triangles.last().unwrap().p.iter().map(|p| p.as_dvec3()).collect();
            let probes = vec![
                probe("in front", -0.2, 0.0, AREA_SAMPLES),
                probe("0.005 to 0.045 from its plane", 0.175, 0.0, HARD_SAMPLES),
                probe("past its side", -0.2, 0.6, AREA_SAMPLES),
                probe("grazing", -1.0, 0.0, AREA_SAMPLES),
                probe("grazing", -1.5, 0.0, AREA_SAMPLES),
                probe("behind", 0.3, 0.0, FEW_SAMPLES),
            ];
            vec![(b, vec![Light::Polygon { vertices, radiance: l }], probes)]
        }
        Kind::Sphere => {
            let center = DVec3::new(0.0, 0.0, 0.15);
            let b = receiver(RECEIVER_HALF).sphere(center.as_vec3(), 0.1, "black").emission([RADIANCE; 3]);
            let probes = vec![
                probe("just outside its silhouette", 0.13, 0.0, HARD_SAMPLES),
                probe("oblique", 0.4, 0.0, HARD_SAMPLES),
                probe("grazing", 1.0, 0.0, HARD_SAMPLES),
                probe("grazing", 1.5, 0.0, HARD_SAMPLES),
            ];
            vec![(b, vec![Light::Sphere { center, radius: 0.1, radiance: l }], probes)]
        }
        Kind::Point => {
            let position = DVec3::new(0.0, 0.0, 0.15);
            let b = receiver(RECEIVER_HALF).point_light(position.as_vec3(), [1.0; 3]);
            let probes = vec![
                probe("below", 0.0, 0.0, FEW_SAMPLES),
                probe("oblique", 0.3, 0.0, FEW_SAMPLES),
                probe("grazing", 1.0, 0.0, FEW_SAMPLES),
                probe("grazing", 1.5, 0.0, FEW_SAMPLES),
            ];
            vec![(b, vec![Light::Point { position, intensity: 1.0 }], probes)]
        }
        Kind::Spot => {
            // (position, axis, cutoff, beam width, probes in the beam, falloff and outside,
            // samples in the first two): the wide spot's probes get a smaller share of its
            // photons, which cover 5.7 sr, and more passes.
            let tilt = 20f64.to_radians();
            let spots = [
                ([0.0, 0.0, 0.2], DVec3::NEG_Z, 30.0, 10.0, [[0.0, 0.0], [0.075, 0.0], [0.16, 0.0]], FEW_SAMPLES),
                (
                    [0.0, 0.0, 0.25],
                    DVec3::new(tilt.sin(), 0.0, -tilt.cos()),
                    30.0,
                    10.0,
                    [[0.091, 0.0], [0.091, 0.09], [0.091, -0.25]],
                    FEW_SAMPLES,
                ),
                ([0.0, 0.0, 0.1], DVec3::X, 110.0, 60.0, [[0.12, 0.0], [0.0, 0.03], [-0.1, 0.0]], WIDE_SPOT_SAMPLES),
            ];
            spots
                .into_iter()
                .map(|(position, axis, cutoff, beam, at, samples)| {
                    let position = DVec3::from(position);
                    let b = receiver(RECEIVER_HALF).spot_light(
                        position.as_vec3(),
                        axis.as_vec3(),
                        [1.0; 3],
                        cutoff as f32,
                        beam as f32,
                    );
                    let light = Light::Spot {
                        position,
                        axis,
                        intensity: 1.0,
                        cutoff: f64::to_radians(cutoff),
                        beam: f64::to_radians(beam),
                    };
                    let probes = ["in the beam", "in the falloff", "outside the cutoff"]
                        .into_iter()
                        .zip(at)
                        .map(|(name, [x, y])| {
                            assert_eq!(spot_zone(&light, [x, y]), name, "the probe at ({x}, {y})");
                            let samples = if name == "outside the cutoff" { FEW_SAMPLES } else { samples };
                            probe(name, x, y, samples)
                        })
                        .collect();
                    (b, vec![light], probes)
                })
                .collect()
        }
        Kind::Directional => [1.0, 0.15]
            .into_iter()
            .map(|cos: f64| {
                let direction = -DVec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let b = receiver(RECEIVER_HALF).directional_light(direction.as_vec3(), [2.0; 3]);
                let name = if cos == 1.0 { "facing it" } else { "grazing" };
                (b, vec![Light::Directional { direction, irradiance: 2.0 }], vec![probe(name, 0.3, 0.2, FEW_SAMPLES)])
            })
            .collect(),
    }
}

/// Where on a spot light's falloff the probe square at `at` lies, with a margin of twice
/// the photons' radius: wholly "in the beam", "in the falloff" or "outside the cutoff" (else
/// "across a kink", where a density estimate would blur it).
fn spot_zone(light: &Light, at: [f64; 2]) -> &'static str {
    let Light::Spot { position, axis, cutoff, beam, .. } = light else { panic!("not a spot light") };
    let half = 0.5 * PROBE_SIDE + 2.0 * PHOTON_RADIUS as f64;
    let n = 16;
    let thetas: Vec<f64> = (0..(n + 1) * (n + 1))
        .map(|i| {
            let (u, v) = ((i % (n + 1)) as f64 / n as f64, (i / (n + 1)) as f64 / n as f64);
            let p = DVec3::new(at[0] + half * (2.0 * u - 1.0), at[1] + half * (2.0 * v - 1.0), 0.0);
            angle((p - *position).normalize(), *axis)
        })
        .collect();
    if thetas.iter().all(|t| t < beam) {
        "in the beam"
    } else if thetas.iter().all(|t| t > beam && t < cutoff) {
        "in the falloff"
    } else if thetas.iter().all(|t| t > cutoff) {
        "outside the cutoff"
    } else {
        "across a kink"
    }
}

/// `b` seen by one camera straight above all of `probes`, at their pixel size (PROBE_SIDE /
/// PROBE_PIXELS), framing the smallest rectangle that holds their squares, with pixel edges on
/// theirs; and each probe's PROBE_PIXELS^2 pixels as a region. The pixels between the squares
/// are rendered and not measured; a single probe's square is the whole image.
fn probes_scene(b: &SceneBuilder, lights: &[Light], probes: &[Probe]) -> (Scene, Vec<Region>) {
    let pixel = PROBE_SIDE / PROBE_PIXELS as f64;
    let lo = [0, 1].map(|i| probes.iter().map(|p| p.at[i]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1].map(|i| probes.iter().map(|p| p.at[i]).fold(f64::NEG_INFINITY, f64::max));
    for p in probes {
        let offset = [0, 1].map(|i| (p.at[i] - lo[i]) / pixel);
        assert!(
            offset.iter().all(|o| (o - o.round()).abs() < 1e-6),
            "{}: {:?} is not whole pixels from the others",
            p.name,
            p.at
        );
    }
    let [width, height] = [0, 1].map(|i| ((hi[i] - lo[i]) / pixel).round() as u32 + PROBE_PIXELS);
    let fov = (2.0 * (0.5 * height as f64 * pixel / CAMERA_HEIGHT).atan()).to_degrees() as f32;
    let (x, y) = ((0.5 * (lo[0] + hi[0])) as f32, (0.5 * (lo[1] + hi[1])) as f32);
    let scene = b
        .clone()
        .size(width, height)
        .camera([x, y, CAMERA_HEIGHT as f32], [x, y, 0.0], [0.0, 1.0, 0.0], fov)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let camera = Pinhole::new(&scene);
    let regions = probes
        .iter()
        .map(|p| {
            let pixels: Vec<usize> = (0..(width * height) as usize)
                .filter(|&i| {
                    let (px, py) = ((i as u32 % width) as f64 + 0.5, (i as u32 / width) as f64 + 0.5);
                    camera
                        .receiver_point(px, py, lights)
                        .is_some_and(|q| (q.x - p.at[0]).abs() < 0.5 * PROBE_SIDE && (q.y - p.at[1]).abs() < 0.5 * PROBE_SIDE)
                })
                .collect();
            assert_eq!(pixels.len(), (PROBE_PIXELS * PROBE_PIXELS) as usize, "{} at {:?}", p.name, p.at);
            Region { name: p.name.into(), pixels }
        })
        .collect();
    (scene, regions)
}

fn check_kind(k: Kind, method: impl Into<Estimator>) {
    let method = method.into();
    let Some(gpu) = common::gpu() else { return };
    let start = Instant::now();
    let mut outcomes = Vec::new();
    // A light's probes differ only in the camera, and a kind's lights (the three spots, the
    // two directional lights) only in where they are and point, which the kernels read from
    // buffers: their kernels are compiled once for the whole kind.
    sppm_gpu::gpu::share_kernels(|| {
        for (b, lights, probes) in kind(k) {
            // A render a probe; but where photons from the light are the cost, the same photons
            // serve every probe: one render a light, its camera framing all its probes, at the
            // passes of the probe that asks most and PHOTONS a pass (the narrow spots' probes in
            // the beam and falloff had a third or half of them, in renders of their own).
            // Measured 2026-12-01 on the spot lights: 52.8 CPU-s -> 28.2, the relative standard
            // errors 0.06 to 0.16% (were 0.11 to 0.16%), against MAX_SE (0.3%).
            let groups: Vec<Vec<Probe>> =
                if method == Estimator::SppmPhotons { vec![probes] } else { probes.into_iter().map(|p| vec![p]).collect() };
            for group in groups {
                let (scene, regions) = probes_scene(&b, &lights, &group);
                let samples = group.iter().map(|p| p.samples).max().unwrap();
                outcomes.extend(measure(
                    &gpu,
                    &format!("{k:?}"),
                    &scene,
                    &lights,
                    &regions,
                    method,
                    samples,
                    PHOTONS,
                    (TOLERANCE, MAX_SE),
                ));
            }
        }
    });
    eprintln!("{k:?} {method:?}: {:.1} s", start.elapsed().as_secs_f64());
    report(&format!("{k:?} {method:?}"), &outcomes, (TOLERANCE, MAX_SE));
}

#[test]
fn quad_light_pt_nee() {
    check_kind(Kind::Quad, Method::PtNee);
}

#[test]
fn triangle_light_pt_nee() {
    check_kind(Kind::Triangle, Method::PtNee);
}

#[test]
fn sphere_light_pt_nee() {
    check_kind(Kind::Sphere, Method::PtNee);
}

#[test]
fn point_light_pt_nee() {
    check_kind(Kind::Point, Method::PtNee);
}

#[test]
fn directional_light_pt_nee() {
    check_kind(Kind::Directional, Method::PtNee);
}

#[test]
fn spot_light_pt_nee() {
    check_kind(Kind::Spot, Method::PtNee);
}

#[test]
fn spot_light_sppm() {
    check_kind(Kind::Spot, Method::Sppm);
}

/// SPPM's photons straight from each spot light, alone, against the same irradiance: the
/// directions photons leave in, and their flux.
#[test]
fn spot_light_sppm_photons() {
    check_kind(Kind::Spot, Estimator::SppmPhotons);
}

#[test]
fn quad_light_sppm() {
    check_kind(Kind::Quad, Method::Sppm);
}

#[test]
fn triangle_light_sppm() {
    check_kind(Kind::Triangle, Method::Sppm);
}

#[test]
fn sphere_light_sppm() {
    check_kind(Kind::Sphere, Method::Sppm);
}

#[test]
fn point_light_sppm() {
    check_kind(Kind::Point, Method::Sppm);
}

#[test]
fn directional_light_sppm() {
    check_kind(Kind::Directional, Method::Sppm);
}

/// The wall of the original report: 2 x 2, albedo 0.5, a sphere light of `radius` and radiance
/// 10 centred 0.4 in front of it, the camera 2 from the wall looking straight at it, 64 x 64,
/// framed so that the sphere's silhouette on the wall is 36 pixels across. Returns the scene,
/// its light and the silhouette's radius on the wall.
fn repro(radius: f64) -> (Scene, Vec<Light>, f64) {
    let center = DVec3::new(0.0, 0.0, 0.4);
    let eye = 2.0;
    let silhouette = eye * (radius / (eye - center.z)).asin().tan();
    let half_width = silhouette * 32.0 / 18.0;
    let fov = (2.0 * (half_width / eye).atan()).to_degrees() as f32;
    let b = receiver(1.0)
        .size(64, 64)
        .camera([0.0, 0.0, eye as f32], [0.0; 3], [0.0, 1.0, 0.0], fov)
        .sphere(center.as_vec3(), radius as f32, "black")
        .emission([RADIANCE; 3]);
    let scene = b.build().unwrap_or_else(|e| panic!("{e}"));
    (scene, vec![Light::Sphere { center, radius, radiance: RADIANCE as f64 }], silhouette)
}

/// The pixels wholly on the wall whose centres lie 1 to 1.5 silhouette radii from the sphere's
/// centre (the ring), and those beyond.
fn ring_regions(scene: &Scene, lights: &[Light], silhouette: f64) -> [Region; 2] {
    let camera = Pinhole::new(scene);
    let analytic = analytic_image(scene, lights);
    let (mut ring, mut beyond) = (Vec::new(), Vec::new());
    for (i, value) in analytic.iter().enumerate() {
        let (x, y) = ((i as u32 % camera.width) as f64 + 0.5, (i as u32 / camera.width) as f64 + 0.5);
        let d = camera.ray(x, y);
        let rho = (camera.origin - camera.origin.z / d.z * d).truncate().length() / silhouette;
        if value.is_none() {
            continue;
        } else if rho < 1.5 {
            ring.push(i);
        } else {
            beyond.push(i);
        }
    }
    [
        Region { name: format!("ring 1-1.5 silhouette radii ({} pixels)", ring.len()), pixels: ring },
        Region { name: format!("beyond ({} pixels)", beyond.len()), pixels: beyond },
    ]
}

/// The original repro, sphere radii 0.08 and 0.3: the ring just outside the sphere's
/// silhouette, whose shadow rays graze the sphere near its limb, and the wall beyond.
fn check_repro(method: Method, samples: [u32; 2], bounds: (f64, f64)) {
    let Some(gpu) = common::gpu() else { return };
    let mut outcomes = Vec::new();
    for (radius, samples) in [0.08, 0.3].into_iter().zip(samples) {
        let (scene, lights, silhouette) = repro(radius);
        let regions = ring_regions(&scene, &lights, silhouette);
        // Of the ring's 1270 pixels, those the silhouette touches are left out.
        assert!(regions[0].pixels.len() > 900, "radius {radius}: {}", regions[0].name);
        outcomes.extend(measure(
            &gpu,
            &format!("sphere r {radius}"),
            &scene,
            &lights,
            &regions,
            method.into(),
            samples,
            PHOTONS,
            bounds,
        ));
    }
    report(&format!("sphere ring {method:?}"), &outcomes, bounds);
}

#[test]
fn sphere_ring_pt_nee() {
    check_repro(Method::PtNee, [1024, 512], (TOLERANCE, MAX_SE));
}

#[test]
fn sphere_ring_sppm() {
    check_repro(Method::Sppm, [1024, 512], (TOLERANCE, MAX_SE));
}

/// Naive path tracing finds the sphere only by hitting it (from the ring, about 4% of cosine
/// samples for radius 0.08), so it gets a looser bound.
#[test]
fn sphere_ring_naive_pt() {
    check_repro(Method::Pt, [1024, 256], (0.02, 0.006));
}

/// Lambert's formula, and the sphere's, against a Monte Carlo estimate of E = integral of
/// L cos(theta) cos(theta_l) / d^2 over the light's area (pbrt-v4 sec. 4.2.3), for points in
/// front of, far from and nearly in the plane of each light, and behind the polygons.
#[test]
fn formulas_match_monte_carlo() {
    let mut rng = common::Rng(7);
    let n = DVec3::Z;
    const SAMPLES: usize = 1_000_000;
    for c in [Kind::Quad, Kind::Triangle, Kind::Sphere] {
        let lights = &kind(c)[0].1;
        for x in [-1.5, -0.2, -0.05, 0.01, 0.04, 0.15, 0.3, 1.0, 1.5] {
            let p = DVec3::new(x, 0.03, 0.0);
            let formula = lights[0].irradiance(p, n);
            // Uniform points on the light by area: (point, outward unit normal); area.
            let (points, area): (Vec<(DVec3, DVec3)>, f64) = match &lights[0] {
                Light::Polygon { vertices, .. } => {
                    let tris: Vec<[DVec3; 3]> =
                        (1..vertices.len() - 1).map(|i| [vertices[0], vertices[i], vertices[i + 1]]).collect();
                    let areas: Vec<f64> = tris.iter().map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()).collect();
                    let total: f64 = areas.iter().sum();
                    let front = (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]).normalize();
                    let points = (0..SAMPLES)
                        .map(|_| {
                            let mut u = rng.uniform() * total;
                            let t = tris
                                .iter()
                                .zip(&areas)
                                .find(|(_, a)| {
                                    u -= **a;
                                    u <= 0.0
                                })
                                .map_or(tris[tris.len() - 1], |(t, _)| *t);
                            let (mut b1, mut b2) = (rng.uniform(), rng.uniform());
                            if b1 + b2 > 1.0 {
                                (b1, b2) = (1.0 - b1, 1.0 - b2);
                            }
                            (t[0] + b1 * (t[1] - t[0]) + b2 * (t[2] - t[0]), front)
                        })
                        .collect();
                    (points, total)
                }
                Light::Sphere { center, radius, .. } => {
                    let points = (0..SAMPLES)
                        .map(|_| {
                            let z = 1.0 - 2.0 * rng.uniform();
                            let phi = 2.0 * PI * rng.uniform();
                            let r = (1.0 - z * z).max(0.0).sqrt();
                            let w = DVec3::new(r * phi.cos(), r * phi.sin(), z);
                            (*center + *radius * w, w)
                        })
                        .collect();
                    (points, 4.0 * PI * radius * radius)
                }
                _ => unreachable!(),
            };
            let values: Vec<f64> = points
                .iter()
                .map(|(q, nl)| {
                    let to = *q - p;
                    let d2 = to.length_squared();
                    let w = to / d2.sqrt();
                    RADIANCE as f64 * n.dot(w).max(0.0) * (-nl.dot(w)).max(0.0) / d2 * area
                })
                .collect();
            let mean = values.iter().sum::<f64>() / SAMPLES as f64;
            let se = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (SAMPLES * (SAMPLES - 1)) as f64).sqrt();
            eprintln!("{c:?} x {x:5.2}: formula {formula:.6e} Monte Carlo {mean:.6e} +- {se:.1e}");
            assert!((formula - mean).abs() <= 4.0 * se + 1e-12, "{c:?} at {p}: formula {formula}, Monte Carlo {mean} +- {se}");
            assert!(se <= 0.005 * mean.max(1e-300) || mean == 0.0, "{c:?} at {p}: Monte Carlo too noisy to tell");
        }
    }
}

/// A spot light's power over its intensity, `spot_solid_angle` in closed form (with its
/// series for narrow falloffs), against the integral of the falloff over the sphere, 2 pi
/// integral_0^pi f(theta) sin(theta) d theta, by the midpoint rule on each smooth piece.
#[test]
fn spot_solid_angle_matches_quadrature() {
    let cases = [
        (20.0, 15.0),
        (30.0, 10.0),
        (30.0, 0.0),
        (20.0, 20.0),
        (20.0, 40.0),
        (100.0, 60.0),
        (180.0, 180.0),
        (180.0, 0.0),
        (5.0, 4.9999),
        (1.0, 0.5),
        (45.0, 44.99),
    ];
    for (cutoff, beam) in cases {
        let (c, b) = (f64::to_radians(cutoff), f64::to_radians(beam).min(f64::to_radians(cutoff)));
        let pieces = [(0.0, b), (b, c)];
        let n = 200_000;
        let quadrature: f64 = pieces
            .iter()
            .map(|&(lo, hi)| {
                let h = (hi - lo) / n as f64;
                (0..n).map(|i| lo + (i as f64 + 0.5) * h).map(|t| falloff(t, c, b) * t.sin() * h).sum::<f64>() * 2.0 * PI
            })
            .sum();
        let formula = sppm_gpu::scene::spot_solid_angle(c, b);
        eprintln!("cutoff {cutoff} beam {beam}: formula {formula:.12e} quadrature {quadrature:.12e}");
        assert!((formula / quadrature - 1.0).abs() < 1e-9, "cutoff {cutoff} beam {beam}: {formula} against {quadrature}");
    }
    // A spot of cutoff 180 and no falloff is a point light.
    assert!((sppm_gpu::scene::spot_solid_angle(PI, PI) / (4.0 * PI) - 1.0).abs() < 1e-15);
}
