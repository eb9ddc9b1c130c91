// What every emitter kind returns: a light sample seen from a receiving point (next-event
// estimation) and a photon leaving the light (SPPM's photon pass).

// A light sample seen from a receiving point (pbrt-v4 sec. 12.2, LightLiSample).
struct LightSample {
    // Unit direction from the receiver towards the light, and the distance to it (3.4e38
    // for a directional light or the environment).
    wi: vec3f,
    dist: f32,
    // Incident radiance over the sample's density: Le / pdf for an area light, I / (d^2 pmf)
    // for a point light (times the falloff for a spot light), E / pmf for a directional one,
    // L / pdf for the environment; zero when the sample is unusable.
    li: vec3f,
    // Solid-angle density of wi, the choice of light included; 0 for a delta light.
    pdf: f32,
    // Where the shadow ray ends: the light point, offset off an area light towards the
    // receiver (pbrt-v4 sec. 6.8.6, SpawnRayTo), or far along wi for a directional light
    // and the environment.
    p_light: vec3f,
    // Cosine between -wi and an area light's normal at the point; 0 for other lights.
    cos_l: f32,
}

// A photon leaving a light: its origin, direction of travel, flux over the total power
// (beta = Le cos / (pmf pdf(position) pdf(direction)) / power_total) and the medium it starts
// in (shared/medium.wgsl).
struct EmittedPhoton {
    o: vec3f,
    d: vec3f,
    beta: vec3f,
    medium: u32,
    // From an area light, its normal where the photon leaves (a light tracer joins that
    // point to the camera); zero from the other lights, which no camera sees.
    n: vec3f,
}

// What the bidirectional methods' MIS (shared/vcm.wgsl) needs of a light at one of its points:
// the densities with which next-event estimation picks the point (direct_pdf_a, area measure,
// the light's choice included; its pmf for a delta light) and a light subpath leaves it in a
// direction (emission_pdf_w: point and direction, solid angle for the direction), the cosine
// between that direction and the light's normal (1 for lights without a surface), whether
// the light is a delta light that no ray can hit, and whether it lies at a finite distance (a
// directional light does not: its emission density is per unit area of its disk, and its
// first segment's length does not enter the MIS quantities; SmallVCM's isFinite).
struct EmissionPdfs {
    direct_pdf_a: f32,
    emission_pdf_w: f32,
    cos_light: f32,
    delta: bool,
    finite: bool,
}
