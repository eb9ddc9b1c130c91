// Point lights (EMITTER_POINT; Mitsuba 3's `point`, pbrt-v4's PointLight): radiant intensity
// I (W/sr) from a point, the same in every direction; power 4 pi I.
// Parameters (the Emitter record): `position`; `radiance`, the intensity I.

#import types
#import sampling
#import medium
#import emitter/light_sample

const EMITTER_POINT: u32 = 1u;

// The scene has point lights (src/scene/emitter/point.rs).
override USES_POINT_LIGHTS: bool = true;

// Point light e seen from p: irradiance I / d^2 over the choice's probability pmf.
fn point_sample(e: Emitter, p: vec3f, u: vec3f) -> LightSample {
    let to = e.position - p;
    let dist = length(to);
    return LightSample(to / dist, dist, e.radiance / (dist * dist * e.pmf), 0.0, e.position, 0.0);
}

// A photon leaving point light e in a uniform direction: I / (1 / 4 pi), times `scale`, 1 over
// the power of the light's choice.
fn point_emit(e: Emitter, u_pos: vec2f, u_dir: vec2f, scale: f32) -> EmittedPhoton {
    return EmittedPhoton(e.position, sample_uniform_sphere(u_dir), e.radiance * (4.0 * PI * scale), CAMERA_MEDIUM, vec3f(0.0));
}

// The MIS densities of point light e (EmissionPdfs): the point itself with its choice's
// probability, a uniform direction 1 / 4 pi; a delta light.
fn point_emission_pdfs(e: Emitter) -> EmissionPdfs {
    return EmissionPdfs(e.pmf, e.pmf * INV_4PI, 1.0, true, true);
}
