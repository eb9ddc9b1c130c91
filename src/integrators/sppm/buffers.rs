//! SPPM's own buffers: one table of their sizes ([`BufferSizes`]) that the allocation
//! ([`Buffers::new`]), the memory estimate before it ([`super::Sppm::renderer_bytes`]) and
//! `--stats` (the allocated buffers' sizes, [`Integrator::gpu_memory`](crate::integrators::Integrator::gpu_memory)) all read, and how
//! much room photon hits and suspended photon threads get.

use std::sync::Arc;

use super::PHOTONS_PER_THREAD;
use crate::gpu::scene_buffers::{storage_buffer, zeroed_buffer, SceneBuffers, STORAGE_USAGE};
use crate::gpu::Resource;
use crate::layout::*;
use crate::scene::{RadiusRule, RenderSettings, Scene};

/// Words per visible point in the flux accumulator (`accum_stride()` in WGSL):
/// [`ACCUM_STRIDE`], and [`ACCUM_MOMENT_WORDS`] more under the adaptive radius rule.
pub fn accum_stride(rule: RadiusRule) -> u32 {
    match rule {
        RadiusRule::Shrink => ACCUM_STRIDE,
        RadiusRule::Adaptive => ACCUM_STRIDE + ACCUM_MOMENT_WORDS,
    }
}

/// Bytes a visible point takes in the largest of the per-point buffers: the flux accumulator
/// (32, or 48 under the adaptive radius rule), statistics, points and grid entries (32 each).
pub(super) fn largest_point_bytes(scene: &Scene) -> u64 {
    (accum_stride(scene.render.radius_rule) as u64 * 4).max(size_of::<VpStats>() as u64)
}

/// Room for photon hits a photon: about 0.9 hits a photon reach the gather on cornell-box,
/// cornell-glossy, cornell-spheres and the glass dragon where direct light is sampled (photons
/// deposit from their second diffuse hit on), 1.5 to 1.7 with direct light from photons
/// (`sppm-gpu bench` prints the count).
pub(super) const HITS_PER_PHOTON: u64 = 2;

/// The most photon hits stored between two gathers (96 MiB of [`PhotonHit`]s): a pass of
/// more than half as many photons gathers more than once, so memory stops growing with the
/// photon count there.
pub(super) const MAX_HITS: u64 = 1 << 21;

/// Photons per visible point from which a pass adds each photon hit to the visible points
/// around it at once rather than storing it for `photon_gather`. The gather reads each hit
/// once for all the points near it, but walks every hit of the buckets a point overlaps; a
/// direct deposit walks the points listed in the hit's bucket. Measured on cornell-box
/// (`sppm-gpu bench`, docs/journal/session-09.md): at 12 photons a point the gather is about
/// 10% faster, at 24 the two are even, at 49 the direct deposits are 25% faster.
pub const AT_ONCE_PHOTONS_PER_POINT: u64 = 32;

/// How a pass adds its photons to the visible points: the same fixed-point sums either way,
/// so the image is the same bit for bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Deposits {
    /// At once where photons outnumber `points` [`AT_ONCE_PHOTONS_PER_POINT`] to 1
    /// ([`deposits_at_once`]), gathered otherwise.
    Auto,
    /// Hits stored in the grid's buckets and gathered by the visible points
    /// (`photon_gather`); a hit that finds no room is added at once.
    Gathered,
    /// Every hit added at once to the visible points listed in its bucket, the grid's lists
    /// built before the photons. No room for hits is allocated.
    AtOnce,
}

/// Whether a pass of `render.photons` photons over `points` visible points adds each hit at
/// once ([`Deposits::Auto`]).
pub fn deposits_at_once(render: &crate::scene::RenderSettings, points: u64) -> bool {
    render.photons as u64 >= AT_ONCE_PHOTONS_PER_POINT * points.max(1)
}

/// Photon hits stored for the gather at a time ([`PhotonHit`], 48 bytes each):
/// `HITS_PER_PHOTON` (2) a photon, at most `MAX_HITS` (2^21), within one storage buffer of
/// `max_binding` bytes; none where hits are added at once. A hit past them is deposited at
/// once (the same sums, found more slowly).
pub fn photon_hit_capacity(render: &crate::scene::RenderSettings, at_once: bool, max_binding: u64) -> u32 {
    if at_once {
        return 0;
    }
    let want = (render.photons as u64 * HITS_PER_PHOTON).min(MAX_HITS);
    want.min(max_binding / size_of::<PhotonHit>() as u64).min(u32::MAX as u64) as u32
}

/// Bytes of `photon_hit_lists`: two counts and a list head a bucket of the grid's `table`;
/// none where hits are added at once.
pub(super) fn hit_lists_bytes(table: u64, at_once: bool) -> u64 {
    if at_once {
        0
    } else {
        (table + 2) * 4
    }
}

/// Bytes of the state a photon thread saves when its hit finds no room.
pub(super) const SUSPENDED_STATE_BYTES: u64 = 64;

/// Bytes of room for the states of photon threads: every thread of a pass, or as many as the
/// room for hits expects ([`HITS_PER_PHOTON`] for each of their photons), within one storage
/// buffer of `max_binding` bytes. The photons of a pass go in rounds of that many threads,
/// each gathered before the next.
pub(super) fn suspended_bytes(render: &crate::scene::RenderSettings, at_once: bool, max_binding: u64) -> u64 {
    let threads = render.photons.div_ceil(PHOTONS_PER_THREAD) as u64;
    let by_hits = photon_hit_capacity(render, at_once, max_binding) as u64 / (HITS_PER_PHOTON * PHOTONS_PER_THREAD as u64);
    threads.min(by_hits).min(max_binding / SUSPENDED_STATE_BYTES).max(1) * SUSPENDED_STATE_BYTES
}

/// What `photon_resume_setup` writes (`photon_resume_args`), as byte offsets: the workgroup
/// counts of grid_count and grid_fill, of photon_pass resuming and of grid_scan, then the
/// pass's hits gathered and threads resumed (a word each). The kernel declares them in words
/// (`ARGS_*` in shaders/photon_resume_setup.wgsl; a test holds the two together).
pub const ARGS_GRID: u64 = 0;

/// See [`ARGS_GRID`].
pub const ARGS_RESUME: u64 = 12;

/// See [`ARGS_GRID`].
pub const ARGS_SCAN: u64 = 24;

/// See [`ARGS_GRID`].
pub const ARGS_COUNTS: u64 = 36;

pub(super) const RESUME_ARGS_BYTES: u64 = ARGS_COUNTS + 8;

/// Bytes of camera_pass's words on a pass's visible points (`grid_max_radius`): the largest
/// radius, then with [`Frame::env_aim`] the bounds of their positions (six order keys).
pub(super) const GRID_POINT_WORDS_BYTES: u64 = 32;

/// Every buffer the kernels bind, each under the name of its WGSL global.
pub(super) struct Buffers {
    pub(super) scene: Arc<SceneBuffers>,
    pub(super) frame: wgpu::Buffer,
    pub(super) visible_points: wgpu::Buffer,
    pub(super) vp_stats: wgpu::Buffer,
    pub(super) flux_accum: wgpu::Buffer,
    pub(super) image: wgpu::Buffer,
    pub(super) grid_scene: wgpu::Buffer,
    pub(super) grid_max_radius: wgpu::Buffer,
    pub(super) grid_params: wgpu::Buffer,
    pub(super) grid: wgpu::Buffer,
    pub(super) grid_cell_count: wgpu::Buffer,
    pub(super) grid_cell_start: wgpu::Buffer,
    pub(super) grid_entries: wgpu::Buffer,
    pub(super) photon_hits: wgpu::Buffer,
    pub(super) photon_hit_lists: wgpu::Buffer,
    pub(super) photon_suspended: wgpu::Buffer,
    pub(super) photon_resume_args: wgpu::Buffer,
    pub(super) radius_tests: wgpu::Buffer,
    pub(super) camera_samples: wgpu::Buffer,
    pub(super) radiance: wgpu::Buffer,
    pub(super) direct_sums: wgpu::Buffer,
}

impl Buffers {
    /// The table each kernel's bind group takes its bindings from.
    pub(super) fn resources(&self) -> Vec<Resource<'_>> {
        let mut resources = self.scene.resources();
        resources.extend([
            Resource { name: "frame", buffer: &self.frame },
            Resource { name: "visible_points", buffer: &self.visible_points },
            Resource { name: "vp_stats", buffer: &self.vp_stats },
            Resource { name: "flux_accum", buffer: &self.flux_accum },
            Resource { name: "image", buffer: &self.image },
            Resource { name: "grid_scene", buffer: &self.grid_scene },
            Resource { name: "grid_max_radius", buffer: &self.grid_max_radius },
            Resource { name: "grid_params", buffer: &self.grid_params },
            Resource { name: "grid", buffer: &self.grid },
            Resource { name: "grid_cell_count", buffer: &self.grid_cell_count },
            Resource { name: "grid_cell_start", buffer: &self.grid_cell_start },
            Resource { name: "grid_entries", buffer: &self.grid_entries },
            Resource { name: "photon_hits", buffer: &self.photon_hits },
            Resource { name: "photon_hit_lists", buffer: &self.photon_hit_lists },
            Resource { name: "photon_suspended", buffer: &self.photon_suspended },
            Resource { name: "photon_resume_args", buffer: &self.photon_resume_args },
            Resource { name: "radius_tests", buffer: &self.radius_tests },
            Resource { name: "camera_samples", buffer: &self.camera_samples },
            Resource { name: "radiance", buffer: &self.radiance },
            Resource { name: "direct_sums", buffer: &self.direct_sums },
        ]);
        resources
    }
}

/// Bytes of every buffer of an SPPM renderer over `points` visible points and `pixels`
/// pixels, each at least 16 (wgpu binds nothing smaller). Per visible point: the point,
/// its statistics, its flux (with the offset moments of the adaptive radius rule), its
/// uniformity test (adaptive rule only: one unused test otherwise), up to 8 grid entries;
/// per grid bucket (the point count rounded up to a power of two): a count, a start and,
/// where hits are gathered, a hit list; per pixel: the image and its read-back copy; per
/// photon: room for its hits ([`photon_hit_capacity`]) and suspended threads
/// (`suspended_bytes`). Where the passes' estimates are splatted through a wide filter
/// ([`super::splat_reach_of`]), a camera sample a point, and a pixel's weighted sums and its
/// direct light summed apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BufferSizes {
    /// `frame`: [`Frame`].
    pub frame: u64,
    /// `visible_points`: a [`VisiblePoint`] a point.
    pub visible_points: u64,
    /// `vp_stats`: a [`VpStats`] a point.
    pub vp_stats: u64,
    /// `flux_accum`: [`accum_stride`] words a point.
    pub flux_accum: u64,
    /// `image`: a `vec4f` a pixel.
    pub image: u64,
    /// `grid_scene`: [`GridScene`].
    pub grid_scene: u64,
    /// `grid_max_radius`: the camera pass's words on a pass's points.
    pub grid_max_radius: u64,
    /// `grid_params`: [`GridParams`].
    pub grid_params: u64,
    /// `grid`: [`GridParams`] and the camera pass's words (a uniform).
    pub grid: u64,
    /// `grid_cell_count`: a word a bucket.
    pub grid_cell_count: u64,
    /// `grid_cell_start`: a word a bucket and one more.
    pub grid_cell_start: u64,
    /// `grid_entries`: 8 words a point.
    pub grid_entries: u64,
    /// `photon_hits`: a [`PhotonHit`] of room a stored hit.
    pub photon_hits: u64,
    /// `photon_hit_lists`: two counts and a list head a bucket where hits are gathered.
    pub photon_hit_lists: u64,
    /// `photon_suspended`: the states of suspended photon threads.
    pub photon_suspended: u64,
    /// `photon_resume_args`: the workgroup counts and counts of [`ARGS_GRID`].
    pub photon_resume_args: u64,
    /// `radius_tests`: a [`RadiusTest`] a point (adaptive rule), or one.
    pub radius_tests: u64,
    /// `image_staging`: the image's read-back copy.
    pub image_staging: u64,
    /// `camera_samples`: a pass's estimate of each point and its place in its pixel where they
    /// are splatted, or one.
    pub camera_samples: u64,
    /// `radiance`: the weighted sums of a pixel where the estimates are splatted, or one.
    pub radiance: u64,
    /// `direct_sums`: the direct light summed apart a pixel where the estimates are
    /// splatted, or one.
    pub direct_sums: u64,
}

impl BufferSizes {
    /// The sizes for `points` visible points over `pixels` pixels under `render`, photon hits
    /// added at once or not, on a device whose storage buffers hold `max_binding` bytes.
    pub fn new(render: &RenderSettings, points: u64, pixels: u64, at_once: bool, max_binding: u64) -> Self {
        let table = points.max(1).next_power_of_two();
        let adaptive = render.radius_rule == RadiusRule::Adaptive;
        let splat = super::splat_reach_of(render) > 0;
        let size = |n: u64, each: usize| (n * each as u64).max(16);
        Self {
            frame: size(1, size_of::<Frame>()),
            visible_points: size(points, size_of::<VisiblePoint>()),
            vp_stats: size(points, size_of::<VpStats>()),
            flux_accum: size(points, accum_stride(render.radius_rule) as usize * 4),
            image: size(pixels, 16),
            grid_scene: size(1, size_of::<GridScene>()),
            grid_max_radius: size(1, GRID_POINT_WORDS_BYTES as usize),
            grid_params: size(1, size_of::<GridParams>()),
            grid: size(1, size_of::<GridParams>() + GRID_POINT_WORDS_BYTES as usize),
            grid_cell_count: size(table, 4),
            grid_cell_start: size(table + 1, 4),
            grid_entries: size(points, 8 * 4),
            photon_hits: size(photon_hit_capacity(render, at_once, max_binding) as u64, size_of::<PhotonHit>()),
            photon_hit_lists: hit_lists_bytes(table, at_once).max(16),
            photon_suspended: suspended_bytes(render, at_once, max_binding).max(16),
            photon_resume_args: RESUME_ARGS_BYTES.max(16),
            radius_tests: size(if adaptive { points } else { 1 }, size_of::<RadiusTest>()),
            image_staging: size(pixels, 16),
            camera_samples: size(if splat { points } else { 1 }, 16),
            radiance: size(if splat { pixels } else { 1 }, 16),
            direct_sums: size(if splat { pixels } else { 1 }, 16),
        }
    }

    /// Every buffer's name (its WGSL global's) and size.
    pub fn named(&self) -> [(&'static str, u64); 21] {
        [
            ("frame", self.frame),
            ("visible_points", self.visible_points),
            ("vp_stats", self.vp_stats),
            ("flux_accum", self.flux_accum),
            ("image", self.image),
            ("grid_scene", self.grid_scene),
            ("grid_max_radius", self.grid_max_radius),
            ("grid_params", self.grid_params),
            ("grid", self.grid),
            ("grid_cell_count", self.grid_cell_count),
            ("grid_cell_start", self.grid_cell_start),
            ("grid_entries", self.grid_entries),
            ("photon_hits", self.photon_hits),
            ("photon_hit_lists", self.photon_hit_lists),
            ("photon_suspended", self.photon_suspended),
            ("photon_resume_args", self.photon_resume_args),
            ("radius_tests", self.radius_tests),
            ("image_staging", self.image_staging),
            ("camera_samples", self.camera_samples),
            ("radiance", self.radiance),
            ("direct_sums", self.direct_sums),
        ]
    }

    /// Bytes of them all.
    pub fn total(&self) -> u64 {
        self.named().iter().map(|(_, b)| b).sum()
    }
}

impl Buffers {
    /// Allocate the buffers of `sizes` beside `scene`'s, the statistics set to `stats` and
    /// the grid's scene to `grid_scene`.
    pub(super) fn new(
        device: &wgpu::Device,
        sizes: &BufferSizes,
        scene: Arc<SceneBuffers>,
        stats: &[VpStats],
        grid_scene: GridScene,
    ) -> Self {
        debug_assert_eq!(sizes.vp_stats, size_of_val(stats).max(16) as u64);
        let uniform = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
        let indirect = STORAGE_USAGE | wgpu::BufferUsages::INDIRECT;
        let s = sizes;
        Buffers {
            scene,
            frame: zeroed_buffer(device, "frame", s.frame, uniform),
            visible_points: zeroed_buffer(device, "visible_points", s.visible_points, STORAGE_USAGE),
            vp_stats: storage_buffer(device, "vp_stats", stats),
            flux_accum: zeroed_buffer(device, "flux_accum", s.flux_accum, STORAGE_USAGE),
            image: zeroed_buffer(device, "image", s.image, STORAGE_USAGE),
            grid_scene: storage_buffer(device, "grid_scene", &[grid_scene]),
            grid_max_radius: zeroed_buffer(device, "grid_max_radius", s.grid_max_radius, STORAGE_USAGE),
            grid_params: zeroed_buffer(device, "grid_params", s.grid_params, STORAGE_USAGE),
            grid: zeroed_buffer(device, "grid", s.grid, uniform),
            grid_cell_count: zeroed_buffer(device, "grid_cell_count", s.grid_cell_count, STORAGE_USAGE),
            grid_cell_start: zeroed_buffer(device, "grid_cell_start", s.grid_cell_start, STORAGE_USAGE),
            grid_entries: zeroed_buffer(device, "grid_entries", s.grid_entries, STORAGE_USAGE),
            photon_hits: zeroed_buffer(device, "photon_hits", s.photon_hits, STORAGE_USAGE),
            photon_hit_lists: zeroed_buffer(device, "photon_hit_lists", s.photon_hit_lists, STORAGE_USAGE),
            photon_suspended: zeroed_buffer(device, "photon_suspended", s.photon_suspended, STORAGE_USAGE),
            photon_resume_args: zeroed_buffer(device, "photon_resume_args", s.photon_resume_args, indirect),
            radius_tests: zeroed_buffer(device, "radius_tests", s.radius_tests, STORAGE_USAGE),
            camera_samples: zeroed_buffer(device, "camera_samples", s.camera_samples, STORAGE_USAGE),
            radiance: zeroed_buffer(device, "radiance", s.radiance, STORAGE_USAGE),
            direct_sums: zeroed_buffer(device, "direct_sums", s.direct_sums, STORAGE_USAGE),
        }
    }
}
