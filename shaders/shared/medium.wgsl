// Homogeneous participating media (src/scene/medium.rs): absorption sigma_a and scattering
// sigma_s per RGB channel, extinction sigma_t = sigma_a + sigma_s, and a Henyey-Greenstein phase
// function of mean cosine g (0: isotropic). Camera paths and photons sample where they next
// interact along a segment (sample_flight); at a scattering event the phase function takes the
// place of a BSDF. Media are assigned by boundaries: a path that crosses a shape with a medium
// inside or outside it enters the medium of the side it crosses to (medium_after); the camera
// sits in CAMERA_MEDIUM, and photons leave an area light into its shape's exterior medium,
// any other light into CAMERA_MEDIUM.
//
// Medium m's coefficients are two entries of `attributes` from MEDIA_FIRST + 2 m: (sigma_a, g)
// and (sigma_s, 0). Only scenes with media compile this in (USES_MEDIA, shared/types.wgsl).

#import types
#import sampling
#import scene

// The first entry of the media in `attributes`, and the camera's medium (NO_MEDIUM: vacuum).
override MEDIA_FIRST: u32 = 0u;
override CAMERA_MEDIUM: u32 = 0xffffu;

// No medium: a vacuum. Shape.media holds the interior's index in its low 16 bits and the
// exterior's in its high 16, NO_MEDIUM where none is given; 0xffffffff when neither is (the
// shape is no boundary: paths keep their medium across it).
const NO_MEDIUM: u32 = 0xffffu;

const INV_4PI: f32 = 0.0795774715459477;

struct MediumCoefficients {
    sigma_a: vec3f,
    g: f32,
    sigma_s: vec3f,
}

fn medium_coefficients(m: u32) -> MediumCoefficients {
    let a = attributes[MEDIA_FIRST + 2u * m];
    let s = attributes[MEDIA_FIRST + 2u * m + 1u];
    return MediumCoefficients(a.xyz, a.w, s.xyz);
}

// The medium a path is in after leaving surface s from direction of travel d along wi: the
// crossed shape's interior or exterior, by the side wi goes to (against the geometric normal:
// inside), as Mitsuba 3's target_medium; `current` where it reflects, or where the shape is no
// boundary.
fn medium_after(current: u32, s: Surface, d: vec3f, wi: vec3f) -> u32 {
    let media = shapes[s.shape].media;
    if !USES_MEDIA || media == 0xffffffffu || dot(wi, s.ng) * dot(d, s.ng) <= 0.0 {
        return current;
    }
    return select(media >> 16u, media & 0xffffu, dot(wi, s.ng) < 0.0);
}

// The fraction exp(-sigma_t dist) of light that crosses dist of medium m (1 in a vacuum).
fn medium_transmittance(m: u32, dist: f32) -> vec3f {
    if !USES_MEDIA || m == NO_MEDIUM {
        return vec3f(1.0);
    }
    let c = medium_coefficients(m);
    return exp(-(c.sigma_a + c.sigma_s) * dist);
}

// Where a segment of length t_max (3.4e38: it escapes) through a medium next interacts.
struct Flight {
    // Distance to the interaction, when `scattered`.
    t: f32,
    scattered: bool,
    // Interaction: Tr(t) / p(t), to be multiplied by sigma_s (a path scattering there) or not
    // (a photon's track-length deposit); passing: Tr(t_max) / P(no interaction).
    weight: vec3f,
}

// Free-flight sampling with chromatic extinction, unbiased by one-sample MIS over the channels
// (the balance heuristic; Wilkie et al. 2014, "Hero Wavelength Spectral Sampling", and pbrt-v4
// sec. 14.2.2): a channel c is chosen uniformly (u.x) and t drawn from sigma_t[c]
// exp(-sigma_t[c] t) (u.y); the density of t is the mean over channels,
//   p(t) = (1/3) sum_c sigma_t[c] exp(-sigma_t[c] t),  P(none before t_max) = (1/3) sum_c Tr_c(t_max).
fn sample_flight(c: MediumCoefficients, t_max: f32, u: vec2f) -> Flight {
    let sigma_t = c.sigma_a + c.sigma_s;
    let channel = min(u32(u.x * 3.0), 2u);
    let st = sigma_t[channel];
    let t = select(3.4e38, -log(1.0 - u.y) / st, st > 0.0);
    if t < t_max {
        let tr = exp(-sigma_t * t);
        let pdf = dot(sigma_t * tr, vec3f(1.0 / 3.0));
        return Flight(t, true, select(vec3f(0.0), tr / pdf, pdf > 0.0));
    }
    let tr = exp(-sigma_t * min(t_max, 3.4e38));
    let p_none = dot(tr, vec3f(1.0 / 3.0));
    return Flight(t_max, false, select(vec3f(0.0), tr / p_none, p_none > 0.0));
}

// Henyey and Greenstein's phase function (1941) at the cosine between the directions of
// travel before and after scattering: (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^1.5); 1 / 4 pi at
// g = 0.
fn phase_hg(cos_theta: f32, g: f32) -> f32 {
    let denom = 1.0 + g * g - 2.0 * g * cos_theta;
    return INV_4PI * (1.0 - g * g) / (denom * sqrt(max(denom, 1e-12)));
}

// A direction of travel after scattering from travel direction d, with density
// phase_hg(dot(d, wi), g): the inverse of the cosine's distribution function,
//   cos = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g),
// (1 - 2u at g = 0), and a uniform azimuth about d.
fn sample_phase(d: vec3f, g: f32, u: vec2f) -> vec3f {
    var cos_t = 1.0 - 2.0 * u.x;
    if abs(g) > 1e-3 {
        let sq = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
        cos_t = clamp((1.0 + g * g - sq * sq) / (2.0 * g), -1.0, 1.0);
    }
    let sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
    let phi = 2.0 * PI * u.y;
    return normalize(basis(d) * vec3f(sin_t * cos(phi), sin_t * sin(phi), cos_t));
}
