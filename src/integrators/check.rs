//! The render's first passes checked against vcm's pilot. The pilot ([`super::shares`]) rates
//! each candidate from a few passes; where the chosen one carries light by paths so rare that
//! those passes do not meet them, its variance in the render is far above what the pilot read.
//! On Mitsuba's sky.xml (the sun's caustics through smooth glass on a wide ground, which few of
//! the light subpaths reach) connections without merging varied 6.3x the pilot's reading in a
//! render's first passes, merging alone 1.7x; on sixteen other scenes the chosen candidate's
//! first passes read 0.5x to 1.4x the pilot's figure (BENCHMARKS.md "VCM").
//!
//! Under a time limit the render's first passes, which it keeps, say again how much the chosen
//! candidate's passes vary: the image after `k` passes and after `2k` give the difference of
//! the two halves' means, `D = 2 (I_k - I_2k)`, whose variance is `2 sigma^2 / k` for passes
//! of variance `sigma^2` ([`halves_rel_variance`]). With that variance in its figure
//! ([`super::shares::Candidate::figure`]) over the whole render's time, against each other
//! candidate's that merges over the time left, the render goes on with its passes or starts
//! over with the other ([`decide`]).

use super::shares::{Candidate, Choice};
use super::Integrator;
use crate::error::Error;
use crate::metrics::REL_MSE_EPSILON;

/// The share of the render's time (the time limit less the pilot's seconds) whose passes the
/// check reads: `k` passes in half of it, then `k` more.
pub const CHECK_SHARE: f64 = 0.1;

/// The passes of each half at least: where they do not fit in [`MAX_CHECK_SHARE`] of the
/// render's time (or in its passes), there is no check.
pub const MIN_CHECK_PASSES: u32 = 8;

/// The share of the render's time the check may take at most.
pub const MAX_CHECK_SHARE: f64 = 0.25;

/// The seconds the check may take at most, whatever the time limit: it runs before the render
/// loop, which a Ctrl-C stops (a long render's first 20 s hold thousands of passes where the
/// pilot ran eight).
pub const MAX_CHECK_SECONDS: f64 = 20.0;

/// The factor by which another candidate's figure over the time left must stay below the
/// chosen one's, with the variance its passes showed, over the whole render's time, for the
/// render to start over with it: the other's figure is still the pilot's reading, which the
/// same rare paths may make too low.
pub const SWITCH_MARGIN: f64 = 1.25;

/// The relative variance of one pass (as [`super::shares::Candidate::rel_variance`]: the mean
/// over pixels and channels of a pass's variance over `mu^2 + 0.01`) from the image after `k`
/// passes, `half`, and after `2k`, `whole` (also `mu`): the means of passes `1..k` and
/// `k+1..2k` differ by `D = 2 (half - whole)`, of variance `2 sigma^2 / k`. Infinite where the
/// images are not finite.
pub fn halves_rel_variance(half: &[[f32; 3]], whole: &[[f32; 3]], k: u32) -> f64 {
    let mut sum = 0.0;
    for (a, b) in half.iter().zip(whole) {
        for c in 0..3 {
            let (a, b) = (a[c] as f64, b[c] as f64);
            let d = 2.0 * (a - b);
            sum += d * d / (b * b + REL_MSE_EPSILON);
        }
    }
    let v = sum / (3 * whole.len().max(1)) as f64 * k as f64 / 2.0;
    if v.is_finite() {
        v
    } else {
        f64::INFINITY
    }
}

/// What the check found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Verdict {
    /// The chosen candidate's relative variance a pass in the render over the pilot's.
    pub ratio: f64,
    /// The candidate that renders from here, where not the chosen one.
    pub switch_to: Option<Choice>,
}

/// Whether `choice` merges: merging alone, or with connections, or photon mapping.
fn merges(choice: Choice) -> bool {
    choice.light_subpaths && (choice.shares.merge > 0.0 || choice.photon_mapping)
}

/// The verdict on `chosen`, one of the pilot's `candidates`, whose passes in the render showed
/// `rel_variance` a pass: its figure with it over `render_seconds` (its passes so far are
/// kept) against each other candidate's that merges over `seconds_left`, by
/// [`SWITCH_MARGIN`]. Paths too rare for the pilot's passes are light through glass or mirrors
/// onto diffuse surfaces (caustics), which merging finds by its density estimate where the
/// other strategies meet them by chance: on sky.xml the render's passes varied 14x the pilot's
/// reading without light subpaths, 6.3x with connections alone, 1.7x merging alone; on
/// cornell-spheres and cornell-skylight 2.2x and 2.4x without light subpaths, 0.6x merging alone
/// (BENCHMARKS.md "VCM"). Where `chosen` is not among `candidates`, the render goes on (the
/// ratio NaN).
pub fn decide(candidates: &[Candidate], chosen: Choice, rel_variance: f64, render_seconds: f64, seconds_left: f64) -> Verdict {
    let Some(own) = candidates.iter().find(|c| c.choice == chosen) else {
        return Verdict { ratio: f64::NAN, switch_to: None };
    };
    let ratio = rel_variance / own.rel_variance;
    let going_on = Candidate { rel_variance, ..own.clone() }.figure() / render_seconds;
    let other = candidates
        .iter()
        .filter(|c| c.choice != chosen && merges(c.choice) && c.figure().is_finite())
        .min_by(|a, b| a.figure().total_cmp(&b.figure()));
    let switch_to =
        other.filter(|o| seconds_left > 0.0 && SWITCH_MARGIN * o.figure() / seconds_left < going_on).map(|o| o.choice);
    Verdict { ratio, switch_to }
}

/// The render's first passes, by `integrator`, for the check: `k` passes in half of
/// [`CHECK_SHARE`] of `render_seconds` (at most half of [`MAX_CHECK_SECONDS`]), at least
/// [`MIN_CHECK_PASSES`], then `k` more, within `iterations` passes. Their relative variance a pass ([`halves_rel_variance`]) and `k`; `None`
/// where they do not fit (the passes run are kept either way).
pub fn first_passes(integrator: &mut dyn Integrator, render_seconds: f64, iterations: u32) -> Result<Option<(f64, u32)>, Error> {
    let start = std::time::Instant::now();
    let elapsed = || start.elapsed().as_secs_f64();
    let (share, most) = (CHECK_SHARE * render_seconds, (MAX_CHECK_SHARE * render_seconds).min(MAX_CHECK_SECONDS));
    while elapsed() < 0.5 * share.min(most) || integrator.passes() < MIN_CHECK_PASSES {
        if elapsed() > 0.5 * most || 2 * (integrator.passes() + 1) > iterations {
            return Ok(None);
        }
        integrator.run_pass()?;
    }
    let half = integrator.image()?;
    let k = integrator.passes();
    for _ in 0..k {
        integrator.run_pass()?;
    }
    let whole = integrator.image()?;
    Ok(Some((halves_rel_variance(&half.pixels, &whole.pixels, k), k)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::shares::Choice;
    use crate::layout::WORK_COUNTS;

    /// Passes of a known variance: the halves' estimate of it, over many renders, is within a
    /// few percent of it (it is unbiased), and a render's at `k = 200` within about 10%.
    #[test]
    fn the_halves_read_the_variance_of_a_pass() {
        let (pixels, sigma, mean) = (400, 0.3f64, 1.0f64);
        let mut state = 12345u64;
        let mut uniform = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        // Gaussian by Box-Muller.
        let mut normal = || (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos();
        let k = 200;
        let mut estimates = Vec::new();
        for _ in 0..20 {
            let mut first = vec![[0.0f64; 3]; pixels];
            let mut second = vec![[0.0f64; 3]; pixels];
            for pass in 0..2 * k {
                let sums = if pass < k { &mut first } else { &mut second };
                for p in sums.iter_mut() {
                    for c in p.iter_mut() {
                        *c += mean + sigma * normal();
                    }
                }
            }
            let half: Vec<[f32; 3]> = first.iter().map(|p| p.map(|x| (x / k as f64) as f32)).collect();
            let whole: Vec<[f32; 3]> =
                first.iter().zip(&second).map(|(a, b)| [0, 1, 2].map(|c| ((a[c] + b[c]) / (2 * k) as f64) as f32)).collect();
            estimates.push(halves_rel_variance(&half, &whole, k as u32));
        }
        let truth = sigma * sigma / (mean * mean + REL_MSE_EPSILON);
        let mean_estimate = estimates.iter().sum::<f64>() / estimates.len() as f64;
        assert!((mean_estimate / truth - 1.0).abs() < 0.03, "mean estimate {mean_estimate} against {truth}");
        assert!(estimates.iter().all(|e| (e / truth - 1.0).abs() < 0.12), "{estimates:?} against {truth}");
        assert_eq!(halves_rel_variance(&[[f32::NAN; 3]], &[[1.0; 3]], 4), f64::INFINITY);
    }

    fn candidate(choice: &str, rel_variance: f64, cost: f64) -> Candidate {
        Candidate {
            choice: choice.parse().unwrap(),
            light_paths: 1,
            rel_variance,
            cost,
            seconds: 0.0,
            passes: 8,
            counts: [0.0; WORK_COUNTS as usize],
            bias: 0.0,
            margin: 1.0,
        }
    }

    /// sky.xml's pilot and check (seed 7, 30 s): connections alone chosen at 1.23e4 against
    /// merging alone's 1.75e4; their passes in the render varied 6.3x the pilot's reading, and
    /// merging alone renders from there. At 1.4x, as on envmap.xml, the render goes on.
    #[test]
    fn the_render_starts_over_only_where_its_passes_vary_far_more_than_the_pilot_read() {
        let pilot = [candidate("1/0", 0.504, 24_489.0), candidate("0/1", 0.665, 26_329.0), candidate("1/1", 0.638, 32_898.0)];
        let chosen: Choice = "1/0".parse().unwrap();
        let sky = decide(&pilot, chosen, 3.15, 27.0, 24.3);
        assert!((sky.ratio - 6.25).abs() < 0.01, "{sky:?}");
        assert_eq!(sky.switch_to, Some("0/1".parse().unwrap()));
        let envmap = decide(&pilot, chosen, 0.504 * 1.4, 27.0, 24.3);
        assert_eq!(envmap.switch_to, None);
        // Nothing left to render the other in: the render goes on.
        assert_eq!(decide(&pilot, chosen, 3.15, 27.0, 0.0).switch_to, None);
        // Without light subpaths chosen over the others, whose figures' best does not merge:
        // the render goes on with the best that merges.
        let mut with_none = pilot.to_vec();
        with_none.push(candidate("none", 0.517, 12_000.0));
        let none = decide(&with_none, "none".parse().unwrap(), 7.1, 27.0, 24.3);
        assert_eq!(none.switch_to, Some("0/1".parse().unwrap()), "{none:?}");
        let absent = decide(&pilot, "0/0".parse().unwrap(), 1.0, 27.0, 24.3);
        assert!(absent.ratio.is_nan() && absent.switch_to.is_none(), "{absent:?}");
    }
}
