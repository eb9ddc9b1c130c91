//! Which optional features a scene uses: one flag per pipeline-overridable constant of the
//! tracing kernels (`override USES_*: bool` in `shaders/shared/`).
//!
//! A kernel compiled with a feature switched off has that code removed by the driver's
//! constant folding. This matters most on CPU drivers: lavapipe runs both sides of every
//! branch, masked, so code for a material or light the scene does not have would otherwise
//! cost time at every bounce. The defaults in WGSL are all `true`: a kernel built without
//! constants handles every scene. Each scene model turns on its own flags
//! (`crate::scene::material`); `crate::gpu` reads a scene's GPU data into them.

/// What a scene's GPU data holds, one flag per `USES_*` override.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Features {
    /// Some triangle (quads, cubes, meshes).
    pub triangles: bool,
    /// Some analytic sphere.
    pub spheres: bool,
    /// Some shape moves over the shutter.
    pub motion: bool,
    /// Some triangle has per-vertex shading normals.
    pub shading_normals: bool,
    /// Some triangle has texture coordinates.
    pub uvs: bool,
    /// Some material has a texture.
    pub textures: bool,
    /// Some material is a smooth conductor (a mirror).
    pub mirror: bool,
    /// Some material is a rough conductor.
    pub glossy: bool,
    /// Some material is a smooth dielectric.
    pub smooth_dielectric: bool,
    /// Some material is a rough dielectric.
    pub rough_dielectric: bool,
    /// Some material is a plastic with a smooth coating.
    pub plastic: bool,
    /// Some material is a plastic with a rough coating.
    pub rough_plastic: bool,
    /// Some material is a thin dielectric.
    pub thin_dielectric: bool,
    /// Some non-dielectric material is one-sided (black seen from behind, as Mitsuba 3's
    /// BSDFs are unless wrapped in `twosided`).
    pub one_sided: bool,
    /// Some conductor has a Fresnel term (a complex index of refraction).
    pub conductor_fresnel: bool,
    /// Some rough conductor, rough dielectric or rough plastic has Beckmann microfacets.
    pub beckmann: bool,
    /// Some emitter is an emitting triangle.
    pub triangle_lights: bool,
    /// Some emitter is an emitting sphere.
    pub sphere_lights: bool,
    /// Some emitter is a point light.
    pub point_lights: bool,
    /// Some emitter is a directional light.
    pub directional_lights: bool,
    /// Some emitter is a spot light.
    pub spot_lights: bool,
    /// The scene has an environment (the last emitter).
    pub environment: bool,
    /// The environment is an image (`envmap`), not a constant.
    pub envmap: bool,
    /// Some shape bounds a participating medium, or the camera sits in one.
    pub media: bool,
}

impl Features {
    /// Every feature on: kernels that handle any scene (the WGSL defaults).
    pub const ALL: Features = Features {
        triangles: true,
        spheres: true,
        motion: true,
        shading_normals: true,
        uvs: true,
        textures: true,
        mirror: true,
        glossy: true,
        smooth_dielectric: true,
        rough_dielectric: true,
        plastic: true,
        rough_plastic: true,
        thin_dielectric: true,
        one_sided: true,
        conductor_fresnel: true,
        beckmann: true,
        triangle_lights: true,
        sphere_lights: true,
        point_lights: true,
        directional_lights: true,
        spot_lights: true,
        environment: true,
        envmap: true,
        media: true,
    };

    /// The pipeline constants: each `USES_*` override with 1.0 (true) or 0.0 (false).
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        [
            ("USES_TRIANGLES", self.triangles),
            ("USES_SPHERES", self.spheres),
            ("USES_MOTION", self.motion),
            ("USES_SHADING_NORMALS", self.shading_normals),
            ("USES_UVS", self.uvs),
            ("USES_TEXTURES", self.textures),
            ("USES_MIRROR", self.mirror),
            ("USES_GLOSSY", self.glossy),
            ("USES_SMOOTH_DIELECTRIC", self.smooth_dielectric),
            ("USES_ROUGH_DIELECTRIC", self.rough_dielectric),
            ("USES_PLASTIC", self.plastic),
            ("USES_ROUGH_PLASTIC", self.rough_plastic),
            ("USES_THIN_DIELECTRIC", self.thin_dielectric),
            ("USES_ONE_SIDED", self.one_sided),
            ("USES_CONDUCTOR_FRESNEL", self.conductor_fresnel),
            ("USES_BECKMANN", self.beckmann),
            ("USES_TRIANGLE_LIGHTS", self.triangle_lights),
            ("USES_SPHERE_LIGHTS", self.sphere_lights),
            ("USES_POINT_LIGHTS", self.point_lights),
            ("USES_DIRECTIONAL_LIGHTS", self.directional_lights),
            ("USES_SPOT_LIGHTS", self.spot_lights),
            ("USES_ENVIRONMENT", self.environment),
            ("USES_ENVMAP", self.envmap),
            ("USES_MEDIA", self.media),
        ]
        .into_iter()
        .map(|(name, on)| (name, if on { 1.0 } else { 0.0 }))
        .collect()
    }
}
