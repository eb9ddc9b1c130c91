//! Homogeneous participating media (issue 35): the scene model, read from our TOML (`[media]`)
//! and from Mitsuba XML (`<medium type="homogeneous">`), and checked. The kernels render them
//! in every method (`shaders/shared/medium.wgsl`).
//!
//! # The model (pbrt-v4's names)
//!
//! A medium fills a region with particles that absorb light with coefficient `sigma_a` and
//! scatter it with coefficient `sigma_s`, per RGB channel, in inverse scene units (1 / the
//! unit of the scene's coordinates), the same everywhere in the region (homogeneous). Along a
//! path of length d the light keeps the fraction exp(-sigma_t d) (transmittance), with the
//! extinction coefficient sigma_t = sigma_a + sigma_s; 1 / sigma_t is the mean free path. The
//! single-scattering albedo sigma_s / sigma_t is the chance that an interaction scatters
//! rather than absorbs. Where a file gives `sigma_t` and `albedo` (Mitsuba's form), sigma_s =
//! albedo sigma_t and sigma_a = sigma_t - sigma_s; a `scale` multiplies both coefficients
//! (Mitsuba's, for coefficients in other units). [`Medium`] holds the coefficients after all
//! of that.
//!
//! Scattered light leaves by the [`Phase`] function: isotropic (1 / 4 pi), or Henyey and
//! Greenstein's (1941) p(cos theta) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos theta)^1.5), theta
//! the angle between the direction the light travelled before and after, g in (-1, 1) the mean
//! cosine: g > 0 scatters forward, g < 0 backward, g = 0 is isotropic (pbrt's and Mitsuba 3's
//! convention).
//!
//! # Where a medium is
//!
//! - Inside a shape: [`Shape::interior`](super::Shape::interior), the medium on the side against its normals; the
//!   shape's surface is the medium's boundary (a dielectric for water or glass holding something
//!   murky, `null` for a boundary that does not bend light). A closed shape holds it; on an open
//!   one (a quad, a disk, an open mesh) it is the medium a path enters crossing the surface
//!   against its normals, as Mitsuba 3 and pbrt-v4 read it: Bitterli's volumetric-caustic fills
//!   a room with fog through its open front's `interface` quad alone.
//! - Outside a shape: [`Shape::exterior`](super::Shape::exterior), the medium on the side its normals point to (as
//!   Mitsuba's `exterior`).
//! - Around the camera: [`Camera::medium`](super::Camera::medium), the medium the camera sits in, such as fog that
//!   fills the whole scene.
//!
//! Media are assigned by boundaries, not by volumes that would have to nest, as in Mitsuba 3
//! and pbrt-v4: a path crossing the surface of a shape that names a medium on either side (a
//! medium transition) enters the shape's interior or exterior, by the side it crosses to,
//! `None` there being a vacuum; crossing (or scattering off) a shape that names neither, the
//! path stays in the medium it was in. So fog around the camera fills the scene, walls and
//! all, and a glass sphere in that fog names the fog as its exterior and no interior (a vacuum
//! inside), or the fog would fill it too.

use glam::Vec3;

/// A homogeneous participating medium (see the module's documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    /// The name shapes and the camera refer to it by: the key of its `[media]` table in TOML,
    /// its `id` in Mitsuba XML (or, for a medium nested without one, where it is).
    pub name: String,
    /// Absorption coefficient per RGB channel, 1 / scene units, >= 0 and finite, after any
    /// scale.
    pub sigma_a: Vec3,
    /// Scattering coefficient per RGB channel, 1 / scene units, >= 0 and finite, after any
    /// scale.
    pub sigma_s: Vec3,
    /// How scattered light is distributed over directions.
    pub phase: Phase,
    /// Line of the medium's table or element in its file (0 where it has none).
    pub line: usize,
}

impl Medium {
    /// The extinction coefficient sigma_a + sigma_s per channel.
    pub fn sigma_t(&self) -> Vec3 {
        self.sigma_a + self.sigma_s
    }

    /// The single-scattering albedo sigma_s / sigma_t per channel (0 where sigma_t is 0).
    pub fn albedo(&self) -> Vec3 {
        let t = self.sigma_t();
        Vec3::select(t.cmpgt(Vec3::ZERO), self.sigma_s / t, Vec3::ZERO)
    }
}

/// A phase function: how a medium scatters light over directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Phase {
    /// The same in every direction, 1 / 4 pi.
    Isotropic,
    /// Henyey and Greenstein's, of mean cosine `g` in (-1, 1); g > 0 scatters forward.
    HenyeyGreenstein {
        /// The mean cosine of the scattering angle.
        g: f32,
    },
}

impl Phase {
    /// Its name as our TOML and Mitsuba name it: `isotropic` or `hg`.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Isotropic => "isotropic",
            Phase::HenyeyGreenstein { .. } => "hg",
        }
    }
}

/// Coefficients from an extinction coefficient `sigma_t` and a single-scattering albedo
/// `albedo`, both scaled by `scale`: (sigma_a, sigma_s) with sigma_s = albedo scale sigma_t
/// and sigma_a = scale sigma_t - sigma_s (a rounding below zero is 0).
pub fn from_extinction(sigma_t: Vec3, albedo: Vec3, scale: f32) -> (Vec3, Vec3) {
    let t = sigma_t * scale;
    let s = albedo * t;
    ((t - s).max(Vec3::ZERO), s)
}

/// Why coefficients are refused, or `None`: each channel must be finite and at least 0.
/// `what` names them (`sigma_a`).
pub fn check_coefficient(what: &str, value: Vec3) -> Option<String> {
    if !value.is_finite() {
        return Some(format!("{what} {value} is not finite (after any scale): coefficients are finite numbers"));
    }
    if value.min_element() < 0.0 {
        return Some(format!("{what} {value} is negative: a medium's coefficients are at least 0 in every channel"));
    }
    None
}

/// Why an albedo is refused, or `None`: each channel in [0, 1] (above 1 would make sigma_a
/// negative: the medium would create light).
pub fn check_albedo(albedo: Vec3) -> Option<String> {
    if !albedo.is_finite() || albedo.min_element() < 0.0 || albedo.max_element() > 1.0 {
        return Some(format!(
            "albedo {albedo} is outside [0, 1]: the single-scattering albedo sigma_s / sigma_t is a fraction (above 1, \
             sigma_a = sigma_t - sigma_s would be negative)"
        ));
    }
    None
}

/// Why a Henyey-Greenstein `g` is refused, or `None`: it must lie in (-1, 1), where the phase
/// function is finite (at |g| = 1 it is a delta).
pub fn check_g(g: f32) -> Option<String> {
    if !(g.is_finite() && g.abs() < 1.0) {
        return Some(format!("g {g} is outside (-1, 1): the Henyey-Greenstein mean cosine must satisfy |g| < 1"));
    }
    None
}
