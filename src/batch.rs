//! A render split into batches of passes, merged: with SPPM's global radius schedule
//! ([`RadiusSchedule::Global`](crate::scene::RadiusSchedule)) or a path tracer, each pass
//! is an estimate of its own drawn from random numbers keyed by its index, and the image is
//! the mean of the passes' estimates. A batch renders passes `first..end` anywhere (another
//! process, GPU or machine) and writes a partial image: the sum of its passes' estimates per
//! pixel, with the pass range and the render's fingerprint in the EXR header, and a checksum
//! of them and the pixels. [`merge`] adds partials of the same render and divides by the
//! passes they hold; a partial altered since it was written, or with a pixel not finite or
//! negative (a sum of estimates cannot be), is refused.
//!
//! Under a splatting filter (the path tracers', bpt's, vcm's and SPPM's camera samples through
//! a tent or gaussian: [`SplatSums`]) the image is not a mean of passes: a partial then also
//! holds the camera samples' weighted sums and weights (channels `splat.R`, `splat.G`,
//! `splat.B`, `splat.W`) and what is averaged by passes apart, bpt's and vcm's light subpaths'
//! splats or SPPM's direct light (`light.R`, `light.G`, `light.B`), and the merge is their
//! sums' ratio plus the light's mean, as one process's.
//!
//! Exactness: a partial holds `mean * count` of its batch in f32, and the merge sums in f64.
//! Against one process rendering all the passes, a pixel differs by the rounding of those
//! products and of the GPU's f32 sums in another order: a few f32 ulps per batch and per
//! pass summed, within `1e-5` relative for renders of up to hundreds of passes
//! (`tests/suite/batch.rs` checks it).

use crate::checkpoint::{Fingerprint, Fnv};
use crate::error::Error;
use crate::image_io::{self, Rgb32Image};
use crate::integrators::SplatSums;
use std::path::{Path, PathBuf};

/// Header names of a partial image's text attributes.
const PASSES: &str = "sppm-gpu passes";
const SETTINGS: &str = "sppm-gpu settings";
const CAMERA: &str = "sppm-gpu camera";
const GEOMETRY: &str = "sppm-gpu geometry";
const APPEARANCE: &str = "sppm-gpu appearance";
const CHECKSUM: &str = "sppm-gpu checksum";

/// A partial's channels beyond R, G and B under a splatting filter: the camera samples' sums
/// and weights, then the light subpaths' sums.
const SPLAT_CHANNELS: [&str; 4] = ["splat.R", "splat.G", "splat.B", "splat.W"];
const LIGHT_CHANNELS: [&str; 3] = ["light.R", "light.G", "light.B"];

/// FNV-1a of a partial's size, pixels, splat sums and `text` attributes (name and value, each
/// length-prefixed), as 16 hex digits.
fn checksum(sum: &Rgb32Image, splat: Option<&SplatSums>, text: &[(&str, &str)]) -> String {
    let mut digest = Fnv::new();
    digest.write(&sum.width.to_le_bytes());
    digest.write(&sum.height.to_le_bytes());
    digest.write_f32s(sum.pixels.iter().flatten().copied());
    if let Some(splat) = splat {
        digest.write_f32s(splat.camera.iter().flatten().copied());
        digest.write_f32s(splat.light.iter().flatten().flat_map(|p| [p[0], p[1], p[2]]));
    }
    for (name, value) in text {
        for s in [name, value] {
            digest.write(&(s.len() as u64).to_le_bytes());
            digest.write(s.as_bytes());
        }
    }
    format!("{:016x}", digest.0)
}

/// A batch's partial image.
#[derive(Clone, Debug)]
pub struct Partial {
    /// Per pixel, the sum of the batch's pass estimates.
    pub sum: Rgb32Image,
    /// The passes it holds: `first..end`.
    pub first: u32,
    /// See `first`.
    pub end: u32,
    /// What it was rendered from.
    pub fingerprint: Fingerprint,
    /// Under a splatting filter, what the batch's image is made of (the light sums' passes
    /// are the batch's).
    pub splat: Option<SplatSums>,
    /// The file it came from (for messages).
    pub path: PathBuf,
}

/// Write the partial of a batch of passes `first..end` whose mean estimate is `mean`, and
/// under a splatting filter the sums it is made of.
pub fn write_partial(
    path: &Path,
    mean: &Rgb32Image,
    splat: Option<&SplatSums>,
    first: u32,
    end: u32,
    fingerprint: &Fingerprint,
) -> Result<(), Error> {
    let count = end
        .checked_sub(first)
        .filter(|&n| n > 0)
        .ok_or_else(|| Error::Setting(format!("{}: a partial needs at least one pass, not {first}..{end}", path.display())))?;
    let sum = Rgb32Image { pixels: mean.pixels.iter().map(|p| p.map(|v| v * count as f32)).collect(), ..mean.clone() };
    let range = format!("{first}..{end}");
    let geometry = format!("{:016x}", fingerprint.geometry);
    let appearance = format!("{:016x}", fingerprint.appearance);
    let text = [
        (PASSES, range.as_str()),
        (SETTINGS, fingerprint.settings.as_str()),
        (CAMERA, fingerprint.camera.as_str()),
        (GEOMETRY, geometry.as_str()),
        (APPEARANCE, appearance.as_str()),
    ];
    let digest = checksum(&sum, splat, &text);
    let text: Vec<(&str, &str)> = text.into_iter().chain([(CHECKSUM, digest.as_str())]).collect();
    let mut planes: Vec<(&str, Vec<f32>)> = Vec::new();
    if let Some(splat) = splat {
        for (c, name) in SPLAT_CHANNELS.iter().enumerate() {
            planes.push((name, splat.camera.iter().map(|p| p[c]).collect()));
        }
        for (c, name) in LIGHT_CHANNELS.iter().enumerate() {
            if let Some(light) = &splat.light {
                planes.push((name, light.iter().map(|p| p[c]).collect()));
            }
        }
    }
    let extra: Vec<(&str, &[f32])> = planes.iter().map(|(n, v)| (*n, v.as_slice())).collect();
    Ok(image_io::write_exr_with_channels(path, &sum, &extra, &text)?)
}

/// Read a partial image written by [`write_partial`].
pub fn read_partial(path: &Path) -> Result<Partial, Error> {
    // The pixels, the splat sums and the header in one read.
    let names: Vec<&str> = ["R", "G", "B"].iter().chain(&SPLAT_CHANNELS).chain(&LIGHT_CHANNELS).copied().collect();
    let image_io::ExrChannels { planes, width, height, text } = image_io::read_exr_channels(path, &names)?;
    let (rgb, splat_planes) = planes.split_at(3);
    let [Some(r), Some(g), Some(b)] = rgb else {
        return Err(Error::Setting(format!("{}: not a partial image of sppm-gpu (no R, G and B channels)", path.display())));
    };
    let sum = Rgb32Image { width, height, pixels: r.iter().zip(g).zip(b).map(|((r, g), b)| [*r, *g, *b]).collect() };
    let get = |name: &str| -> Result<&str, Error> {
        text.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str()).ok_or_else(|| {
            Error::Setting(format!("{}: not a partial image of sppm-gpu (no `{name}` in its header)", path.display()))
        })
    };
    let bad = |what: &str| Error::Setting(format!("{}: the partial's `{what}` is malformed", path.display()));
    let names = [PASSES, SETTINGS, CAMERA, GEOMETRY, APPEARANCE];
    let text_of = names.iter().map(|&n| Ok((n, get(n)?))).collect::<Result<Vec<_>, Error>>()?;
    let stored = get(CHECKSUM).map_err(|_| {
        Error::Setting(format!(
            "{}: the partial has no `{CHECKSUM}` in its header: not written by this version of sppm-gpu; render the batch again",
            path.display()
        ))
    })?;
    let mut splat = splat_of(path, splat_planes, sum.pixels.len())?;
    if checksum(&sum, splat.as_ref(), &text_of) != stored {
        return Err(Error::Setting(format!(
            "{}: the partial is corrupt: checksum mismatch (its pixels or header changed since it was written)",
            path.display()
        )));
    }
    let (first, end) = get(PASSES)?.split_once("..").ok_or_else(|| bad(PASSES))?;
    let first: u32 = first.parse().map_err(|_| bad(PASSES))?;
    let end: u32 = end.parse().map_err(|_| bad(PASSES))?;
    if end <= first {
        return Err(bad(PASSES));
    }
    let digest = |name: &str| u64::from_str_radix(get(name)?, 16).map_err(|_| bad(name));
    let fingerprint = Fingerprint {
        settings: get(SETTINGS)?.to_string(),
        camera: get(CAMERA)?.to_string(),
        geometry: digest(GEOMETRY)?,
        appearance: digest(APPEARANCE)?,
    };
    for light in splat.iter_mut().flat_map(|s| s.light.iter_mut()).flatten() {
        light[3] = (end - first) as f32;
    }
    Ok(Partial { sum, first, end, fingerprint, splat, path: path.to_path_buf() })
}

/// A partial's splat sums from its `splat.*` and `light.*` planes (in that order), where it
/// has them: the `splat.*` channels all or none, the light channels all or none (their passes,
/// the batch's, set by the caller).
fn splat_of(path: &Path, planes: &[Option<Vec<f32>>], pixels: usize) -> Result<Option<SplatSums>, Error> {
    let (camera, light) = planes.split_at(SPLAT_CHANNELS.len());
    let all = |planes: &[Option<Vec<f32>>]| -> Result<Option<Vec<Vec<f32>>>, Error> {
        match planes.iter().filter(|p| p.is_some()).count() {
            0 => Ok(None),
            n if n == planes.len() => Ok(Some(planes.iter().flatten().cloned().collect())),
            _ => {
                Err(Error::Setting(format!("{}: the partial is corrupt: some of its splat channels are missing", path.display())))
            }
        }
    };
    let Some(camera) = all(camera)? else { return Ok(None) };
    let camera = (0..pixels).map(|i| [camera[0][i], camera[1][i], camera[2][i], camera[3][i]]).collect();
    let light = all(light)?.map(|l| (0..pixels).map(|i| [l[0][i], l[1][i], l[2][i], 0.0]).collect());
    Ok(Some(SplatSums { camera, light }))
}

/// Errors naming the first pixel of `part` (row by row) that is not finite or is negative: a
/// sum of non-negative estimates is neither.
fn check_pixels(part: &Partial) -> Result<(), Error> {
    let bad = |v: &f32| !(v.is_finite() && *v >= 0.0);
    if let Some(splat) = &part.splat {
        let mut planes = splat.camera.iter().chain(splat.light.iter().flatten());
        if planes.any(|p| p.iter().any(bad)) {
            return Err(Error::Setting(format!(
                "{}: a splat sum of the partial is not finite or is negative: sums of weights and samples must be neither",
                part.path.display()
            )));
        }
    }
    let Some(i) = part.sum.pixels.iter().position(|p| p.iter().any(bad)) else {
        return Ok(());
    };
    let (x, y) = (i % part.sum.width.max(1) as usize, i / part.sum.width.max(1) as usize);
    Err(Error::Setting(format!(
        "{}: pixel ({x}, {y}) of the partial is {:?}: a sum of estimates must be finite and non-negative",
        part.path.display(),
        part.sum.pixels[i]
    )))
}

/// The merged image of `parts`, and warnings (passes missing between them). Errors when
/// they come from different renders, differ in size, or share a pass.
pub fn merge(parts: &[Partial]) -> Result<(Rgb32Image, Vec<String>), Error> {
    let Some(head) = parts.first() else {
        return Err(Error::Setting("nothing to merge: give the partial images".into()));
    };
    for p in parts {
        check_pixels(p)?;
    }
    for p in &parts[1..] {
        head.fingerprint.check(&p.fingerprint).map_err(|e| {
            Error::Setting(format!("{} and {}: not batches of one render: {e}", head.path.display(), p.path.display()))
        })?;
        if (p.sum.width, p.sum.height) != (head.sum.width, head.sum.height) {
            return Err(Error::Setting(format!("{} and {}: the images differ in size", head.path.display(), p.path.display())));
        }
    }
    let mut order: Vec<&Partial> = parts.iter().collect();
    order.sort_by_key(|p| (p.first, p.end));
    let mut warnings = Vec::new();
    // The part reaching furthest so far, and where it ends.
    let mut reach: Option<&Partial> = None;
    for p in order.iter().copied() {
        let next = reach.map_or(0, |r| r.end);
        if let Some(r) = reach.filter(|_| p.first < next) {
            return Err(Error::Setting(format!(
                "{} (passes {}..{}) and {} (passes {}..{}) share passes: each pass must be in one part",
                r.path.display(),
                r.first,
                r.end,
                p.path.display(),
                p.first,
                p.end
            )));
        }
        if p.first > next {
            warnings.push(format!("passes {next}..{} are in no part: the image is the mean of the passes present", p.first));
        }
        reach = Some(p);
    }
    let count: u64 = parts.iter().map(|p| (p.end - p.first) as u64).sum();
    let splatted = parts.iter().filter(|p| p.splat.is_some()).count();
    if splatted == parts.len() {
        return Ok((merge_splats(&order, head, count), warnings));
    } else if splatted > 0 {
        return Err(Error::Setting(format!(
            "{}: some partials hold splat sums and some do not: not batches of one render",
            head.path.display()
        )));
    }
    let mut total = vec![[0f64; 3]; head.sum.pixels.len()];
    for p in &order {
        for (t, s) in total.iter_mut().zip(&p.sum.pixels) {
            for c in 0..3 {
                t[c] += s[c] as f64;
            }
        }
    }
    let pixels = total.iter().map(|t| t.map(|v| (v / count as f64) as f32)).collect();
    Ok((Rgb32Image { width: head.sum.width, height: head.sum.height, pixels }, warnings))
}

/// The merge of partials under a splatting filter (each with [`SplatSums`]), `count` passes
/// among them: per pixel the camera samples' weighted sums over their weights, plus the light
/// subpaths' sums over the passes, in f64.
fn merge_splats(parts: &[&Partial], head: &Partial, count: u64) -> Rgb32Image {
    let pixels = head.sum.pixels.len();
    let (mut camera, mut light) = (vec![[0f64; 4]; pixels], vec![[0f64; 3]; pixels]);
    for p in parts {
        let splat = p.splat.as_ref().expect("every part splatted");
        for (t, s) in camera.iter_mut().zip(&splat.camera) {
            for c in 0..4 {
                t[c] += s[c] as f64;
            }
        }
        for (t, s) in light.iter_mut().zip(splat.light.iter().flatten()) {
            for c in 0..3 {
                t[c] += s[c] as f64;
            }
        }
    }
    let pixels = camera
        .iter()
        .zip(&light)
        .map(|(c, l)| {
            let w = c[3];
            std::array::from_fn(|i| ((if w > 0.0 { c[i] / w } else { 0.0 }) + l[i] / count as f64) as f32)
        })
        .collect();
    Rgb32Image { width: head.sum.width, height: head.sum.height, pixels }
}
