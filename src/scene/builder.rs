//! Assembling a [`Scene`] in code instead of a TOML file.
//!
//! [`SceneBuilder`] takes the same things a scene file holds (render settings, a camera,
//! named materials of every family, quads, spheres, cubes and meshes with optional emission,
//! lights of every kind) and turns them into the same world-space primitives through the
//! loader's own tessellation, so a scene built here and the same scene loaded from a file
//! have identical triangles. Every value is checked as the loader checks it (a material or a
//! light by its model's own check, [`super::material`], [`super::emitter`]); the first
//! problem comes back from [`SceneBuilder::build`] as a [`SceneError`] naming the key in
//! the file's dotted form (`shapes[3].radius`, `materials.white.albedo`). Nothing panics.
//!
//! ```no_run
//! use sppm_gpu::scene::SceneBuilder;
//! let scene = SceneBuilder::new(256, 256)
//!     .photons(200_000)
//!     .camera([0.0, 1.0, 3.9], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0], 39.3)
//!     .diffuse("white", [0.725, 0.71, 0.68])
//!     .diffuse("black", [0.0, 0.0, 0.0])
//!     .quad([-1.0, 0.0, 1.0], [2.0, 0.0, 0.0], [0.0, 0.0, -2.0], "white")
//!     .quad([-0.25, 1.98, -0.25], [0.5, 0.0, 0.0], [0.0, 0.0, 0.5], "black")
//!     .emission([17.0, 12.0, 4.0])
//!     .cube([0.3, 0.6, 0.3], [0.0, 20.0, 0.0], [-0.35, 0.6, -0.3], "white")
//!     .build()?;
//! # Ok::<(), sppm_gpu::scene::SceneError>(())
//! ```

use super::load::{MAX_DIRECT_SAMPLES, MAX_RESOLUTION};
use super::mesh::{self, Transform};
use super::param::{out_of, Bound};
use super::{
    Camera, DirectLight, Light, LightKind, Material, MaterialKind, Method, Microfacet, RenderSettings, Scene, SceneError, Shape,
    ShapeKind, Sphere, Texture,
};
use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};

type Result<T> = std::result::Result<T, SceneError>;

/// The name a built scene goes by in error messages unless [`SceneBuilder::path`] sets one.
const BUILDER_PATH: &str = "<scene builder>";

/// Builds a [`Scene`] in code. Methods chain; [`SceneBuilder::build`] checks everything and
/// returns the scene or the first error. Shape modifiers ([`SceneBuilder::emission`],
/// [`SceneBuilder::velocity`], [`SceneBuilder::uv_scale`], [`SceneBuilder::smooth`]) apply
/// to the shape added last. Materials may be defined before or after the shapes that use
/// them; their indices follow the order they were defined in, as in a file.
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    path: PathBuf,
    render: RenderSettings,
    camera: Option<Camera>,
    lens: Option<(f32, f32)>,
    materials: Vec<MaterialEntry>,
    shapes: Vec<ShapeEntry>,
    lights: Vec<LightKind>,
    /// The first misuse of the chain (a modifier with no shape to apply to, or to the wrong
    /// kind of shape), reported by `build`.
    misuse: Option<SceneError>,
}

#[derive(Clone, Debug)]
enum MaterialEntry {
    Kind(String, MaterialKind),
    /// A diffuse material reading its albedo from an image file.
    Textured(String, PathBuf),
}

impl MaterialEntry {
    fn name(&self) -> &str {
        match self {
            MaterialEntry::Kind(name, _) | MaterialEntry::Textured(name, _) => name,
        }
    }
}

#[derive(Clone, Debug)]
struct ShapeEntry {
    geometry: Geometry,
    material: String,
    emission: Option<Vec3>,
    emission_two_sided: bool,
    velocity: Option<Vec3>,
}

#[derive(Clone, Debug)]
enum Geometry {
    Quad { corner: Vec3, u: Vec3, v: Vec3, uv_scale: Vec2 },
    Sphere { center: Vec3, radius: f32 },
    Cube { scale: Vec3, rotate: Vec3, translate: Vec3 },
    Mesh { file: PathBuf, smooth: bool, scale: Vec3, rotate: Vec3, translate: Vec3 },
}

impl Geometry {
    fn kind(&self) -> ShapeKind {
        match self {
            Geometry::Quad { .. } => ShapeKind::Quad,
            Geometry::Sphere { .. } => ShapeKind::Sphere,
            Geometry::Cube { .. } => ShapeKind::Cube,
            Geometry::Mesh { .. } => ShapeKind::Mesh,
        }
    }
}

impl SceneBuilder {
    /// A scene of `width` x `height` pixels with the loader's defaults for everything else in
    /// `[render]` (SPPM, 1 sample per pixel, 100 000 photons, automatic radius, alpha 0.6667,
    /// max depth 64, seed 0) and 1 iteration (an embedding application drives the passes
    /// itself; the command line's `--iterations` or [`SceneBuilder::iterations`] sets more).
    pub fn new(width: u32, height: u32) -> Self {
        SceneBuilder {
            path: PathBuf::from(BUILDER_PATH),
            render: RenderSettings { width, height, ..RenderSettings::default() },
            camera: None,
            lens: None,
            materials: Vec::new(),
            shapes: Vec::new(),
            lights: Vec::new(),
            misuse: None,
        }
    }

    /// The name the scene goes by in errors ([`Scene::path`]); relative mesh and texture
    /// file names are resolved against its directory, as the loader resolves them against
    /// the scene file's. Without it they are relative to the working directory.
    pub fn path(mut self, path: impl Into<PathBuf>) -> Self {
        self.path = path.into();
        self
    }

    /// Replace the whole `[render]` table (width and height included).
    pub fn render(mut self, render: RenderSettings) -> Self {
        self.render = render;
        self
    }

    /// Image size in pixels (1 to 16384 each).
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.render.width = width;
        self.render.height = height;
        self
    }

    /// Rendering method (`render.method`).
    pub fn method(mut self, method: Method) -> Self {
        self.render.method = method;
        self
    }

    /// SPPM's source of direct light (`render.direct`).
    pub fn direct(mut self, direct: DirectLight) -> Self {
        self.render.direct = direct;
        self
    }

    /// Camera paths per visible point per pass that gather direct light
    /// (`render.direct_samples`, 1 to [`MAX_DIRECT_SAMPLES`]); automatic when not set.
    pub fn direct_samples(mut self, paths: u32) -> Self {
        self.render.direct_samples = Some(paths);
        self
    }

    /// SPPM passes, or samples per pixel for the path tracers (`render.iterations`, >= 1).
    pub fn iterations(mut self, iterations: u32) -> Self {
        self.render.iterations = iterations;
        self
    }

    /// Camera samples per pixel in each pass (`render.spp`, >= 1).
    pub fn spp(mut self, spp: u32) -> Self {
        self.render.spp = spp;
        self.render.work_given.spp = true;
        self
    }

    /// Photons per pass (`render.photons`, >= 1).
    pub fn photons(mut self, photons: u32) -> Self {
        self.render.photons = photons;
        self.render.work_given.photons = true;
        self
    }

    /// Initial gather radius in scene units (`render.radius`, > 0); without it the radius
    /// is chosen from the camera and image size.
    pub fn radius(mut self, radius: f32) -> Self {
        self.render.radius = Some(radius);
        self
    }

    /// Radius reduction parameter (`render.alpha`, in (0, 1)).
    pub fn alpha(mut self, alpha: f32) -> Self {
        self.render.alpha = alpha;
        self
    }

    /// Most scattering events on a path (`render.max_depth`, >= 1).
    pub fn max_depth(mut self, max_depth: u32) -> Self {
        self.render.max_depth = max_depth;
        self
    }

    /// Random seed (`render.seed`).
    pub fn seed(mut self, seed: u32) -> Self {
        self.render.seed = seed;
        self
    }

    /// Time limit in seconds for the command line (`render.time_limit`, > 0).
    pub fn time_limit(mut self, seconds: f64) -> Self {
        self.render.time_limit = Some(seconds);
        self
    }

    /// A pinhole camera at `position` looking at `look_at`, `up` roughly up, `fov` degrees
    /// of vertical field of view. Required.
    pub fn camera(mut self, position: impl Into<Vec3>, look_at: impl Into<Vec3>, up: impl Into<Vec3>, fov: f32) -> Self {
        let (position, look_at) = (position.into(), look_at.into());
        self.camera = Some(Camera {
            position,
            look_at,
            up: up.into(),
            fov,
            aperture_radius: 0.0,
            focus_distance: look_at.distance(position),
            aperture_line: None,
            crop: None,
            medium: None,
        });
        self
    }

    /// Make the camera a thin lens of `aperture_radius` focused at `focus_distance` (in any
    /// order with [`SceneBuilder::camera`]).
    pub fn thin_lens(mut self, aperture_radius: f32, focus_distance: f32) -> Self {
        self.lens = Some((aperture_radius, focus_distance));
        self
    }

    /// A material of any kind under `name`. A `Diffuse` kind's `texture` must be `None`
    /// here; use [`SceneBuilder::textured`] for textures.
    pub fn material(mut self, name: impl Into<String>, kind: MaterialKind) -> Self {
        self.materials.push(MaterialEntry::Kind(name.into(), kind));
        self
    }

    /// A Lambertian material of reflectance `albedo` (each channel in [0, 1]).
    pub fn diffuse(self, name: impl Into<String>, albedo: impl Into<Vec3>) -> Self {
        self.material(name, MaterialKind::Diffuse { albedo: albedo.into(), texture: None })
    }

    /// A Lambertian material whose reflectance is read from an sRGB image file (PNG).
    pub fn textured(mut self, name: impl Into<String>, file: impl Into<PathBuf>) -> Self {
        self.materials.push(MaterialEntry::Textured(name.into(), file.into()));
        self
    }

    /// A perfect mirror of reflectance `albedo`.
    pub fn mirror(self, name: impl Into<String>, albedo: impl Into<Vec3>) -> Self {
        let (roughness, distribution) = (0.0, Microfacet::Ggx);
        self.material(
            name,
            MaterialKind::Conductor { albedo: albedo.into(), texture: None, roughness, distribution, fresnel: None },
        )
    }

    /// A GGX conductor of reflectance `albedo` and GGX alpha `roughness` (in [0, 1]).
    pub fn glossy(self, name: impl Into<String>, albedo: impl Into<Vec3>, roughness: f32) -> Self {
        self.material(
            name,
            MaterialKind::Conductor {
                albedo: albedo.into(),
                texture: None,
                roughness,
                distribution: Microfacet::Ggx,
                fresnel: None,
            },
        )
    }

    /// A dielectric of index of refraction `ior`, smooth when `roughness` is 0.
    pub fn dielectric(self, name: impl Into<String>, ior: f32, roughness: f32) -> Self {
        let (reflectance, transmittance) = (Vec3::ONE, Vec3::ONE);
        self.material(
            name,
            MaterialKind::Dielectric { ior, roughness, distribution: Microfacet::Ggx, reflectance, transmittance },
        )
    }

    fn shape(mut self, geometry: Geometry, material: impl Into<String>) -> Self {
        self.shapes.push(ShapeEntry {
            geometry,
            material: material.into(),
            emission: None,
            emission_two_sided: false,
            velocity: None,
        });
        self
    }

    /// The parallelogram `corner, corner + u, corner + u + v, corner + v`; its front (for
    /// emission) faces along `u x v`.
    pub fn quad(self, corner: impl Into<Vec3>, u: impl Into<Vec3>, v: impl Into<Vec3>, material: impl Into<String>) -> Self {
        let geometry = Geometry::Quad { corner: corner.into(), u: u.into(), v: v.into(), uv_scale: Vec2::ONE };
        self.shape(geometry, material)
    }

    /// A sphere.
    pub fn sphere(self, center: impl Into<Vec3>, radius: f32, material: impl Into<String>) -> Self {
        self.shape(Geometry::Sphere { center: center.into(), radius }, material)
    }

    /// The cube [-1, 1]^3 scaled by `scale` (nonzero), rotated by `rotate` degrees about x,
    /// then y, then z, and moved by `translate`, as a file's `cube` shape.
    pub fn cube(
        self,
        scale: impl Into<Vec3>,
        rotate: impl Into<Vec3>,
        translate: impl Into<Vec3>,
        material: impl Into<String>,
    ) -> Self {
        let geometry = Geometry::Cube { scale: scale.into(), rotate: rotate.into(), translate: translate.into() };
        self.shape(geometry, material)
    }

    /// The triangles of a Wavefront OBJ file under the same transform as
    /// [`SceneBuilder::cube`]; flat-shaded unless [`SceneBuilder::smooth`] follows.
    pub fn mesh(
        self,
        file: impl Into<PathBuf>,
        scale: impl Into<Vec3>,
        rotate: impl Into<Vec3>,
        translate: impl Into<Vec3>,
        material: impl Into<String>,
    ) -> Self {
        let geometry = Geometry::Mesh {
            file: file.into(),
            smooth: false,
            scale: scale.into(),
            rotate: rotate.into(),
            translate: translate.into(),
        };
        self.shape(geometry, material)
    }

    /// Record a misuse of the chain (the first one is reported by `build`).
    fn misuse(&mut self, key: String, message: String) {
        if self.misuse.is_none() {
            self.misuse = Some(SceneError::new(&self.path, None, Some(&key), message));
        }
    }

    /// The last shape added, or a misuse when there is none (or it is not of `kind`).
    fn last_shape(&mut self, what: &str, kind: Option<ShapeKind>) -> Option<&mut ShapeEntry> {
        let index = self.shapes.len();
        match self.shapes.last().map(|s| s.geometry.kind()) {
            None => {
                self.misuse(format!("shapes[{index}].{what}"), format!("`{what}` was given before any shape"));
                None
            }
            Some(actual) if kind.is_some_and(|k| k != actual) => {
                let message = format!("`{what}` applies to a {kind:?} shape, not a {actual:?}", kind = kind.unwrap());
                self.misuse(format!("shapes[{}].{what}", index - 1), message.to_lowercase());
                None
            }
            Some(_) => self.shapes.last_mut(),
        }
    }

    /// Radiance (each channel >= 0) leaving the front of the last shape added: the side of
    /// `u x v` for a quad, outside for a sphere or cube, the winding's side for a mesh.
    pub fn emission(mut self, radiance: impl Into<Vec3>) -> Self {
        if let Some(shape) = self.last_shape("emission", None) {
            shape.emission = Some(radiance.into());
        }
        self
    }

    /// The last shape's emission leaves both of its sides (TOML's `emission_two_sided`).
    pub fn emission_two_sided(mut self) -> Self {
        if let Some(shape) = self.last_shape("emission_two_sided", None) {
            shape.emission_two_sided = true;
        }
        self
    }

    /// Velocity (scene units per shutter) of the last shape added, for motion blur.
    pub fn velocity(mut self, velocity: impl Into<Vec3>) -> Self {
        if let Some(shape) = self.last_shape("velocity", None) {
            shape.velocity = Some(velocity.into());
        }
        self
    }

    /// Texture coordinates (s, t) = `scale` * (a, b) on the last shape added, a quad.
    pub fn uv_scale(mut self, scale: impl Into<Vec2>) -> Self {
        if let Some(shape) = self.last_shape("uv_scale", Some(ShapeKind::Quad)) {
            if let Geometry::Quad { uv_scale, .. } = &mut shape.geometry {
                *uv_scale = scale.into();
            }
        }
        self
    }

    /// Smooth shading normals on the last shape added, a mesh.
    pub fn smooth(mut self, on: bool) -> Self {
        if let Some(shape) = self.last_shape("smooth", Some(ShapeKind::Mesh)) {
            if let Geometry::Mesh { smooth, .. } = &mut shape.geometry {
                *smooth = on;
            }
        }
        self
    }

    /// A light of any kind (a `[[lights]]` entry), checked by [`SceneBuilder::build`] as a
    /// file's is; its direction, if it has one, is made unit length there.
    pub fn light(mut self, kind: LightKind) -> Self {
        self.lights.push(kind);
        self
    }

    /// A point light of radiant `intensity` (W/sr, each channel >= 0).
    pub fn point_light(self, position: impl Into<Vec3>, intensity: impl Into<Vec3>) -> Self {
        self.light(LightKind::Point { position: position.into(), intensity: intensity.into() })
    }

    /// Parallel light travelling along `direction` (nonzero; normalized here), giving
    /// `irradiance` on a surface facing it.
    pub fn directional_light(self, direction: impl Into<Vec3>, irradiance: impl Into<Vec3>) -> Self {
        self.light(LightKind::Directional { direction: direction.into(), irradiance: irradiance.into() })
    }

    /// A constant environment: `radiance` (each channel >= 0) from every direction, at
    /// infinity (Mitsuba 3's `constant`). A scene has at most one.
    pub fn constant_environment(self, radiance: impl Into<Vec3>) -> Self {
        self.light(LightKind::Constant { radiance: radiance.into() })
    }

    /// An environment map (Mitsuba 3's `envmap`, already checked by
    /// [`super::envmap::Envmap::new`]), at infinity. A scene has at most one environment.
    pub fn envmap_environment(self, map: super::envmap::Envmap) -> Self {
        self.light(LightKind::Envmap(std::sync::Arc::new(map)))
    }

    /// A spot light at `position` whose cone's axis points along `direction` (nonzero;
    /// normalized here): radiant `intensity` (W/sr, each channel >= 0) within `beam_width`
    /// degrees of the axis, falling off linearly in the angle to zero at `cutoff_angle`
    /// degrees (in (0, 180]), as Mitsuba 3's `spot` (whose default beam width is 3/4 of the
    /// cutoff); see [`LightKind::Spot`].
    pub fn spot_light(
        self,
        position: impl Into<Vec3>,
        direction: impl Into<Vec3>,
        intensity: impl Into<Vec3>,
        cutoff_angle: f32,
        beam_width: f32,
    ) -> Self {
        self.light(LightKind::Spot {
            position: position.into(),
            direction: direction.into(),
            intensity: intensity.into(),
            cutoff_angle,
            beam_width,
        })
    }

    /// Check everything and make the scene: the first error, with the key it concerns, or
    /// the scene with the same primitives the loader would make from the equivalent file.
    /// Mesh and texture files are read here.
    pub fn build(&self) -> Result<Scene> {
        if let Some(e) = &self.misuse {
            return Err(e.clone());
        }
        let check = Check { path: &self.path };
        let render = check.render(&self.render)?;
        let camera = check.camera(self.camera.as_ref(), self.lens)?;
        let mut textures = Vec::new();
        let mut materials: Vec<Material> = Vec::with_capacity(self.materials.len());
        for entry in &self.materials {
            let name = entry.name();
            let key = format!("materials.{name}");
            if name.is_empty() {
                return Err(check.error(&key, "a material needs a name".into()));
            }
            if materials.iter().any(|m| m.name == name) {
                return Err(check.error(&key, format!("material `{name}` is defined twice")));
            }
            let kind = match entry {
                MaterialEntry::Kind(_, kind) => check.material(&key, kind)?,
                MaterialEntry::Textured(_, file) => {
                    let texture = check.texture(&format!("{key}.texture"), file, &mut textures)?;
                    MaterialKind::Diffuse { albedo: Vec3::ONE, texture: Some(texture) }
                }
            };
            materials.push(Material { name: name.to_owned(), kind, one_sided: false, line: 0 });
        }
        let mut lights = Vec::new();
        for (i, light) in self.lights.iter().enumerate() {
            let kind = check.light(&format!("lights[{i}]"), light)?;
            if let Some(why) = super::emitter::second_environment(&lights, &kind) {
                return Err(check.error(&format!("lights[{i}]"), why));
            }
            lights.push(Light { kind, line: 0 });
        }
        let mut scene = Scene::new(self.path.clone(), render, camera, materials, textures, lights, Vec::new());
        let budget = mesh::PrimitiveBudget::new();
        for (index, entry) in self.shapes.iter().enumerate() {
            let shape = check.shape(index as u32, entry, &mut scene, &budget)?;
            scene.shapes.push(shape);
        }
        if !scene.is_lit() {
            // At the first emission or light given, all zero; with none, where a light goes.
            let key = match (scene.shapes.iter().position(|s| s.emission.is_some()), scene.lights.first()) {
                (Some(i), _) => format!("shapes[{i}].emission"),
                (None, Some(light)) => format!("lights[0].{}", light.kind.brightness_key()),
                (None, None) => "lights".into(),
            };
            return Err(check.error(
                &key,
                "the scene has no light: give a shape an emission greater than zero, or add a point, \
                 directional or spot light with positive intensity or irradiance"
                    .into(),
            ));
        }
        Ok(scene)
    }
}

/// The checks of `build`, each failing with the key in the file's dotted form.
struct Check<'a> {
    path: &'a Path,
}

impl Check<'_> {
    fn error(&self, key: &str, message: String) -> SceneError {
        SceneError::new(self.path, None, Some(key), message)
    }

    fn count(&self, key: &str, n: u32, max: u32) -> Result<u32> {
        if (1..=max).contains(&n) {
            Ok(n)
        } else {
            Err(self.error(key, format!("must be between 1 and {max}, found {n}")))
        }
    }

    fn f64(&self, key: &str, x: f64, bound: Bound) -> Result<f64> {
        match out_of(x, &x, bound) {
            Some(why) => Err(self.error(key, why)),
            None => Ok(x),
        }
    }

    fn f32(&self, key: &str, x: f32, bound: Bound) -> Result<f32> {
        match out_of(x as f64, &x, bound) {
            Some(why) => Err(self.error(key, why)),
            None => Ok(x),
        }
    }

    fn vec3(&self, key: &str, v: Vec3, bound: Bound) -> Result<Vec3> {
        for x in v.to_array() {
            self.f32(key, x, bound)?;
        }
        Ok(v)
    }

    fn render(&self, r: &RenderSettings) -> Result<RenderSettings> {
        self.count("render.width", r.width, MAX_RESOLUTION)?;
        self.count("render.height", r.height, MAX_RESOLUTION)?;
        self.count("render.iterations", r.iterations, u32::MAX)?;
        self.count("render.spp", r.spp, u32::MAX)?;
        self.count("render.photons", r.photons, u32::MAX)?;
        self.count("render.max_depth", r.max_depth, u32::MAX)?;
        if let Some(paths) = r.direct_samples {
            self.count("render.direct_samples", paths, MAX_DIRECT_SAMPLES)?;
        }
        // 0: vcm without light subpaths (RenderSettings::light_paths).
        for (key, share) in [("render.connect_share", r.connect_share), ("render.merge_share", r.merge_share)] {
            if let Some(share) = share {
                self.f32(key, share, Bound::Closed(0.0, 1.0))?;
            }
        }
        if let Some(radius) = r.radius {
            self.f32("render.radius", radius, Bound::Positive)?;
        }
        self.f32("render.alpha", r.alpha, Bound::Open(0.0, 1.0))?;
        if let Some(t) = r.time_limit {
            self.f64("render.time_limit", t, Bound::Positive)?;
        }
        Ok(r.clone())
    }

    fn camera(&self, camera: Option<&Camera>, lens: Option<(f32, f32)>) -> Result<Camera> {
        let mut camera =
            camera.cloned().ok_or_else(|| self.error("camera", "no camera: call .camera(position, look_at, up, fov)".into()))?;
        if let Some((aperture_radius, focus_distance)) = lens {
            camera.aperture_radius = aperture_radius;
            camera.focus_distance = focus_distance;
        }
        super::validate_camera(&camera).map_err(|message| self.error("camera", message))?;
        Ok(camera)
    }

    /// A material's kind, checked by its family ([`MaterialKind::check`]) as a file's is.
    fn material(&self, key: &str, kind: &MaterialKind) -> Result<MaterialKind> {
        if kind.texture().is_some() {
            return Err(
                self.error(&format!("{key}.texture"), "a texture index cannot be given here; use SceneBuilder::textured".into())
            );
        }
        kind.check().map_err(|e| self.error(&format!("{key}.{}", e.key), e.message))?;
        Ok(kind.clone())
    }

    /// Index of the texture `file` names (relative to the scene's directory), read once per
    /// distinct path.
    fn texture(&self, key: &str, file: &Path, textures: &mut Vec<Texture>) -> Result<u32> {
        let path = self.resolve(file);
        if let Some(index) = textures.iter().position(|t| t.path == path) {
            return Ok(index as u32);
        }
        let texture =
            mesh::read_texture(&path).map_err(|e| self.error(key, format!("cannot read texture {}: {e}", path.display())))?;
        textures.push(texture);
        Ok(textures.len() as u32 - 1)
    }

    /// A file name relative to the scene's directory, as the loader resolves them.
    fn resolve(&self, file: &Path) -> PathBuf {
        self.path.parent().unwrap_or(Path::new("")).join(file)
    }

    /// A light, checked by its kind ([`LightKind::check`]) as a file's is, its direction made
    /// unit length.
    fn light(&self, key: &str, light: &LightKind) -> Result<LightKind> {
        light.check().map_err(|e| self.error(&format!("{key}.{}", e.key), e.message))?;
        Ok(light.with_unit_direction())
    }

    fn transform(&self, key: &str, scale: Vec3, rotate: Vec3, translate: Vec3) -> Result<Transform> {
        Ok(Transform::new(
            self.vec3(&format!("{key}.scale"), scale, Bound::NonZero)?,
            self.vec3(&format!("{key}.rotate"), rotate, Bound::Any)?,
            self.vec3(&format!("{key}.translate"), translate, Bound::Any)?,
        ))
    }

    /// Checks `shapes[index]` and appends its primitives to the scene, within `budget`.
    fn shape(&self, index: u32, entry: &ShapeEntry, scene: &mut Scene, budget: &mesh::PrimitiveBudget) -> Result<Shape> {
        let key = format!("shapes[{index}]");
        let material =
            super::material::index(&scene.materials, &entry.material).map_err(|e| self.error(&format!("{key}.material"), e))?;
        let shape = Shape {
            kind: entry.geometry.kind(),
            material,
            emission: entry
                .emission
                .map(|e| super::emitter::check_emission(e).map_err(|e| self.error(&format!("{key}.{}", e.key), e.message)))
                .transpose()?,
            emission_two_sided: entry.emission_two_sided,
            velocity: entry.velocity.map(|v| self.vec3(&format!("{key}.velocity"), v, Bound::Any)).transpose()?,
            line: 0,
            velocity_line: None,
            sphere_frame: None,
            interior: None,
            exterior: None,
        };
        let first_triangle = scene.triangles.len();
        let first_sphere = scene.spheres.len();
        // A warning for skipped degenerate triangles, printed once the shape is accepted.
        let mut warning = None;
        let count = mesh::fixed_primitives(entry.geometry.kind());
        budget.check(super::load::primitives(scene), count, "").map_err(|e| self.error(&key, e))?;
        match entry.geometry {
            Geometry::Quad { corner, u, v, uv_scale } => {
                let corner = self.vec3(&format!("{key}.corner"), corner, Bound::Any)?;
                let u = self.vec3(&format!("{key}.u"), u, Bound::Any)?;
                let v = self.vec3(&format!("{key}.v"), v, Bound::Any)?;
                if u.cross(v).length_squared() == 0.0 {
                    return Err(self.error(&format!("{key}.v"), "u and v are parallel or zero: the quad has no area".into()));
                }
                for x in uv_scale.to_array() {
                    self.f32(&format!("{key}.uv_scale"), x, Bound::Any)?;
                }
                scene.triangles.extend(mesh::quad(corner, u, v, uv_scale, index));
            }
            Geometry::Sphere { center, radius } => scene.spheres.push(Sphere {
                center: self.vec3(&format!("{key}.center"), center, Bound::Any)?,
                radius: self.f32(&format!("{key}.radius"), radius, Bound::Positive)?,
                shape: index,
            }),
            Geometry::Cube { scale, rotate, translate } => {
                let transform = self.transform(&key, scale, rotate, translate)?;
                let (triangles, skipped) = mesh::triangles(&mesh::unit_cube(), &transform, mesh::Normals::Flat, index)
                    .map_err(|e| self.error(&key, e))?;
                let scale_key = format!("{key}.scale");
                if triangles.is_empty() {
                    return Err(self.error(
                        &scale_key,
                        "all 12 triangles of the cube have no area in 32-bit floats (scale too small \
                         for its size, or too small for its distance from the origin)"
                            .into(),
                    ));
                }
                if skipped > 0 {
                    let message = format!("{skipped} of the cube's 12 triangles have no area and are skipped");
                    warning = Some(self.error(&scale_key, message));
                }
                scene.triangles.extend(triangles);
            }
            Geometry::Mesh { ref file, smooth, scale, rotate, translate } => {
                let transform = self.transform(&key, scale, rotate, translate)?;
                let path = self.resolve(file);
                let file_key = format!("{key}.file");
                let obj = mesh::read_obj(&path)
                    .map_err(|e| self.error(&file_key, format!("cannot read mesh {}: {e}", path.display())))?;
                budget
                    .check(super::load::primitives(scene), obj.indices.len() as u64, "")
                    .map_err(|e| self.error(&file_key, e))?;
                let (triangles, skipped) =
                    mesh::triangles(&obj, &transform, if smooth { mesh::Normals::Smooth } else { mesh::Normals::Flat }, index)
                        .map_err(|e| self.error(&key, e))?;
                if triangles.is_empty() {
                    return Err(
                        self.error(&file_key, format!("all {skipped} triangles of mesh {} are degenerate", path.display()))
                    );
                }
                if skipped > 0 {
                    let s = if skipped == 1 { "" } else { "s" };
                    let message = format!("{skipped} degenerate triangle{s} (zero area) skipped in mesh {}", path.display());
                    warning = Some(self.error(&file_key, message));
                }
                scene.triangles.extend(triangles);
            }
        }
        let triangles = &scene.triangles[first_triangle..];
        let spheres = &scene.spheres[first_sphere..];
        mesh::check_extent(triangles, spheres, Vec3::ZERO).map_err(|e| self.error(&key, e))?;
        if let Some(velocity) = shape.velocity {
            mesh::check_extent(triangles, spheres, velocity)
                .map_err(|e| self.error(&format!("{key}.velocity"), format!("moved by its velocity, {e}")))?;
        }
        if matches!(entry.geometry, Geometry::Quad { .. }) && triangles.iter().any(mesh::is_degenerate) {
            return Err(self.error(
                &format!("{key}.corner"),
                "the quad has no area in 32-bit floats: u and v are too small for its distance from the origin".into(),
            ));
        }
        if let Some(warning) = warning {
            eprintln!("warning: {warning}");
        }
        Ok(shape)
    }
}
