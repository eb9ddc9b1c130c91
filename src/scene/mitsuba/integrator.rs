//! The integrator, as our method and render settings: Mitsuba 3's plugins and those of Mitsuba
//! 0.5/0.6, each of their parameters mapped, passed over with a warning (it changes only the
//! noise, the speed or the scheduling, or we read it but model it differently) or refused (it
//! would change the image).
//!
//! - `path`, `volpath`, 0.6's `volpath_simple`: rendered by pt-nee, which samples lights at
//!   every vertex with MIS as they do, the sampler's `sample_count` its passes (one sample a
//!   pixel each). `max_depth` (-1, unbounded) counts path
//!   vertices after the camera's, so 2 is direct light alone: our `max_depth` (scattering
//!   events) is one less. `rr_depth` is warned: our Russian roulette starts by its own rule.
//!   `hide_emitters` true is refused: the emitters seen directly would be black. 0.6's
//!   `strict_normals` ([`strict_normals`]).
//! - `direct`: pt-nee with max_depth 1 (ours); `emitter_samples`, `bsdf_samples`, `shading_samples` (how
//!   many samples of each strategy: the noise); `hide_emitters` and 0.6's `strict_normals` as
//!   `path`'s.
//! - `sppm` and `ppm` (0.6): `photon_count` (250000) photons a pass, `initial_radius` (0:
//!   automatic), `alpha` (0.7), `max_depth` as `path`'s, `max_passes` (-1, until stopped:
//!   here the sampler's `sample_count`, warned) passes. `granularity`, `rr_depth` and
//!   `auto_cancel_gathering` are warned. `ppm` is rendered by SPPM, warned.
//! - `photonmapper` (0.6): `max_depth` as `path`'s (its -1 means 128 vertices) and
//!   `hide_emitters`. The sizes, lookup radii and counts of its photon maps and its direct
//!   and glossy sample counts set its bias and noise: warned, and SPPM renders the image they
//!   approximate.
//! - `vpl` (0.6): `max_depth` (5) as `path`'s; `clamping` and `shadow_map_resolution`, its
//!   bias and noise, warned.
//! - `adaptive` and `irrcache` (0.6) render their nested integrator's image: adaptive's
//!   stopping rule (`max_error`, `p_value`, `max_sample_factor`, `verbose`) and irrcache's
//!   accuracy (`resolution`, `quality`, `quality_adjustment`, `gradients`, `clamp_neighbor`,
//!   `clamp_screen`, `overture`) are warned. irrcache adds a bounce on diffuse surfaces, so a
//!   nested integrator of bounded depth is refused, and so are `indirect_only` and `debug`.
//! - `ao`, `field`, `multichannel`, `motion` (0.6) are refused: they render no light
//!   transport, or several images.
//! - `bdpt` (0.6): our bpt, `max_depth` as `path`'s; `lightImage` and `sampleDirect` false
//!   (strategies left out: the same image) warned.
//! - Any other integrator (0.6's `ptracer`, `pssmlt`, `mlt`, `erpt`, which converge to
//!   `path`'s image; another project's path guider) is a warning, and our default method
//!   renders, at the integrator's `max_depth` if it has one (as `path`'s); its other
//!   parameters, how it samples, are not read.

use super::props::Props;
use super::sensor::SensorSettings;
use super::xml::Node;
use super::Result;
use crate::scene::{Method, RenderSettings};

/// Our `max_depth` for Mitsuba's -1 (unbounded): Russian roulette ends paths long before.
const UNBOUNDED_DEPTH: u32 = 1024;

/// Our render settings from the sensor and the integrator element. `shading_normals`: whether
/// some triangle has shading normals.
pub(super) fn render_settings(
    sensor: &SensorSettings,
    integrator: Option<&Node>,
    shading_normals: bool,
) -> Result<RenderSettings> {
    let mut render = RenderSettings {
        width: sensor.width,
        height: sensor.height,
        iterations: sensor.sample_count,
        max_depth: UNBOUNDED_DEPTH,
        seed: sensor.seed,
        filter: sensor.filter,
        sampler: sensor.sampler,
        ..RenderSettings::default()
    };
    if let Some(node) = integrator {
        read_integrator(node, &mut render, shading_normals)?;
    }
    Ok(render)
}

/// Reads integrator element `node` into `render`.
fn read_integrator(node: &Node, render: &mut RenderSettings, shading_normals: bool) -> Result<()> {
    node.allow_attrs(&["type", "id", "name"])?;
    let kind = node.req_attr("type")?;
    let p = Props::new(node)?;
    match kind {
        "path" | "volpath" | "volpath_simple" => {
            // Light sampled at every vertex with MIS: our pt-nee, its sample_count its passes.
            render.method = Method::PtNee;
            render.max_depth = max_depth(&p, -1)?;
            rr_depth(&p)?;
            hide_emitters(&p)?;
            strict_normals(&p, shading_normals)?;
        }
        // Emission seen and direct light at the first hit, by light and BSDF samples with
        // MIS: the paths `path` draws with max_depth 2, so ours with max_depth 1.
        "direct" => {
            render.method = Method::PtNee;
            render.max_depth = 1;
            // How many samples of each strategy: the noise, not the image.
            for name in ["emitter_samples", "bsdf_samples", "shading_samples"] {
                p.integer(name)?;
            }
            hide_emitters(&p)?;
            strict_normals(&p, shading_normals)?;
        }
        "sppm" | "ppm" => {
            render.max_depth = max_depth(&p, -1)?;
            // Mitsuba 0.6's default is the file's meaning: given.
            render.photons = 250_000;
            render.work_given.photons = true;
            if let Some(n) = p.integer("photon_count")? {
                render.photons = u32::try_from(n).ok().filter(|&n| n > 0).ok_or_else(|| {
                    p.get("photon_count").unwrap().error(Some("photon_count"), format!("photon_count {n} is not positive"))
                })?;
            }
            if let Some(r) = p.float("initial_radius")? {
                if r < 0.0 {
                    return Err(p.get("initial_radius").unwrap().error(Some("initial_radius"), "initial_radius is negative"));
                }
                render.radius = (r > 0.0).then_some(r);
            }
            render.alpha = p.float_or("alpha", 0.7)?;
            if !(render.alpha > 0.0 && render.alpha < 1.0) {
                let at = p.get("alpha").unwrap();
                return Err(at.error(Some("alpha"), format!("alpha {} is outside (0, 1)", render.alpha)));
            }
            match p.integer("max_passes")?.unwrap_or(-1) {
                -1 => p.get("max_passes").unwrap_or(node).warn(
                    Some("max_passes"),
                    format!(
                        "max_passes is -1: Mitsuba 0.6's {kind} renders until stopped; sppm-gpu renders {} passes, the \
                         sampler's sample_count (--iterations or --time-limit sets another)",
                        render.iterations
                    ),
                ),
                n if n >= 1 => render.iterations = n.min(u32::MAX as i64) as u32,
                n => {
                    let at = p.get("max_passes").unwrap();
                    return Err(at.error(Some("max_passes"), format!("max_passes {n}: -1 (until stopped) or 1 or more")));
                }
            }
            rr_depth(&p)?;
            p.legacy_ignored(&["granularity"], "it sets how many photons make one of Mitsuba 0.6's work units: the speed");
            p.legacy_ignored(
                &["auto_cancel_gathering"],
                "it lets Mitsuba 0.6 give up a pass whose photons are seldom stored, which changes the noise and the speed",
            );
            if kind == "ppm" {
                node.warn(
                    None,
                    "the `ppm` integrator is rendered by SPPM: PPM keeps the visible points it traced first, SPPM \
                     traces them anew each pass and so also converges over each pixel's area",
                );
            }
        }
        "photonmapper" => {
            render.max_depth = max_depth(&p, -1)?;
            hide_emitters(&p)?;
            rr_depth(&p)?;
            p.legacy_ignored(
                &[
                    "global_photons",
                    "caustic_photons",
                    "volume_photons",
                    "global_lookup_radius",
                    "caustic_lookup_radius",
                    "lookup_size",
                    "global_lookup_size",
                    "caustic_lookup_size",
                    "volume_lookup_size",
                    "direct_samples",
                    "glossy_samples",
                    "max_specular_depth",
                    "granularity",
                    "gather_locally",
                    "auto_cancel_gathering",
                ],
                "it sets the bias, noise or speed of Mitsuba 0.6's photon maps; sppm-gpu renders the image they \
                 approximate by SPPM",
            );
            node.warn(
                None,
                "the `photonmapper` integrator is rendered by SPPM, which converges to the image its photon maps \
                 approximate",
            );
        }
        "vpl" => {
            render.max_depth = max_depth(&p, 5)?;
            p.legacy_ignored(
                &["clamping", "shadow_map_resolution"],
                "it sets the bias and noise of Mitsuba 0.6's virtual point lights; sppm-gpu renders the image they \
                 approximate",
            );
            node.warn(None, "the `vpl` integrator is rendered by SPPM, which converges to the image it approximates");
        }
        "adaptive" | "irrcache" => {
            let nested = p.all_objects();
            let [inner] = nested.as_slice() else {
                return Err(node.error(None, format!("{kind} wraps one nested <integrator>, not {}", nested.len())));
            };
            if inner.tag != "integrator" {
                return Err(inner.error(None, format!("{} inside {kind}: it wraps an <integrator>", inner.describe())));
            }
            read_integrator(inner, render, shading_normals)?;
            if kind == "adaptive" {
                p.legacy_ignored(
                    &["max_error", "p_value", "max_sample_factor", "verbose"],
                    "it sets when Mitsuba 0.6's adaptive integrator stops sampling a pixel, which changes the noise",
                );
            } else {
                if render.max_depth != UNBOUNDED_DEPTH {
                    return Err(inner.error(
                        Some("max_depth"),
                        "irrcache adds a bounce on diffuse surfaces (not on others) to a nested integrator of bounded \
                         depth: not modelled by sppm-gpu",
                    ));
                }
                for name in ["indirect_only", "debug"] {
                    if p.boolean_or(name, false)? {
                        let at = p.get(name).unwrap();
                        return Err(at.error(
                            Some(name),
                            format!("irrcache's {name} (an image of the cache, not of the scene) is not modelled by sppm-gpu"),
                        ));
                    }
                }
                p.legacy_ignored(
                    &["resolution", "quality", "quality_adjustment", "gradients", "clamp_neighbor", "clamp_screen", "overture"],
                    "it sets how closely Mitsuba 0.6's irradiance cache interpolates the image, which sppm-gpu renders",
                );
            }
        }
        "ao" | "field" | "multichannel" | "motion" => {
            return Err(node.error(
                Some("type"),
                format!(
                    "the `{kind}` integrator renders no light transport (ambient occlusion, a field of the surface, several \
                     images, motion): not modelled by sppm-gpu"
                ),
            ))
        }
        "bdpt" => {
            // Mitsuba 0.6's bidirectional path tracer: our bpt, its max_depth as path's. Which
            // strategies it keeps (lightImage, sampleDirect) changes the noise, not the image.
            render.method = Method::Bpt;
            render.max_depth = max_depth(&p, -1)?;
            rr_depth(&p)?;
            for name in ["light_image", "sample_direct"] {
                if p.get(name).is_some() && !p.boolean_or(name, true)? {
                    p.get(name).unwrap().warn(
                        Some(name),
                        format!("{name} false leaves strategies out of Mitsuba's bdpt; sppm-gpu's bpt keeps them all (the same image)"),
                    );
                }
            }
        }
        other => {
            // A plugin of another project (a path guider, a bidirectional tracer) that says
            // how long its paths are means light transport as Mitsuba's path counts it.
            let depth = match p.get("max_depth").filter(|n| n.tag == "integer") {
                Some(_) => {
                    render.max_depth = max_depth(&p, -1)?;
                    format!(" its max_depth ({} scattering events),", render.max_depth)
                }
                None => String::new(),
            };
            node.warn(
                Some("type"),
                format!(
                    "the `{other}` integrator is not one sppm-gpu has: rendering with SPPM at{depth} as Mitsuba's path \
                     would (--method picks another); its other parameters are not read"
                ),
            );
            return Ok(());
        }
    }
    p.finish()
}

/// Mitsuba's `max_depth` (path vertices after the camera; -1 unbounded; `default` when left
/// out) as ours (scattering events): one less.
fn max_depth(p: &Props, default: i64) -> Result<u32> {
    match p.integer("max_depth")?.unwrap_or(default) {
        -1 => Ok(UNBOUNDED_DEPTH),
        d if d >= 2 => Ok((d - 1).min(UNBOUNDED_DEPTH as i64) as u32),
        d => Err(p.get("max_depth").unwrap().error(
            Some("max_depth"),
            format!(
                "max_depth {d}: Mitsuba would render {} ; sppm-gpu needs 2 or more (or -1)",
                if d == 1 { "only the emitters seen directly" } else { "nothing" }
            ),
        )),
    }
}

/// `rr_depth`, the depth where Mitsuba's Russian roulette starts: ours starts by its own rule.
/// Either ends paths without bias, so it changes the noise, not the image: a warning.
fn rr_depth(p: &Props) -> Result<()> {
    if let Some(depth) = p.integer("rr_depth")? {
        p.get("rr_depth").unwrap().warn(
            Some("rr_depth"),
            format!(
                "rr_depth {depth} is not applied: sppm-gpu's Russian roulette starts by its own rule, which changes \
                 the noise, not the image"
            ),
        );
    }
    Ok(())
}

/// `hide_emitters`: true (emitters seen directly are black) is refused.
fn hide_emitters(p: &Props) -> Result<()> {
    if p.boolean_or("hide_emitters", false)? {
        let at = p.get("hide_emitters").unwrap();
        return Err(at.error(Some("hide_emitters"), "hide_emitters is not modelled by sppm-gpu"));
    }
    Ok(())
}

/// Mitsuba 0.6's `strict_normals` (false) of `path`, `volpath` and `direct`, read in a 0.x
/// scene (Mitsuba 3 has none, and refuses it). True ends a path where a surface's shading and
/// geometric normals disagree on the side of the direction it arrives from or leaves by; ours
/// end where a shading normal sends the next direction to the wrong side of the surface, the
/// light leak strict_normals guards against, not where only the arriving direction disagrees.
/// Without shading normals the two normals agree and it changes nothing; with them it darkens
/// the silhouettes of smooth meshes in Mitsuba 0.6's image, which ours do not: a warning.
fn strict_normals(p: &Props, shading_normals: bool) -> Result<()> {
    if !p.node.legacy() {
        return Ok(());
    }
    if p.boolean_or("strict_normals", false)? && shading_normals {
        p.get("strict_normals").unwrap().warn(
            Some("strict_normals"),
            "strict_normals true is modelled in part: sppm-gpu ends a path where a shading normal sends it to the \
             wrong side of the surface, but not, as Mitsuba 0.6 does, where only the direction it arrives from \
             disagrees: the silhouettes of smooth meshes are lighter than in Mitsuba 0.6's image",
        );
    }
    Ok(())
}
