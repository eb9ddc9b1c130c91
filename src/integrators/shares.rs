//! vcm's pilot: which camera vertices connect and which merge, chosen for the scene before
//! the render (where the scene sets neither `connect_share` nor `merge_share`).
//!
//! Merging pays where light reaches diffuse surfaces through mirrors and glass, connections
//! where light vertices are few and spread out; each costs a pass time. Following the
//! efficiency-aware MIS of Grittmann et al. 2022 (a strategy's error against its cost, which
//! it estimates while rendering, and where light subpaths do not pay their cost, none), the
//! pilot renders a few passes of the scene at a small size for each candidate of
//! [`CANDIDATES`]: everything (1, 1), merging without connections (0, 1), connections without
//! merging (1, 0), light tracing alone beside the camera's strategies (0, 0), and no light
//! subpaths at all (camera subpaths with next-event estimation, as pt-nee but weighed by the
//! power heuristic); then, where merging alone is the best of those, merging alone with four
//! times its light subpaths, and where the best traces light subpaths, photon mapping (merging
//! at each camera subpath's first diffuse vertex alone, where the subpath ends: SPPM's
//! estimator, by SPPM's kernels), weighed with its bias ([`Candidate::bias`]; chosen up to
//! [`PHOTON_MAPPING_MARGIN`] times the others' figure). Each
//! candidate's error is the relative variance of its passes' estimates (the mean over pixels and
//! channels of each pixel's sample variance over `mu^2 + 0.01`, `mu` the pixel's mean over every
//! pilot pass: a pass's relMSE as `diff` measures it, less the bias; a rare pass far off the
//! others left out, [`OUTLIER_DEVIATION`]); its cost is a weighted count of the work its kernels
//! did ([`CostModel`]). The pair of least error times cost renders the image.
//!
//! Without a time limit the choice is a function of the scene, its passes and its seed alone
//! (counted work, not time), so that on one device a seed's image stays the same to the bit
//! from run to run and batch to batch.
//!
//! Its passes are worth those of the render they stand for: the pilot's image has as many
//! pixels as fit [`PILOT_SIDE`] on its longer side, light subpaths in the same proportion,
//! and a radius that keeps merging's density estimate as noisy as the render's at its
//! [`representative_pass`] (the variance of a merge goes as 1 / (n_light r^2), Georgiev et
//! al. 2012, sec. 5.1), from the passes the render will run: its `iterations`, or under a time
//! limit as many as fit by a timed pass of the pilot ([`render_passes`]). Under a time limit the
//! choice may then differ with the device's speed, as the passes do; a checkpoint keeps the
//! choice, and a render resumed from it renders that choice again.

use super::light::{light_paths, vcm_radius, LightTracer, Shares};
use super::Integrator;
use super::SplatSums;
use crate::error::Error;
use crate::gpu::scene_buffers::{SceneBuffers, SceneData};
use crate::layout::{WORK_CAMERA_VERTICES, WORK_CONNECTIONS, WORK_COUNTS, WORK_LIGHT_VERTICES, WORK_MERGE_CANDIDATES};
use crate::scene::{RadiusSchedule, RenderSettings, Scene};
use std::fmt;
use std::sync::Arc;

/// A configuration of vcm's strategies: the shares of camera vertices that connect and that
/// merge, whether light subpaths are traced at all, and how many.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Choice {
    /// The shares.
    pub shares: Shares,
    /// Whether light subpaths are traced (else `light_paths = 0`, and both shares are 0).
    pub light_subpaths: bool,
    /// Pixels for each light subpath of a pass; 0 for the method's own count
    /// ([`light_paths`]).
    pub pixels_per_light_path: u32,
    /// Photon mapping ([`RenderSettings::photon_mapping`]): merging at each camera subpath's
    /// first diffuse vertex alone, SPPM's estimator, its photons a pass SPPM's `photons`.
    pub photon_mapping: bool,
}

impl Choice {
    const fn new(connect: f32, merge: f32, light_subpaths: bool, pixels_per_light_path: u32) -> Self {
        Self { shares: Shares { connect, merge }, light_subpaths, pixels_per_light_path, photon_mapping: false }
    }

    /// Photon mapping, whose shares read as merging alone's.
    pub const PHOTON_MAPPING: Self = Self { photon_mapping: true, ..Self::new(0.0, 1.0, true, 0) };

    /// Sets the choice in `render`: its shares, no light subpaths where it traces none, and
    /// its light subpaths a pass where it sets them.
    pub fn apply(&self, render: &mut RenderSettings) {
        (render.connect_share, render.merge_share) = (Some(self.shares.connect), Some(self.shares.merge));
        if self.photon_mapping {
            (render.photon_mapping, render.radius_schedule, render.radius_schedule_given) = (true, RadiusSchedule::Global, true);
        } else if !self.light_subpaths {
            render.light_paths = Some(0);
        } else if let Some(n) = render.width.saturating_mul(render.height).checked_div(self.pixels_per_light_path) {
            render.light_paths = Some(n.max(1));
        }
    }
}

impl Choice {
    /// The choice in words, for the user.
    pub fn description(&self) -> String {
        let shares = self.shares;
        if self.photon_mapping {
            "photon mapping (merging at each camera subpath's first diffuse vertex alone: sppm with the global radius schedule)"
                .into()
        } else if self.light_subpaths {
            let pixels = match self.pixels_per_light_path {
                0 => String::new(),
                1 => ", a light subpath a pixel".into(),
                n => format!(", a light subpath for every {n} pixels"),
            };
            format!("connect share {} and merge share {}{pixels}", shares.connect, shares.merge)
        } else {
            "no light subpaths (light_paths = 0: camera subpaths with next-event estimation, as pt-nee)".into()
        }
    }
}

impl fmt::Display for Choice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.light_subpaths {
            return write!(f, "none");
        }
        if self.photon_mapping {
            return write!(f, "sppm");
        }
        write!(f, "{}/{}", self.shares.connect, self.shares.merge)?;
        if self.pixels_per_light_path > 0 {
            write!(f, "@{}", self.pixels_per_light_path)?;
        }
        Ok(())
    }
}

impl std::str::FromStr for Choice {
    type Err = String;

    /// A choice as [`fmt::Display`] writes it: `none`, `sppm`, or `connect/merge` with
    /// `@pixels` where it sets its light subpaths.
    fn from_str(text: &str) -> Result<Self, String> {
        let bad = || format!("`{text}` is not a choice of vcm's pilot (none, sppm, or connect/merge[@pixels])");
        match text {
            "none" => return Ok(Self::new(0.0, 0.0, false, 0)),
            "sppm" => return Ok(Self::PHOTON_MAPPING),
            _ => {}
        }
        let (shares, pixels) = text.split_once('@').map_or((text, None), |(s, p)| (s, Some(p)));
        let (connect, merge) = shares.split_once('/').ok_or_else(bad)?;
        let share = |v: &str| v.parse::<f32>().ok().filter(|s| (0.0..=1.0).contains(s)).ok_or_else(bad);
        let pixels = pixels.map_or(Ok(0), |p| p.parse::<u32>().ok().filter(|&p| p > 0).ok_or_else(bad))?;
        Ok(Self::new(share(connect)?, share(merge)?, true, pixels))
    }
}

/// The configurations the pilot weighs ([`candidates`] says which of them for a scene). The
/// sixth merges alone with a light subpath for every pixel, four times merging alone's own
/// ([`super::light::PIXELS_PER_LIGHT_PATH_MERGING`]): where light reaches every surface through
/// glass, merging finds it and nothing else does, and its variance is the image's (on
/// cornell-skylight 85% of it, `--strategy-images`); there the pilot rates it 0.75x merging
/// alone (relative variance x cost) and at 60 s it renders 2.43e-3 against 2.72e-3 (sppm's
/// 2.67e-3 to 2.70e-3), where on the other canonical scenes the pilot rates it 1.04x to 1.54x
/// (BENCHMARKS.md "VCM"). The last is photon mapping, SPPM's estimator: its camera subpaths
/// end at their first diffuse vertex, which merges with many photons (200,000 a pass by
/// default, twelve times merging alone's light subpaths at 256x256) and samples direct light
/// several times; where light crosses rough glass onto diffuse walls (the bunny box) it
/// renders at equal passes and photons half the error of merging alone at every camera vertex.
pub const CANDIDATES: [Choice; 7] = [
    Choice::new(1.0, 1.0, true, 0),
    Choice::new(0.0, 1.0, true, 0),
    Choice::new(1.0, 0.0, true, 0),
    Choice::new(0.0, 0.0, true, 0),
    Choice::new(0.0, 0.0, false, 0),
    Choice::new(0.0, 1.0, true, 1),
    Choice::PHOTON_MAPPING,
];

/// The candidates the pilot weighs for `scene`: every one of [`CANDIDATES`], but where a
/// surface hides lights from next-event estimation (mirrors, glass, smooth coatings:
/// `MaterialKind::hides_lights`), only those that connect or merge. Light through such
/// surfaces onto a diffuse one, a caustic, seen in a mirror or through glass, is found only by
/// merging (or by connections, seen directly by light tracing too), else where BSDF sampling
/// hits a light: paths too rare for the pilot's passes to see. On cornell-spheres the pilot
/// rates (relative variance x cost) light tracing beside the camera's strategies at 1.03x
/// merging alone and camera subpaths alone at 1.05x, where at 30 s their relMSE is 2x and
/// (pt-nee's) 10x merging alone's (BENCHMARKS.md "VCM").
/// A scene that sets `light_paths` keeps its count: the candidates that set one, and photon
/// mapping (whose photons stand for them), are left out.
pub fn candidates(scene: &Scene) -> Vec<Choice> {
    // A measuring hook (scripts/measure/vcm-pilot-cost.sh): every candidate on every scene.
    let every = std::env::var_os("SPPM_GPU_PILOT_ALL").is_some();
    let hidden = !every && scene.materials.iter().any(|m| m.kind.hides_lights());
    let counted = scene.render.light_paths.is_some();
    CANDIDATES
        .into_iter()
        .filter(|c| !hidden || c.shares.connect > 0.0 || c.shares.merge > 0.0)
        .filter(|c| !counted || (c.pixels_per_light_path == 0 && !c.photon_mapping))
        .collect()
}

/// Whether vcm's pilot may weigh photon mapping for `scene` (where it chooses the shares, and
/// photon mapping is one of its [`candidates`]).
pub fn weighs_photon_mapping(scene: &Scene) -> bool {
    super::light::pilot_chooses_shares(scene) && candidates(scene).iter().any(|c| c.photon_mapping)
}

/// Pixels of the pilot's image on its longer side (at most the render's).
pub const PILOT_SIDE: u32 = 128;

/// Pilot passes of each candidate, at most.
pub const PILOT_PASSES: u32 = 8;

/// Pilot passes of each candidate, at least ([`PILOT_SHARE`]).
pub const MIN_PILOT_PASSES: u32 = 4;

/// The share of a time limit the pilot's passes may take: under a time limit each candidate
/// runs as many passes as fit in it, from [`MIN_PILOT_PASSES`] to [`PILOT_PASSES`], by the time
/// of a pilot pass with everything traced. On the canonical scenes 8 passes a candidate take 1
/// to 3 s of 60, within the share; on Bitterli's staircase (262k triangles, 180x320) the 4 to
/// 6 passes a candidate that 5% allowed rated photon mapping at 0.92x to 1.12x merging alone by
/// seed, where 8 rated it 0.79x to 0.93x (and it renders about 0.9x): 8% of a minute gives it 8
/// (BENCHMARKS.md "VCM").
pub const PILOT_SHARE: f64 = 0.08;

/// The pass whose radius the pilot's merges stand for in a render of `passes` passes: the
/// variance of a merge grows as the radius shrinks over the passes, and a render's error is
/// most that of its later passes. With r_i^2 = r_1^2 i^(alpha - 1) (Hachisuka and Jensen
/// 2009; Georgiev et al. 2012, sec. 5.1) the mean of r_i^(-2) over n passes is about
/// n^b / (1 + b), b = 1 - alpha, the value at pass k = n (1 + b)^(-1/b): 0.42 n for alpha =
/// 2/3, n / e as alpha goes to 1 (a fixed radius, any pass).
/// A fixed 256 (a render of some 640 passes) made the pilot rate merging's noise 1.9x too
/// high on Bitterli's staircase, which runs 94 passes in 60 s (BENCHMARKS.md "VCM").
pub fn representative_pass(passes: f64, alpha: f32) -> u32 {
    let b = (1.0 - alpha as f64).clamp(0.0, 1.0);
    let share = if b < 1e-6 { (-1.0f64).exp() } else { (1.0 + b).powf(-1.0 / b) };
    (share * passes).round().clamp(1.0, u32::MAX as f64) as u32
}

/// The passes the render of `scene` will run: its `iterations`, and under a time limit at most
/// as many as fit in what the pilot leaves of it, a render pass taking `pass_seconds` (a pilot
/// pass's time, with everything traced, scaled to the render's pixels) and the pilot
/// `pilot_seconds`.
pub fn render_passes(scene: &Scene, pass_seconds: Option<f64>, pilot_seconds: f64) -> f64 {
    let r = &scene.render;
    match (r.time_limit, pass_seconds) {
        (Some(limit), Some(pass)) if pass > 0.0 => ((limit - pilot_seconds).max(0.0) / pass).min(r.iterations as f64),
        _ => r.iterations as f64,
    }
}

/// What a pass's work costs, in units of a camera vertex (its next-event estimate and its
/// next segment, with its share of the pass's camera subpaths' starts): a connection (a shadow
/// ray and four BSDF evaluations), a light vertex a merging camera vertex looks at in the grid
/// (with its share of building the grid), a camera vertex's lookups where the pass merges, a
/// light vertex (its segment, light tracing's join to the camera), and a pixel's splats added
/// to its estimate where light subpaths are traced (2.1e-8 s on the two cores: 400 passes of
/// cornell-box without light subpaths, 8.99 s with that pass and 8.43 s without). The
/// connection, the merge candidate and the lookups fitted on lavapipe to the pass times of the
/// candidates on six scenes, the light vertex held at earlier fits' figure (it and the
/// candidates grow together, and a free fit gives it a cost below 0; `scripts/measure/vcm-pilot-cost.sh`,
/// BENCHMARKS.md "VCM"; since light straight from a lamp stopped merging, the mean of two runs,
/// each pass time within 17% of either run's fit on the scenes traced by code, 4% on the one
/// through a BVH):
/// a camera vertex and a connection cost what the scene's rays cost, about three
/// times more in scenes traced through a BVH than in those small enough to be traced by code
/// ([`crate::gpu::baked_bvh`]), a merge candidate and a lookup less so.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostModel {
    /// A connection's cost in camera vertices.
    pub connection: f64,
    /// A merge candidate's cost in camera vertices.
    pub merge_candidate: f64,
    /// A camera vertex's cost besides, in camera vertices, where the pass merges: the lookups
    /// in the grid of its subpath's merging vertices (the bounds of the buckets their radius
    /// reaches), which the candidates they find do not stand for.
    pub merging_camera_vertex: f64,
    /// A light vertex's cost in camera vertices (its segment, storing it, light tracing's join
    /// to the camera).
    pub light_vertex: f64,
    /// A pixel's cost in camera vertices where a pass traces light subpaths: its splats added
    /// to its estimate (`splat_accumulate`).
    pub splat_pixel: f64,
    /// A camera vertex where no light subpath is traced, in camera vertices of the pilot's
    /// kernel: that candidate renders by pt-nee's kernel (`light::camera_subpaths_alone`),
    /// whose pass at 256x256 took 0.89 of the bidirectional kernel's on cornell-box and 0.91
    /// on the bunny box (passes a second, alternating, BENCHMARKS.md "VCM").
    pub camera_vertex_alone: f64,
    /// Photon mapping (SPPM's kernels): a camera path of its camera pass (to the first diffuse
    /// vertex, with next-event estimation along it), with its share of the visible points'
    /// grid.
    pub visible_point_path: f64,
    /// Photon mapping: a photon hit gathered (the visible points of its cell looked at).
    pub photon_hit: f64,
    /// Photon mapping: a photon (its path, but for its hits' gathering).
    pub photon: f64,
}

/// [`CostModel`] of a scene traced by code (at most
/// [`MAX_BAKED_PRIMITIVES`](crate::gpu::scene_buffers::MAX_BAKED_PRIMITIVES) primitives).
pub const BAKED_COST: CostModel = CostModel {
    connection: 0.55,
    merge_candidate: 0.35,
    merging_camera_vertex: 0.55,
    light_vertex: 0.29,
    splat_pixel: 0.14,
    camera_vertex_alone: 0.89,
    visible_point_path: 1.02,
    photon_hit: 1.43,
    photon: 1.35,
};

/// [`CostModel`] of a scene traced through a BVH.
pub const TRAVERSED_COST: CostModel = CostModel {
    connection: 0.62,
    merge_candidate: 0.16,
    merging_camera_vertex: 0.14,
    light_vertex: 1.04,
    splat_pixel: 0.04,
    camera_vertex_alone: 0.91,
    visible_point_path: 1.37,
    photon_hit: 0.10,
    photon: 1.47,
};

impl CostModel {
    /// The cost model of the scene of `data`.
    pub fn of(data: &SceneData) -> Self {
        let primitives = data.bvh.prim_refs.len();
        if primitives > 0 && primitives <= crate::gpu::scene_buffers::MAX_BAKED_PRIMITIVES {
            BAKED_COST
        } else {
            TRAVERSED_COST
        }
    }

    /// A pass's cost, in camera vertices, from its counts of work (`WORK_*` words), whether it
    /// traces light subpaths, and its `pixels` (whose splats it adds where it does).
    pub fn cost(&self, counts: &[u32], light_subpaths: bool, pixels: u32) -> f64 {
        let n = |word: u32| counts[word as usize] as f64;
        if !light_subpaths {
            return self.camera_vertex_alone * n(WORK_CAMERA_VERTICES);
        }
        let merging = if n(WORK_MERGE_CANDIDATES) > 0.0 { self.merging_camera_vertex } else { 0.0 };
        n(WORK_CAMERA_VERTICES) * (1.0 + merging)
            + self.connection * n(WORK_CONNECTIONS)
            + self.merge_candidate * n(WORK_MERGE_CANDIDATES)
            + self.light_vertex * n(WORK_LIGHT_VERTICES)
            + self.splat_pixel * pixels as f64
    }

    /// A pass of photon mapping's cost, in camera vertices, from its camera paths, the photon
    /// hits it gathered and its photons.
    pub fn photon_mapping_cost(&self, camera_paths: f64, hits: f64, photons: f64) -> f64 {
        self.visible_point_path * camera_paths + self.photon_hit * hits + self.photon * photons
    }
}

/// One candidate's figures.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The candidate.
    pub choice: Choice,
    /// Its light subpaths a pilot pass.
    pub light_paths: u32,
    /// The relative variance of one of its passes (see the module's documentation).
    pub rel_variance: f64,
    /// The cost of one of its passes, in camera vertices ([`CostModel`]); under a time limit,
    /// photon mapping's by its measured time against the best other candidate's
    /// ([`Candidate::seconds`]).
    pub cost: f64,
    /// The measured seconds of one of its pilot passes (their mean, read-backs included).
    pub seconds: f64,
    /// Its pilot passes: the pilot's passes a candidate, or for photon mapping half of them
    /// where its figure after them had lost by [`EARLY_LOSS`].
    pub passes: u32,
    /// Its work a pass, by `WORK_*` word (the mean over its passes); for photon mapping its
    /// camera paths in the camera vertices' word, its photon hits in the merge candidates'.
    pub counts: [f64; WORK_COUNTS as usize],
    /// For photon mapping, what its bias adds to its relative variance in the render's error:
    /// its squared bias ([`paired_bias`]) times the passes it would render (the error after n
    /// passes is V / n + B^2, so n times it V + n B^2); 0 for the others, whose merges share
    /// the light with unbiased strategies.
    pub bias: f64,
    /// The share of the best other candidate's figure that its own must stay below: 1, or
    /// [`DENSER_MARGIN`], [`NO_LIGHT_SUBPATHS_MARGIN`] or [`PHOTON_MAPPING_MARGIN`] (above 1: a
    /// near tie goes to it).
    pub margin: f64,
}

impl Candidate {
    /// The figure the pilot chooses by: relative variance (and photon mapping's [`Self::bias`])
    /// times cost, over its [`Self::margin`].
    pub fn figure(&self) -> f64 {
        (self.rel_variance + self.bias) * self.cost / self.margin
    }
}

/// The share of merging alone's figure that merging alone with a light subpath a pixel (four
/// times its own) must stay below: a near tie goes to the method's own light subpaths. On
/// Mitsuba's box.xml the pilot rated it at 0.94x merging alone (relative variance 0.61x, cost
/// 1.55x) where at 60 s it rendered 1.16x the error (1.80e-4 against 1.55e-4); on
/// cornell-skylight, where it pays, the pilot rates it at 0.75x to 0.80x (BENCHMARKS.md "VCM").
pub const DENSER_MARGIN: f64 = 0.9;

/// The share of the best other candidate's figure that no light subpaths at all (camera
/// subpaths with next-event estimation, rendered by pt-nee's kernel) must stay below: above 1,
/// a near tie goes to it, whose image is pt-nee's. The pilot runs it on the bidirectional
/// kernel and its cost model prices light subpaths from fitted counts; on Mitsuba's
/// textures.xml at 30 s it rated light tracing beside the camera's strategies (0, 0) at 1.00x
/// no light subpaths over 1.1 (1.10x better), whose passes then rendered 1.19x to 1.23x no light
/// subpaths' error (4.38e-5 against 3.67e-5), a pass with light subpaths costing 1.39x one
/// without where the pilot counted 1.20x (BENCHMARKS.md "VCM"). At 1.25 it goes to no light
/// subpaths.
pub const NO_LIGHT_SUBPATHS_MARGIN: f64 = 1.25;

/// The share of the best other candidate's figure that photon mapping's must stay below: above
/// 1, photon mapping wins ties and more. Its figure holds its bias ([`Candidate::bias`]) and,
/// under a time limit, its measured time; what is left is the pilot's reading of noise from a
/// few passes, which on the scenes where photon mapping renders better than vcm's own
/// strategies rates it too high: merging alone's variance at 8 pilot passes was 0.65x what
/// its renders showed on Mitsuba's lens.xml (rare bright paths through the mirror that 8
/// passes do not meet) and 0.7x on Bitterli's staircase, photon mapping's own 1.3x to 1.7x on
/// lens.xml and plastic.xml, where on Mitsuba's box.xml both were within 17%. At 1.4 vcm
/// chooses photon mapping on plastic.xml (rated 0.86x to 0.98x merging alone), lens.xml
/// (1.12x to 1.20x), the staircase (1.14x to 1.34x), the bunny box and cornell-glossy, and not
/// where its bias is most of its figure (cornell-spheres 8.5x, cornell-skylight 4.2x, null.xml
/// 3.6x, metals.xml 2.5x, tinted.xml 2.1x); box.xml's near tie (0.95x to 1.24x) goes to it
/// and renders 1.05x to 1.08x sppm's error (BENCHMARKS.md "VCM").
pub const PHOTON_MAPPING_MARGIN: f64 = 1.4;

/// What vcm's pilot measured and chose.
#[derive(Clone, Debug)]
pub struct Pilot {
    /// The candidate of least relative variance times cost.
    pub chosen: Choice,
    /// The figures of each candidate the pilot ran: those of [`candidates`] at the method's own
    /// light subpaths in order, then, where merging alone was the best of them, the rest.
    pub candidates: Vec<Candidate>,
    /// The pilot image's width.
    pub width: u32,
    /// The pilot image's height.
    pub height: u32,
    /// Its passes of each candidate ([`PILOT_PASSES`], fewer under a short time limit).
    pub passes: u32,
    /// The render's pass whose radius its merges stood for ([`representative_pass`]).
    pub representative: u32,
    /// Seconds the pilot took (its passes and read-backs).
    pub seconds: f64,
}

impl fmt::Display for Pilot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "vcm's pilot ({} passes at {}x{}, merges as at pass {}, {:.2} s) chose ",
            self.passes * self.candidates.len() as u32,
            self.width,
            self.height,
            self.representative,
            self.seconds,
        )?;
        write!(f, "{}", self.chosen.description())?;
        write!(
            f,
            " (relative variance x cost of connect/merge shares, @ pixels a light subpath where set, none for no light \
             subpaths, sppm photon mapping, each over its margin where not 1:"
        )?;
        for c in &self.candidates {
            write!(f, " {} {:.3e}", c.choice, c.figure())?;
            if c.margin != 1.0 {
                write!(f, " (over {})", c.margin)?;
            }
        }
        write!(f, ")")
    }
}

/// Each pixel's estimate of the pass between the pilot's sums `before` and `after`: their
/// difference (over a count of 1), or where the camera's samples are splatted through a wide
/// filter (sums of weighted samples and of weights, the light subpaths' apart where traced)
/// the pass's weighted mean of the camera's samples plus its light splats.
fn pass_estimate(after: &SplatSums, before: &SplatSums) -> Vec<[f32; 3]> {
    let camera = after.camera.iter().zip(&before.camera);
    match (&after.light, &before.light) {
        (Some(light), Some(light_before)) => camera
            .zip(light.iter().zip(light_before))
            .map(|((a, b), (l, lb))| {
                let w = a[3] - b[3];
                let c = |i: usize| if w > 0.0 { (a[i] - b[i]) / w } else { 0.0 };
                [c(0) + l[0] - lb[0], c(1) + l[1] - lb[1], c(2) + l[2] - lb[2]]
            })
            .collect(),
        // A count of 1 a pass (nothing splats), or SPPM's splatted estimates' weights.
        _ => camera
            .map(|(a, b)| {
                let w = a[3] - b[3];
                let c = |i: usize| if w > 0.0 { (a[i] - b[i]) / w } else { 0.0 };
                [c(0), c(1), c(2)]
            })
            .collect(),
    }
}

/// Each pixel's mean over the pilot's `passes` so far, from its sums: their sum over the
/// passes, or where the camera's samples are splatted their weighted mean plus the light
/// splats' sum over the passes.
fn pass_mean(sums: &SplatSums, passes: f64) -> Vec<[f64; 3]> {
    match &sums.light {
        Some(light) => sums
            .camera
            .iter()
            .zip(light)
            .map(|(s, l)| {
                let w = s[3] as f64;
                let c = |i: usize| if w > 0.0 { s[i] as f64 / w } else { 0.0 };
                [c(0) + l[0] as f64 / passes, c(1) + l[1] as f64 / passes, c(2) + l[2] as f64 / passes]
            })
            .collect(),
        None => sums.camera.iter().map(|s| [s[0] as f64 / passes, s[1] as f64 / passes, s[2] as f64 / passes]).collect(),
    }
}

/// The scene the pilot renders for `scene` (see the module's documentation), each candidate's
/// light subpaths a pilot pass, in proportion to the render's, for light subpaths that keep
/// `vertices` each on average ([`light_paths`]), and the factor on the render's radius that
/// keeps the pilot's merges as noisy as the render's (the variance of a merge goes as
/// 1 / (n_light r^2)). Its radius is the render's first pass's so scaled; [`pilot_radius`]
/// gives that of another pass.
fn pilot_scene(scene: &Scene, candidates: &[Choice], limit: u64, vertices: Option<f64>) -> Result<(Scene, Vec<u32>, f64), Error> {
    let mut pilot = scene.clone();
    // Every strategy weighed and kept (a render for `--strategy-images` keeps one).
    (pilot.render.method, pilot.render.strategies) = (crate::scene::Method::Vcm, crate::layout::STRATEGIES_ALL);
    let r = &mut pilot.render;
    // The measuring hook's pilot at another size (SPPM_GPU_PILOT_SIDE).
    let side = std::env::var("SPPM_GPU_PILOT_SIDE").ok().and_then(|v| v.parse().ok()).unwrap_or(PILOT_SIDE);
    let scale = (side as f64 / r.width.max(r.height) as f64).min(1.0);
    let pixels = r.width as f64 * r.height as f64;
    (r.width, r.height) = (((r.width as f64 * scale).round() as u32).max(1), ((r.height as f64 * scale).round() as u32).max(1));
    let pilot_pixels = r.width as f64 * r.height as f64;
    if let Some(n) = r.light_paths {
        r.light_paths = Some(((n as f64 * pilot_pixels / pixels).round() as u32).max(1));
    }
    // Each candidate's light subpaths, from the render settings alone (no copy of the scene).
    let with = |r: &RenderSettings, choice: &Choice| {
        let mut r = r.clone();
        choice.apply(&mut r);
        light_paths(&r, limit, vertices)
    };
    let counts = candidates.iter().map(|c| with(&pilot.render, c)).collect::<Result<Vec<u32>, Error>>()?;
    let n_render = with(&scene.render, &candidates[0])? as f64;
    let n_pilot = counts[0] as f64;
    let factor = (n_render / n_pilot).sqrt();
    let r = &mut pilot.render;
    // Room for the most any candidate traces.
    r.light_paths = counts.iter().copied().max();
    (r.radius, r.alpha) = (pilot_radius(scene, 1, factor), 1.0);
    (r.time_limit, r.iterations) = (None, PILOT_PASSES * candidates.len() as u32);
    // Set, so that the pilot's own shares are its candidates' (`LightTracer::counted_pass`).
    (r.connect_share, r.merge_share) = (Some(1.0), Some(1.0));
    // Numbers of their own, not the render's first passes'.
    r.seed = r.seed.wrapping_add(0x9e37_79b9);
    Ok((pilot, counts, factor))
}

/// The pilot's radius for merges as noisy as the render's at pass `representative`, with the
/// radius factor of [`pilot_scene`].
fn pilot_radius(scene: &Scene, representative: u32, factor: f64) -> Option<f32> {
    Some((vcm_radius(scene, representative) as f64 * factor) as f32)
}

/// Runs vcm's pilot for `scene` (its scene data built and uploaded for it) and chooses its
/// shares, whether or not the scene sets them.
pub fn choose_for(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<Pilot, Error> {
    let data = SceneData::new(scene)?;
    let buffers = Arc::new(SceneBuffers::upload(device, scene, &data)?);
    choose(device, queue, scene, &data, buffers)
}

/// Runs vcm's pilot for `scene` on its uploaded buffers and chooses its shares.
pub fn choose(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    data: &SceneData,
    buffers: Arc<SceneBuffers>,
) -> Result<Pilot, Error> {
    let start = std::time::Instant::now();
    let limit = device.limits().max_storage_buffer_binding_size;
    let choices = candidates(scene);
    // The tracer first, with room for the light subpaths the candidates want: its probe says
    // how many vertices they keep, and so how many a pass of the pilot and of the render hold.
    let (wanting, _, _) = pilot_scene(scene, &choices, limit, Some(0.0))?;
    let (width, height) = (wanting.render.width, wanting.render.height);
    let mut tracer = LightTracer::with_scene_buffers(device, queue, &wanting, data, buffers.clone(), 0..height)?;
    let (mut pilot, counts, factor) = pilot_scene(scene, &choices, limit, tracer.vertices_per_subpath())?;
    // Under a time limit, the pilot's passes and the render's from a pilot pass's time with
    // everything traced.
    let (mut pass_seconds, mut passes_each) = (None, PILOT_PASSES);
    if let Some(time_limit) = scene.render.time_limit {
        let pilot_pass = timed_pass(&mut tracer, choices[0].shares, counts[0])?;
        let fit = (PILOT_SHARE * time_limit / (pilot_pass * choices.len() as f64)).floor();
        passes_each = fit.clamp(MIN_PILOT_PASSES as f64, PILOT_PASSES as f64) as u32;
        let pilot_seconds = start.elapsed().as_secs_f64() + pilot_pass * (passes_each as usize * choices.len()) as f64;
        let share = (scene.render.width as f64 * scene.render.height as f64) / (width as f64 * height as f64);
        pass_seconds = Some((pilot_pass * share, pilot_seconds));
    }
    let (render_pass, pilot_seconds) = pass_seconds.unzip();
    let passes = render_passes(scene, render_pass, pilot_seconds.unwrap_or(0.0));
    let representative = representative_pass(passes, scene.render.alpha);
    // A measuring hook (scripts/measure/vcm-pilot-cost.sh): what the render's passes came from.
    let log = std::env::var_os("SPPM_GPU_PILOT_LOG").is_some();
    if log {
        eprintln!("pilot render passes {passes:.1} (a render pass {render_pass:?} s, the pilot {pilot_seconds:?} s)");
    }
    pilot.render.radius = pilot_radius(scene, representative, factor);
    tracer.set_radius(pilot.render.radius);
    let pixels = (width * height) as usize;
    let model = CostModel::of(data);
    // Each candidate's passes' estimates, pixel by pixel.
    let mut estimates = vec![Vec::new(); choices.len()];
    let mut costs = vec![0.0; choices.len()];
    let mut seconds = vec![0.0; choices.len()];
    let mut work = vec![[0.0; WORK_COUNTS as usize]; choices.len()];
    let mut before = SplatSums::zero(pixels, tracer.splats_apart());
    // The passes of candidates `ks`, in turn; then every candidate run so far, its figures
    // with each pixel's mean over every pilot pass so far, and those means.
    let mut ran: Vec<usize> = Vec::new();
    let mut run = |ks: &[usize]| -> Result<(Vec<Candidate>, Vec<[f64; 3]>), Error> {
        for pass in 0..passes_each * ks.len() as u32 {
            let k = ks[pass as usize % ks.len()];
            let pass_start = std::time::Instant::now();
            let (sums, work_counts) = tracer.counted_pass(choices[k].shares, counts[k])?;
            let pass_seconds = pass_start.elapsed().as_secs_f64();
            seconds[k] += pass_seconds / passes_each as f64;
            // The measuring hook: each pilot pass's time and counts.
            if log {
                eprintln!("pilot pass {k} {pass_seconds:.6} {work_counts:?}");
            }
            let estimate = pass_estimate(&sums, &before);
            before = sums;
            estimates[k].push(estimate);
            costs[k] += model.cost(&work_counts, counts[k] > 0, pixels as u32) / passes_each as f64;
            for (w, &n) in work[k].iter_mut().zip(&work_counts) {
                *w += n as f64 / passes_each as f64;
            }
        }
        ran.extend_from_slice(ks);
        let all = tracer.passes().max(1) as f64;
        let mu = pass_mean(&before, all);
        let candidates = ran
            .iter()
            .map(|&k| Candidate {
                choice: choices[k],
                light_paths: counts[k],
                rel_variance: rel_variance(&estimates[k], &mu),
                cost: costs[k],
                seconds: seconds[k],
                passes: passes_each,
                counts: work[k],
                bias: 0.0,
                margin: match choices[k] {
                    c if !c.light_subpaths => NO_LIGHT_SUBPATHS_MARGIN,
                    c if c.pixels_per_light_path > 0 => DENSER_MARGIN,
                    _ => 1.0,
                },
            })
            .collect();
        Ok((candidates, mu))
    };
    let best = |candidates: &[Candidate]| best_of(candidates).map_or(CANDIDATES[0], |c| c.choice);
    // Those at the method's own light subpaths first; merging alone with more light subpaths
    // only where merging alone is the best of them, photon mapping where the best traces light
    // subpaths (or both for the measuring hook).
    let (first, more): (Vec<usize>, Vec<usize>) =
        (0..choices.len()).partition(|&k| choices[k].pixels_per_light_path == 0 && !choices[k].photon_mapping);
    let (mut candidates, mut mu) = run(&first)?;
    let every = std::env::var_os("SPPM_GPU_PILOT_ALL").is_some();
    let (mapping, denser): (Vec<usize>, Vec<usize>) = more.iter().partition(|&&k| choices[k].photon_mapping);
    if !denser.is_empty() && (best(&candidates) == CANDIDATES[1] || every) {
        (candidates, mu) = run(&denser)?;
    }
    if !mapping.is_empty() && (best(&candidates).light_subpaths || every) {
        let timed = scene.render.time_limit.map(|limit| Timed { limit, start });
        let at = (representative, passes_each);
        let rival = best_of(&candidates);
        let mapping = photon_mapping(device, queue, scene, &pilot, data, buffers, &mu, &model, at, rival, timed, log)?;
        candidates.push(mapping);
    }
    if log {
        for c in &candidates {
            eprintln!("pilot candidate {} {:.6e} {:.6e}", c.choice, c.rel_variance, c.cost);
            // Each pass's share of its relative variance (`OUTLIER_DEVIATION`).
            if let Some(k) = ran.iter().position(|&k| choices[k] == c.choice) {
                let d = pass_deviations(&estimates[ran[k]], &mu);
                eprintln!("pilot deviations {} {:?}", c.choice, d.iter().map(|x| format!("{x:.3e}")).collect::<Vec<_>>());
            }
        }
    }
    let chosen = best(&candidates);
    let seconds = start.elapsed().as_secs_f64();
    Ok(Pilot { chosen, candidates, width, height, passes: passes_each, representative, seconds })
}

/// The candidate of least figure, the pilot's choice among `candidates`.
fn best_of(candidates: &[Candidate]) -> Option<&Candidate> {
    candidates.iter().min_by(|a, b| a.figure().total_cmp(&b.figure()))
}

/// Seconds of a pass of `tracer` at `shares` with `paths` light subpaths: the second of two
/// (the first may set up what later passes reuse). Then the tracer starts over.
fn timed_pass(tracer: &mut LightTracer, shares: Shares, paths: u32) -> Result<f64, Error> {
    tracer.counted_pass(shares, paths)?;
    let start = std::time::Instant::now();
    tracer.counted_pass(shares, paths)?;
    let seconds = start.elapsed().as_secs_f64();
    tracer.reset();
    Ok(seconds)
}

/// Under a time limit, what photon mapping's pilot needs of it: the limit and when the pilot
/// started.
struct Timed {
    limit: f64,
    start: std::time::Instant,
}

/// The factor on photon mapping's pilot radius of its second set of passes, whose difference
/// from the first measures its bias ([`paired_bias`]).
pub const BIAS_RADIUS_FACTOR: f32 = 2.0;

/// Photon mapping's pilot passes at [`BIAS_RADIUS_FACTOR`] times the radius, at most, each
/// paired with one of its first passes, whose random numbers it shares. At eight pairs the
/// bias' standard error over pixels was 3% to 30% of it on fifteen scenes; four, for half the
/// passes, leave it about 1.4x that (BENCHMARKS.md "VCM").
pub const BIAS_PASSES: u32 = 4;

/// The factor by which photon mapping's figure after half its pilot passes (without its bias,
/// or with it from as many pairs) may exceed the best other candidate's before the rest are not
/// run: a pass's share of a candidate's relative variance stays within 2x of their median but
/// for a rare pass, which raises the figure (BENCHMARKS.md "VCM").
pub const EARLY_LOSS: f64 = 2.0;

/// Photon mapping's figures ([`Choice::PHOTON_MAPPING`]): `passes` passes of SPPM's
/// estimator on the pilot's image `pilot` (its size and seed), with photons in the same
/// proportion to the render's as its pixels and a fixed radius that keeps the density
/// estimate as noisy as the render's at its representative pass (as the other candidates'
/// merges); its relative variance against `mu`, each pixel's mean over the other
/// candidates' passes.
///
/// Without a time limit photon mapping renders the scene's passes, as the others do, and its
/// representative pass is theirs, `representative`; its cost is the cost model's. Under a time
/// limit it renders as many passes as fit, far fewer than vcm's (a pass gathers many photons at
/// several camera paths a pixel): a first pass, timed and set aside, says how many, and so the
/// pass its radius stands for; and its cost is the best other candidate's times the ratio of
/// their measured pass times. On Mitsuba's lens.xml at 30 s photon mapping runs about 200
/// passes to merging alone's 1,300: the radius of vcm's representative pass made its pilot
/// variance 1.6x what its render showed, and the cost model priced its pass at 0.22x to 1.9x
/// its measured time relative to the others', by scene (BENCHMARKS.md "VCM").
///
/// Its bias, which the others' merges share with unbiased strategies and its relative variance
/// cannot show, from the same passes again at [`BIAS_RADIUS_FACTOR`] times the radius with the
/// same random numbers ([`paired_bias`]), weighed by the passes it would render
/// ([`Candidate::bias`]).
///
/// Its bias only adds to its figure, so the pilot spends on it only while it can win against
/// `rival`, the best other candidate: after half its passes it stops where its relative variance
/// alone has lost by [`EARLY_LOSS`], else it runs the passes at the wider radius then, paired
/// with those, and stops where with its bias it has lost by [`EARLY_LOSS`]; after all its
/// passes, the pairs that are left run only where its relative variance alone has not lost. On Mitsuba's legacy.xml
/// at 30 s, where photon mapping's figure is 1.4x to 3.4x merging alone's, the pilot took 1.84
/// to 3.16 s where it took 3.18 to 3.39 (BENCHMARKS.md "VCM").
#[allow(clippy::too_many_arguments)]
fn photon_mapping(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    pilot: &Scene,
    data: &SceneData,
    buffers: Arc<SceneBuffers>,
    mu: &[[f64; 3]],
    model: &CostModel,
    (representative, passes): (u32, u32),
    rival: Option<&Candidate>,
    timed: Option<Timed>,
    log: bool,
) -> Result<Candidate, Error> {
    let mut mapping = pilot.clone();
    Choice::PHOTON_MAPPING.apply(&mut mapping.render);
    let r = &mut mapping.render;
    let share = (r.width as f64 * r.height as f64) / (scene.render.width as f64 * scene.render.height as f64);
    r.photons = ((scene.render.photons as f64 * share).round() as u32).max(1);
    let r1 = scene.render.radius.unwrap_or_else(|| super::sppm::auto_radius(scene));
    let photons_factor = (scene.render.photons as f64 / r.photons as f64).sqrt();
    let radius_at = |pass: u32| (super::sppm::global_radius_sq(r1, scene.render.alpha, pass).sqrt() * photons_factor) as f32;
    (r.radius, r.alpha) = (Some(radius_at(representative)), 1.0);
    r.iterations = passes;
    let height = r.height;
    let sppm_at = |mapping: &Scene| {
        super::Sppm::with_scene_buffers(device, queue, mapping, data, buffers.clone(), 0..height, super::Deposits::Auto)
    };
    let mut render_passes = scene.render.iterations as f64;
    if let Some(timed) = &timed {
        let mut first = SppmPasses::new(sppm_at(&mapping)?);
        first.run(1, false)?;
        let (_, pass) = first.means();
        let left = timed.limit - timed.start.elapsed().as_secs_f64() - (passes + BIAS_PASSES.min(passes)) as f64 * pass;
        render_passes = (left.max(0.0) / (pass / share)).min(render_passes);
        let representative = representative_pass(render_passes, scene.render.alpha);
        mapping.render.radius = Some(radius_at(representative));
        if log {
            eprintln!("pilot sppm render passes {render_passes:.1} (a pilot pass {pass:.6} s), as at pass {representative}");
        }
    }
    let r = &mapping.render;
    let pixels = r.width as usize * r.height as usize;
    let camera_paths = (pixels as u64 * r.spp as u64 * super::sppm::direct_samples(r) as u64) as f64;
    // Its relative variance and cost after the passes run so far.
    let figures = |run: &SppmPasses| {
        let (hits, seconds) = run.means();
        let cost = match (&timed, rival) {
            (Some(_), Some(other)) => other.cost * seconds / other.seconds,
            _ => model.photon_mapping_cost(camera_paths, hits, r.photons as f64),
        };
        (rel_variance(&run.estimates, mu), cost)
    };
    // Whether photon mapping's figure, from `variance` (its relative variance, and its bias
    // where measured) and `cost`, has lost to the best other candidate by `factor`.
    let lost = |variance: f64, cost: f64, factor: f64| {
        rival.is_some_and(|other| variance * cost / PHOTON_MAPPING_MARGIN > factor * other.figure())
    };
    let mut wide_scene = mapping.clone();
    wide_scene.render.radius = mapping.render.radius.map(|r| r * BIAS_RADIUS_FACTOR);
    let bias_of = |run: &SppmPasses, wide: &SppmPasses| paired_bias(&run.estimates, &wide.estimates, mu).max(0.0);
    let mut run = SppmPasses::new(sppm_at(&mapping)?);
    let half = passes.div_ceil(2).max(2).min(passes);
    run.run(half, log)?;
    let (mut variance, mut cost) = figures(&run);
    // After half its passes: it stops where its variance alone has lost by EARLY_LOSS; else
    // its passes at the wider radius pair with those it ran, and it stops where with its bias
    // it has lost by EARLY_LOSS.
    let mut wide: Option<SppmPasses> = None;
    let mut stop = lost(variance, cost, EARLY_LOSS);
    if !stop {
        let mut pairs = SppmPasses::new(sppm_at(&wide_scene)?);
        pairs.run(BIAS_PASSES.min(half), false)?;
        stop = lost(variance + bias_of(&run, &pairs) * render_passes, cost, EARLY_LOSS);
        wide = Some(pairs);
    }
    if !stop {
        run.run(passes - half, log)?;
        (variance, cost) = figures(&run);
        // Its bias, where it could still win.
        if !lost(variance, cost, 1.0) {
            let mut pairs = match wide.take() {
                Some(pairs) => pairs,
                None => SppmPasses::new(sppm_at(&wide_scene)?),
            };
            let more = BIAS_PASSES.min(passes).saturating_sub(pairs.estimates.len() as u32);
            pairs.run(more, false)?;
            wide = Some(pairs);
        }
    }
    let bias = wide.as_ref().map_or(0.0, |pairs| bias_of(&run, pairs));
    let (hits, seconds) = run.means();
    if log {
        let d = pass_deviations(&run.estimates, mu);
        eprintln!("pilot deviations sppm {:?}", d.iter().map(|x| format!("{x:.3e}")).collect::<Vec<_>>());
        let wide = wide.map_or("not run: its variance alone loses".into(), |wide| {
            format!("{:.4e} at {BIAS_RADIUS_FACTOR}x the radius", rel_variance(&wide.estimates, mu))
        });
        eprintln!(
            "pilot sppm bias {bias:.4e} over {render_passes:.1} passes, relative variance {variance:.4e} ({wide}), {seconds:.6} s a pass, {} passes",
            run.estimates.len(),
        );
    }
    let mut counts = [0.0; WORK_COUNTS as usize];
    (counts[WORK_CAMERA_VERTICES as usize], counts[WORK_MERGE_CANDIDATES as usize]) = (camera_paths, hits);
    Ok(Candidate {
        choice: Choice::PHOTON_MAPPING,
        light_paths: mapping.render.photons,
        rel_variance: variance,
        cost,
        seconds,
        passes: run.estimates.len() as u32,
        counts,
        bias: bias * render_passes,
        margin: PHOTON_MAPPING_MARGIN,
    })
}

/// Each pass's estimate, pixel by pixel.
type Passes = Vec<Vec<[f32; 3]>>;

/// Passes of an SPPM renderer (the global schedule), run a few at a time: each pass's own
/// estimate (the image after k passes is the mean of theirs, so pass k's is k times it less
/// the sum before), the photon hits a pass gathered and its seconds (read-backs included).
struct SppmPasses {
    sppm: super::Sppm,
    estimates: Passes,
    sum: Vec<[f64; 3]>,
    /// Where the passes' estimates are splatted: the sums after the last pass.
    splat: Option<SplatSums>,
    hits: f64,
    seconds: f64,
}

impl SppmPasses {
    fn new(sppm: super::Sppm) -> Self {
        Self { sppm, estimates: Vec::new(), sum: Vec::new(), splat: None, hits: 0.0, seconds: 0.0 }
    }

    /// Runs `passes` passes more.
    fn run(&mut self, passes: u32, log: bool) -> Result<(), Error> {
        for _ in 0..passes {
            let start = std::time::Instant::now();
            self.sppm.run_pass()?;
            let estimate = self.last_estimate()?;
            let gathered = self.sppm.photon_hits_gathered()?.0 as f64;
            let pass_seconds = start.elapsed().as_secs_f64();
            // The measuring hook (scripts/measure/pilot-time-cost.py): each pass's time and hits.
            if log {
                eprintln!("pilot sppm pass {pass_seconds:.6} [{gathered}]");
            }
            (self.seconds, self.hits) = (self.seconds + pass_seconds, self.hits + gathered);
            self.estimates.push(estimate);
        }
        Ok(())
    }

    /// Each pixel's estimate of the pass just run (waits for it): where the estimates are
    /// splatted, the pass's weighted mean from the sums (plus its direct light summed apart),
    /// else from the image of the passes so far and the sum of those before.
    fn last_estimate(&mut self) -> Result<Vec<[f32; 3]>, Error> {
        if let Some(sums) = Integrator::splat_sums(&mut self.sppm)? {
            let zero = || SplatSums::zero(sums.camera.len(), sums.light.is_some());
            let estimate = pass_estimate(&sums, self.splat.as_ref().unwrap_or(&zero()));
            self.splat = Some(sums);
            return Ok(estimate);
        }
        let image = self.sppm.image()?;
        self.sum.resize(image.pixels.len(), [0.0; 3]);
        let k = (self.estimates.len() + 1) as f64;
        Ok(image
            .pixels
            .iter()
            .zip(self.sum.iter_mut())
            .map(|(mean, sum)| {
                let e = [0, 1, 2].map(|c| k * mean[c] as f64 - sum[c]);
                (0..3).for_each(|c| sum[c] += e[c]);
                e.map(|x| x as f32)
            })
            .collect())
    }

    /// The mean photon hits a pass gathered, and the mean seconds of a pass.
    fn means(&self) -> (f64, f64) {
        let n = self.estimates.len().max(1) as f64;
        (self.hits / n, self.seconds / n)
    }
}

/// Photon mapping's squared bias, relative as a candidate's relative variance: over pixels and
/// channels, the squared mean difference of the passes `narrow` and `wide`, the second at
/// [`BIAS_RADIUS_FACTOR`] times the first's radius with the same random numbers, less its noise
/// (the variance of the pairs' differences over the passes), relative to `mu^2 + 0.01`, `mu`
/// each pixel's mean over the pilot's passes. The pairs see the same photons and camera paths,
/// so their difference is nearly free of the noise that swamped the difference of photon
/// mapping's image from the other candidates'.
/// It is b(2r) - b(r): the bias itself where the blur reaches across an edge (a fixed share of
/// a pixel near it, b nearly as large at r as at 2r, the share of pixels it reaches growing as
/// r), three times it where the light varies smoothly (b as r^2).
pub fn paired_bias(narrow: &[Vec<[f32; 3]>], wide: &[Vec<[f32; 3]>], mu: &[[f64; 3]]) -> f64 {
    let n = narrow.len().min(wide.len());
    if n < 2 {
        return 0.0;
    }
    let differences: Vec<Vec<[f32; 3]>> = narrow[..n]
        .iter()
        .zip(&wide[..n])
        .map(|(a, b)| a.iter().zip(b).map(|(a, b)| [b[0] - a[0], b[1] - a[1], b[2] - a[2]]).collect())
        .collect();
    let mut sum = 0.0;
    for (p, mu) in mu.iter().enumerate() {
        let (mean, variance) = mean_and_variance(&differences, p);
        for c in 0..3 {
            sum += (mean[c].powi(2) - variance[c] / n as f64) / (mu[c] * mu[c] + crate::metrics::REL_MSE_EPSILON);
        }
    }
    sum / (3 * mu.len()) as f64
}

/// The mean and sample variance of pixel `p` over `passes`.
fn mean_and_variance(passes: &[Vec<[f32; 3]>], p: usize) -> ([f64; 3], [f64; 3]) {
    let n = passes.len() as f64;
    let mean = [0, 1, 2].map(|c| passes.iter().map(|x| x[p][c] as f64).sum::<f64>() / n);
    let variance = [0, 1, 2].map(|c| passes.iter().map(|x| (x[p][c] as f64 - mean[c]).powi(2)).sum::<f64>() / (n - 1.0));
    (mean, variance)
}

/// The mean over pixels and channels of each pixel's sample variance over `passes` relative
/// to `mu^2 + 0.01` ([`crate::metrics::REL_MSE_EPSILON`]), over the passes that are not
/// [`OUTLIER_DEVIATION`] times the median pass's deviation or more; infinite where a pass is
/// not finite.
fn rel_variance(passes: &[Vec<[f32; 3]>], mu: &[[f64; 3]]) -> f64 {
    if passes.len() < 2 {
        return f64::INFINITY;
    }
    let deviations = pass_deviations(passes, mu);
    if deviations.iter().any(|d| !d.is_finite()) {
        return f64::INFINITY;
    }
    let mut sorted = deviations.clone();
    sorted.sort_by(f64::total_cmp);
    let median = (sorted[(sorted.len() - 1) / 2] + sorted[sorted.len() / 2]) / 2.0;
    let kept: Vec<Vec<[f32; 3]>> =
        passes.iter().zip(&deviations).filter(|&(_, &d)| d < OUTLIER_DEVIATION * median).map(|(pass, _)| pass.clone()).collect();
    let deviations = if kept.len() < passes.len() && kept.len() >= 2 { pass_deviations(&kept, mu) } else { deviations };
    deviations.iter().sum::<f64>() / (deviations.len() - 1) as f64
}

/// How many times the median pass's deviation from the pixels' means (its share of a
/// candidate's relative variance) a pilot pass's may be before the pilot leaves it out of that
/// relative variance. A pass's deviation is a mean over
/// every pixel, so a candidate's passes spread little (within 1.8x of their median on nine
/// scenes at three seeds); photon mapping's on Bitterli's staircase are one in seven 2x to 8x
/// their median (a photon that lights many pixels at once at the pilot's radius; one such pass
/// also lifts the others' deviations from their mean), and on cornell-spheres one in eight.
/// With them its relative variance on the staircase was 0.41 to 0.84 by seed (six seeds) and
/// the pilot rated it 0.96x to 1.99x merging alone where it renders about 0.9x its error;
/// without them 0.79x to 0.93x (three seeds). No other candidate's figure changed on those
/// scenes, nor photon mapping's on the others (BENCHMARKS.md "VCM").
pub const OUTLIER_DEVIATION: f64 = 2.0;

/// Each pass's share of [`rel_variance`]: the mean over pixels and channels of its squared
/// deviation from the pixel's mean over `passes`, relative to `mu^2 + 0.01`.
fn pass_deviations(passes: &[Vec<[f32; 3]>], mu: &[[f64; 3]]) -> Vec<f64> {
    let mut sums = vec![0.0; passes.len()];
    for (p, mu) in mu.iter().enumerate() {
        let (mean, _) = mean_and_variance(passes, p);
        for c in 0..3 {
            let scale = mu[c] * mu[c] + crate::metrics::REL_MSE_EPSILON;
            for (sum, pass) in sums.iter_mut().zip(passes) {
                *sum += (pass[p][c] as f64 - mean[c]).powi(2) / scale;
            }
        }
    }
    sums.iter().map(|s| s / (3 * mu.len()) as f64).collect()
}

/// Where vcm's pilot chooses `scene`'s shares ([`super::light::pilot_chooses_shares`]): the
/// scene with the pilot's shares, and the pilot.
pub(super) fn resolve(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    data: &SceneData,
    buffers: &Arc<SceneBuffers>,
) -> Result<Option<(Scene, Pilot)>, Error> {
    if !super::light::pilot_chooses_shares(scene) {
        return Ok(None);
    }
    let pilot = choose(device, queue, scene, data, buffers.clone())?;
    let mut scene = scene.clone();
    pilot.chosen.apply(&mut scene.render);
    Ok(Some((scene, pilot)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pass's estimate from the sums before and after it: their difference over a count of
    /// 1, the camera's weighted mean where they are weights (path tracers, SPPM's splatted
    /// passes), plus the light's (or SPPM's direct light's) difference where summed apart.
    #[test]
    fn a_pass_estimate_is_its_weighted_mean() {
        let before = SplatSums { camera: vec![[1.0, 2.0, 3.0, 2.0]], light: None };
        let counted = SplatSums { camera: vec![[1.5, 2.5, 3.5, 3.0]], light: None };
        assert_eq!(pass_estimate(&counted, &before), vec![[0.5, 0.5, 0.5]]);
        let weighted = SplatSums { camera: vec![[2.0, 3.0, 4.0, 2.5]], light: None };
        assert_eq!(pass_estimate(&weighted, &before), vec![[2.0, 2.0, 2.0]]);
        let light = |v: f32, passes: f32| Some(vec![[v, v, v, passes]]);
        let before = SplatSums { light: light(1.0, 2.0), ..before };
        let after = SplatSums { light: light(1.25, 3.0), ..weighted };
        assert_eq!(pass_estimate(&after, &before), vec![[2.25, 2.25, 2.25]]);
        // No weight in the pass: nothing from the camera.
        assert_eq!(pass_estimate(&before, &before), vec![[0.0, 0.0, 0.0]]);
    }

    /// `passes` passes of `pixels` pixels, each channel `mu` plus noise of relative spread
    /// about `spread` (a fixed sequence), and the pixels' means `mu`.
    fn noisy(passes: usize, pixels: usize, spread: f32) -> (Vec<Vec<[f32; 3]>>, Vec<[f64; 3]>) {
        let mut state = 0x2545_f491u32;
        let mut uniform = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let mu = 0.5f32;
        let passes = (0..passes)
            .map(|_| (0..pixels).map(|_| [0; 3].map(|_| mu * (1.0 + spread * (2.0 * uniform() - 1.0)))).collect())
            .collect();
        (passes, vec![[mu as f64; 3]; pixels])
    }

    #[test]
    fn the_passes_deviations_sum_to_the_pixels_sample_variances() {
        let (passes, mu) = noisy(8, 64, 0.3);
        let by_pixel = (0..mu.len())
            .map(|p| mean_and_variance(&passes, p).1.iter().map(|v| v / (0.25 + crate::metrics::REL_MSE_EPSILON)).sum::<f64>())
            .sum::<f64>()
            / (3 * mu.len()) as f64;
        let by_pass = pass_deviations(&passes, &mu).iter().sum::<f64>() / 7.0;
        assert!((by_pass / by_pixel - 1.0).abs() < 1e-9, "{by_pass} against {by_pixel}");
        // No pass is an outlier: every one counts.
        assert!((rel_variance(&passes, &mu) / by_pixel - 1.0).abs() < 1e-9);
    }

    #[test]
    fn paired_passes_read_the_bias_through_the_noise_they_share() {
        // Passes at two radii that share their noise (their random numbers) and differ by a
        // bias of 0.1 mu in a quarter of the pixels: the squared bias, 0.25 * (0.1 * 0.5)^2 /
        // (0.25 + 0.01), read within 5%, where the noise of one pass is 0.3 mu.
        let (narrow, mu) = noisy(8, 256, 0.3);
        let wide: Vec<Vec<[f32; 3]>> = narrow
            .iter()
            .map(|pass| pass.iter().enumerate().map(|(p, x)| if p % 4 == 0 { x.map(|v| v + 0.05) } else { *x }).collect())
            .collect();
        let expected = 0.25 * 0.05f64.powi(2) / (0.25 + crate::metrics::REL_MSE_EPSILON);
        let bias = paired_bias(&narrow, &wide, &mu);
        assert!((bias / expected - 1.0).abs() < 0.05, "{bias} against {expected}");
        // No bias: the pairs' own noise (independent passes here) is taken out, to within its
        // error, a small share of one pass's relative variance.
        let (other, _) = noisy(16, 256, 0.3);
        let unbiased = paired_bias(&narrow, &other[8..], &mu);
        assert!(unbiased.abs() < 0.02 * rel_variance(&narrow, &mu), "{unbiased}");
        // Fewer than two pairs say nothing.
        assert_eq!(paired_bias(&narrow[..1], &wide[..1], &mu), 0.0);
    }

    #[test]
    fn a_pass_not_finite_is_not_left_out() {
        let (mut passes, mu) = noisy(8, 64, 0.3);
        passes[3][10][1] = f32::NAN;
        assert_eq!(rel_variance(&passes, &mu), f64::INFINITY);
        passes[3][10][1] = f32::INFINITY;
        assert_eq!(rel_variance(&passes, &mu), f64::INFINITY);
    }

    #[test]
    fn a_rare_bright_pass_is_left_out_of_the_relative_variance() {
        let (mut passes, mu) = noisy(8, 256, 0.3);
        let clean = rel_variance(&passes[1..], &mu);
        // One pass where a bright photon lit a quarter of the image at 5x its mean.
        for pixel in passes[0].iter_mut().take(64) {
            *pixel = pixel.map(|x| 5.0 * x);
        }
        let all = pass_deviations(&passes, &mu).iter().sum::<f64>() / 7.0;
        let kept = rel_variance(&passes, &mu);
        assert!(all > 10.0 * clean, "the bright pass: {all} against {clean}");
        assert!((kept / clean - 1.0).abs() < 1e-9, "{kept} against {clean} without the pass");
    }
}
