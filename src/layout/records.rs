//! The records (see [`super`] for how they are held to their WGSL twins).

use bytemuck::{Pod, Zeroable};

/// Per-pass constants (uniform `frame`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Frame {
    /// Camera position, world space: the pinhole, or the centre of the thin lens.
    pub cam_position: [f32; 3],
    /// Thin-lens aperture radius in scene units; 0 for a pinhole.
    pub lens_radius: f32,
    /// `right * tan(fov / 2) * aspect`: on the image plane at distance 1, half the image
    /// width (+x in raster space).
    pub cam_right: [f32; 3],
    /// Distance from the lens to the plane in focus, scene units (only read when
    /// `lens_radius > 0`).
    pub focus_distance: f32,
    /// `up * tan(fov / 2)`: on the image plane at distance 1, half the image height (raster
    /// row 0 is at `+cam_up`).
    pub cam_up: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Unit view direction, towards the look-at point.
    pub cam_forward: [f32; 3],
    /// Image height in pixels.
    pub height: u32,
    /// Camera samples per pixel per SPPM pass: visible point `pixel * spp + s` is sample `s`
    /// of pixel `pixel` (row-major).
    pub spp: u32,
    /// Index of the pass being run, from 0; the random streams are keyed by it and `seed`.
    /// While resolving, the last completed pass (so `pass_index + 1` passes are averaged).
    pub pass_index: u32,
    /// The scene's `seed`: same seed, same image.
    pub seed: u32,
    /// Most scattering events on a camera path and on a photon path.
    pub max_depth: u32,
    /// Photons emitted per SPPM pass (0 for the path tracers).
    pub photon_count: u32,
    /// Entries in the `emitters` buffer.
    pub emitter_count: u32,
    /// Distance ray origins are pushed off a surface along its normal, scene units (see
    /// [`SceneData::ray_epsilon`](crate::gpu::scene_buffers::SceneData::ray_epsilon)).
    pub ray_epsilon: f32,
    /// Sum of the emitters' power (average over RGB). Photon flux and [`VpStats::tau`]
    /// are stored relative to it and scaled back when resolving.
    pub power_total: f32,
    /// SPPM radius reduction: the fraction of each pass's photons kept in N
    /// (Hachisuka & Jensen 2009, eq. 7), in (0, 1).
    pub alpha: f32,
    /// Visible points per pass: `width * height * spp`.
    pub vp_count: u32,
    /// Shutter time of this pass in [0, 1): camera and photon paths both see the scene then.
    pub time: f32,
    /// Padding; always 0.
    pub _pad3: u32,
    /// First image row this renderer covers: `height` rows from here of an image
    /// `image_height` rows high (a band of a large image; 0 for a whole image).
    pub row_offset: u32,
    /// Rows of the whole image, for the camera's projection.
    pub image_height: u32,
    /// SPPM: 1 when the camera pass samples direct light and photons deposit only after
    /// their first bounce ([`DirectLight::Sampled`](crate::scene::DirectLight)), 0 when
    /// photons carry all light.
    pub direct: u32,
    /// SPPM: camera paths per visible point per pass that gather emitted and direct light
    /// (the first leaves the visible point); 1 when `direct` is 0.
    pub direct_samples: u32,
    /// The part of the pass a dispatch covers ([`PartSize`](crate::integrators::PartSize)):
    /// camera paths (visible points, or pixels for the path tracers) or photons with indices
    /// in `work_first..work_end`.
    pub work_first: u32,
    /// See `work_first`.
    pub work_end: u32,
    /// SPPM with [`RadiusSchedule::Global`](crate::scene::RadiusSchedule): the radius of this
    /// pass, the same for every visible point; 0 when each point has its own.
    pub global_radius: f32,
    /// The first pass this renderer ran: a batch of a render split into batches renders
    /// passes `first_pass..` (0 for a whole render). The estimate averages
    /// `pass_index + 1 - first_pass` passes.
    pub first_pass: u32,
    /// SPPM: photon hits the photon pass may store in `photon_hits` for `photon_gather`. A
    /// thread whose hit finds no room stops, and is resumed after the gather (see `resume`).
    pub hit_capacity: u32,
    /// SPPM: 0 when `photon_pass` traces the photons `work_first..work_end`; 1 when it
    /// resumes the threads that found no room for a hit (see `at_once`).
    pub resume: u32,
    /// SPPM: 1 when `photon_pass` adds each hit's flux to the visible points around it at
    /// once, through the grid of visible points, rather than storing it for `photon_gather`
    /// (the same sums: see [`PhotonHit`]): for resumed threads, and for every photon where
    /// photons outnumber visible points (`integrators::sppm::deposits_at_once`).
    pub at_once: u32,
    /// The pixel filter ([`FILTER_BOX`], [`FILTER_TENT`] or [`FILTER_GAUSSIAN`]): the density
    /// of a camera sample's offset from its pixel's centre, in x and in y (set by
    /// `integrators::set_pixel_filter`).
    pub pixel_filter: u32,
    /// [`FILTER_TENT`]: the radius; [`FILTER_GAUSSIAN`]: the standard deviation (pixels).
    pub filter_width: f32,
    /// SPPM with an environment light: the share of its photons aimed at this pass's visible
    /// points (from a disk covering their bounding sphere; the rest from the disk covering the
    /// scene, with weights of the mixture); 0 for none (`integrators::sppm::ENV_AIM`).
    pub env_aim: f32,
    /// bpt and vcm: the strategies whose weighted contributions the pass keeps (bits of
    /// [`STRATEGY_EMISSION`] and its siblings; [`STRATEGIES_ALL`] but for
    /// `--strategy-images`).
    pub strategies: u32,
    /// vcm: the share of camera vertices that connect to light vertices (1: every one; drawn
    /// per 64-pixel block, depth and pass by `shaders/shared/bidir.wgsl`'s `bidir_takes`).
    pub connect_share: f32,
    /// vcm: the share of camera vertices that merge with light vertices.
    pub merge_share: f32,
    /// vcm's pilot: 1 when the kernels add their counts of work to `work_counts`
    /// ([`WORK_COUNTS`] words), 0 otherwise.
    pub count_work: u32,
    /// The path tracers under a wide pixel filter: how many pixels either way a camera sample
    /// reaches, its weight added to theirs (`shaders/filter_splat.wgsl`); 0 where each sample is
    /// its pixel's alone, its offset drawn from the filter (see
    /// [`PixelFilter::splat_reach`](crate::scene::PixelFilter::splat_reach)).
    pub filter_reach: u32,
    /// Padding; always 0.
    pub _pad5: u32,
    /// [`FILTER_GAUSSIAN`]: the CDF of the filter's density on [0, 4] standard deviations at
    /// the ends of [`FILTER_TABLE_SIZE`] equal intervals, `C_1..=C_256` (`C_0 = 0`,
    /// `C_256 = 1`), four an entry; zeros for the other filters.
    pub filter_cdf: [[f32; 4]; FILTER_TABLE_SIZE as usize / 4],
}

impl Default for Frame {
    /// All zeros (a box filter).
    fn default() -> Self {
        Self::zeroed()
    }
}

/// A triangle as a corner and two edges.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTriangle {
    /// First vertex, world space (at rest: time 0 for a moving shape).
    pub p0: [f32; 3],
    /// Index into the `materials` buffer.
    pub material: u32,
    /// First edge, `p1 - p0`.
    pub e1: [f32; 3],
    /// Index into the `shapes` buffer (emission, velocity).
    pub shape: u32,
    /// Second edge, `p2 - p0`. The geometric normal `cross(e1, e2)` is the emitting side.
    pub e2: [f32; 3],
    /// Where the triangle's vertex attributes start in the `attributes` buffer, with flags:
    /// [`HAS_NORMALS`] (three shading normals, xyz) and [`HAS_UVS`] (then two entries,
    /// `(u0, v0, u1, v1)` and `(u2, v2, -, -)`); 0 for none.
    pub attributes: u32,
}

/// An analytic sphere (emitting from its outside).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuSphere {
    /// Centre, world space (at rest: time 0 for a moving shape).
    pub center: [f32; 3],
    /// Radius, scene units.
    pub radius: f32,
    /// Index into the `materials` buffer.
    pub material: u32,
    /// Index into the `shapes` buffer (emission, velocity).
    pub shape: u32,
    /// [`HAS_UVS`] and the first of three entries in `attributes` when the sphere is
    /// textured: the rows of the world-to-object rotation of its texture coordinates'
    /// frame (`crate::scene::Shape::sphere_frame`); 0 otherwise.
    pub attributes: u32,
    /// Padding to 32 bytes; always 0.
    pub _pad: u32,
}

/// A material's scattering model (see [`crate::scene::MaterialKind`]), as its family packs it
/// (`src/scene/material/<family>.rs`): the fields its kind reads, the others 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Reflectance, linear RGB in [0, 1]: the Lambertian albedo (unused when textured), a
    /// conductor's reflectance, a plastic's base; `[1, 1, 1]` for a dielectric.
    pub albedo: [f32; 3],
    /// The family's `MATERIAL_*`, declared in its host file and its WGSL file
    /// (`shaders/shared/bsdf/<family>.wgsl`).
    pub kind: u32,
    /// Index of refraction of a dielectric, thin or not, or of a plastic's coating, relative
    /// to the outside; 0 for other kinds.
    pub ior: f32,
    /// Microfacet alpha of a rough conductor, dielectric or plastic coating; 0 is smooth.
    pub roughness: f32,
    /// The texture that replaces `albedo`, whatever the kind, or [`NO_TEXTURE`]: the first of
    /// its two header entries in the `texels` buffer, (m00, m01, t0, first texel) and (m10,
    /// m11, t1, flags), the last word of each as bits, where m and t are its `to_uv`: image
    /// coordinates x = m00 u + m01 v + t0 and y = m10 u + m11 v + t1, y down. Flags:
    /// [`TEXTURE_NEAREST`], a wrap mode ([`TEXTURE_MIRROR`], [`TEXTURE_CLAMP`]; neither is
    /// repeat) and [`TEXTURE_PALETTE`] for a palette-coded image.
    pub texture: u32,
    /// Texture width in the low 16 bits, height in the high 16.
    pub texture_size: u32,
    /// 1 when the BSDF is black seen from behind its shading normal and for directions
    /// behind it (Mitsuba 3's BSDFs unless wrapped in `twosided`); 0 for a two-sided
    /// material and always for a dielectric, which is two-sided by nature.
    pub one_sided: u32,
    /// [`MICROFACET_GGX`] or [`MICROFACET_BECKMANN`]: the microfacet normals of a rough
    /// conductor, dielectric or plastic coating.
    pub distribution: u32,
    /// Padding; always 0.
    pub _pad: [u32; 2],
    /// Real part of a conductor's complex index of refraction (per RGB channel), when
    /// `fresnel` is 1.
    pub eta: [f32; 3],
    /// 1 when a conductor's reflectance is scaled by the conductor Fresnel term of `eta` +
    /// i `k`; 0 for Fresnel 1 (a perfect mirror), where none is computed.
    pub fresnel: u32,
    /// Imaginary part of the complex index of refraction, when `fresnel` is 1.
    pub k: [f32; 3],
    /// Padding; always 0.
    pub _pad1: u32,
    /// A plastic: the coating's `specular_reflectance`; a dielectric, thin or not: its
    /// `specular_reflectance`.
    pub specular: [f32; 3],
    /// A plastic: Mitsuba's `specular_sampling_weight`, mean(specular) /
    /// (mean(albedo) + mean(specular)), which with the coating's transmittance sets the
    /// probability of sampling the coating's lobe rather than the base's.
    pub coat_weight: f32,
    /// A dielectric, thin or not: its `specular_transmittance`.
    pub transmittance: [f32; 3],
    /// A plastic: Fdr, the coating's diffuse reflectance seen from inside
    /// ([`crate::scene::coating`]).
    pub coat_fdr: f32,
    /// A rough plastic: the first of the [`COAT_TABLE_SIZE`] / 4 entries of the
    /// `attributes` buffer that hold its coating's transmittance T(cos) at cos = k / 63, four
    /// values an entry.
    pub coat_table: u32,
    /// A plastic: 1 for Mitsuba's `nonlinear` (the base's trapped light scaled by
    /// 1 / (1 - albedo Fdr)), 0 for 1 / (1 - Fdr).
    pub nonlinear: u32,
    /// A plastic: the optical thickness of the layer under its coating, each crossing at cos_t
    /// inside keeping exp(-thickness / cos_t) (pbrt-v4's `coateddiffuse`); 0 for none.
    pub coat_thickness: f32,
    /// A plastic: the most times the base scatters the light trapped under its coating (the
    /// series 1 / (1 - x) cut to (1 - x^n) / (1 - x), pbrt-v4's walk of `maxdepth` 2n - 1 or
    /// 2n steps); 0 for no limit.
    pub coat_scatterings: u32,
}

/// Per-shape data, looked up through a primitive's `shape` index.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuShape {
    /// Radiance Le leaving the front side, linear RGB; zero when the shape does not emit.
    pub emission: [f32; 3],
    /// [`EMITS_FRONT`] or [`EMITS_BOTH`] when some channel of `emission` is positive, else 0.
    pub emits: u32,
    /// Displacement over the shutter: the shape sits at its position + velocity * time.
    pub velocity: [f32; 3],
    /// The participating media it bounds: the interior's index into the media
    /// ([`SceneData::media_first`](crate::gpu::scene_buffers::SceneData::media_first)) in the
    /// low 16 bits, the exterior's in the high 16, [`NO_MEDIUM`] for a vacuum; [`NOT_A_BOUNDARY`]
    /// when neither is given (paths keep their medium across it).
    pub media: u32,
}

/// [`GpuShape::media`]'s index of no medium (a vacuum).
pub const NO_MEDIUM: u32 = 0xffff;
/// [`GpuShape::media`] of a shape that bounds no medium.
pub const NOT_A_BOUNDARY: u32 = 0xffff_ffff;

/// One light: what its kind (`src/scene/emitter/<kind>.rs`) packs for its kernel
/// (`shaders/shared/emitter/<kind>.wgsl`), chosen with probability `pmf` in proportion to its
/// power.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Emitter {
    /// The kind's `EMITTER_*`, declared in its host file and its WGSL file.
    pub kind: u32,
    /// An area emitter's primitive (a sphere's index with [`SPHERE_BIT`]); an envmap's first
    /// entry in `texels`, [`NO_TEXTURE`] for a constant environment.
    pub prim_ref: u32,
    /// Inclusive running sum of `pmf`; the last is infinite so that every u < 1 falls in.
    pub cdf: f32,
    /// Probability of choosing this emitter, proportional to its power.
    pub pmf: f32,
    /// Point and spot light: its position. Directional: the centre of the disk photons leave
    /// from. Environment: the centre of the scene's bounding sphere.
    pub position: [f32; 3],
    /// Area of the primitive, or of the directional light's or environment's disk (pi R^2);
    /// a spot light's Omega, the integral of its falloff over directions (steradians; power
    /// I * Omega).
    pub area: f32,
    /// Point and spot light: intensity (W/sr; a spot's on its axis). Directional: irradiance.
    /// Environment: radiance, or an envmap's scale.
    pub radiance: [f32; 3],
    /// Radius R of the directional light's or environment's disk, the scene's bounding
    /// sphere's; a spot light's cutoff angle (radians).
    pub radius: f32,
    /// Direction of travel of a directional light; the axis of a spot light's cone; the centre
    /// of the sphere an environment's light subpaths are aimed at (bpt, vcm).
    pub direction: [f32; 3],
    /// A spot light's falloff width, cutoff angle minus beam width (radians, >= 0; 0: a hard
    /// edge); the radius of the sphere an environment's light subpaths are aimed at (0: not
    /// aimed); 0 for the other kinds.
    pub width: f32,
}

/// What `grid_setup` needs from the host: the box holding every visible point and the hash
/// table's size (a power of two).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GridScene {
    /// Minimum corner of the box: the scene's bounds swept over the shutter.
    pub lo: [f32; 3],
    /// Buckets in the hash table: `vp_count` rounded up to a power of two.
    pub table_size: u32,
    /// Maximum corner of the box.
    pub hi: [f32; 3],
    /// Padding to 32 bytes; always 0.
    pub _pad: u32,
}

/// A photon's diffuse hit that deposits (48 bytes), stored by `photon_pass` in a list per
/// bucket of the grid (the bucket of the cell the hit lies in) and gathered after the pass by
/// each visible point from the buckets of the cells its disc overlaps (`photon_gather`). The
/// gather adds the same 32.32 fixed-point terms a direct deposit adds, so where a hit is
/// deposited does not change a bit of the sums.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct PhotonHit {
    /// Where the photon hit.
    pub p: [f32; 3],
    /// The next hit in the same bucket's list, as its index plus one; 0 ends the list.
    pub next: u32,
    /// The photon's direction of travel.
    pub d: [f32; 3],
    /// Scattering events before the hit (0 straight from a light); the hit lights a visible
    /// point only where the joined path stays within `max_depth`.
    pub depth: u32,
    /// The photon's flux, relative to [`Frame::power_total`].
    pub beta: [f32; 3],
    /// The geometric normal of the surface hit, turned to the side the photon arrived from,
    /// octahedral in bits 0-23 as [`VisiblePoint::normal`] stores it (bits 24-31 are 0): a
    /// visible point gathers the hit only where it faces alike (within the angle of cosine
    /// 0.1, as Mitsuba 0.6's photon map requires), or across a crease where the two surfaces
    /// face each other or turn away from each other (`same_side` in
    /// `shaders/shared/grid.wgsl`), so that light inside a thin shell stays off its outside.
    pub normal: u32,
}

/// A light subpath's vertex where a BSDF can be evaluated, kept for the bidirectional methods'
/// connections and merging (`LightVertex` in `shaders/shared/light_vertex.wgsl`), 112 bytes.
/// Written and read only by the kernels; the host sizes their buffers by it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LightVertex {
    /// Position.
    pub p: [f32; 3],
    /// The surface's material index.
    pub material: u32,
    /// Geometric normal.
    pub ng: [f32; 3],
    /// The surface's shape index.
    pub shape: u32,
    /// Shading normal.
    pub ns: [f32; 3],
    /// Segments from the light to the vertex.
    pub length: u32,
    /// Unit direction towards the subpath's previous vertex.
    pub w_prev: [f32; 3],
    /// SmallVCM's dVCM (`shaders/shared/vcm.wgsl`).
    pub d_vcm: f32,
    /// The throughput: the flux estimate of one subpath.
    pub beta: [f32; 3],
    /// SmallVCM's dVC.
    pub d_vc: f32,
    /// Texture coordinates of the surface point.
    pub uv: [f32; 2],
    /// SmallVCM's dVM.
    pub d_vm: f32,
    /// The slot of the subpath's next stored vertex, or `u32::MAX` (the store is a cache
    /// filled in the order the vertices come: `shaders/shared/light_vertex.wgsl`).
    pub next: u32,
    /// The subpath's two latest merges, apart from `d_vc` and `d_vm` (`SubpathMis` in
    /// `shaders/shared/vcm.wgsl`).
    pub d_merge: [f32; 2],
    /// Padding to the WGSL struct's 16-byte alignment.
    pub _pad: [u32; 2],
}

/// Where a camera path of the current pass ended on a diffuse surface (Hachisuka & Jensen
/// 2009, sec. 4), in 32 bytes, so that what a photon's deposit reads (position, radius,
/// normal) lies in one cache line.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct VisiblePoint {
    /// Position.
    pub p: [f32; 3],
    /// Gather radius: the point's own, or the pass's with a global radius schedule; 0 where
    /// the camera path found no point.
    pub radius: f32,
    /// Path throughput times the BSDF, beta * albedo / pi: what the flux of the photons that
    /// land within the radius is multiplied by. Zero where there is no visible point.
    pub weight: [f32; 3],
    /// Geometric normal, flipped to the side the camera path arrived from, octahedral in two
    /// 12-bit coordinates (bits 0-11 and 12-23, `encode_normal` in
    /// `shaders/shared/sampling.wgsl`): photons arriving from the other side are not counted.
    /// Bits 24-31: the scattering events on the camera path before the point (saturated at
    /// 255), which with the photon's bound the joined path by `max_depth`.
    pub normal: u32,
}

/// Per visible-point SPPM statistics, carried from pass to pass (Hachisuka & Jensen 2009,
/// sec. 4; pbrt-v4 sec. 16.3). After `update_stats` with M new photons carrying flux phi:
/// N' = N + alpha M, r' = r sqrt(N' / (N + M)), tau' = (tau + phi) r'^2 / r^2. The pixel's
/// estimate after k passes of P photons is L = ld / k + tau power_total / (k P pi r^2).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct VpStats {
    /// Accumulated flux tau (weighted by [`VisiblePoint::weight`]), relative to
    /// [`Frame::power_total`] and not yet divided by the photon count or area.
    pub tau: [f32; 3],
    /// Accumulated photon count N (fractional: alpha of each pass's photons).
    pub n: f32,
    /// Sum over passes of the emission the camera path saw directly (the direct term).
    pub ld: [f32; 3],
    /// Current gather radius r, scene units.
    pub radius: f32,
}

/// Per visible point, the uniformity test of the adaptive radius rule
/// ([`RadiusRule::Adaptive`](crate::scene::RadiusRule), `update_stats.wgsl`), carried from pass
/// to pass: the photons' offsets u = (x - p) / r from the point since the last rejection, their
/// sum and the sum of |u|^2 - 1/2, which for M photons uniform on the disc
/// make X^2 = |sum u|^2 / (M / 4) + (sum (|u|^2 - 1/2))^2 / (M / 12) chi-square with 3 degrees
/// of freedom.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct RadiusTest {
    /// The sum of the offsets u (along the normal, 0 for photons on a flat surface).
    pub offset_sum: [f32; 3],
    /// The photons counted in `offset_sum` and `spread_sum`.
    pub tested: u32,
    /// The sum of |u|^2 - 1/2 over the same photons.
    pub spread_sum: f32,
    /// 1 while the last test rejected uniformity (the radius shrinks by alpha), else 0.
    pub shrinking: u32,
    /// Tests made over the render.
    pub tests: u32,
    /// Tests that rejected uniformity.
    pub rejections: u32,
}

/// Flag in [`GpuTriangle::attributes`]: three shading normals (unit, xyz) come first.
pub const HAS_NORMALS: u32 = 1 << 31;
/// Flag in [`GpuTriangle::attributes`]: two entries of texture coordinates follow (after
/// the normals, if any).
pub const HAS_UVS: u32 = 1 << 30;
/// The bits of [`GpuTriangle::attributes`] that hold the index of its first entry.
pub const ATTRIBUTE_INDEX_MASK: u32 = HAS_UVS - 1;
/// [`GpuShape::emits`] of a shape whose emission leaves its front side.
pub const EMITS_FRONT: u32 = 1;
/// [`GpuShape::emits`] of a shape whose emission leaves both sides.
pub const EMITS_BOTH: u32 = 2;
/// The bit of a primitive reference (a BVH leaf's, an area [`Emitter`]'s) that marks a sphere:
/// `i | SPHERE_BIT` is sphere `i`, a reference without it a triangle.
pub const SPHERE_BIT: u32 = 0x8000_0000;
/// [`GpuMaterial::texture`] of a material without a texture.
pub const NO_TEXTURE: u32 = u32::MAX;
/// Texture header flag: nearest-texel lookups (else bilinear).
pub const TEXTURE_NEAREST: u32 = 1;
/// Texture header flag: mirrored repeat.
pub const TEXTURE_MIRROR: u32 = 2;
/// Texture header flag: edge texels extended.
pub const TEXTURE_CLAMP: u32 = 4;
/// Texture header flag: the image is palette-coded, losslessly: its first
/// [`PALETTE_ENTRIES`]` / 4` texels hold the distinct channel values (at most
/// [`PALETTE_ENTRIES`] of them, four to a texel), then each word of the following texels one
/// texel's red, green and blue as 8-bit indices into them (bits 0-7, 8-15, 16-23), four
/// words to a texel. An 8-bit image takes 4 bytes a texel rather than 16, whatever its
/// transfer function; one with more distinct values is stored as floats. Used only where a
/// scene's images would pass `PALETTE_ABOVE_BYTES` as floats (gpu::scene_buffers): the
/// lookups cost time.
pub const TEXTURE_PALETTE: u32 = 8;
/// The channel values a palette-coded texture can hold ([`TEXTURE_PALETTE`]).
pub const PALETTE_ENTRIES: u32 = 256;
/// Values in a rough plastic's table of its coating's transmittance ([`GpuMaterial::coat_table`]).
pub const COAT_TABLE_SIZE: u32 = 64;
/// [`GpuMaterial::distribution`]: GGX (Trowbridge-Reitz).
pub const MICROFACET_GGX: u32 = 0;
/// [`GpuMaterial::distribution`]: Beckmann.
pub const MICROFACET_BECKMANN: u32 = 1;
/// u32 words of flux and photon count per visible point in the flux accumulator; the adaptive
/// radius rule adds [`ACCUM_MOMENT_WORDS`] (see [`accum_stride`](crate::integrators::sppm::accum_stride)).
pub const ACCUM_STRIDE: u32 = 8;
/// The accumulator's words of photon offset moments per visible point under the adaptive
/// radius rule (`offset_moments` in WGSL): sum (u + 1) OFFSET_SCALE per axis, then
/// sum |u|^2 SPREAD_SCALE.
pub const ACCUM_MOMENT_WORDS: u32 = 4;
/// Fixed-point steps per unit of a photon offset's coordinate (`offset_moments`).
pub const OFFSET_SCALE: u32 = 1024;
/// Fixed-point steps per unit of a photon offset's squared length (`offset_moments`).
pub const SPREAD_SCALE: u32 = 2048;
/// Photons gathered before the adaptive rule's first test after a rejection.
pub const RADIUS_TEST_PHOTONS: u32 = 16;
/// The 99th percentile of the chi-square distribution with 3 degrees of freedom: the
/// adaptive rule rejects uniformity above it.
pub const RADIUS_TEST_CHI2: f32 = 11.3449;
/// The fraction of a pass's photons kept (alpha) while a point's photons look uniform.
pub const ALPHA_UNIFORM: f32 = 0.95;
/// Invocations per workgroup of every kernel.
pub const WORKGROUP_SIZE: u32 = 64;
/// [`Frame::pixel_filter`]: uniform over the pixel's square (Mitsuba's `box`, radius 1/2).
pub const FILTER_BOX: u32 = 0;
/// [`Frame::pixel_filter`]: `max(0, 1 - |x| / radius)` (Mitsuba's `tent`).
pub const FILTER_TENT: u32 = 1;
/// [`Frame::pixel_filter`]: `max(0, exp(-x^2 / (2 stddev^2)) - exp(-8))` on `|x| < 4 stddev`
/// (Mitsuba 3's `gaussian`).
pub const FILTER_GAUSSIAN: u32 = 2;
/// Intervals of [`Frame::filter_cdf`].
pub const FILTER_TABLE_SIZE: u32 = 256;
/// The bidirectional methods' strategies (`shaders/shared/bidir.wgsl`), as bits of the set
/// whose weighted contributions a render keeps (`RenderSettings::strategies`): emission hit by
/// the camera subpath.
pub const STRATEGY_EMISSION: u32 = 1;
/// Next-event estimation at a camera vertex.
pub const STRATEGY_NEE: u32 = 2;
/// A camera vertex connected to the vertices of a light subpath.
pub const STRATEGY_CONNECT: u32 = 4;
/// A camera vertex merged with the light vertices within the radius (vcm).
pub const STRATEGY_MERGE: u32 = 8;
/// A light vertex joined to the camera (light tracing).
pub const STRATEGY_LIGHT_TRACE: u32 = 16;
/// Every strategy: a render's default.
pub const STRATEGIES_ALL: u32 = 31;
/// Words of vcm's `work_counts` (`shaders/shared/bidir.wgsl`): what a pass of its pilot did,
/// counted where [`Frame::count_work`] is 1, each word one of the `WORK_*` below.
pub const WORK_COUNTS: u32 = 4;
/// `work_counts` word: camera vertices (scattering events of camera subpaths).
pub const WORK_CAMERA_VERTICES: u32 = 0;
/// `work_counts` word: light vertices a camera vertex was joined to (a connection each).
pub const WORK_CONNECTIONS: u32 = 1;
/// `work_counts` word: light vertices a merging camera vertex looked at in the grid.
pub const WORK_MERGE_CANDIDATES: u32 = 2;
/// `work_counts` word: light vertices (scattering events of light subpaths).
pub const WORK_LIGHT_VERTICES: u32 = 3;

/// One interior node as the kernels read it (32 bytes): the boxes of its two children,
/// quantized to 16 bits per coordinate on a grid over the root's box ([`BvhParams`]), and a
/// reference to each child. A traversal step loads one node and tests both children without
/// loading them: 8 words instead of the 24 of three [`BvhNode`](crate::accel::BvhNode)s, which matters where loads
/// at per-ray addresses are expensive (lavapipe gathers them one lane at a time).
///
/// A child box is `(lo.x | lo.y << 16, lo.z | hi.x << 16, hi.y | hi.z << 16)`; decoded as
/// `origin + q * scale`, it contains the child's exact box (lower corners rounded down,
/// upper corners up, with a margin for the rounding of the decode). An empty child has the
/// inverted box `lo = 65535, hi = 0`, which no ray enters.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuBvhNode {
    /// Quantized box of the first child.
    pub box_a: [u32; 3],
    /// Reference to the first child (see [`LEAF_BIT`](crate::accel::bvh::LEAF_BIT)).
    pub child_a: u32,
    /// Quantized box of the second child.
    pub box_b: [u32; 3],
    /// Reference to the second child.
    pub child_b: u32,
}

/// How quantized child boxes decode: `origin + q * scale` (a uniform buffer for the kernels,
/// 32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhParams {
    /// World position of q = 0.
    pub origin: [f32; 3],
    /// Which tree the kernels' `bvh_nodes` and `prim_refs` hold: 0 this binary one, 1 a
    /// [`CwBvh`](crate::accel::cwbvh::CwBvh) (whose nodes carry their own grids: origin and scale unused).
    pub tree_kind: u32,
    /// World size of one quantization step, per axis.
    pub scale: [f32; 3],
    /// With a CWBVH, the entry of `bvh_nodes` (16 bytes each) where its leaf primitives
    /// start; 0 otherwise.
    pub leaf_base: u32,
}

/// GPU-side grid parameters (32 bytes, std430/uniform compatible).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GridParams {
    /// Minimum corner of the grid.
    pub origin: [f32; 3],
    /// Side of the cubic cells: [`CELL_RADII`](crate::accel::grid::CELL_RADII) times the largest radius.
    pub cell_size: f32,
    /// Cells per axis; `[0, 0, 0]` when there are no points, so that every lookup misses.
    pub res: [u32; 3],
    /// `table_size - 1`; `table_size` is a power of two.
    pub table_mask: u32,
}
