//! Checkpoints: a render's state written to a file, so that a run stopped by a fault, a
//! signal or the user goes on later from where it was.
//!
//! A checkpoint holds an integrator's [`state`](crate::integrators::Integrator::state) and a
//! fingerprint of what made it: the settings that shape the image (not `iterations` or
//! `time_limit`, which a resumed run may change), the camera, and digests of the geometry
//! and of the materials, textures, shapes and lights. Resuming from a checkpoint of another
//! scene or other settings is refused, naming what differs. Files are written whole to a
//! temporary file beside the target and renamed over it, so a process killed while writing
//! leaves the previous checkpoint intact.
//!
//! Where vcm's pilot chose the render's strategies, the checkpoint keeps its choice, and a
//! render resumed from it renders that choice without a pilot: under a time limit the pilot's
//! choice depends on the passes that fit (`crate::integrators::shares::representative_pass`),
//! and a resumed run has another limit.
//!
//! Layout: `SPPMGPU-CHECKPOINT`, a format version (u32), then length-prefixed (u64, little
//! endian) fields: the settings text, the camera text, the two digests (u64 each), the state,
//! and (from version 3) the pilot's choice as text (empty where none chose); last, the FNV-1a
//! digest (u64) of every byte before it. A file whose digest differs, or with bytes after it,
//! is refused as corrupt; the integrator checks the state itself on
//! [`restore`](crate::integrators::Integrator::restore). Version 2 (no choice) is read too.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::Error;
use crate::scene::Scene;

/// The bytes a checkpoint starts with.
pub const MAGIC: &[u8] = b"SPPMGPU-CHECKPOINT";
const VERSION: u32 = 3;

/// A checkpoint: what made the render, its state, and vcm's pilot's choice.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Checkpoint {
    /// What the render was made from.
    pub fingerprint: Fingerprint,
    /// The integrator's state ([`crate::integrators::Integrator::state`]).
    pub state: Vec<u8>,
    /// vcm's pilot's choice (`crate::integrators::shares::Choice` as text), where one chose.
    pub pilot: Option<String>,
}

/// What a checkpoint was made from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fingerprint {
    /// `key = value` lines of the settings that shape the image.
    pub settings: String,
    /// The camera, as text.
    pub camera: String,
    /// Digest of every triangle and sphere.
    pub geometry: u64,
    /// Digest of the materials, textures, shapes and lights.
    pub appearance: u64,
}

/// 64-bit FNV-1a (Fowler, Noll and Vo): a fixed function, so that digests agree between runs
/// and builds.
pub(crate) struct Fnv(pub(crate) u64);

impl Fnv {
    pub(crate) fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    pub(crate) fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    pub(crate) fn write_f32s(&mut self, values: impl IntoIterator<Item = f32>) {
        for v in values {
            self.write(&v.to_bits().to_le_bytes());
        }
    }
}

impl Fingerprint {
    /// The fingerprint of `scene` with its current settings.
    pub fn of(scene: &Scene) -> Self {
        let r = &scene.render;
        let settings = format!(
            "width = {}\nheight = {}\nmethod = {:?}\nspp = {}\nphotons = {}\nradius = {:?}\nalpha = {}\nmax_depth = {}\n\
             seed = {}\ndirect = {:?}\ndirect_samples = {:?}\nlight_paths = {:?}\nradius_schedule = {:?}\nradius_rule = {:?}\nfilter = {:?}\nsampler = {:?}\n",
            r.width,
            r.height,
            r.method,
            r.spp,
            r.photons,
            r.radius,
            r.alpha,
            r.max_depth,
            r.seed,
            r.direct,
            r.direct_samples,
            r.light_paths,
            r.radius_schedule,
            r.radius_rule,
            r.filter,
            r.sampler
        );
        // The shares joined the settings later: written only where they are set and not 1
        // (before, the default), so that a checkpoint written before resumes; vcm's shares
        // chosen by its pilot are a function of the rest (written as "auto").
        let mut settings = settings;
        for (key, share) in [("connect_share", r.connect_share), ("merge_share", r.merge_share)] {
            if let Some(share) = share.filter(|&s| s != 1.0) {
                settings.push_str(&format!("{key} = {share:?}\n"));
            }
        }
        if crate::integrators::light::pilot_chooses_shares(scene) {
            settings.push_str("shares = \"auto\"\n");
        }
        let mut geometry = Fnv::new();
        for t in &scene.triangles {
            geometry.write_f32s(t.p.iter().flat_map(|p| p.to_array()));
            if let Some(n) = t.n {
                geometry.write_f32s(n.iter().flat_map(|v| v.to_array()));
            }
            if let Some(uv) = t.uv {
                geometry.write_f32s(uv.iter().flat_map(|v| v.to_array()));
            }
            geometry.write(&t.shape.to_le_bytes());
        }
        for s in &scene.spheres {
            geometry.write_f32s(s.center.to_array().into_iter().chain([s.radius]));
            geometry.write(&s.shape.to_le_bytes());
        }
        let mut appearance = Fnv::new();
        appearance.write(format!("{:?}{:?}{:?}{:?}", scene.materials, scene.textures, scene.shapes, scene.lights).as_bytes());
        Fingerprint { settings, camera: format!("{:?}", scene.camera), geometry: geometry.0, appearance: appearance.0 }
    }

    /// `Err` naming what differs between this fingerprint (of a checkpoint) and `now`.
    pub fn check(&self, now: &Fingerprint) -> Result<(), String> {
        let mut differences: Vec<String> = Vec::new();
        for (saved, current) in self.settings.lines().zip(now.settings.lines()) {
            if saved != current {
                let key = current.split(" = ").next().unwrap_or(current);
                let value = |line: &str| line.split(" = ").nth(1).unwrap_or("").to_string();
                differences.push(format!("{key} {} (now {})", value(saved), value(current)));
            }
        }
        if self.settings.lines().count() != now.settings.lines().count() {
            differences.push("its settings".into());
        }
        if self.camera != now.camera {
            differences.push("the camera".into());
        }
        if self.geometry != now.geometry {
            differences.push("the geometry".into());
        }
        if self.appearance != now.appearance {
            differences.push("the materials, textures, shapes or lights".into());
        }
        if differences.is_empty() {
            Ok(())
        } else {
            Err(format!("it was made from another scene or other settings: {}", differences.join(", ")))
        }
    }
}

fn field(out: &mut Vec<u8>, bytes: &[u8]) {
    out.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    out.extend_from_slice(bytes);
}

/// Write `checkpoint` to `path`, whole or not at all.
pub fn write(path: &Path, checkpoint: &Checkpoint) -> Result<(), Error> {
    let Checkpoint { fingerprint, state, pilot } = checkpoint;
    let mut bytes = Vec::with_capacity(state.len() + 256);
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&VERSION.to_le_bytes());
    field(&mut bytes, fingerprint.settings.as_bytes());
    field(&mut bytes, fingerprint.camera.as_bytes());
    field(&mut bytes, &fingerprint.geometry.to_le_bytes());
    field(&mut bytes, &fingerprint.appearance.to_le_bytes());
    field(&mut bytes, state);
    field(&mut bytes, pilot.as_deref().unwrap_or("").as_bytes());
    let mut checksum = Fnv::new();
    checksum.write(&bytes);
    bytes.extend_from_slice(&checksum.0.to_le_bytes());
    let mut temporary = PathBuf::from(path);
    temporary.as_mut_os_string().push(format!(".{}.tmp", std::process::id()));
    let written = std::fs::File::create(&temporary)
        .and_then(|mut file| file.write_all(&bytes).and_then(|()| file.sync_all()))
        .and_then(|()| std::fs::rename(&temporary, path));
    written.map_err(|e| {
        // A full disk or a failed rename leaves no temporary file behind.
        let _ = std::fs::remove_file(&temporary);
        Error::Setting(format!("{}: cannot write the checkpoint: {e}", path.display()))
    })
}

/// The checkpoint at `path`.
pub fn read(path: &Path) -> Result<Checkpoint, Error> {
    let bytes =
        std::fs::read(path).map_err(|e| Error::Setting(format!("{}: cannot read the checkpoint: {e}", path.display())))?;
    let bad = |what: &str| Error::Setting(format!("{}: not a checkpoint of this renderer ({what})", path.display()));
    let rest = bytes.strip_prefix(MAGIC).ok_or_else(|| bad("no header"))?;
    let version = rest.get(..4).ok_or_else(|| bad("truncated"))?;
    let version = u32::from_le_bytes(version.try_into().expect("4 bytes"));
    if version != VERSION && version != 2 {
        return Err(bad(&format!("format version {version}, where this renderer reads 2 and {VERSION}")));
    }
    let corrupt = |what: &str| Error::Setting(format!("{}: the checkpoint is corrupt: {what}", path.display()));
    let body = bytes.len().checked_sub(8).filter(|&n| n >= MAGIC.len() + 4).ok_or_else(|| bad("truncated"))?;
    let mut checksum = Fnv::new();
    checksum.write(&bytes[..body]);
    if checksum.0.to_le_bytes() != bytes[body..] {
        return Err(corrupt("checksum mismatch (truncated, extended or altered)"));
    }
    let mut rest = &bytes[MAGIC.len() + 4..body];
    let mut next = || -> Result<Vec<u8>, Error> {
        let len = rest.get(..8).ok_or_else(|| bad("truncated"))?;
        let len = u64::from_le_bytes(len.try_into().expect("8 bytes"));
        let body = usize::try_from(len).ok().and_then(|len| rest.get(8..8 + len)).ok_or_else(|| bad("truncated"))?;
        let body = body.to_vec();
        rest = &rest[8 + body.len()..];
        Ok(body)
    };
    let text = |b: Vec<u8>| String::from_utf8(b).map_err(|_| bad("corrupt"));
    let digest = |b: Vec<u8>| b.try_into().map(u64::from_le_bytes).map_err(|_| bad("corrupt"));
    let settings = text(next()?)?;
    let camera = text(next()?)?;
    let geometry = digest(next()?)?;
    let appearance = digest(next()?)?;
    let state = next()?;
    let pilot = match version {
        2 => None,
        _ => Some(text(next()?)?).filter(|p| !p.is_empty()),
    };
    if !rest.is_empty() {
        return Err(corrupt(&format!("{} bytes after its fields", rest.len())));
    }
    Ok(Checkpoint { fingerprint: Fingerprint { settings, camera, geometry, appearance }, state, pilot })
}
