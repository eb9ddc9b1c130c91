//! The scene in GPU layout: host arrays built from a loaded scene and its BVH (no device
//! needed, so they can be tested alone), then uploaded as storage buffers.

use crate::accel::bvh::PackedBvh;
use crate::accel::{Bvh, SPHERE_BIT};
use crate::layout::*;
use crate::scene::{Scene, SceneError, TextureFilter, TextureWrap, TOML_SPHERE_FRAME};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// Everything the tracing kernels read about the scene, in GPU layout.
pub struct SceneData {
    /// The BVH over triangles and spheres, boxes swept over the shutter for moving shapes.
    pub bvh: Bvh,
    /// The same tree in the kernels' layout (quantized child boxes in each interior node).
    pub packed_bvh: PackedBvh,
    /// The compressed 8-wide BVH the kernels traverse instead, for scenes where
    /// [`uses_cwbvh`] says it is faster.
    pub cwbvh: Option<crate::accel::CwBvh>,
    /// Every triangle, in the scene's order (the BVH's triangle references index this).
    pub triangles: Vec<GpuTriangle>,
    /// Every analytic sphere, in the scene's order (references `i | SPHERE_BIT`).
    pub spheres: Vec<GpuSphere>,
    /// One per scene material, in the scene's order.
    pub materials: Vec<GpuMaterial>,
    /// One per `[[shapes]]` entry: emission and velocity.
    pub shapes: Vec<GpuShape>,
    /// Shading normals and texture coordinates of the triangles that have them (see
    /// [`GpuTriangle::attributes`]), and the frames of textured spheres
    /// ([`GpuSphere::attributes`]).
    pub attributes: Vec<[f32; 4]>,
    /// The first entry in `attributes` of the participating media, two each (see
    /// `shaders/shared/medium.wgsl`).
    pub media_first: u32,
    /// The medium the camera sits in, as an index into the media, [`NO_MEDIUM`] for a vacuum.
    pub camera_medium: u32,
    /// Whether the scene has a participating medium that a path can be in.
    pub media: bool,
    /// Every texture: its two-entry header (see [`GpuMaterial::texture`]), and its linear RGB
    /// texels, row 0 at the top, once for each distinct image.
    pub texels: Vec<[f32; 4]>,
    /// Emitting triangles, then emitting spheres, then `[[lights]]`, with their discrete
    /// distribution by power (`pmf`, `cdf`).
    pub emitters: Vec<Emitter>,
    /// Sum of the emitters' power (average over RGB).
    pub power_total: f32,
    /// Whether some shape moves.
    pub motion: bool,
    /// Minimum corner of the box holding every surface at rest (time 0); zero for an empty
    /// scene.
    pub bounds_min: Vec3,
    /// Maximum corner of the box holding every surface at rest.
    pub bounds_max: Vec3,
    /// Bounds over the whole shutter (moving shapes at times 0 and 1).
    pub swept_min: Vec3,
    /// Maximum corner of the bounds over the whole shutter.
    pub swept_max: Vec3,
}

fn setting_error(scene: &Scene, line: usize, key: &str, message: String) -> SceneError {
    SceneError { file: scene.path.clone(), line: Some(line), key: Some(key.to_string()), message }
}

fn material_of(scene: &Scene, shape: u32) -> u32 {
    scene.shapes[shape as usize].material
}

pub use crate::scene::emitter::{MAX_EMISSION, MAX_LIGHT_POWER};

impl SceneData {
    /// Build the BVH and the GPU arrays of `scene`, and the light distribution by power.
    ///
    /// Errors when the scene has no light with positive power, a light brighter than
    /// [`MAX_EMISSION`] or lights more powerful than [`MAX_LIGHT_POWER`], or holds more texels
    /// or vertex attributes than [`ATTRIBUTE_INDEX_MASK`] addresses, or a texture larger than
    /// 65535 on a side.
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        crate::scene::emitter::check_brightness(scene)?;
        let velocity = |shape: u32| scene.shapes[shape as usize].velocity.unwrap_or(Vec3::ZERO);
        let motion = scene.shapes.iter().any(|s| s.velocity.is_some_and(|v| v != Vec3::ZERO));
        let bvh = crate::accel::build_bvh_moving(&scene.triangles, &scene.spheres, velocity);
        let cwbvh = uses_cwbvh(bvh.prim_refs.len())
            .then(|| crate::accel::build_cwbvh(&scene.triangles, &scene.spheres, velocity))
            .flatten();

        // Textures: a header each, then the texels of each distinct image; a material refers
        // to its texture's header.
        let mut texels: Vec<[f32; 4]> = Vec::new();
        let mut texture_at = Vec::new();
        // Each distinct image once: (its first texture, its first texel, TEXTURE_PALETTE or 0).
        let mut image_at: Vec<(usize, u32, u32)> = Vec::new();
        // Palette-coded only where the images' floats would pass the binding every device
        // offers: a palette costs a lookup a channel (textured.toml's pt-nee 5% slower).
        let mut distinct = std::collections::HashSet::new();
        let float_bytes: u64 = scene
            .textures
            .iter()
            .filter(|t| distinct.insert((&t.path, t.width, t.height)))
            .map(|t| 16 * t.texels.len() as u64)
            .sum();
        let palettes = scene.render.texture_palettes || float_bytes > PALETTE_ABOVE_BYTES;
        for (i, t) in scene.textures.iter().enumerate() {
            if t.width > 0xffff || t.height > 0xffff {
                return Err(SceneError {
                    file: t.path.clone(),
                    line: None,
                    key: None,
                    message: format!("a texture of {}x{} is larger than the 65535x65535 supported", t.width, t.height),
                });
            }
            let header = texels.len() as u32;
            texture_at.push((header, t.width | (t.height << 16)));
            let same_image = |&&(j, _, _): &&(usize, u32, u32)| {
                let u = &scene.textures[j];
                (&u.path, u.width, &u.texels) == (&t.path, t.width, &t.texels)
            };
            let (first, coding, image) = match image_at.iter().find(same_image) {
                Some(&(_, first, coding)) => (first, coding, None),
                None => {
                    let first = header + 2;
                    let image = if palettes { palette_coded(&t.texels) } else { None };
                    let coding = if image.is_some() { TEXTURE_PALETTE } else { 0 };
                    image_at.push((i, first, coding));
                    (first, coding, Some(image))
                }
            };
            let flags = match t.filter {
                TextureFilter::Bilinear => 0,
                TextureFilter::Nearest => TEXTURE_NEAREST,
            } | match t.wrap {
                TextureWrap::Repeat => 0,
                TextureWrap::Mirror => TEXTURE_MIRROR,
                TextureWrap::Clamp => TEXTURE_CLAMP,
            } | coding;
            let (m, o) = (t.to_uv.matrix2, t.to_uv.translation);
            texels.push([m.x_axis.x, m.y_axis.x, o.x, f32::from_bits(first)]);
            texels.push([m.x_axis.y, m.y_axis.y, o.y, f32::from_bits(flags)]);
            match image {
                Some(Some(coded)) => texels.extend(coded),
                Some(None) => texels.extend(t.texels.iter().map(|c| [c.x, c.y, c.z, 0.0])),
                None => {}
            }
        }
        if texels.len() > ATTRIBUTE_INDEX_MASK as usize {
            return Err(setting_error(scene, 1, "materials", "the textures hold more texels than the renderer addresses".into()));
        }
        let textured = |shape: u32| scene.shape_material(shape).kind.texture().is_some();

        // Per-vertex attributes only where they are used: shading normals of smooth shapes,
        // texture coordinates of textured ones.
        let mut attributes: Vec<[f32; 4]> = Vec::new();
        let mut triangles = Vec::with_capacity(scene.triangles.len());
        for t in &scene.triangles {
            let first = attributes.len() as u32;
            let mut flags = 0;
            if let Some(n) = t.n {
                flags |= HAS_NORMALS;
                attributes.extend(n.iter().map(|v| [v.x, v.y, v.z, 0.0]));
            }
            if textured(t.shape) {
                flags |= HAS_UVS;
                let uv = t.uv.unwrap_or([glam::Vec2::ZERO; 3]);
                attributes.push([uv[0].x, uv[0].y, uv[1].x, uv[1].y]);
                attributes.push([uv[2].x, uv[2].y, 0.0, 0.0]);
            }
            if attributes.len() > ATTRIBUTE_INDEX_MASK as usize {
                return Err(setting_error(
                    scene,
                    1,
                    "shapes",
                    "the meshes hold more vertex attributes than the renderer addresses".into(),
                ));
            }
            triangles.push(GpuTriangle {
                p0: t.p[0].into(),
                material: material_of(scene, t.shape),
                e1: (t.p[1] - t.p[0]).into(),
                shape: t.shape,
                e2: (t.p[2] - t.p[0]).into(),
                attributes: if flags == 0 { 0 } else { first | flags },
            });
        }
        let spheres: Vec<GpuSphere> = scene
            .spheres
            .iter()
            .map(|s| {
                let mut attributes_at = 0;
                if textured(s.shape) {
                    // Rows of the frame's transpose: dot products with its axes.
                    attributes_at = attributes.len() as u32 | HAS_UVS;
                    let frame = scene.shapes[s.shape as usize].sphere_frame.unwrap_or(TOML_SPHERE_FRAME);
                    attributes.extend([frame.x_axis, frame.y_axis, frame.z_axis].map(|a| [a.x, a.y, a.z, 0.0]));
                }
                GpuSphere {
                    center: s.center.into(),
                    radius: s.radius,
                    material: material_of(scene, s.shape),
                    shape: s.shape,
                    attributes: attributes_at,
                    _pad: 0,
                }
            })
            .collect();
        if attributes.len() > ATTRIBUTE_INDEX_MASK as usize {
            return Err(setting_error(
                scene,
                1,
                "shapes",
                "the spheres' texture frames exceed what the renderer addresses".into(),
            ));
        }
        // The participating media after everything else in `attributes`: (sigma_a, g) and
        // (sigma_s, 0) each (shared/medium.wgsl).
        let media_first = attributes.len() as u32;
        for m in &scene.media {
            let g = match m.phase {
                crate::scene::Phase::Isotropic => 0.0,
                crate::scene::Phase::HenyeyGreenstein { g } => g,
            };
            attributes.push([m.sigma_a.x, m.sigma_a.y, m.sigma_a.z, g]);
            attributes.push([m.sigma_s.x, m.sigma_s.y, m.sigma_s.z, 0.0]);
        }
        let materials = scene
            .materials
            .iter()
            .map(|m| {
                let mut g = m.kind.gpu(&scene.textures, &mut attributes);
                if let Some(t) = m.kind.texture() {
                    (g.texture, g.texture_size) = texture_at[t as usize];
                }
                g.one_sided = (m.one_sided && !m.kind.two_sided_by_nature()) as u32;
                g
            })
            .collect();
        let shapes = scene
            .shapes
            .iter()
            .map(|s| GpuShape {
                emission: s.emission.unwrap_or(Vec3::ZERO).into(),
                emits: match (s.emission.is_some_and(|e| e.max_element() > 0.0), s.emission_two_sided) {
                    (false, _) => 0,
                    (true, false) => EMITS_FRONT,
                    (true, true) => EMITS_BOTH,
                },
                velocity: s.velocity.unwrap_or(Vec3::ZERO).into(),
                media: match (s.interior, s.exterior) {
                    (None, None) => NOT_A_BOUNDARY,
                    (interior, exterior) => interior.unwrap_or(NO_MEDIUM) | (exterior.unwrap_or(NO_MEDIUM) << 16),
                },
            })
            .collect::<Vec<_>>();
        let (bounds_min, bounds_max) = scene.bounds();

        // The lights, chosen in proportion to power. A directional light and the environment
        // cover the scene's bounding sphere (moving shapes included) with a disk of photons.
        let (swept_min, swept_max) = swept_bounds(scene, bounds_min, bounds_max);
        let center = 0.5 * (swept_min + swept_max);
        let radius = (0.5 * (swept_max - swept_min).length()).max(1e-3);
        let mut lights = crate::scene::emitter::pack(scene, center, radius, &mut texels)?;
        // The environment's light subpaths (bpt, vcm) aimed at what the camera sees.
        if let Some(env) = lights.emitters.last_mut().filter(|e| e.kind == crate::scene::emitter::EMITTER_ENVIRONMENT) {
            if let Some((centre, r)) = camera_sees(scene, &bvh, radius).filter(|&(_, r)| r < radius) {
                (env.direction, env.width) = (centre.into(), r);
            }
        }

        Ok(Self {
            packed_bvh: bvh.pack(),
            bvh,
            cwbvh,
            triangles,
            spheres,
            materials,
            shapes,
            attributes,
            media_first,
            camera_medium: scene.camera.medium.unwrap_or(NO_MEDIUM),
            media: !scene.media.is_empty(),
            texels,
            emitters: lights.emitters,
            power_total: lights.power_total,
            motion,
            bounds_min,
            bounds_max,
            swept_min,
            swept_max,
        })
    }

    /// The box holding every surface at every shutter time.
    pub fn swept_bounds(&self) -> (Vec3, Vec3) {
        (self.swept_min, self.swept_max)
    }

    /// Distance to push ray origins off surfaces: small against the scene, large against the
    /// rounding error of single-precision positions in it.
    pub fn ray_epsilon(&self) -> f32 {
        let diagonal = (self.bounds_max - self.bounds_min).length();
        let magnitude = self.bounds_min.abs().max(self.bounds_max.abs()).max_element();
        (1e-5 * diagonal).max(1e-6 * magnitude)
    }
}

/// The scene's bounds over the whole shutter: moving shapes at time 0 and at time 1.
fn swept_bounds(scene: &Scene, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = (lo, hi);
    for t in &scene.triangles {
        if let Some(v) = scene.shapes[t.shape as usize].velocity {
            for p in t.p {
                lo = lo.min(p + v);
                hi = hi.max(p + v);
            }
        }
    }
    for s in &scene.spheres {
        if let Some(v) = scene.shapes[s.shape as usize].velocity {
            lo = lo.min(s.center + v - s.radius);
            hi = hi.max(s.center + v + s.radius);
        }
    }
    (lo, hi)
}

// Which tree the buffers hold: the traversal a scene gets.

/// Scenes of at most this many primitives are traced by code. Compile time grows with the
/// code (lavapipe compiles each kernel once per run): a 36-triangle Cornell box adds a
/// fraction of a second.
pub const MAX_BAKED_PRIMITIVES: usize = 256;

/// Whether a scene of `primitives` primitives is traced through the compressed 8-wide BVH
/// ([`crate::accel::cwbvh`]) rather than the binary tree's data traversal.
///
/// Scenes small enough to bake are traced by code, which loads nothing and beats both
/// (`cargo bench --bench traversal`, see docs/journal/session-12.md "CWBVH (issue 24)": on the Cornell box the
/// baked traversal traces about twice the CWBVH's rays per second, the CWBVH twice the binary
/// tree's); the CWBVH takes every larger scene, where it traced 1.3x to 1.7x the binary
/// tree's closest hits and 2.6x to 3x its shadow rays (the bunny box, the 48k and 871k
/// dragons), and pt-nee drew 1.5x the samples on the bunny box; SPPM's passes on the 871k
/// dragon took as long either way (not yet explained). `SPPM_GPU_TRAVERSAL=binary` in the
/// environment keeps the binary tree instead, to compare the two in one binary (images agree
/// bit for bit but for ties).
pub fn uses_cwbvh(primitives: usize) -> bool {
    primitives > MAX_BAKED_PRIMITIVES && std::env::var("SPPM_GPU_TRAVERSAL").map_or(true, |v| v != "binary")
}

/// The `BVH_LAYOUT` override for `data`'s scene (`shaders/shared/scene.wgsl`): 2 when its
/// buffers hold the CWBVH, 1 for the binary tree, so that kernels compile only the
/// traversal the scene uses.
pub fn layout_constant(data: &SceneData) -> (&'static str, f64) {
    ("BVH_LAYOUT", if data.cwbvh.is_some() { 2.0 } else { 1.0 })
}

/// A primitive of [`leaf_prims`]: three `vec4f`.
type LeafPrim = [[f32; 4]; 3];

/// Bytes of a primitive of [`leaf_prims`] (48).
pub const LEAF_PRIM_BYTES: usize = std::mem::size_of::<LeafPrim>();

/// The primitives of [`SceneData::cwbvh`]'s leaves in leaf order, three `vec4f` each, as the
/// CWBVH traversal reads them after its nodes in `bvh_nodes` (`shaders/shared/cwbvh.wgsl`):
/// a triangle as `(p0, prim_ref)`, `(e1, shape)`, `(e2, 0)`, a sphere as
/// `(center, prim_ref)`, `(radius, shape, 0, 0)`, `0`, the integers as `f32` bits. The
/// coordinates are those of `triangles` and `spheres`, so the intersection tests compute the
/// same numbers. Empty without a CWBVH.
pub fn leaf_prims(data: &SceneData) -> Vec<[f32; 4]> {
    let Some(cw) = &data.cwbvh else { return Vec::new() };
    let bits = f32::from_bits;
    cw.prim_refs
        .iter()
        .flat_map(|&r| -> LeafPrim {
            if r & SPHERE_BIT != 0 {
                let s = &data.spheres[(r & !SPHERE_BIT) as usize];
                let c = s.center;
                [[c[0], c[1], c[2], bits(r)], [s.radius, bits(s.shape), 0.0, 0.0], [0.0; 4]]
            } else {
                let t = &data.triangles[r as usize];
                let (p, e1, e2) = (t.p0, t.e1, t.e2);
                [[p[0], p[1], p[2], bits(r)], [e1[0], e1[1], e1[2], bits(t.shape)], [e2[0], e2[1], e2[2], 0.0]]
            }
        })
        .collect()
}

/// Storage buffers of a [`SceneData`]. Empty arrays get one zeroed element, since wgpu
/// cannot bind a zero-sized buffer.
pub struct SceneBuffers {
    /// [`PackedBvh::nodes`]: `array<BvhNode>`, or the nodes of [`SceneData::cwbvh`] then
    /// its leaves' primitives ([`leaf_prims`]).
    pub bvh_nodes: wgpu::Buffer,
    /// [`PackedBvh::params`]: `var<uniform> bvh: BvhParams` (its `tree_kind` 1 with a CWBVH,
    /// `leaf_base` where the primitives start).
    pub bvh: wgpu::Buffer,
    /// [`Bvh::prim_refs`]: `array<u32>`, or those of [`SceneData::cwbvh`].
    pub prim_refs: wgpu::Buffer,
    /// [`SceneData::triangles`]: `array<Triangle>`.
    pub triangles: wgpu::Buffer,
    /// [`SceneData::spheres`]: `array<Sphere>`.
    pub spheres: wgpu::Buffer,
    /// [`SceneData::materials`]: `array<Material>`.
    pub materials: wgpu::Buffer,
    /// [`SceneData::attributes`]: `array<vec4f>`.
    pub attributes: wgpu::Buffer,
    /// [`SceneData::texels`]: `array<vec4f>`.
    pub texels: wgpu::Buffer,
    /// [`SceneData::shapes`]: `array<Shape>`.
    pub shapes: wgpu::Buffer,
    /// [`SceneData::emitters`]: `array<Emitter>`.
    pub emitters: wgpu::Buffer,
}

/// The sphere around what the camera sees directly: the points 32 x 32 rays through the image
/// first meet (the shapes at rest), its radius grown by 1% of the scene's, `scene_radius`;
/// `None` where every ray escapes. An environment's light subpaths are aimed at it
/// ([`Emitter::direction`], [`Emitter::width`]), as SPPM's photons are at its visible points.
fn camera_sees(scene: &Scene, bvh: &Bvh, scene_radius: f32) -> Option<(Vec3, f32)> {
    let c = &scene.camera;
    let (forward, right, up) = c.basis();
    let tan_half = (c.fov.to_radians() * 0.5).tan();
    let aspect = scene.render.width as f32 / scene.render.height.max(1) as f32;
    let mut bounds: Option<(Vec3, Vec3)> = None;
    for j in 0..32 {
        for i in 0..32 {
            let (sx, sy) = ((i as f32 + 0.5) / 16.0 - 1.0, (j as f32 + 0.5) / 16.0 - 1.0);
            let d = forward + right * (sx * tan_half * aspect) + up * (sy * tan_half);
            if let Some(hit) = bvh.intersect(&scene.triangles, &scene.spheres, c.position, d, f32::INFINITY) {
                let p = c.position + hit.t * d;
                bounds = Some(bounds.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))));
            }
        }
    }
    bounds.map(|(lo, hi)| (0.5 * (lo + hi), 0.5 * (hi - lo).length() + 0.01 * scene_radius))
}

/// Bytes of a scene's texture images as floats beyond which its 8-bit images are
/// palette-coded ([`palette_coded`]): wgpu's default storage binding, which every device
/// offers (lavapipe's too).
pub const PALETTE_ABOVE_BYTES: u64 = 128 << 20;

/// `texels` palette-coded ([`TEXTURE_PALETTE`]) as the `texels` buffer stores them, or
/// `None` when their channels take more than [`PALETTE_ENTRIES`] distinct values or the image
/// is so small that its floats take no more room than the palette would. Lossless: the
/// palette holds the very `f32`s, so lookups return what the float texels would.
pub fn palette_coded(texels: &[Vec3]) -> Option<Vec<[f32; 4]>> {
    const PALETTE: usize = PALETTE_ENTRIES as usize;
    if PALETTE / 4 + texels.len().div_ceil(4) >= texels.len() {
        return None;
    }
    // An open-addressing table of the values' bits (a hash map's per-lookup cost is most of
    // the time on a texture of millions of texels); `EMPTY` is a NaN no image holds.
    const SLOTS: usize = 4 * PALETTE;
    const EMPTY: u32 = 0x7fff_ffff;
    let mut slots = [(EMPTY, 0u8); SLOTS];
    let mut palette = [0.0f32; PALETTE];
    let mut used = 0;
    let mut index = |value: f32| -> Option<u32> {
        let bits = value.to_bits();
        // Checked first: an empty slot would match it.
        if bits == EMPTY {
            return None;
        }
        let mut slot = (bits.wrapping_mul(0x9e37_79b1) >> 22) as usize;
        loop {
            match slots[slot] {
                (b, i) if b == bits => return Some(i as u32),
                (EMPTY, _) => {
                    if used == PALETTE {
                        return None;
                    }
                    slots[slot] = (bits, used as u8);
                    palette[used] = value;
                    used += 1;
                    return Some(used as u32 - 1);
                }
                _ => slot = (slot + 1) % SLOTS,
            }
        }
    };
    let mut words = Vec::with_capacity(texels.len());
    for c in texels {
        words.push(index(c.x)? | index(c.y)? << 8 | index(c.z)? << 16);
    }
    let mut coded: Vec<[f32; 4]> = palette.chunks(4).map(|p| [p[0], p[1], p[2], p[3]]).collect();
    coded.extend(words.chunks(4).map(|w| {
        let mut texel = [0.0; 4];
        texel.iter_mut().zip(w).for_each(|(t, w)| *t = f32::from_bits(*w));
        texel
    }));
    Some(coded)
}

/// A read-only storage buffer holding `data` (one zeroed element when it is empty).
pub fn storage_buffer<T: bytemuck::Pod>(device: &wgpu::Device, label: &str, data: &[T]) -> wgpu::Buffer {
    let placeholder = [T::zeroed()];
    let data = if data.is_empty() { &placeholder[..] } else { data };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(data),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
    })
}

/// A buffer of `size` bytes (at least 16) for `usage`, zeroed by the device rather than
/// uploaded from the host: a large one costs no host memory or copy.
pub fn zeroed_buffer(device: &wgpu::Device, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16), usage, mapped_at_creation: false })
}

/// The usages of a storage buffer that the host writes, clears and reads back.
pub const STORAGE_USAGE: wgpu::BufferUsages =
    wgpu::BufferUsages::STORAGE.union(wgpu::BufferUsages::COPY_DST).union(wgpu::BufferUsages::COPY_SRC);

impl SceneBuffers {
    /// [`SceneBuffers::new`] after checking that each array of `data` fits in one binding of
    /// `device` (128 MiB on lavapipe): a scene too large for the device is refused before
    /// any work, naming what is too large, rather than failing its first pass.
    pub fn upload(device: &wgpu::Device, scene: &Scene, data: &SceneData) -> Result<Self, SceneError> {
        let limit = device.limits().max_storage_buffer_binding_size;
        let bvh_nodes = match &data.cwbvh {
            Some(cw) => std::mem::size_of_val(&cw.nodes[..]) + LEAF_PRIM_BYTES * cw.prim_refs.len(),
            None => std::mem::size_of_val(&data.packed_bvh.nodes[..]),
        };
        let arrays = [
            ("BVH", bvh_nodes),
            ("triangles", std::mem::size_of_val(&data.triangles[..])),
            ("shading normals and texture coordinates", std::mem::size_of_val(&data.attributes[..])),
            ("textures (and environment map)", std::mem::size_of_val(&data.texels[..])),
        ];
        for (what, bytes) in arrays {
            if bytes as u64 > limit {
                let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
                return Err(SceneError {
                    file: scene.path.clone(),
                    line: None,
                    key: None,
                    message: format!(
                        "the scene's {what} take {:.1} MiB on the GPU, more than this device binds in one buffer ({:.1} MiB)",
                        mib(bytes as u64),
                        mib(limit)
                    ),
                });
            }
        }
        Ok(Self::new(device, data))
    }

    /// Upload every array of `data` to a storage buffer named like its WGSL global.
    pub fn new(device: &wgpu::Device, data: &SceneData) -> Self {
        let mut params = data.packed_bvh.params;
        let bvh_nodes = match &data.cwbvh {
            Some(cw) => {
                let mut words: Vec<[f32; 4]> = bytemuck::cast_slice(&cw.nodes).to_vec();
                (params.tree_kind, params.leaf_base) = (1, words.len() as u32);
                words.extend(leaf_prims(data));
                storage_buffer(device, "bvh_nodes", &words)
            }
            None => storage_buffer(device, "bvh_nodes", &data.packed_bvh.nodes),
        };
        Self {
            bvh_nodes,
            bvh: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("bvh"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            }),
            prim_refs: storage_buffer(device, "prim_refs", data.cwbvh.as_ref().map_or(&data.bvh.prim_refs, |cw| &cw.prim_refs)),
            triangles: storage_buffer(device, "triangles", &data.triangles),
            spheres: storage_buffer(device, "spheres", &data.spheres),
            materials: storage_buffer(device, "materials", &data.materials),
            attributes: storage_buffer(device, "attributes", &data.attributes),
            texels: storage_buffer(device, "texels", &data.texels),
            shapes: storage_buffer(device, "shapes", &data.shapes),
            emitters: storage_buffer(device, "emitters", &data.emitters),
        }
    }

    /// The buffers under the names of their WGSL globals.
    pub fn resources(&self) -> Vec<super::Resource<'_>> {
        use super::Resource as R;
        vec![
            R { name: "bvh_nodes", buffer: &self.bvh_nodes },
            R { name: "bvh", buffer: &self.bvh },
            R { name: "prim_refs", buffer: &self.prim_refs },
            R { name: "triangles", buffer: &self.triangles },
            R { name: "spheres", buffer: &self.spheres },
            R { name: "materials", buffer: &self.materials },
            R { name: "attributes", buffer: &self.attributes },
            R { name: "texels", buffer: &self.texels },
            R { name: "shapes", buffer: &self.shapes },
            R { name: "emitters", buffer: &self.emitters },
        ]
    }
}
