// Structs shared between the host and the kernels. Each one is declared once here and once in
// src/gpu/types.rs; tests/gpu_layout.rs checks that every offset and size agree.

// Per-pass constants (uniform).
struct Frame {
    cam_position: vec3f,
    lens_radius: f32,
    // Camera basis scaled to the image plane at distance 1: right * tan(fov/2) * aspect.
    cam_right: vec3f,
    focus_distance: f32,
    // up * tan(fov/2).
    cam_up: vec3f,
    width: u32,
    cam_forward: vec3f,
    height: u32,
    spp: u32,
    pass_index: u32,
    seed: u32,
    max_depth: u32,
    photon_count: u32,
    emitter_count: u32,
    ray_epsilon: f32,
    // Sum of the emitters' power; photon weights are stored relative to it.
    power_total: f32,
    alpha: f32,
    vp_count: u32,
    // Shutter time of this pass in [0, 1); camera and photon paths both see the scene then.
    time: f32,
    _pad3: u32,
    // This renderer covers rows [row_offset, row_offset + height) of an image image_height
    // rows high (a band of a large image).
    row_offset: u32,
    image_height: u32,
    // SPPM: 1 when the camera pass samples direct light and photons deposit only after their
    // first bounce, 0 when photons carry all light.
    direct: u32,
    // SPPM: camera paths per visible point per pass that gather emitted and direct light (the
    // first leaves the visible point); 1 when direct is 0.
    direct_samples: u32,
    // The part of the pass a dispatch covers: camera paths (visible points or pixels) or
    // photons with indices in [work_first, work_end).
    work_first: u32,
    work_end: u32,
    // SPPM with a global radius schedule: the radius of this pass, the same for every point
    // (Knaus & Zwicker 2011); 0 with a radius per point.
    global_radius: f32,
    // The first pass this renderer ran: a batch of passes first_pass.. of a render.
    first_pass: u32,
    // SPPM: photon hits the photon pass may store for photon_gather (at most the length of
    // photon_hits). A thread whose hit finds no room stops and is resumed after the gather.
    hit_capacity: u32,
    // SPPM: 0 when photon_pass traces this part's photons, 1 when it resumes the threads that
    // found no room.
    resume: u32,
    // SPPM: 1 when photon_pass adds each hit to the visible points around it at once, through
    // the grid of visible points, rather than storing it for photon_gather: for resumed
    // threads, and for every photon where photons outnumber visible points.
    at_once: u32,
    // The pixel filter (FILTER_*): the density of a camera sample's offset from its pixel's
    // centre, in x and in y (shared/camera.wgsl).
    pixel_filter: u32,
    // FILTER_TENT: the radius; FILTER_GAUSSIAN: the standard deviation (pixels).
    filter_width: f32,
    // SPPM with an environment light: the share of its photons aimed at this pass's visible
    // points (photon_pass.wgsl, emit_photon); 0 for none.
    env_aim: f32,
    strategies: u32,
    // vcm: the shares of camera vertices that connect to light vertices and that merge with
    // them (shared/bidir.wgsl's bidir_takes; 1: every one).
    connect_share: f32,
    merge_share: f32,
    // vcm's pilot (src/integrators/light.rs): 1 when the kernels add their counts of work to
    // work_counts (shared/bidir.wgsl), 0 otherwise.
    count_work: u32,
    // The path tracers under a wide pixel filter: how many pixels either way a camera sample
    // reaches (filter_splat.wgsl); 0 where its offset is drawn from the filter instead.
    filter_reach: u32,
    _pad5: u32,
    // FILTER_GAUSSIAN: the CDF of the filter's density on [0, 4] standard deviations at the
    // ends of FILTER_TABLE_SIZE equal intervals, C_1..C_256 (C_0 = 0, C_256 = 1), four a vec4f.
    filter_cdf: array<vec4f, 64>,
}

// Pixel filters (Frame.pixel_filter), as Mitsuba 3 defines them: box, radius 1/2 pixel;
// tent, max(0, 1 - |x| / radius); gaussian, max(0, exp(-x^2 / (2 stddev^2)) - exp(-8)) on
// |x| < 4 stddev.
const FILTER_BOX: u32 = 0u;
const FILTER_TENT: u32 = 1u;
const FILTER_GAUSSIAN: u32 = 2u;
// Intervals of Frame.filter_cdf.
const FILTER_TABLE_SIZE: u32 = 256u;

// An interior BVH node: its children's boxes, quantized to 16 bits per coordinate
// (lo.x | lo.y << 16, lo.z | hi.x << 16, hi.y | hi.z << 16; decoded with BvhParams), and
// references to them: a node index, or LEAF_BIT | count << LEAF_COUNT_SHIFT | first
// primitive reference.
struct BvhNode {
    box_a: vec3u,
    child_a: u32,
    box_b: vec3u,
    child_b: u32,
}

// Quantized coordinate q decodes to origin + q * scale. tree_kind: 0 for the binary tree, 1
// for the CWBVH (which needs no origin or scale), whose leaf primitives start at entry
// leaf_base of bvh_nodes.
struct BvhParams {
    origin: vec3f,
    tree_kind: u32,
    scale: vec3f,
    leaf_base: u32,
}

// A triangle as a corner and two edges (Moller & Trumbore 1997).
struct Triangle {
    p0: vec3f,
    material: u32,
    e1: vec3f,
    shape: u32,
    e2: vec3f,
    // First of the triangle's entries in `attributes`, with flags: HAS_NORMALS (three shading
    // normals, xyz), HAS_UVS (then (u0, v0, u1, v1) and (u2, v2, -, -)); 0 for none.
    attributes: u32,
}

struct Sphere {
    center: vec3f,
    radius: f32,
    material: u32,
    shape: u32,
    // HAS_UVS and the first of three entries in `attributes` (the rows of the world-to-object
    // rotation of the sphere's texture frame) when it is textured; 0 otherwise.
    attributes: u32,
    _pad: u32,
}

struct Material {
    albedo: vec3f,
    // The family's MATERIAL_* (shared/bsdf/<family>.wgsl).
    kind: u32,
    ior: f32,
    roughness: f32,
    // The texture that replaces albedo, or NO_TEXTURE: the first of its two header entries
    // in `texels` (texture_value in shared/scene.wgsl).
    texture: u32,
    // Width in the low 16 bits, height in the high 16.
    texture_size: u32,
    // 1 when black seen from behind ns and for directions behind it (Mitsuba 3's BSDFs
    // unless wrapped in `twosided`); 0 when two-sided, and always for dielectrics.
    one_sided: u32,
    // MICROFACET_GGX or MICROFACET_BECKMANN (rough conductors, dielectrics and plastics).
    distribution: u32,
    _pad: array<u32, 2>,
    // A conductor's complex index of refraction eta + i k, whose Fresnel term scales albedo
    // when fresnel is 1; fresnel 0 is Fresnel 1.
    eta: vec3f,
    fresnel: u32,
    k: vec3f,
    _pad1: u32,
    // MATERIAL_PLASTIC: the coating's specular_reflectance; MATERIAL_THIN_DIELECTRIC: the
    // slab's specular_reflectance.
    specular: vec3f,
    // MATERIAL_PLASTIC: Mitsuba's specular_sampling_weight (shared/bsdf/plastic.wgsl).
    coat_weight: f32,
    // MATERIAL_THIN_DIELECTRIC: the slab's specular_transmittance.
    transmittance: vec3f,
    // MATERIAL_PLASTIC: Fdr, the coating's diffuse reflectance seen from inside.
    coat_fdr: f32,
    // A rough MATERIAL_PLASTIC: the first entry in `attributes` of the table of its
    // coating's transmittance, COAT_TABLE_SIZE values four an entry.
    coat_table: u32,
    // MATERIAL_PLASTIC: 1 for Mitsuba's nonlinear (1 / (1 - albedo Fdr)), 0 for 1 / (1 - Fdr).
    nonlinear: u32,
    // MATERIAL_PLASTIC: the optical thickness of the layer under the coating (pbrt-v4's
    // coateddiffuse; 0 none) and the most times the base scatters the trapped light (0 no limit).
    coat_thickness: f32,
    coat_scatterings: u32,
}

// Shape.emits: the emission leaves the front side (of ng; a sphere's outside), or both.
const EMITS_FRONT: u32 = 1u;
const EMITS_BOTH: u32 = 2u;

// Per-shape data the kernels look up through a primitive's shape index.
struct Shape {
    emission: vec3f,
    // 0, EMITS_FRONT or EMITS_BOTH.
    emits: u32,
    // The shape sits at its position + velocity * time.
    velocity: vec3f,
    // The media it bounds: interior index (low 16 bits), exterior (high 16); NO_MEDIUM for a
    // vacuum, 0xffffffff when neither is given (shared/medium.wgsl).
    media: u32,
}

// One light, chosen with probability pmf (proportional to its power), as its kind packs it
// (shared/emitter/<kind>.wgsl says what each field holds for it).
struct Emitter {
    // The kind's EMITTER_*.
    kind: u32,
    prim_ref: u32,
    // Inclusive running sum of pmf over the emitters up to this one.
    cdf: f32,
    pmf: f32,
    // Point and spot: position. Directional: centre of the disk photons leave from.
    position: vec3f,
    // Area of the primitive, or of the directional light's disk; a spot's Omega, the
    // integral of its falloff over directions (power I Omega).
    area: f32,
    // Point and spot: intensity (a spot's on its axis). Directional: irradiance.
    radiance: vec3f,
    // Radius of the directional light's disk; a spot's cutoff angle (radians).
    radius: f32,
    // Directional: direction of travel. Spot: the axis of its cone. Environment: the centre of
    // the sphere its light subpaths are aimed at (bpt, vcm: emitter/environment.wgsl).
    direction: vec3f,
    // Spot: cutoff angle minus beam width (radians, >= 0). Environment: the radius of that
    // sphere (0: not aimed). 0 for the other kinds.
    width: f32,
}

// Where a camera path of the current pass ended on a non-specular surface, in 32 bytes: what
// a photon's deposit reads (position, radius, normal) lies in one cache line.
struct VisiblePoint {
    p: vec3f,
    // Gather radius; 0 when the path found no point.
    radius: f32,
    // Path throughput times the BSDF (albedo / pi).
    weight: vec3f,
    // Geometric normal, flipped to the side the camera path arrived from, and the camera
    // path's scattering events before the point, in 32 bits (encode_normal in
    // shared/sampling.wgsl): a deposit loads one word for both.
    normal: u32,
}

// Per visible-point SPPM statistics (Hachisuka & Jensen 2009, sec. 4).
struct VpStats {
    // Unnormalized flux, relative to Frame.power_total.
    tau: vec3f,
    n: f32,
    // Sum over passes of the emission the camera path saw directly.
    ld: vec3f,
    radius: f32,
}

// Per visible point, the adaptive radius rule's uniformity test (update_stats.wgsl; only with
// ADAPTIVE_RADIUS).
struct RadiusTest {
    // Since the last rejection: the photons' offsets u = (x - p) / r, summed, and the
    // photons counted.
    offset_sum: vec3f,
    tested: u32,
    // Since the last rejection: the sum of |u|^2 - 1/2.
    spread_sum: f32,
    // 1 while the last test rejected uniformity (the radius shrinks by alpha), else 0.
    shrinking: u32,
    // Tests made and uniformity rejected, over the whole render.
    tests: u32,
    rejections: u32,
}

// What grid_setup needs from the host: the box holding every visible point (the scene's
// bounds over the shutter) and the hash table's size (a power of two).
struct GridScene {
    lo: vec3f,
    table_size: u32,
    hi: vec3f,
    _pad: u32,
}

// A photon's diffuse hit that deposits, stored by photon_pass and gathered by the visible
// points around it (photon_gather): where it hit, the next hit of its bucket's list (index
// plus one; 0 ends the list), the direction it arrived along, its scattering events before
// the hit, its flux, and the geometric normal of the surface it hit, turned to the side it
// arrived from, as encode_normal stores it (depth 0): only visible points on the same side of
// their own surface gather it (same_side in shared/grid.wgsl). The kernels read it as three
// vec4u, one load each.
struct PhotonHit {
    p: vec3f,
    next: u32,
    d: vec3f,
    depth: u32,
    beta: vec3f,
    normal: u32,
}

struct GridParams {
    origin: vec3f,
    cell_size: f32,
    res: vec3u,
    table_mask: u32,
}

const LEAF_BIT: u32 = 0x80000000u;
const LEAF_COUNT_SHIFT: u32 = 27u;
const LEAF_FIRST_MASK: u32 = 0x07ffffffu;
const HAS_NORMALS: u32 = 0x80000000u;
const HAS_UVS: u32 = 0x40000000u;
const ATTRIBUTE_INDEX_MASK: u32 = 0x3fffffffu;
// An Emitter's kind, EMITTER_*, is declared by its kind in shared/emitter/.
const NO_TEXTURE: u32 = 0xffffffffu;
const TEXTURE_NEAREST: u32 = 1u;
const TEXTURE_MIRROR: u32 = 2u;
const TEXTURE_CLAMP: u32 = 4u;
const TEXTURE_PALETTE: u32 = 8u;
const PALETTE_ENTRIES: u32 = 256u;
const SPHERE_BIT: u32 = 0x80000000u;

// A Material's kind, MATERIAL_*, is declared by its family in shared/bsdf/.
const COAT_TABLE_SIZE: u32 = 64u;
const MICROFACET_GGX: u32 = 0u;
const MICROFACET_BECKMANN: u32 = 1u;

// Flux words per visible point in the flux accumulator: (lo, hi) for r, g, b, the photon count
// and a word no count reaches. With ADAPTIVE_RADIUS the photons' offset moments follow
// (offset_moments, 4 words): accum_stride() words a point.
const ACCUM_STRIDE: u32 = 8u;

// Some shape or the camera is in a participating medium (shared/medium.wgsl;
// src/gpu/features.rs).
override USES_MEDIA: bool = true;

// The adaptive radius rule (radius_rule = "adaptive", update_stats.wgsl): the sums of each
// photon's offset u = (x - p) / r from a visible point are only kept where it is compiled in.
// Off unless the host says (integrators::specialization sets it for every kernel, as
// SAMPLER_SOBOL), so that a kernel built without it reads the 8-word accumulator.
override ADAPTIVE_RADIUS: bool = false;
// Words per visible point in the flux accumulator.
fn accum_stride() -> u32 {
    return select(ACCUM_STRIDE, ACCUM_STRIDE + 4u, ADAPTIVE_RADIUS);
}

// Fixed-point steps per unit of u's coordinates and of |u|^2 in offset_moments.
const OFFSET_SCALE: u32 = 1024u;
const SPREAD_SCALE: u32 = 2048u;
// Photons gathered before the first test after a rejection.
const RADIUS_TEST_PHOTONS: u32 = 16u;
// The chi-square statistic with 3 degrees of freedom above which uniformity is rejected
// (its 99th percentile).
const RADIUS_TEST_CHI2: f32 = 11.3449;
// The fraction of a pass's photons kept while the photons look uniform (alpha otherwise).
const ALPHA_UNIFORM: f32 = 0.95;

// A photon's offset u = (x - p) / r (|u| <= 1) from a visible point, as the accumulator's four
// moment words: u + 1 per axis in steps of 1 / OFFSET_SCALE and |u|^2 in steps of
// 1 / SPREAD_SCALE (each at most 2048), so that integer sums, in any order, stay exact for
// fewer than 2^21 photons per point and pass.
fn offset_moments(u: vec3f) -> vec4u {
    let axes = floor((clamp(u, vec3f(-1.0), vec3f(1.0)) + 1.0) * f32(OFFSET_SCALE) + 0.5);
    let spread = floor(min(dot(u, u), 1.0) * f32(SPREAD_SCALE) + 0.5);
    return vec4u(vec3u(axes), u32(spread));
}

// c >= 0 in the accumulator's 32.32 fixed point as (lo, hi) words, the low word rounded down
// and kept below 2^32: one rounding for shared/flux.wgsl and flux_u32.wgsl alike, so that the
// two give the same sums.
fn fixed_point_words(c: f32) -> vec2u {
    let hi = floor(c);
    return vec2u(u32(min((c - hi) * 4294967296.0, 4294967040.0)), u32(hi));
}

const PI: f32 = 3.14159265358979;
const INV_PI: f32 = 0.318309886183791;
