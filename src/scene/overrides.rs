//! Settings that override a scene's `[render]` table after it is loaded: the command line's
//! options (`--width`, `--method`, ...) and the Python package's keyword arguments
//! (`width=`, `method=`, ...) are both applied by [`Overrides::apply_to_scene`], so that one
//! scene and one set of settings give one image whichever drives the renderer.

use super::{DirectLight, Method, RadiusRule, RadiusSchedule, RenderSettings, Scene};
use crate::Error;

/// Values that replace the scene's `[render]` settings; `None` keeps the scene's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Passes (`render.iterations`).
    pub iterations: Option<u32>,
    /// Photons per SPPM pass (`render.photons`).
    pub photons: Option<u32>,
    /// Initial gather radius in scene units (`render.radius`).
    pub radius: Option<f32>,
    /// Radius reduction parameter, 0 < alpha < 1 (`render.alpha`).
    pub alpha: Option<f32>,
    /// Random seed (`render.seed`).
    pub seed: Option<u32>,
    /// Seconds of completed passes (`render.time_limit`).
    pub time_limit: Option<f64>,
    /// Image width in pixels (`render.width`).
    pub width: Option<u32>,
    /// Image height in pixels (`render.height`).
    pub height: Option<u32>,
    /// The rendering method (`render.method`).
    pub method: Option<Method>,
    /// SPPM's camera samples a pixel in each pass (`render.spp`); a path tracer's samples a
    /// pixel in all, that is its passes (`render.iterations`).
    pub spp: Option<u32>,
    /// Most scattering events on a path (`render.max_depth`).
    pub max_depth: Option<u32>,
    /// SPPM's direct light (`render.direct`).
    pub direct: Option<DirectLight>,
    /// SPPM's camera paths per visible point that gather direct light
    /// (`render.direct_samples`).
    pub direct_samples: Option<u32>,
    /// bpt's and vcm's light subpaths a pass (`render.light_paths`).
    pub light_paths: Option<u32>,
    /// bpt's and vcm's share of camera vertices that connect (`render.connect_share`).
    pub connect_share: Option<f32>,
    /// vcm's share of camera vertices that merge (`render.merge_share`).
    pub merge_share: Option<f32>,
    /// SPPM's radius schedule (`render.radius_schedule`).
    pub radius_schedule: Option<RadiusSchedule>,
    /// SPPM's radius rule (`render.radius_rule`).
    pub radius_rule: Option<RadiusRule>,
    /// Where the kernels' random numbers come from (`render.sampler`).
    pub sampler: Option<crate::sampler::Sampler>,
}

/// How an error message names a setting: as the command line's option (`--max-depth`,
/// `--iterations`) or as the Python package's keyword argument (`max_depth`, `passes`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SettingNames {
    /// `--max-depth`, `--iterations`.
    Options,
    /// `max_depth`, `passes`.
    Keywords,
}

impl SettingNames {
    /// `flag` (the option's name without `--`) as this style writes it.
    fn name(self, flag: &str) -> String {
        match self {
            SettingNames::Options => format!("--{flag}"),
            SettingNames::Keywords if flag == "iterations" => "passes".to_string(),
            SettingNames::Keywords => flag.replace('-', "_"),
        }
    }
}

impl Overrides {
    /// Apply the overrides to a loaded scene: [`Overrides::apply`] to its `[render]` table,
    /// after the one rule that depends on the file: a Mitsuba or pbrt film's size sets its
    /// field of view along one axis, so one of width and height alone keeps the file's aspect
    /// ratio, and so the framing.
    pub fn apply_to_scene(&self, scene: &mut Scene, names: SettingNames) -> Result<(), Error> {
        if super::is_foreign(&scene.path) {
            let (w, h) = (scene.render.width as f64, scene.render.height as f64);
            match (self.width, self.height) {
                (Some(width), None) => scene.render.height = ((width as f64 * h / w).round() as u32).max(1),
                (None, Some(height)) => scene.render.width = ((height as f64 * w / h).round() as u32).max(1),
                _ => {}
            }
        }
        self.apply(&mut scene.render, names)
    }

    /// Apply the overrides to a scene's `[render]` table, checking each; an error names the
    /// setting as `names` says.
    pub fn apply(&self, render: &mut RenderSettings, names: SettingNames) -> Result<(), Error> {
        let positive = |flag: &str, v: Option<u32>, max: u32, dst: &mut u32| -> Result<(), Error> {
            if let Some(v) = v {
                if v == 0 || v > max {
                    return Err(Error::Setting(format!("{} must be between 1 and {max}, got {v}", names.name(flag))));
                }
                *dst = v;
            }
            Ok(())
        };
        positive("iterations", self.iterations, u32::MAX, &mut render.iterations)?;
        positive("photons", self.photons, u32::MAX, &mut render.photons)?;
        render.work_given.photons |= self.photons.is_some();
        positive("width", self.width, 16384, &mut render.width)?;
        positive("height", self.height, 16384, &mut render.height)?;
        render.method = self.method.unwrap_or(render.method);
        if render.method == Method::Sppm {
            positive("spp", self.spp, 1024, &mut render.spp)?;
            render.work_given.spp |= self.spp.is_some();
        } else if let Some(spp) = self.spp {
            // A path tracer's pass is one sample a pixel: spp is its passes, as pbrt's
            // pixelsamples and Mitsuba's sample_count count samples a pixel in all.
            if self.iterations.is_some_and(|n| n != spp) {
                return Err(Error::Setting(format!(
                    "{} {spp} and {} {}: a path tracer's samples a pixel are its passes; give one of them",
                    names.name("spp"),
                    names.name("iterations"),
                    self.iterations.unwrap_or_default()
                )));
            }
            positive("spp", Some(spp), u32::MAX, &mut render.iterations)?;
        }
        positive("max-depth", self.max_depth, 1024, &mut render.max_depth)?;
        if self.direct_samples.is_some() {
            let mut n = 1;
            positive("direct-samples", self.direct_samples, super::MAX_DIRECT_SAMPLES, &mut n)?;
            render.direct_samples = Some(n);
        }
        // 0: vcm without light subpaths (RenderSettings::light_paths).
        render.light_paths = self.light_paths.or(render.light_paths);
        for (key, share, to) in [
            ("connect-share", self.connect_share, &mut render.connect_share),
            ("merge-share", self.merge_share, &mut render.merge_share),
        ] {
            if let Some(share) = share {
                if !(0.0..=1.0).contains(&share) {
                    return Err(Error::Setting(format!("{} must lie in [0, 1], got {share}", names.name(key))));
                }
                *to = Some(share);
            }
        }
        if let Some(r) = self.radius {
            if !(r > 0.0 && r.is_finite()) {
                return Err(Error::Setting(format!("{} must be a positive number, got {r}", names.name("radius"))));
            }
            render.radius = Some(r);
        }
        if let Some(a) = self.alpha {
            if !(a > 0.0 && a < 1.0) {
                return Err(Error::Setting(format!("{} must be between 0 and 1 (exclusive), got {a}", names.name("alpha"))));
            }
            render.alpha = a;
        }
        if let Some(t) = self.time_limit {
            if !(t > 0.0 && t.is_finite()) {
                return Err(Error::Setting(format!(
                    "{} must be a positive number of seconds, got {t}",
                    names.name("time-limit")
                )));
            }
            render.time_limit = Some(t);
        }
        if let Some(s) = self.seed {
            render.seed = s;
        }
        render.direct = self.direct.unwrap_or(render.direct);
        render.radius_schedule = self.radius_schedule.unwrap_or(render.radius_schedule);
        render.radius_schedule_given |= self.radius_schedule.is_some();
        render.radius_rule = self.radius_rule.unwrap_or(render.radius_rule);
        render.sampler = self.sampler.unwrap_or(render.sampler);
        render.settle_radius_schedule();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_setting_in_the_callers_style() {
        let bad = Overrides { max_depth: Some(0), ..Default::default() };
        let mut render = RenderSettings::default();
        let cli = bad.apply(&mut render, SettingNames::Options).unwrap_err().to_string();
        let py = bad.apply(&mut render, SettingNames::Keywords).unwrap_err().to_string();
        assert!(cli.starts_with("--max-depth must be between 1 and 1024"), "{cli}");
        assert!(py.starts_with("max_depth must be between 1 and 1024"), "{py}");
    }

    #[test]
    fn a_path_tracers_spp_is_its_passes() {
        let mut render = RenderSettings::default();
        let o = Overrides { method: Some(Method::PtNee), spp: Some(7), ..Default::default() };
        o.apply(&mut render, SettingNames::Keywords).unwrap();
        assert_eq!((render.iterations, render.method), (7, Method::PtNee));
        assert!(!render.work_given.spp);
    }
}
