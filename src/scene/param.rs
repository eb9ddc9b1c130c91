//! A parameter's range and the check of a value against it: the one wording of a value out of
//! range, which every reader (the TOML file, Mitsuba's XML, [`super::SceneBuilder`]) reports
//! at its own place. Each model checks its parameters once, in its file
//! ([`super::material`], [`super::emitter`]), naming them as a TOML scene does.

use glam::Vec3;
use std::fmt;

/// A range that a number must lie in.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Bound {
    Any,
    Positive,
    NonNegative,
    NonZero,
    /// Strictly between the two.
    Open(f64, f64),
    /// Between the two, inclusive.
    Closed(f64, f64),
}

/// Reflectances and roughnesses lie in [0, 1].
pub(crate) const UNIT: Bound = Bound::Closed(0.0, 1.0);

impl Bound {
    pub(crate) fn contains(self, x: f64) -> bool {
        match self {
            Bound::Any => true,
            Bound::Positive => x > 0.0,
            Bound::NonNegative => x >= 0.0,
            Bound::NonZero => x != 0.0,
            Bound::Open(low, high) => low < x && x < high,
            Bound::Closed(low, high) => low <= x && x <= high,
        }
    }
}

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Bound::Any => write!(f, "a number"),
            Bound::Positive => write!(f, "greater than 0"),
            Bound::NonNegative => write!(f, "at least 0"),
            Bound::NonZero => write!(f, "nonzero"),
            Bound::Open(low, high) => write!(f, "greater than {low} and less than {high}"),
            Bound::Closed(low, high) => write!(f, "between {low} and {high}"),
        }
    }
}

/// A parameter that a model's check refuses: its key, as a TOML scene names it (`roughness`),
/// and why. Each reader puts it at its own place: the key's line in a TOML file, the
/// parameter Mitsuba names it by, the builder's dotted key.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Invalid {
    pub key: &'static str,
    /// The channel of a colour or vector that is out, where it is one.
    pub channel: Option<usize>,
    pub message: String,
}

impl Invalid {
    pub(crate) fn new(key: &'static str, message: impl Into<String>) -> Self {
        Invalid { key, channel: None, message: message.into() }
    }
}

/// Why `x` (as written: `shown`) lies outside `bound`, if it does.
pub(crate) fn out_of(x: f64, shown: &dyn fmt::Display, bound: Bound) -> Option<String> {
    if !x.is_finite() {
        Some(format!("must be a finite number, found {shown}"))
    } else if !bound.contains(x) {
        Some(format!("must be {bound}, found {shown}"))
    } else {
        None
    }
}

/// `x`, when it is finite and within `bound`.
pub(crate) fn float(key: &'static str, x: f32, bound: Bound) -> Result<f32, Invalid> {
    match out_of(x as f64, &x, bound) {
        Some(why) => Err(Invalid::new(key, why)),
        None => Ok(x),
    }
}

/// `v`, when each channel is finite and within `bound`.
pub(crate) fn rgb(key: &'static str, v: Vec3, bound: Bound) -> Result<Vec3, Invalid> {
    for (channel, x) in v.to_array().into_iter().enumerate() {
        float(key, x, bound).map_err(|e| Invalid { channel: Some(channel), ..e })?;
    }
    Ok(v)
}

/// A unit direction along `v`, normalized in f64 so that no finite vector over- or
/// underflows to zero; an error for a zero or infinite one.
pub(crate) fn direction(key: &'static str, v: Vec3) -> Result<Vec3, Invalid> {
    let unit = rgb(key, v, Bound::Any)?.as_dvec3().normalize_or_zero().as_vec3();
    if unit == Vec3::ZERO {
        return Err(Invalid::new(key, "the direction must not be zero"));
    }
    Ok(unit)
}

/// A value for a message, exactly: as written for moderate magnitudes (`4`, `0.5`), else in
/// exponent form (`1e37`, `4.2535296e37`).
pub fn number(x: f32) -> String {
    if x == 0.0 || (1e-3..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
