//! What the subcommands share: the overrides of a scene's `[render]` table, loading a scene
//! with them, and the checks and parsers of their arguments (cargo's `command_prelude.rs`).

use sppm_gpu::scene::{self, DirectLight, Method, Named, RadiusSchedule};
use sppm_gpu::Error;
use std::path::Path;

/// Settings that override the scene's `[render]` table.
#[derive(clap::Args, Debug, Default)]
pub(crate) struct Overrides {
    /// Passes: SPPM's, or the path tracers' samples a pixel (overrides render.iterations).
    /// With --time-limit and without this, as many passes as fit.
    #[arg(long)]
    pub(crate) iterations: Option<u32>,
    /// Photons per pass (overrides render.photons).
    #[arg(long)]
    pub(crate) photons: Option<u32>,
    /// Initial gather radius in scene units (overrides render.radius).
    #[arg(long)]
    pub(crate) radius: Option<f32>,
    /// Radius reduction parameter, 0 < alpha < 1 (overrides render.alpha).
    #[arg(long)]
    pub(crate) alpha: Option<f32>,
    /// Random seed (overrides render.seed).
    #[arg(long)]
    pub(crate) seed: Option<u32>,
    /// Stop at the pass boundary nearest this many seconds of completed passes, counted
    /// after the kernels are compiled (overrides render.time_limit).
    #[arg(long)]
    pub(crate) time_limit: Option<f64>,
    /// Image width in pixels (overrides render.width).
    #[arg(long)]
    pub(crate) width: Option<u32>,
    /// Image height in pixels (overrides render.height).
    #[arg(long)]
    pub(crate) height: Option<u32>,
    /// Rendering method: sppm, pt (naive path tracing), pt-nee (next-event estimation with
    /// MIS) or lt (light tracing) (overrides render.method).
    #[arg(long, value_parser = named::<Method>())]
    pub(crate) method: Option<Method>,
    /// Samples a pixel: for the path tracers, in all (their passes, one sample a pixel each;
    /// overrides render.iterations); for SPPM, camera samples a pixel in each pass (overrides
    /// render.spp).
    #[arg(long)]
    pub(crate) spp: Option<u32>,
    /// Most scattering events on a path (overrides render.max_depth).
    #[arg(long)]
    pub(crate) max_depth: Option<u32>,
    /// SPPM's direct light: sampled in the camera pass (default) or from photons alone, as
    /// in the original algorithm (overrides render.direct).
    #[arg(long, value_parser = named::<DirectLight>())]
    pub(crate) direct: Option<DirectLight>,
    /// SPPM with sampled direct light: camera paths per visible point per pass that gather
    /// direct light (overrides render.direct_samples; default automatic).
    #[arg(long)]
    pub(crate) direct_samples: Option<u32>,
    /// bpt and vcm: light subpaths a pass (overrides render.light_paths; default one for
    /// every 16 pixels, every 4 for vcm merging without connecting; 0: vcm with none, camera
    /// subpaths and next-event estimation alone).
    #[arg(long)]
    pub(crate) light_paths: Option<u32>,
    /// bpt and vcm: the share of camera vertices that connect to light vertices, in [0, 1]
    /// (overrides render.connect_share; default 1, or for vcm with neither share set, chosen by
    /// a pilot).
    #[arg(long)]
    pub(crate) connect_share: Option<f32>,
    /// vcm: the share of camera vertices that merge with light vertices, in [0, 1] (overrides
    /// render.merge_share; default as --connect-share's).
    #[arg(long)]
    pub(crate) merge_share: Option<f32>,
    /// SPPM's radius schedule: per-point (each visible point's radius shrinks with its
    /// photons) or global (the radius of pass i depends on i alone, so passes can run in
    /// batches and splat through a tent or gaussian filter; Knaus & Zwicker 2011); default
    /// global where it splats (a tent or gaussian, spp 1, radius rule shrink), else per-point
    /// (overrides render.radius_schedule).
    #[arg(long, value_parser = named::<RadiusSchedule>())]
    pub(crate) radius_schedule: Option<RadiusSchedule>,
    /// How each SPPM visible point's radius shrinks (per-point schedule): shrink (by alpha of
    /// each pass's photons; default) or adaptive (by alpha only where its photons stop looking
    /// uniform over its disc, by a chi-square test) (overrides render.radius_rule).
    #[arg(long, value_parser = named::<scene::RadiusRule>())]
    pub(crate) radius_rule: Option<scene::RadiusRule>,
    /// Where the kernels' random numbers come from: independent (PCG streams) or sobol
    /// (Owen-scrambled Sobol points) (overrides render.sampler).
    #[arg(long, value_parser = named::<sppm_gpu::sampler::Sampler>())]
    pub(crate) sampler: Option<sppm_gpu::sampler::Sampler>,
    /// Set a Mitsuba XML scene's parameter `$name`, as Mitsuba's own `-D name=value` (over the
    /// file's `<default>`); repeatable.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
    pub(crate) defines: Vec<(String, String)>,
}

impl Overrides {
    /// The overrides of the scene's `[render]` table, as the library applies them
    /// ([`scene::Overrides::apply_to_scene`]).
    pub(crate) fn settings(&self) -> scene::Overrides {
        scene::Overrides {
            iterations: self.iterations,
            photons: self.photons,
            radius: self.radius,
            alpha: self.alpha,
            seed: self.seed,
            time_limit: self.time_limit,
            width: self.width,
            height: self.height,
            method: self.method,
            spp: self.spp,
            max_depth: self.max_depth,
            direct: self.direct,
            direct_samples: self.direct_samples,
            light_paths: self.light_paths,
            connect_share: self.connect_share,
            merge_share: self.merge_share,
            radius_schedule: self.radius_schedule,
            radius_rule: self.radius_rule,
            sampler: self.sampler,
        }
    }

    /// Refuses the options among `unused` that were given, for a command that does not read
    /// them (`why` says what it reads instead): an option is never accepted and ignored.
    pub(crate) fn refuse(&self, command: &str, unused: &[&str], why: &str) -> Result<(), Error> {
        let given = [
            ("method", self.method.is_some()),
            ("time-limit", self.time_limit.is_some()),
            ("iterations", self.iterations.is_some()),
            ("spp", self.spp.is_some()),
            ("direct", self.direct.is_some()),
        ];
        match given.iter().find(|(flag, given)| *given && unused.contains(flag)) {
            Some((flag, _)) => Err(Error::Setting(format!("{command} does not take --{flag}: {why}"))),
            None => Ok(()),
        }
    }
}

/// A [`Named`] setting's value parser: its names listed in `--help` and checked by clap, its
/// aliases accepted without being listed.
pub(crate) fn named<T: Named + Send + Sync>() -> impl clap::builder::TypedValueParser<Value = T> {
    use clap::builder::{PossibleValue, TypedValueParser};
    let values = T::NAMES.iter().map(|&(name, value)| {
        let aliases = T::ALIASES.iter().filter(|(_, v)| *v == value).map(|(alias, _)| *alias);
        PossibleValue::new(name).aliases(aliases)
    });
    clap::builder::PossibleValuesParser::new(values).map(|name| T::from_name(&name).expect("a name of the table"))
}

/// `NAME=VALUE` of `-D`.
pub(crate) fn parse_define(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.is_empty() => Ok((name.to_owned(), value.to_owned())),
        _ => Err(format!("\"{text}\" is not NAME=VALUE")),
    }
}

/// Load a scene and apply the command line's overrides; also its name (the file stem).
pub(crate) fn load_scene(path: &Path, overrides: &Overrides) -> Result<(scene::Scene, String), Error> {
    let mut scene = scene::load_with(path, &overrides.defines)?;
    overrides.settings().apply_to_scene(&mut scene, scene::SettingNames::Options)?;
    let name = path.file_stem().map_or_else(|| path.display().to_string(), |s| s.to_string_lossy().into_owned());
    Ok((scene, name))
}

/// `A..B` (passes A to B-1, B > A) as `(A, B)`.
pub(crate) fn parse_pass_range(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`{text}`: a range of passes A..B (A from 0, B > A), such as 0..16");
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let (a, b): (u32, u32) = (a.trim().parse().map_err(|_| bad())?, b.trim().parse().map_err(|_| bad())?);
    if b <= a {
        return Err(bad());
    }
    Ok((a, b))
}

/// `1000000`, `512K`, `64M`, `8G` (powers of 1024) as bytes.
pub(crate) fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let (digits, unit) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&t[..i], c.to_ascii_uppercase()),
        _ => (t, 'B'),
    };
    let shift = match unit {
        'B' => 0,
        'K' => 10,
        'M' => 20,
        'G' => 30,
        _ => return Err(format!("`{text}`: a number of bytes, with K, M or G for powers of 1024")),
    };
    let n: u64 = digits.trim().parse().map_err(|_| format!("`{text}`: a number of bytes, with K, M or G for powers of 1024"))?;
    n.checked_mul(1 << shift).filter(|&b| b > 0).ok_or_else(|| format!("`{text}`: out of range"))
}
