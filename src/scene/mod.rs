//! Scene description: the TOML format (version 1, see docs/guide/scene-format.md) and Mitsuba's scene XML
//! ([`mitsuba`]), each parsed and validated into the same world-space [`Scene`]. Nothing here knows the GPU API.
//!
//! Loading turns every shape into triangles (quads, cubes, meshes) or analytic spheres, in
//! world space, each tagged with its shape index so that emission, velocity and texture
//! coordinates can be looked up per shape.

mod builder;
pub mod coating;
pub mod emitter;
pub mod envmap;
mod error;
pub mod files;
mod load;
pub mod material;
pub mod medium;
mod mesh;
pub mod mitsuba;
mod overrides;
mod param;
pub mod pbrt;
mod ply;
mod serialized;
mod toml_table;

pub use builder::SceneBuilder;
pub use emitter::{spot_falloff, spot_solid_angle, Light, LightKind};
pub use error::SceneError;
pub use load::{load_str, MAX_DIRECT_SAMPLES};
pub use material::{ComplexIor, Material, MaterialKind, Microfacet};
pub use medium::{Medium, Phase};
pub use overrides::{Overrides, SettingNames};
pub use param::number;

/// Reads a scene file: Mitsuba scene XML when its name ends in `.xml`, a pbrt-v4 scene when
/// it ends in `.pbrt` ([`pbrt`]), our TOML otherwise.
pub fn load(path: &std::path::Path) -> Result<Scene, SceneError> {
    load_with(path, &[])
}

/// Reads a scene file as [`load`] does, with Mitsuba's `-D name=value` parameters for an XML
/// scene's `$name`s (refused for a TOML scene, which has none).
pub fn load_with(path: &std::path::Path, defines: &[(String, String)]) -> Result<Scene, SceneError> {
    if !is_mitsuba_xml(path) {
        if let Some((name, _)) = defines.first() {
            return Err(SceneError::new(
                path,
                None,
                Some(name),
                if is_pbrt(path) {
                    "-D sets parameters of Mitsuba XML scenes; this is a pbrt-v4 scene"
                } else {
                    "-D sets parameters of Mitsuba XML scenes; this is a TOML scene"
                },
            ));
        }
    }
    let (scene, inputs) = files::collect(|| {
        if is_mitsuba_xml(path) {
            mitsuba::load(path, defines)
        } else if is_pbrt(path) {
            pbrt::load(path)
        } else {
            load::load(path)
        }
    });
    let mut scene = scene?;
    scene.inputs = inputs;
    Ok(scene)
}

/// Whether `path` names a Mitsuba XML scene (by its extension, in any case).
pub fn is_mitsuba_xml(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}

/// Whether `path` names a pbrt-v4 scene (by its extension `.pbrt`, in any case).
pub fn is_pbrt(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("pbrt"))
}

/// Whether `path` names a scene of another renderer (Mitsuba XML or pbrt-v4), whose camera
/// and film are read rather than written back.
pub fn is_foreign(path: &std::path::Path) -> bool {
    is_mitsuba_xml(path) || is_pbrt(path)
}

use glam::{Vec2, Vec3};
use std::path::PathBuf;

/// A setting chosen by name (`method = "pt-nee"`): the one table of its names, which the TOML
/// and Mitsuba readers, the command line, `convert`, `info` and `compare` all read.
pub trait Named: Copy + PartialEq + Sized + 'static {
    /// What the setting is called (`method`), for messages.
    const WHAT: &'static str;
    /// Every value with its name.
    const NAMES: &'static [(&'static str, Self)];

    /// Its name.
    fn name(self) -> &'static str {
        Self::NAMES.iter().find(|(_, v)| *v == self).map(|(n, _)| *n).expect("every value is named")
    }

    /// Other renderers' names for some values, accepted as theirs (`path` for `pt-nee`).
    const ALIASES: &'static [(&'static str, Self)] = &[];

    /// The value of `name` (or of an alias), or an error that lists the names.
    fn from_name(name: &str) -> Result<Self, String> {
        Self::NAMES.iter().chain(Self::ALIASES).find(|(n, _)| *n == name).map(|(_, v)| *v).ok_or_else(|| {
            let names: Vec<&str> = Self::NAMES.iter().map(|(n, _)| *n).collect();
            format!("unknown {} `{name}`; expected one of: {}", Self::WHAT, names.join(", "))
        })
    }

    /// The names, in [`Named::NAMES`]'s order.
    fn names() -> Vec<&'static str> {
        Self::NAMES.iter().map(|(n, _)| *n).collect()
    }
}

impl Named for Method {
    const WHAT: &'static str = "method";
    const NAMES: &'static [(&'static str, Self)] = &[
        ("sppm", Method::Sppm),
        ("pt", Method::Pt),
        ("pt-nee", Method::PtNee),
        ("lt", Method::Lt),
        ("bpt", Method::Bpt),
        ("vcm", Method::Vcm),
    ];
    /// Mitsuba's and pbrt-v4's integrators of the same images: their `path` and `volpath`
    /// sample lights at each vertex with MIS, as pt-nee does; Mitsuba's `ppm` is SPPM's
    /// ancestor.
    const ALIASES: &'static [(&'static str, Self)] =
        &[("path", Method::PtNee), ("volpath", Method::PtNee), ("ppm", Method::Sppm)];
}

impl Named for DirectLight {
    const WHAT: &'static str = "direct";
    const NAMES: &'static [(&'static str, Self)] = &[("sampled", DirectLight::Sampled), ("photons", DirectLight::Photons)];
}

impl Named for RadiusSchedule {
    const WHAT: &'static str = "radius_schedule";
    const NAMES: &'static [(&'static str, Self)] = &[("per-point", RadiusSchedule::PerPoint), ("global", RadiusSchedule::Global)];
}

impl Named for RadiusRule {
    const WHAT: &'static str = "radius_rule";
    const NAMES: &'static [(&'static str, Self)] = &[("shrink", RadiusRule::Shrink), ("adaptive", RadiusRule::Adaptive)];
}

impl Named for crate::sampler::Sampler {
    const WHAT: &'static str = "sampler";
    const NAMES: &'static [(&'static str, Self)] =
        &[("independent", crate::sampler::Sampler::Independent), ("sobol", crate::sampler::Sampler::Sobol)];
}

/// Which integrator renders the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Stochastic progressive photon mapping (Hachisuka & Jensen 2009).
    Sppm,
    /// Naive path tracing.
    Pt,
    /// Path tracing with next-event estimation and multiple importance sampling.
    PtNee,
    /// Light tracing: light subpaths joined to the camera.
    Lt,
    /// Bidirectional path tracing: camera and light subpaths, every connection between them,
    /// next-event estimation, emission hit and light tracing weighted by the balance heuristic.
    Bpt,
    /// Vertex connection and merging: bpt's strategies and photon merging at a camera
    /// subpath's first two diffuse vertices, one estimator weighted by the power heuristic
    /// (Georgiev et al. 2012).
    Vcm,
}

/// Where SPPM's direct light comes from (`direct` in `[render]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectLight {
    /// Sampled at the camera path's diffuse and glossy vertices (next-event estimation with
    /// MIS, as pt-nee does); photons deposit only after their first bounce, so they carry
    /// indirect light and caustics. The default.
    Sampled,
    /// From photons alone, as in Hachisuka & Jensen 2009 and the study this project grew
    /// from: photons deposit at every diffuse hit and camera paths add only the emission they
    /// hit.
    Photons,
}

/// How SPPM's gather radius shrinks over the passes (`radius_schedule` in `[render]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusSchedule {
    /// Each visible point's radius shrinks with the photons it has gathered (Hachisuka &
    /// Jensen 2009): the radius adapts to the local photon density, but each pass depends on
    /// every pass before it. The default where passes do not splat
    /// ([`RenderSettings::settle_radius_schedule`]).
    PerPoint,
    /// The radius of pass i is a function of i alone, r_i^2 = r_1^2 prod_{k=1}^{i-1} (k + alpha)
    /// / (k + 1), the same for every point (Knaus & Zwicker 2011, "Progressive photon mapping:
    /// a probabilistic approach"). Each pass is an estimate of its own and the image is their
    /// mean, so passes can run in separate batches, processes and machines and be merged
    /// (`--passes A..B --partial`, `sppm-gpu merge`).
    Global,
}

/// How each SPPM visible point's radius shrinks with [`RadiusSchedule::PerPoint`]
/// (`radius_rule` in `[render]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusRule {
    /// Every pass by the fraction alpha of its photons (Hachisuka & Jensen 2009). The default.
    Shrink,
    /// By alpha only where the photons around the point stop looking uniform over its disc (a
    /// chi-square test on their offsets' moments, in the spirit of Lin et al. 2020, "CPPM:
    /// Chi-squared Progressive Photon Mapping"), else by the milder
    /// [`ALPHA_UNIFORM`](crate::layout::ALPHA_UNIFORM); see `update_stats.wgsl`.
    Adaptive,
}

impl RadiusRule {
    /// The kernels' `ADAPTIVE_RADIUS` override constant: the offsets' moments are summed and
    /// tested only under the adaptive rule.
    pub fn constants(self) -> [(&'static str, f64); 1] {
        [("ADAPTIVE_RADIUS", (self == RadiusRule::Adaptive) as u32 as f64)]
    }
}

/// The pixel filter (`filter` in `[render]`; Mitsuba's `rfilter`): each camera sample's
/// offset from the pixel centre is drawn from the filter's density, separably in x and y
/// (filter importance sampling, pbrt-v4 sec. 8.8.3), so a pixel is the filter-weighted mean
/// of the radiance around it, as Mitsuba's weighted splatting converges to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PixelFilter {
    /// Uniform over the pixel's square (radius 1/2 pixel). The default.
    Box,
    /// `max(0, 1 - |x| / radius)`, radius in pixels (Mitsuba's `tent`, default radius 1).
    Tent {
        /// Half-width in pixels.
        radius: f32,
    },
    /// `max(0, exp(-x^2 / (2 stddev^2)) - exp(-radius^2 / (2 stddev^2)))` with radius = 4
    /// stddev, in pixels (Mitsuba 3's `gaussian`, default stddev 0.5; Mitsuba's default filter).
    Gaussian {
        /// Standard deviation in pixels.
        stddev: f32,
    },
}

/// Where Mitsuba 3 cuts its gaussian off, in standard deviations.
pub const GAUSSIAN_CUTOFF: f64 = 4.0;

/// The most pixels either way a splatted sample may reach: a wider filter (a gaussian of
/// standard deviation over 2.125 pixels, a tent of radius over 8.5) is sampled by importance
/// instead, as each pixel's gather reads `(2 reach + 1)^2` samples a pass.
pub const MAX_SPLAT_REACH: u32 = 8;

impl PixelFilter {
    /// How many pixels either way a sample splatted through the filter reaches: a sample lies
    /// within half a pixel of its pixel's centre in x and y, so it reaches the pixels whose
    /// centres lie closer than the filter's radius plus 1/2, `ceil(radius + 1/2) - 1` of them
    /// either way. 0, importance sampling, for the box and for filters no wider than it (a
    /// pixel's own sample could weigh nothing) or wider than [`MAX_SPLAT_REACH`].
    pub fn splat_reach(self) -> u32 {
        let radius = match self {
            PixelFilter::Box => return 0,
            PixelFilter::Tent { radius } => radius as f64,
            PixelFilter::Gaussian { stddev } => GAUSSIAN_CUTOFF * stddev as f64,
        };
        if radius.is_nan() || radius <= 0.5 {
            return 0;
        }
        let reach = (radius + 0.5).ceil() as u32 - 1;
        if reach > MAX_SPLAT_REACH {
            0
        } else {
            reach
        }
    }
}

/// The `[render]` table, with defaults applied.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The integrator (`method`; default [`Method::Sppm`]).
    pub method: Method,
    /// SPPM passes, or samples per pixel for the path tracers.
    pub iterations: u32,
    /// Camera samples per pixel in each SPPM pass.
    pub spp: u32,
    /// Photons emitted per SPPM pass.
    pub photons: u32,
    /// Initial gather radius; `None` asks for the automatic choice.
    pub radius: Option<f32>,
    /// SPPM radius reduction (Hachisuka & Jensen 2009): the fraction of each pass's photons
    /// kept, in (0, 1); default 0.6667.
    pub alpha: f32,
    /// Most scattering events on a camera path and on a photon path (default 64); Russian
    /// roulette may end paths earlier.
    pub max_depth: u32,
    /// Seed of every random stream: the same seed gives the same image (default 0).
    pub seed: u32,
    /// Stop at the pass boundary nearest this many seconds, judged on passes the device has
    /// completed (`pacing`); at least one pass runs. `None` runs every iteration.
    pub time_limit: Option<f64>,
    /// SPPM's source of direct light (`direct`: `"sampled"`, the default, or `"photons"`).
    pub direct: DirectLight,
    /// SPPM with sampled direct light: camera paths per visible point per pass that gather
    /// direct light (`direct_samples`); `None` asks for the automatic choice.
    pub direct_samples: Option<u32>,
    /// bpt's and vcm's light subpaths a pass (`light_paths`); `None` asks for the automatic
    /// choice, one for every [`crate::integrators::light::PIXELS_PER_LIGHT_PATH`] pixels. 0
    /// (vcm alone, with neither share above 0) traces none: camera subpaths with next-event
    /// estimation, their strategies weighed as vcm weighs them.
    pub light_paths: Option<u32>,
    /// bpt's and vcm's share of camera vertices that connect to light vertices
    /// (`connect_share`, in [0, 1]; 1 is every one). A share enters the MIS as the
    /// strategy's count, and a connection taken is divided by it. `None`: 1 for bpt; for vcm,
    /// where `merge_share` is `None` too, chosen by a pilot
    /// (`integrators::shares`), else 1.
    pub connect_share: Option<f32>,
    /// vcm's share of camera vertices that merge with light vertices (`merge_share`, in
    /// [0, 1]), as [`RenderSettings::connect_share`] for merging.
    pub merge_share: Option<f32>,
    /// SPPM's radius schedule (`radius_schedule`: `"per-point"` or `"global"`; by default
    /// the one [`RenderSettings::settle_radius_schedule`] chooses).
    pub radius_schedule: RadiusSchedule,
    /// Whether the scene or an override gave `radius_schedule`; where not, it follows the
    /// other settings ([`RenderSettings::settle_radius_schedule`]).
    pub radius_schedule_given: bool,
    /// How a visible point's radius shrinks under [`RadiusSchedule::PerPoint`]
    /// (`radius_rule`: `"shrink"`, the default, or `"adaptive"`).
    pub radius_rule: RadiusRule,
    /// The pixel filter (default [`PixelFilter::Box`]).
    pub filter: PixelFilter,
    /// Where the kernels' random numbers come from (`sampler`: `"independent"` or
    /// `"sobol"`; default [`crate::sampler::Sampler::DEFAULT`]).
    pub sampler: crate::sampler::Sampler,
    /// Which of a pass's work settings (`photons`, `spp`) the scene or the command line gave:
    /// the others are the loader's defaults until [`RenderSettings::fit_pass_work`] sets them
    /// for the device.
    pub work_given: WorkGiven,
    /// The strategies of bpt and vcm whose weighted contributions the image keeps (bits of
    /// [`crate::layout::STRATEGY_EMISSION`] and its siblings; default
    /// [`crate::layout::STRATEGIES_ALL`]): one alone gives that strategy's share of the image
    /// (`--strategy-images`). Not a scene key.
    pub strategies: u32,
    /// vcm as photon mapping: each camera subpath merges at its first diffuse vertex alone
    /// and ends there, with next-event estimation there and at the glossy vertices before it:
    /// SPPM's estimator (sampled direct light, the global radius schedule), rendered by SPPM's
    /// kernels. Chosen by vcm's pilot (`integrators::shares`) where it is the best of vcm's
    /// configurations. Not a scene key.
    pub photon_mapping: bool,
    /// Every 8-bit texture palette-coded whatever the textures' size, as only a scene whose
    /// images pass `gpu::scene_buffers::PALETTE_ABOVE_BYTES` as floats has them: the same
    /// image (the palette is lossless), for tests of that. Not a scene key.
    pub texture_palettes: bool,
}

/// Which of [`PassWork`]'s settings a scene gave.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WorkGiven {
    /// `photons` was given.
    pub photons: bool,
    /// `spp` was given.
    pub spp: bool,
}

impl WorkGiven {
    /// Both given: nothing follows the device.
    pub const ALL: WorkGiven = WorkGiven { photons: true, spp: true };
}

/// The work of one SPPM pass: photons, and camera samples per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassWork {
    /// Photons a pass.
    pub photons: u32,
    /// Camera samples per pixel a pass.
    pub spp: u32,
}

impl PassWork {
    /// The loader's defaults, chosen on a CPU device (lavapipe): 100,000 photons and one
    /// camera sample a pass.
    pub const DEFAULT: PassWork = PassWork { photons: 100_000, spp: 1 };
    /// A GPU's (`gpu::GpuContext::pass_work`): 400,000 photons and four camera samples a
    /// pass, the lowest equal-time error of 4 x 2 choices on three canonical scenes on an
    /// H200 (BENCHMARKS.md "GPU"): a GPU's pass has fixed costs that small passes repeat.
    pub const GPU: PassWork = PassWork { photons: 400_000, spp: 4 };
}

impl Default for RenderSettings {
    /// The defaults of every reader (TOML, Mitsuba XML, [`SceneBuilder`]), each of which
    /// sets the image size and pass count it reads.
    fn default() -> Self {
        RenderSettings {
            width: 256,
            height: 256,
            method: Method::Sppm,
            iterations: 1,
            spp: PassWork::DEFAULT.spp,
            photons: PassWork::DEFAULT.photons,
            radius: None,
            alpha: 0.6667,
            max_depth: 64,
            seed: 0,
            time_limit: None,
            direct: DirectLight::Sampled,
            direct_samples: None,
            light_paths: None,
            connect_share: None,
            merge_share: None,
            radius_schedule: RadiusSchedule::PerPoint,
            radius_schedule_given: false,
            radius_rule: RadiusRule::Shrink,
            filter: PixelFilter::Box,
            sampler: crate::sampler::Sampler::DEFAULT,
            work_given: WorkGiven::default(),
            strategies: crate::layout::STRATEGIES_ALL,
            photon_mapping: false,
            texture_palettes: false,
        }
    }
}

impl RenderSettings {
    /// Give the work settings the scene did not give ([`RenderSettings::work_given`]) the
    /// values of `work`: the device's defaults, chosen from its kind, never from timings, so
    /// one scene and seed give one image on one machine.
    pub fn fit_pass_work(&mut self, work: PassWork) {
        if !self.work_given.photons {
            self.photons = work.photons;
        }
        if !self.work_given.spp {
            self.spp = work.spp;
        }
        self.settle_radius_schedule();
    }

    /// SPPM's radius schedule where none was given: the global one where its passes then
    /// splat through a filter wider than the box (one visible point a pixel, the plain radius
    /// rule: `integrators::sppm::splat_reach_of`), a radius per point elsewhere. At equal time
    /// on Mitsuba's tent- and gaussian-filtered test scenes the splatted global schedule's
    /// relMSE is 1.02x to 2.0x below the per-point one's (BENCHMARKS.md "VCM"). Called by
    /// [`Scene::new`] (every reader), the overrides and [`RenderSettings::fit_pass_work`],
    /// after which these settings may have changed.
    pub fn settle_radius_schedule(&mut self) {
        if !self.radius_schedule_given {
            let splats = self.radius_rule == RadiusRule::Shrink && self.global_splat_reach() > 0;
            self.radius_schedule = if splats { RadiusSchedule::Global } else { RadiusSchedule::PerPoint };
        }
    }

    /// How many pixels either way SPPM splats each pass's estimate of a visible point under
    /// the global radius schedule: the filter's reach with one visible point a pixel, 0 with
    /// more (their camera rays then sample the filter).
    pub fn global_splat_reach(&self) -> u32 {
        if self.spp == 1 {
            self.filter.splat_reach()
        } else {
            0
        }
    }
}

/// The `[camera]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (the pinhole, or the centre of the lens), world space.
    pub position: Vec3,
    /// The point the camera looks at, world space.
    pub look_at: Vec3,
    /// Up direction, any length, not parallel to the view direction (default `+y`).
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov: f32,
    /// Thin-lens aperture radius, scene units; 0 is a pinhole.
    pub aperture_radius: f32,
    /// Distance to the plane in focus, scene units (used only when `aperture_radius > 0`);
    /// defaults to the distance from `position` to `look_at`.
    pub focus_distance: f32,
    /// Line of `aperture_radius` in the file, when given.
    pub aperture_line: Option<usize>,
    /// The part of a larger film the image shows (a Mitsuba film's crop window), `None` for
    /// the whole: `fov` and the aspect ratio are the whole film's, and the image's pixels
    /// are those of the window.
    pub crop: Option<CropWindow>,
    /// Index into [`Scene::media`] of the medium the camera sits in (fog filling the scene),
    /// `None` for a vacuum.
    pub medium: Option<u32>,
}

impl Camera {
    /// The view's orthonormal basis: forward (towards `look_at`), right and up (in the plane
    /// of `up` and forward), as the kernels' image plane and the host's camera rays take it.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.look_at - self.position).normalize();
        let right = forward.cross(self.up).normalize();
        (forward, right, right.cross(forward))
    }
}

/// A window of the film, in fractions of its width and height from its top-left corner:
/// `min` < `max`, both in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CropWindow {
    /// Top-left corner.
    pub min: Vec2,
    /// Bottom-right corner.
    pub max: Vec2,
}

/// A texture: an image decoded to linear RGB, row 0 at the top, and how it is sampled.
///
/// A lookup at a surface's texture coordinates uv takes (x, y) = `to_uv` * uv, x across the
/// image from its left edge (0) to its right (1), y down from its top row (0) to its bottom
/// (1), as Mitsuba 3's `bitmap` does; a TOML scene's t runs up, so its textures map uv by
/// (s, 1 - t).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// The image file, resolved against the scene file's directory (for a procedural texture,
    /// the scene file).
    pub path: PathBuf,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Linear RGB, row-major, `width * height` texels; shared by the scene's clones (a render
    /// clones its scene for vcm's pilot and for each renderer it makes, and a scene's images
    /// can take hundreds of megabytes: Bitterli's staircase 222 MB).
    pub texels: std::sync::Arc<Vec<Vec3>>,
    /// How texels are interpolated.
    pub filter: TextureFilter,
    /// How coordinates outside [0, 1] are brought back in.
    pub wrap: TextureWrap,
    /// Texture coordinates to image coordinates (x, y) in [0, 1]^2.
    pub to_uv: glam::Affine2,
}

/// How a texture interpolates its texels (Mitsuba's `filter_type`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextureFilter {
    /// Bilinear between the four nearest texel centres, which lie at half-integers in texel
    /// units (Mitsuba's default).
    #[default]
    Bilinear,
    /// The texel the point lies in.
    Nearest,
}

/// How a texture extends beyond [0, 1]^2 (Mitsuba's `wrap_mode`), texel by texel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextureWrap {
    /// Tiled (Mitsuba's default).
    #[default]
    Repeat,
    /// Tiled with every other tile mirrored, so that the edge texels repeat at the seams.
    Mirror,
    /// The edge texels extended.
    Clamp,
}

/// The kind of a `[[shapes]]` entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeKind {
    /// A parallelogram `corner, corner + u, corner + u + v, corner + v`: two triangles.
    Quad,
    /// An analytic sphere.
    Sphere,
    /// The cube `[-1, 1]^3` scaled, rotated and translated: twelve triangles.
    Cube,
    /// A Wavefront OBJ file, triangulated and transformed.
    Mesh,
}

/// One `[[shapes]]` entry, after its primitives were generated.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// The entry's `type`.
    pub kind: ShapeKind,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Radiance leaving the front side (quads, meshes: side of the winding's normal;
    /// spheres: outside). `None` when the shape does not emit.
    pub emission: Option<Vec3>,
    /// Whether `emission` leaves both sides (pbrt-v4's `"bool twosided" true` area lights;
    /// TOML's `emission_two_sided`), with twice the power.
    pub emission_two_sided: bool,
    /// Displacement over the shutter: at shutter time t in [0, 1) the shape sits at its
    /// position + velocity * t. `None` when it does not move.
    pub velocity: Option<Vec3>,
    /// Line of the `[[shapes]]` header.
    pub line: usize,
    /// Line of `velocity`, when given.
    pub velocity_line: Option<usize>,
    /// A sphere's frame for its texture coordinates (Mitsuba's `sphere`): columns are its
    /// object-space x, y and z axes in world space, unit length, and uv = (phi / 2 pi,
    /// theta / pi) of the normal in that frame, phi from x towards y in [0, 2 pi), theta from
    /// z. `None` for every other shape, and for TOML's spheres without a `uv_frame` (theirs is
    /// [`TOML_SPHERE_FRAME`]).
    pub sphere_frame: Option<glam::Mat3>,
    /// Index into [`Scene::media`] of the medium inside the shape, on the side against its
    /// normals (see [`medium`]), `None` for a vacuum or none given.
    pub interior: Option<u32>,
    /// Index into [`Scene::media`] of the medium outside it, on the side its normals point to.
    pub exterior: Option<u32>,
}

/// The frame of a TOML sphere's texture coordinates (see [`Shape::sphere_frame`]): s is the
/// longitude about +y from +z towards +x, t the latitude from the bottom (-y) pole.
pub const TOML_SPHERE_FRAME: glam::Mat3 = glam::Mat3::from_cols(Vec3::Z, Vec3::X, Vec3::NEG_Y);

/// A world-space triangle. The geometric normal is `normalize(cross(p[1]-p[0], p[2]-p[0]))`,
/// which is the front side for emission.
#[derive(Clone, Debug, PartialEq)]
pub struct Triangle {
    /// Vertices, world space (at rest: time 0 for a moving shape).
    pub p: [Vec3; 3],
    /// Per-vertex shading normals (unit length), only for `smooth = true` meshes.
    pub n: Option<[Vec3; 3]>,
    /// Per-vertex texture coordinates, when the shape has them (quads: `uv_scale * (a, b)`;
    /// meshes: OBJ `vt`).
    pub uv: Option<[Vec2; 3]>,
    /// Index into [`Scene::shapes`] of the shape the triangle belongs to.
    pub shape: u32,
}

/// A world-space analytic sphere.
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, world space (at rest: time 0 for a moving shape).
    pub center: Vec3,
    /// Radius, scene units.
    pub radius: f32,
    /// Index into [`Scene::shapes`].
    pub shape: u32,
}

/// A loaded, validated scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene file, for error messages.
    pub path: PathBuf,
    /// The `[render]` table.
    pub render: RenderSettings,
    /// The `[camera]` table.
    pub camera: Camera,
    /// The `[materials]` entries; shapes refer to them by index.
    pub materials: Vec<Material>,
    /// Every distinct texture file the materials name, loaded once each.
    pub textures: Vec<Texture>,
    /// The `[[shapes]]` entries, in file order.
    pub shapes: Vec<Shape>,
    /// Every shape's triangles (quads, cubes, meshes), world space; degenerate mesh
    /// triangles are skipped.
    pub triangles: Vec<Triangle>,
    /// Every analytic sphere, world space.
    pub spheres: Vec<Sphere>,
    /// The `[[lights]]` entries, in file order.
    pub lights: Vec<Light>,
    /// The participating media that the camera or shapes are in ([`medium`]); they refer to
    /// them by index.
    pub media: Vec<Medium>,
    /// Every file the scene was read from (canonical paths): the scene file, its includes,
    /// meshes, textures and environment maps, which a run must never write over. Empty for
    /// a scene built in code or from text.
    pub inputs: Vec<PathBuf>,
}

impl Scene {
    /// A scene of these settings, camera, materials (with the textures they name), lights and
    /// media, without shapes: each reader adds its shapes and their primitives. A radius
    /// schedule the settings do not give is settled ([`RenderSettings::settle_radius_schedule`]).
    pub fn new(
        path: PathBuf,
        mut render: RenderSettings,
        camera: Camera,
        materials: Vec<Material>,
        textures: Vec<Texture>,
        lights: Vec<Light>,
        media: Vec<Medium>,
    ) -> Self {
        render.settle_radius_schedule();
        Scene {
            path,
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
        }
    }

    /// Move the camera's look-at point along its view to the depth of the scene's centre (the
    /// same view), and return that depth: the automatic SPPM radius follows pixel footprints
    /// at the look-at point, and a file's own target (Mitsuba's `lookat`, often one unit
    /// ahead; pbrt's) need not lie near the scene. Behind the camera, the box's diagonal.
    pub fn look_at_scene_depth(&mut self) -> f32 {
        let (lo, hi) = self.bounds();
        let c = &mut self.camera;
        let forward = (c.look_at - c.position).normalize();
        let depth = forward.dot((lo + hi) * 0.5 - c.position);
        let depth = if depth > 0.0 { depth } else { (hi - lo).length().max(1.0) };
        c.look_at = c.position + forward * depth;
        depth
    }

    /// The box around every surface at rest (time 0); zero for a scene with no surfaces.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::INFINITY;
        let mut hi = Vec3::NEG_INFINITY;
        for t in &self.triangles {
            for p in t.p {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        for s in &self.spheres {
            lo = lo.min(s.center - s.radius);
            hi = hi.max(s.center + s.radius);
        }
        if lo.x > hi.x {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        (lo, hi)
    }

    /// Whether anything gives light: an emitting shape, or a point, spot, directional or
    /// environment light, with some channel above zero.
    pub fn is_lit(&self) -> bool {
        self.shapes.iter().any(|s| emitter::emission_gives_light(s.emission)) || self.lights.iter().any(|l| l.kind.gives_light())
    }

    /// Material of a shape.
    pub fn shape_material(&self, shape: u32) -> &Material {
        &self.materials[self.shapes[shape as usize].material as usize]
    }
}

/// Check a camera built in code the way the loader checks `[camera]`: finite values, a view
/// direction, an `up` not parallel to it, `fov` in (0, 180), a non-negative aperture and a
/// positive focus distance. The message names the offending field.
pub fn validate_camera(c: &Camera) -> Result<(), String> {
    let finite = c.position.is_finite() && c.look_at.is_finite() && c.up.is_finite();
    if finite && !(c.look_at - c.position).length_squared().is_finite() {
        return Err(format!("camera.{}", load::VIEW_OUT_OF_RANGE));
    }
    if !finite || !c.fov.is_finite() || !c.aperture_radius.is_finite() || !c.focus_distance.is_finite() {
        return Err("camera: every value must be finite".into());
    }
    let view = (c.look_at - c.position).normalize_or_zero();
    if view == Vec3::ZERO {
        return Err("camera.look_at equals camera.position: the camera has no view direction".into());
    }
    if view.cross(c.up.normalize_or_zero()).length() < 1e-6 {
        return Err("camera.up is zero or parallel to the view direction".into());
    }
    if !(c.fov > 0.0 && c.fov < 180.0) {
        return Err(format!("camera.fov must be in (0, 180), got {}", c.fov));
    }
    if c.aperture_radius < 0.0 || c.focus_distance <= 0.0 {
        return Err("camera.aperture_radius must be >= 0 and camera.focus_distance > 0".into());
    }
    Ok(())
}
