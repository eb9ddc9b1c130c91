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
    _pad: vec2u,
}

// Leaf when count > 0: primitives prim_refs[first .. first + count].
// Interior when count == 0: children at first and first + 1.
struct BvhNode {
    min: vec3f,
    first: u32,
    max: vec3f,
    count: u32,
}

// A triangle as a corner and two edges (Moller & Trumbore 1997).
struct Triangle {
    p0: vec3f,
    material: u32,
    e1: vec3f,
    shape: u32,
    e2: vec3f,
    // First of three shading normals in `normals`, or NO_NORMALS for flat triangles.
    normals: u32,
}

struct Sphere {
    center: vec3f,
    radius: f32,
    material: u32,
    shape: u32,
    _pad: vec2u,
}

struct Material {
    albedo: vec3f,
    kind: u32,
    ior: f32,
    roughness: f32,
    texture: u32,
    _pad: u32,
}

// Per-shape data the kernels look up through a primitive's shape index.
struct Shape {
    emission: vec3f,
    emits: u32,
}

// One emitting primitive, chosen with probability pmf (proportional to its power).
struct Emitter {
    prim_ref: u32,
    // Inclusive running sum of pmf over the emitters up to this one.
    cdf: f32,
    pmf: f32,
    area: f32,
}

// Where a camera path of the current pass ended on a non-specular surface.
// Its position and radius live in `vp_points` (xyz, radius; radius 0 when there is none).
struct VisiblePoint {
    // Geometric normal, flipped to the side the camera path arrived from.
    normal: vec3f,
    _pad0: u32,
    // Path throughput times the BSDF (albedo / pi).
    weight: vec3f,
    _pad1: u32,
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

struct GridParams {
    origin: vec3f,
    cell_size: f32,
    res: vec3u,
    table_mask: u32,
}

const NO_NORMALS: u32 = 0xffffffffu;
const NO_TEXTURE: u32 = 0xffffffffu;
const SPHERE_BIT: u32 = 0x80000000u;

const MATERIAL_DIFFUSE: u32 = 0u;
const MATERIAL_MIRROR: u32 = 1u;
const MATERIAL_DIELECTRIC: u32 = 2u;

// Words per visible point in the flux accumulator: (lo, hi) for r, g, b, then the photon count.
const ACCUM_STRIDE: u32 = 8u;

const PI: f32 = 3.14159265358979;
const INV_PI: f32 = 0.318309886183791;
