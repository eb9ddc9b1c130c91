// Spot lights (EMITTER_SPOT; Mitsuba 3's `spot`, pbrt-v4's SpotLight): a point that emits
// intensity I (W/sr) within the beam width b of its axis, falling off linearly in the angle
// from there to zero at the cutoff angle c (Mitsuba 3's falloff; src/scene/emitter/spot.rs,
// spot_falloff), dark beyond; power I Omega, Omega the falloff's integral over directions.
// Parameters (the Emitter record): `position`; `direction`, the axis; `radiance`, I on the
// axis; `radius`, the cutoff c (radians); `width`, c - b (0: a hard edge); `area`, Omega.

#import types
#import sampling
#import medium
#import emitter/light_sample

const EMITTER_SPOT: u32 = 3u;

// The scene has spot lights (src/scene/emitter/spot.rs).
override USES_SPOT_LIGHTS: bool = true;

// Mitsuba 3's spot falloff in unit direction d leaving spot light e: 1 within the beam width
// of its axis, then linear in the angle theta from the axis down to 0 at the cutoff angle
// (e.radius), over the width e.width; 0 beyond. theta by atan2 of |d x axis| and d . axis,
// accurate at every angle, where acos(d . axis) loses half the digits near the axis.
fn spot_falloff(e: Emitter, d: vec3f) -> f32 {
    let theta = atan2(length(cross(d, e.direction)), dot(d, e.direction));
    let ramp = (e.radius - theta) / max(e.width, 1e-30);
    return select(select(ramp, 1.0, theta <= e.radius - e.width), 0.0, theta >= e.radius);
}

// Spot light e seen from p: a point light whose intensity in direction -wi is I times the
// falloff.
fn spot_sample(e: Emitter, p: vec3f, u: vec3f) -> LightSample {
    let to = e.position - p;
    let dist = length(to);
    let wi = to / dist;
    return LightSample(wi, dist, e.radiance * (spot_falloff(e, -wi) / (dist * dist * e.pmf)), 0.0, e.position, 0.0);
}

// A direction leaving spot light e and its weight: intensity times falloff over the
// direction's density, divided by the intensity I on the axis. Two parts, chosen by u_part:
// the cone of full intensity (half-angle b = cutoff - width) with probability P_beam =
// A / Omega, A = 2 pi (1 - cos b) = 4 pi sin^2(b / 2) its solid angle and Omega (e.area) the
// falloff's integral, and the ring of falloff otherwise. In the cone directions are uniform
// (density 1 / A), weight A / P_beam. In the ring phi = cutoff - theta is drawn with density
// 2 phi / w^2 on [0, w] (phi = w sqrt(u), w = e.width), proportional to the falloff phi / w;
// over solid angle that is 2 phi / (w^2 2 pi sin(theta)), so the weight, falloff over density
// over (1 - P_beam), is pi w sin(theta) / (1 - P_beam), nearly constant across the ring
// (sin(theta) from sin(b) to sin(cutoff)). Both parts divide by the probability actually used,
// so rounding in P_beam biases nothing.
struct SpotDirection {
    d: vec3f,
    weight: f32,
}

fn spot_direction(e: Emitter, u_part: f32, u: vec2f) -> SpotDirection {
    let half_beam = 0.5 * max(e.radius - e.width, 0.0);
    let sin_half = sin(half_beam);
    // 1 - cos b, without the cancellation of 1 - cos near b = 0.
    let one_minus_cos_b = 2.0 * sin_half * sin_half;
    let beam_solid_angle = 2.0 * PI * one_minus_cos_b;
    let p_beam = min(beam_solid_angle / e.area, 1.0);
    var cos_theta: f32;
    var sin_theta: f32;
    var weight: f32;
    if u_part < p_beam {
        let one_minus_cos = u.x * one_minus_cos_b;
        cos_theta = 1.0 - one_minus_cos;
        sin_theta = sqrt(max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
        weight = beam_solid_angle / p_beam;
    } else {
        let theta = e.radius - e.width * sqrt(u.x);
        cos_theta = cos(theta);
        sin_theta = max(sin(theta), 0.0);
        weight = PI * e.width * sin_theta / (1.0 - p_beam);
    }
    let phi = 2.0 * PI * u.y;
    let d = basis(e.direction) * vec3f(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
    return SpotDirection(d, weight);
}

// A photon leaving spot light e along spot_direction: flux I weight, times `scale`.
fn spot_emit(e: Emitter, u_pos: vec2f, u_dir: vec2f, scale: f32) -> EmittedPhoton {
    let s = spot_direction(e, u_pos.x, u_dir);
    return EmittedPhoton(e.position, s.d, e.radiance * (s.weight * scale), CAMERA_MEDIUM, vec3f(0.0));
}

// The density with which spot_direction draws unit direction d (solid angle): p_beam / A in
// the cone of full intensity, (1 - p_beam) 2 phi / (w^2 2 pi sin(theta)) in the ring of
// falloff (phi = cutoff - theta), 0 beyond the cutoff.
fn spot_direction_pdf(e: Emitter, d: vec3f) -> f32 {
    let theta = atan2(length(cross(d, e.direction)), dot(d, e.direction));
    if theta >= e.radius {
        return 0.0;
    }
    let half_beam = 0.5 * max(e.radius - e.width, 0.0);
    let sin_half = sin(half_beam);
    let beam_solid_angle = 4.0 * PI * sin_half * sin_half;
    let p_beam = min(beam_solid_angle / e.area, 1.0);
    if theta <= e.radius - e.width {
        return p_beam / beam_solid_angle;
    }
    let phi = e.radius - theta;
    return (1.0 - p_beam) * phi / (e.width * e.width * PI * max(sin(theta), 1e-8));
}

// The MIS densities of spot light e emitting along d (EmissionPdfs): the point with its
// choice's probability, the direction spot_direction's; a delta light.
fn spot_emission_pdfs(e: Emitter, d: vec3f) -> EmissionPdfs {
    return EmissionPdfs(e.pmf, e.pmf * spot_direction_pdf(e, d), 1.0, true, true);
}
