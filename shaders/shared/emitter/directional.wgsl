// Directional lights (EMITTER_DIRECTIONAL; Mitsuba 3's `directional`, pbrt-v4's
// DistantLight): parallel light travelling along a direction, irradiance E on a surface facing
// it. Its photons leave a disk facing it that covers the scene's bounding sphere, radius R,
// placed outside it; power E pi R^2.
// Parameters (the Emitter record): `direction` of travel; `radiance`, the irradiance E;
// `position`, the disk's centre; `radius` R; `area`, pi R^2.

#import types
#import sampling
#import medium
#import emitter/light_sample

const EMITTER_DIRECTIONAL: u32 = 2u;

// The scene has directional lights (src/scene/emitter/directional.rs).
override USES_DIRECTIONAL_LIGHTS: bool = true;

// Directional light e seen from p: E / pmf from -direction, the shadow ray ending past the
// disk, which encloses the scene.
fn directional_sample(e: Emitter, p: vec3f, u: vec3f) -> LightSample {
    let wi = -e.direction;
    let far = 2.0 * e.radius + length(p - e.position);
    return LightSample(wi, 3.4e38, e.radiance / e.pmf, 0.0, p + far * wi, 0.0);
}

// A photon leaving directional light e from a point uniform on its disk: E / (1 / disk area).
fn directional_emit(e: Emitter, u_pos: vec2f, u_dir: vec2f, scale: f32) -> EmittedPhoton {
    let b = basis(e.direction);
    let q = e.radius * sample_disk(u_pos);
    let p = e.position + b[0] * q.x + b[1] * q.y;
    return EmittedPhoton(p, e.direction, e.radiance * (e.area * scale), CAMERA_MEDIUM, vec3f(0.0));
}

// The MIS densities of directional light e (EmissionPdfs): a delta direction with its
// choice's probability, a point uniform on its disk of area e.area; at infinity.
fn directional_emission_pdfs(e: Emitter) -> EmissionPdfs {
    return EmissionPdfs(e.pmf, e.pmf / e.area, 1.0, true, false);
}
