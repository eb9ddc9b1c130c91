//! Bounding volume hierarchy over the scene's triangles and spheres.
//!
//! The tree is built by obvhs (PLOC, Meister & Bittner 2018, followed by reinsertion
//! optimization and leaf collapsing) over the bounding boxes of all primitives, then
//! flattened into [`BvhNode`]s: a binary tree stored depth-first with the root at index 0 and
//! the two children of every interior node in adjacent slots, plus one array of primitive
//! references that leaves index into.
//!
//! The kernels traverse the same tree packed by [`Bvh::pack`] into [`GpuBvhNode`]s (interior
//! nodes holding their children's quantized boxes). [`Bvh::intersect`] traverses the
//! unpacked tree on the CPU, with a fixed stack of [`STACK_SIZE`] entries and `f32`
//! arithmetic as in the kernels: the oracle the kernels' hits are checked against.

use std::time::Duration;

use bytemuck::Zeroable;
use glam::{Vec3, Vec3A};
use obvhs::{aabb::Aabb, bvh2::builder::build_bvh2, bvh2::Bvh2, BvhBuildParams};

pub use crate::layout::SPHERE_BIT;
use crate::layout::{BvhParams, GpuBvhNode};
use crate::scene::{Sphere, Triangle};

/// One node of the host tree (32 bytes). Leaf when `count > 0`: primitives
/// `prim_refs[first .. first + count]`. Interior when `count == 0`: children at `first` and
/// `first + 1`.
///
/// The tree of an empty scene is a single node with `count == 0` and an inverted box
/// (`min = +inf`, `max = -inf`), packed for the kernels as a root with two empty children.
/// [`Bvh::intersect`] tests a node's box before looking at its children, and no ray with a finite origin and direction passes the slab test of an
/// inverted box, so that root is never descended into (its "children" do not exist). This
/// relies on the slab test picking near and far planes by the sign of the direction, as
/// `slab_test` does: taking per-axis min and max of the two plane distances instead would
/// turn the inverted box into a valid one.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BvhNode {
    /// Minimum corner of the node's bounding box (world space; swept over the shutter for
    /// moving primitives).
    pub min: [f32; 3],
    /// Leaf: index of its first entry in [`Bvh::prim_refs`]. Interior: index of its first
    /// child in [`Bvh::nodes`] (the second is at `first + 1`).
    pub first: u32,
    /// Maximum corner of the node's bounding box.
    pub max: [f32; 3],
    /// Primitives in a leaf (1 to [`MAX_PRIMS_PER_LEAF`]); 0 marks an interior node.
    pub count: u32,
}

/// Entries in the traversal stack, here and in the kernels. [`build_bvh`] guarantees that
/// trees are shallow enough for it (depth below `STACK_SIZE`).
pub const STACK_SIZE: usize = 64;

/// Leaves hold at most this many primitives.
pub const MAX_PRIMS_PER_LEAF: u32 = 4;

/// Marks a child reference as a leaf: `LEAF_BIT | count << LEAF_COUNT_SHIFT | first`, its
/// primitives `prim_refs[first .. first + count]`. Without the bit, a reference is the index
/// of an interior node in [`PackedBvh::nodes`].
pub const LEAF_BIT: u32 = 0x8000_0000;
/// Position of a leaf's primitive count in its reference (4 bits).
pub const LEAF_COUNT_SHIFT: u32 = 27;
/// Mask of a leaf's first primitive in its reference.
pub const LEAF_FIRST_MASK: u32 = (1 << LEAF_COUNT_SHIFT) - 1;

/// The BVH in the layout the kernels traverse: interior nodes only, root at index 0 (see
/// [`GpuBvhNode`]), with the primitive references of [`Bvh::prim_refs`].
#[derive(Clone, Debug, PartialEq)]
pub struct PackedBvh {
    /// Interior nodes, root first; a tree whose root is a leaf gets a root with that leaf
    /// and an empty child.
    pub nodes: Vec<GpuBvhNode>,
    /// The decode of the quantized boxes.
    pub params: BvhParams,
}

/// The quantized box that never contains a point.
const EMPTY_BOX: [u32; 3] = [0xffff_ffff, 0x0000_ffff, 0];

/// A flattened BVH; see [`BvhNode`] for the layout.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    /// Nodes depth-first, root at index 0, siblings in adjacent slots.
    pub nodes: Vec<BvhNode>,
    /// Primitive references of the leaves: triangle index, or sphere index | [`SPHERE_BIT`].
    pub prim_refs: Vec<u32>,
}

/// The nearest intersection along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter: the hit point is `origin + t * dir`.
    pub t: f32,
    /// The primitive hit: a triangle index, or a sphere index | [`SPHERE_BIT`].
    pub prim_ref: u32,
    /// Barycentric coordinates of `p[1]` and `p[2]` for triangles (`p[0]` has `1 - b1 - b2`);
    /// zero for spheres.
    pub b1: f32,
    /// Barycentric coordinate of `p[2]` (see `b1`); zero for spheres.
    pub b2: f32,
}

/// Builds the BVH over `triangles` (references `0..triangles.len()`) and `spheres`
/// (references `i | SPHERE_BIT`).
///
/// # Panics
/// If there are `SPHERE_BIT` or more triangles or spheres. A PLOC tree too deep for the
/// traversal stack (many coincident primitives chain it) has its deep subtrees rebuilt by
/// median splits (see `flatten`).
pub fn build_bvh(triangles: &[Triangle], spheres: &[Sphere]) -> Bvh {
    build_bvh_moving(triangles, spheres, |_| Vec3::ZERO)
}

/// [`build_bvh`] for shapes that move: primitive boxes are swept from time 0 to time 1,
/// over which the primitive of shape `s` moves by `velocity(s)`, so that a ray offset by
/// `-velocity * t` into the primitive's rest frame is tested against every primitive it
/// can meet at any shutter time `t` in [0, 1).
pub fn build_bvh_moving(triangles: &[Triangle], spheres: &[Sphere], velocity: impl Fn(u32) -> Vec3) -> Bvh {
    assert!(
        triangles.len() < SPHERE_BIT as usize && spheres.len() < SPHERE_BIT as usize,
        "too many primitives for 31-bit primitive references"
    );
    if triangles.is_empty() && spheres.is_empty() {
        return Bvh {
            nodes: vec![BvhNode { min: [f32::INFINITY; 3], first: 0, max: [f32::NEG_INFINITY; 3], count: 0 }],
            prim_refs: Vec::new(),
        };
    }

    let aabbs = primitive_aabbs(triangles, spheres, velocity);
    let params = BvhBuildParams { max_prims_per_leaf: MAX_PRIMS_PER_LEAF, ..BvhBuildParams::medium_build() };
    let bvh2 = build_bvh2(&aabbs, params, &mut Duration::default());

    flatten(&bvh2, &aabbs, triangles.len() as u32)
}

/// The boxes of `triangles` then `spheres` (primitive i of the obvhs builds), swept over the
/// shutter by `velocity` (see [`build_bvh_moving`]).
pub(crate) fn primitive_aabbs(triangles: &[Triangle], spheres: &[Sphere], velocity: impl Fn(u32) -> Vec3) -> Vec<Aabb> {
    triangles
        .iter()
        .map(|t| {
            let (lo, hi) = (t.p[0].min(t.p[1]).min(t.p[2]), t.p[0].max(t.p[1]).max(t.p[2]));
            let v = velocity(t.shape);
            aabb(lo.min(lo + v), hi.max(hi + v))
        })
        .chain(spheres.iter().map(|s| {
            let (lo, hi) = (s.center - s.radius, s.center + s.radius);
            let v = velocity(s.shape);
            aabb(lo.min(lo + v), hi.max(hi + v))
        }))
        .collect()
}

fn aabb(min: Vec3, max: Vec3) -> Aabb {
    Aabb::new(Vec3A::from(min), Vec3A::from(max))
}

/// Depth at which a subtree too deep for the traversal stack is rebuilt by median splits: a
/// median tree of fewer than 2^31 primitives, 4 a leaf, has at most 29 interior levels, so
/// its interior nodes stay above depth `STACK_SIZE - 2` (see `flatten`).
const REBUILD_DEPTH: usize = STACK_SIZE - 32;

/// Lays out an obvhs tree depth first from its root, children of a node in adjacent slots,
/// and maps its primitive ids (triangles first, then spheres) to primitive references.
///
/// obvhs already keeps siblings adjacent with the root at 0, but its node array may be in any
/// order and leaves index through `primitive_indices`; rebuilding the layout makes the
/// invariants hold by construction and puts each leaf's references contiguously in
/// traversal order.
///
/// Interior nodes must lie above depth `STACK_SIZE - 1` (the traversal pushes two children
/// where it popped one). PLOC makes chains of coincident primitives (meshes given twice):
/// a subtree that would reach that depth is rebuilt from its primitives' `aabbs` by median
/// splits where it starts at `REBUILD_DEPTH`.
fn flatten(bvh2: &Bvh2, aabbs: &[Aabb], triangle_count: u32) -> Bvh {
    let to_ref = |id: u32| {
        if id < triangle_count {
            id
        } else {
            (id - triangle_count) | SPHERE_BIT
        }
    };
    let height = subtree_heights(bvh2);
    let mut nodes = Vec::with_capacity(bvh2.nodes.len());
    let mut prim_refs = Vec::with_capacity(bvh2.primitive_indices.len());
    nodes.push(BvhNode::zeroed());
    // (obvhs node, output slot, depth)
    let mut todo = vec![(0usize, 0usize, 0usize)];
    while let Some((src, dst, depth)) = todo.pop() {
        let node = &bvh2.nodes[src];
        if !node.is_leaf() && depth >= REBUILD_DEPTH && depth + height[src] >= STACK_SIZE {
            let mut ids = subtree_primitives(bvh2, src);
            median_tree(&mut ids, aabbs, dst, &mut nodes, &mut prim_refs, &to_ref);
            continue;
        }
        let (first, count) = if node.is_leaf() {
            let first = prim_refs.len() as u32;
            let ids = node.first_index as usize..(node.first_index + node.prim_count) as usize;
            prim_refs.extend(bvh2.primitive_indices[ids].iter().map(|&id| to_ref(id)));
            (first, node.prim_count)
        } else {
            debug_assert!(depth + 1 < STACK_SIZE);
            let first = nodes.len();
            nodes.extend([BvhNode::zeroed(); 2]);
            let child = node.first_index as usize;
            // Right pushed first so that the left subtree is laid out first.
            todo.push((child + 1, first + 1, depth + 1));
            todo.push((child, first, depth + 1));
            (first as u32, 0)
        };
        // Only x, y, z: the w lane of obvhs's Vec3A is not meaningful.
        let b = node.aabb();
        nodes[dst] = BvhNode { min: Vec3::from(b.min).to_array(), first, max: Vec3::from(b.max).to_array(), count };
    }
    Bvh { nodes, prim_refs }
}

/// Interior levels under each obvhs node: 0 for a leaf, 1 + the larger child's otherwise.
fn subtree_heights(bvh2: &Bvh2) -> Vec<usize> {
    let mut height = vec![0usize; bvh2.nodes.len()];
    if bvh2.nodes.is_empty() {
        return height;
    }
    // Pre-order, so that children come after their parent; heights are summed in reverse.
    let mut order = Vec::with_capacity(bvh2.nodes.len());
    let mut todo = vec![0usize];
    while let Some(i) = todo.pop() {
        order.push(i);
        let node = &bvh2.nodes[i];
        if !node.is_leaf() {
            todo.extend([node.first_index as usize, node.first_index as usize + 1]);
        }
    }
    for &i in order.iter().rev() {
        let node = &bvh2.nodes[i];
        if !node.is_leaf() {
            let c = node.first_index as usize;
            height[i] = 1 + height[c].max(height[c + 1]);
        }
    }
    height
}

/// The primitive ids under an obvhs node.
fn subtree_primitives(bvh2: &Bvh2, root: usize) -> Vec<u32> {
    let mut ids = Vec::new();
    let mut todo = vec![root];
    while let Some(i) = todo.pop() {
        let node = &bvh2.nodes[i];
        if node.is_leaf() {
            let r = node.first_index as usize..(node.first_index + node.prim_count) as usize;
            ids.extend_from_slice(&bvh2.primitive_indices[r]);
        } else {
            todo.extend([node.first_index as usize, node.first_index as usize + 1]);
        }
    }
    ids
}

/// Writes a tree over primitive `ids` at slot `dst`: a leaf of up to `MAX_PRIMS_PER_LEAF`,
/// else two halves split at the median centroid along the longest axis of the centroids'
/// box (an object median: ceil(log2(n / 4)) interior levels whatever the boxes).
fn median_tree(
    ids: &mut [u32],
    aabbs: &[Aabb],
    dst: usize,
    nodes: &mut Vec<BvhNode>,
    prim_refs: &mut Vec<u32>,
    to_ref: &impl Fn(u32) -> u32,
) {
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let (mut c_lo, mut c_hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for &id in ids.iter() {
        let b = &aabbs[id as usize];
        let (min, max) = (Vec3::from(b.min), Vec3::from(b.max));
        lo = lo.min(min);
        hi = hi.max(max);
        let c = 0.5 * (min + max);
        c_lo = c_lo.min(c);
        c_hi = c_hi.max(c);
    }
    let (first, count) = if ids.len() <= MAX_PRIMS_PER_LEAF as usize {
        let first = prim_refs.len() as u32;
        prim_refs.extend(ids.iter().map(|&id| to_ref(id)));
        (first, ids.len() as u32)
    } else {
        let axis = (c_hi - c_lo).max_position();
        let centre = |id: &u32| {
            let b = &aabbs[*id as usize];
            b.min[axis] + b.max[axis]
        };
        let mid = ids.len() / 2;
        ids.select_nth_unstable_by(mid, |a, b| centre(a).total_cmp(&centre(b)));
        let first = nodes.len();
        nodes.extend([BvhNode::zeroed(); 2]);
        let (left, right) = ids.split_at_mut(mid);
        median_tree(left, aabbs, first, nodes, prim_refs, to_ref);
        median_tree(right, aabbs, first + 1, nodes, prim_refs, to_ref);
        (first as u32, 0)
    };
    nodes[dst] = BvhNode { min: lo.to_array(), first, max: hi.to_array(), count };
}

impl Bvh {
    /// Nearest intersection with `0 < t < t_max` along `origin + t * dir` (`dir` need not be
    /// unit length), or `None`. `triangles` and `spheres` must be the ones the tree was built
    /// from.
    ///
    /// Stack traversal as in the kernels: pop a node, skip it unless the ray segment overlaps
    /// its box (against the current nearest hit, so entries pushed before a hit was found are
    /// culled when popped), intersect the primitives of leaves, and push both children of
    /// interior nodes, the nearer one last so that it is visited first.
    pub fn intersect(&self, triangles: &[Triangle], spheres: &[Sphere], origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        // A NaN ray would pass every slab test (see `slab_test`); it can hit nothing anyway.
        if !(origin.is_finite() && dir.is_finite()) {
            return None;
        }
        // Zero components give infinities, which `slab_test` is written for.
        let inv_dir = 1.0 / dir;
        let mut t_max = t_max;
        let mut hit: Option<Hit> = None;
        let mut stack = [0u32; STACK_SIZE];
        stack[0] = 0;
        let mut stack_len = 1usize;
        while stack_len > 0 {
            stack_len -= 1;
            let node = self.nodes[stack[stack_len] as usize];
            if !slab_test(node.min.into(), node.max.into(), origin, inv_dir, t_max) {
                continue;
            }
            if node.count > 0 {
                for i in node.first..node.first + node.count {
                    let prim_ref = self.prim_refs[i as usize];
                    if let Some(h) = intersect_prim(triangles, spheres, prim_ref, origin, dir, t_max) {
                        t_max = h.t;
                        hit = Some(h);
                    }
                }
            } else {
                // Order the children by the projection of their box centres onto the ray.
                let a = self.nodes[node.first as usize];
                let b = self.nodes[node.first as usize + 1];
                let a_centre = Vec3::from(a.min) + Vec3::from(a.max);
                let b_centre = Vec3::from(b.min) + Vec3::from(b.max);
                let b_nearer = (b_centre - a_centre).dot(dir) < 0.0;
                let (near, far) = if b_nearer { (node.first + 1, node.first) } else { (node.first, node.first + 1) };
                stack[stack_len] = far;
                stack[stack_len + 1] = near;
                stack_len += 2;
            }
        }
        hit
    }
}

impl Bvh {
    /// The tree in the kernels' layout, [`PackedBvh`].
    ///
    /// # Panics
    /// If a leaf holds more primitives or starts further in than a reference can say
    /// (16 and 2^27; [`build_bvh`] makes leaves of at most [`MAX_PRIMS_PER_LEAF`]).
    pub fn pack(&self) -> PackedBvh {
        let root = self.nodes[0];
        // The grid spans the root's box grown by a margin far above the rounding of the f32
        // decode (a few ulps of the largest coordinate), so decoded boxes still contain the
        // exact ones.
        let (lo, hi) = (Vec3::from(root.min), Vec3::from(root.max));
        if !(lo.cmple(hi).all()) {
            // Empty scene: a root with two empty children.
            let empty = GpuBvhNode { box_a: EMPTY_BOX, child_a: LEAF_BIT, box_b: EMPTY_BOX, child_b: LEAF_BIT };
            let params = BvhParams { scale: [1.0; 3], ..BvhParams::default() };
            return PackedBvh { nodes: vec![empty], params };
        }
        let magnitude = lo.abs().max(hi.abs()).max_element();
        let margin = 1e-6 * magnitude + 1e-30;
        let origin = (lo - margin).as_dvec3();
        let extent = (hi + margin).as_dvec3() - origin;
        // One step per 65535th of the extent, rounded up so that q = 65535 reaches the top.
        let scale = (extent / 65535.0).to_array().map(|s| {
            let f = s as f32;
            if (f as f64) < s {
                f.next_up()
            } else {
                f
            }
        });
        let quantize = |node: &BvhNode| -> [u32; 3] {
            let q = |x: f32, axis: usize, up: bool| -> u32 {
                if scale[axis] == 0.0 {
                    return 0;
                }
                // In f64, then one step further out, so f32 rounding cannot undercut.
                let (m, step) = if up { (margin, 1.0) } else { (-margin, -1.0) };
                let v = ((x + m) as f64 - origin[axis]) / scale[axis] as f64;
                let v = if up { v.ceil() } else { v.floor() } + step;
                v.clamp(0.0, 65535.0) as u32
            };
            let l = [0, 1, 2].map(|a| q(node.min[a], a, false));
            let h = [0, 1, 2].map(|a| q(node.max[a], a, true));
            [l[0] | l[1] << 16, l[2] | h[0] << 16, h[1] | h[2] << 16]
        };
        let leaf_ref = |node: &BvhNode| -> u32 {
            assert!(node.count < 16 && node.first <= LEAF_FIRST_MASK, "BVH leaf too large to reference");
            LEAF_BIT | node.count << LEAF_COUNT_SHIFT | node.first
        };

        let mut nodes = Vec::with_capacity(self.nodes.len() / 2 + 1);
        if root.count > 0 {
            nodes.push(GpuBvhNode { box_a: quantize(&root), child_a: leaf_ref(&root), box_b: EMPTY_BOX, child_b: LEAF_BIT });
        } else {
            // Interior nodes in the order of the host tree's depth-first layout; (host index,
            // packed index) of nodes whose children are still to be written.
            let mut todo = vec![(0usize, 0usize)];
            nodes.push(GpuBvhNode::zeroed());
            while let Some((src, dst)) = todo.pop() {
                let first = self.nodes[src].first as usize;
                let mut refs = [0u32; 2];
                for (k, child) in [first, first + 1].into_iter().enumerate() {
                    let c = &self.nodes[child];
                    refs[k] = if c.count > 0 {
                        leaf_ref(c)
                    } else {
                        nodes.push(GpuBvhNode::zeroed());
                        todo.push((child, nodes.len() - 1));
                        (nodes.len() - 1) as u32
                    };
                }
                let (a, b) = (&self.nodes[first], &self.nodes[first + 1]);
                nodes[dst] = GpuBvhNode { box_a: quantize(a), child_a: refs[0], box_b: quantize(b), child_b: refs[1] };
            }
        }
        PackedBvh { nodes, params: BvhParams { origin: origin.as_vec3().to_array(), tree_kind: 0, scale, leaf_base: 0 } }
    }
}

impl PackedBvh {
    /// The box of a child as the kernels decode it (`origin + q * scale`, in f32); an
    /// inverted box for an empty child.
    pub fn decode(&self, q: [u32; 3]) -> (Vec3, Vec3) {
        let lo = [q[0] & 0xffff, q[0] >> 16, q[1] & 0xffff];
        let hi = [q[1] >> 16, q[2] & 0xffff, q[2] >> 16];
        let origin = Vec3::from(self.params.origin);
        let scale = Vec3::from(self.params.scale);
        let f = |v: [u32; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
        (origin + f(lo) * scale, origin + f(hi) * scale)
    }
}

/// Slab test (Kay & Kajiya 1986): whether the segment `0 <= t <= t_max` of the ray overlaps
/// the box, given `inv_dir = 1 / dir`.
///
/// The near and far planes of each slab are picked by the sign of `inv_dir` (Williams et al.
/// 2005), so a zero direction component (`inv_dir = ±inf`) needs no special case: the slab
/// gives `(-inf, +inf)` when the origin lies strictly inside it and an empty interval
/// otherwise. When the origin lies exactly on one of its planes, `0 * inf` is NaN; the
/// interval is narrowed through comparisons, which are false for NaN (as in pbrt), so that
/// bound is ignored and the ray, which lies in the closed slab, is kept. (`f32::max` would
/// do the same, but WGSL's `max` becomes SPIR-V `FMax`, whose result for NaN is undefined:
/// the kernels should keep the comparisons, `select(t0, t_near.x, t_near.x > t0)`.) The far
/// distance is padded by `1 + 2 gamma(3)` (pbrt-v3, section 3.9.2) so that rounding does not
/// cull the box of a primitive hit at the box's boundary.
#[inline]
pub(crate) fn slab_test(min: Vec3, max: Vec3, origin: Vec3, inv_dir: Vec3, t_max: f32) -> bool {
    let negative = inv_dir.cmplt(Vec3::ZERO);
    let near = Vec3::select(negative, max, min);
    let far = Vec3::select(negative, min, max);
    let t_near = (near - origin) * inv_dir;
    let t_far = (far - origin) * inv_dir * SLAB_PAD;
    let mut t0 = 0.0f32;
    let mut t1 = t_max;
    for axis in 0..3 {
        if t_near[axis] > t0 {
            t0 = t_near[axis];
        }
        if t_far[axis] < t1 {
            t1 = t_far[axis];
        }
    }
    t0 <= t1
}

/// `1 + 2 gamma(3)` with `gamma(n) = n u / (1 - n u)`, `u = 2^-24` (pbrt-v3, section 3.9.1).
const SLAB_PAD: f32 = 1.0 + 2.0 * (3.0 * 0.5 * f32::EPSILON) / (1.0 - 3.0 * 0.5 * f32::EPSILON);

/// Intersects one primitive reference.
#[inline]
pub(crate) fn intersect_prim(
    triangles: &[Triangle],
    spheres: &[Sphere],
    prim_ref: u32,
    origin: Vec3,
    dir: Vec3,
    t_max: f32,
) -> Option<Hit> {
    if prim_ref & SPHERE_BIT != 0 {
        let s = &spheres[(prim_ref & !SPHERE_BIT) as usize];
        let t = intersect_sphere(s.center, s.radius, origin, dir, t_max)?;
        Some(Hit { t, prim_ref, b1: 0.0, b2: 0.0 })
    } else {
        let [p0, p1, p2] = triangles[prim_ref as usize].p;
        let (t, b1, b2) = intersect_triangle(p0, p1 - p0, p2 - p0, origin, dir, t_max)?;
        Some(Hit { t, prim_ref, b1, b2 })
    }
}

/// Ray/triangle intersection (Möller & Trumbore 1997, "Fast, minimum storage ray-triangle
/// intersection") for the triangle `p0`, `p0 + e1`, `p0 + e2`, seen from both sides.
/// Returns `(t, b1, b2)` with `0 < t < t_max`, where `b1`, `b2` are the barycentric
/// coordinates of `p0 + e1` and `p0 + e2`. Rays in the triangle's plane (`det == 0`) miss,
/// and every comparison is written so that NaN means a miss.
#[inline]
pub fn intersect_triangle(p0: Vec3, e1: Vec3, e2: Vec3, origin: Vec3, dir: Vec3, t_max: f32) -> Option<(f32, f32, f32)> {
    let pvec = dir.cross(e2);
    let det = e1.dot(pvec);
    if det == 0.0 {
        return None;
    }
    let inv_det = 1.0 / det;
    let tvec = origin - p0;
    let b1 = tvec.dot(pvec) * inv_det;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let qvec = tvec.cross(e1);
    let b2 = dir.dot(qvec) * inv_det;
    if !(b2 >= 0.0 && b1 + b2 <= 1.0) {
        return None;
    }
    let t = e2.dot(qvec) * inv_det;
    if !(t > 0.0 && t < t_max) {
        return None;
    }
    Some((t, b1, b2))
}

/// Ray/sphere intersection: the nearest root with `0 < t < t_max` (the far one when the
/// origin is inside the sphere), for any `dir` length.
///
/// Numerically stable form of Haines et al., "Precision Improvements for Ray/Sphere
/// Intersection" (Ray Tracing Gems, ch. 7, 2019): with `f = origin - center`, the roots of
/// `a t^2 + 2 b t + c` (`a = d.d`, `b = f.d`, `c = f.f - r^2`) use the discriminant
/// `b^2 - a c = a (r^2 - |f - (b / a) d|^2)`, which does not cancel catastrophically for
/// small spheres far away, and the roots `q / a` and `c / q` with
/// `q = -(b + sign(b) sqrt(discriminant))`, which avoid cancellation between `b` and the
/// square root.
#[inline]
pub fn intersect_sphere(center: Vec3, radius: f32, origin: Vec3, dir: Vec3, t_max: f32) -> Option<f32> {
    let f = origin - center;
    let a = dir.dot(dir);
    let b = f.dot(dir);
    let c = f.dot(f) - radius * radius;
    let l = f - (b / a) * dir;
    let discriminant = a * (radius * radius - l.dot(l));
    // NaN (zero `dir`) goes on and fails the root tests below.
    if discriminant < 0.0 {
        return None;
    }
    let q = -(b + discriminant.sqrt().copysign(b));
    // With q == 0 (tangent ray starting on the sphere) c / q is NaN and is rejected below.
    let (r0, r1) = (c / q, q / a);
    let (t_near, t_far) = if r0 <= r1 { (r0, r1) } else { (r1, r0) };
    if t_near > 0.0 && t_near < t_max {
        Some(t_near)
    } else if t_far > 0.0 && t_far < t_max {
        Some(t_far)
    } else {
        None
    }
}

/// Nearest intersection by testing every primitive: the oracle for [`Bvh::intersect`].
/// Among primitives hit at exactly the same `t`, the first (triangles, then spheres, in
/// order) wins.
pub fn brute_force_intersect(triangles: &[Triangle], spheres: &[Sphere], origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
    let refs = (0..triangles.len() as u32).chain((0..spheres.len() as u32).map(|i| i | SPHERE_BIT));
    let mut t_max = t_max;
    let mut hit = None;
    for prim_ref in refs {
        if let Some(h) = intersect_prim(triangles, spheres, prim_ref, origin, dir, t_max) {
            t_max = h.t;
            hit = Some(h);
        }
    }
    hit
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_is_32_bytes() {
        assert_eq!(std::mem::size_of::<BvhNode>(), 32);
    }

    #[test]
    fn triangle_barycentrics_and_both_sides() {
        let (p0, e1, e2) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let o = Vec3::new(0.25, 0.5, 1.0);
        let (t, b1, b2) = intersect_triangle(p0, e1, e2, o, -Vec3::Z, 10.0).unwrap();
        assert_eq!((t, b1, b2), (1.0, 0.25, 0.5));
        let o = Vec3::new(0.25, 0.5, -2.0);
        assert_eq!(intersect_triangle(p0, e1, e2, o, Vec3::Z, 10.0).unwrap().0, 2.0);
        assert!(intersect_triangle(p0, e1, e2, o, Vec3::Z, 2.0).is_none());
    }

    #[test]
    fn sphere_near_and_far_roots() {
        let c = Vec3::new(0.0, 0.0, 5.0);
        assert_eq!(intersect_sphere(c, 1.0, Vec3::ZERO, Vec3::Z, 100.0), Some(4.0));
        assert_eq!(intersect_sphere(c, 1.0, c, Vec3::Z * 2.0, 100.0), Some(0.5));
        assert_eq!(intersect_sphere(c, 1.0, Vec3::ZERO, -Vec3::Z, 100.0), None);
    }

    #[test]
    fn slab_test_with_zero_direction_components() {
        let (min, max) = (Vec3::ZERO, Vec3::ONE);
        let v = Vec3::new;
        // (origin, direction, hit): rays parallel to slabs, with the origin inside them, on
        // their planes (the 0 * inf = NaN case, for +0 and -0 components), or outside.
        let cases = [
            (v(-1.0, 0.5, 0.5), Vec3::X, true),
            (v(-1.0, 0.0, 1.0), Vec3::X, true),
            (v(2.0, 1.0, 0.0), -Vec3::X, true),
            (v(1.0, 0.0, -1.0), v(-0.0, -0.0, 1.0), true),
            (v(0.0, 1.0, 2.0), v(0.0, -0.0, -1.0), true),
            (v(-1.0, 1.5, 0.5), Vec3::X, false),
            (v(1.0, -0.0, 1.5), v(-0.0, 1.0, 0.0), false),
            (v(2.0, 0.5, 0.5), Vec3::X, false),
        ];
        for (o, d, expected) in cases {
            assert_eq!(slab_test(min, max, o, 1.0 / d, f32::INFINITY), expected, "{o} {d}");
        }
    }

    /// Depth of the deepest node of a host tree.
    fn tree_depth(bvh: &Bvh) -> usize {
        let (mut deepest, mut todo) = (0, vec![(0usize, 0usize)]);
        while let Some((i, d)) = todo.pop() {
            deepest = deepest.max(d);
            let n = bvh.nodes[i];
            if n.count == 0 && !bvh.prim_refs.is_empty() {
                todo.extend([(n.first as usize, d + 1), (n.first as usize + 1, d + 1)]);
            }
        }
        deepest
    }

    #[test]
    fn coincident_triangles_stay_within_the_stack() {
        // Meshes given many times over (Bitterli's coffee has some) chain a PLOC tree; the
        // rebuilt subtrees must keep every interior node above depth STACK_SIZE - 1 and find
        // the same hits as brute force.
        let tri = |k: u32, z: f32| Triangle {
            p: [Vec3::new(0.0, 0.0, z), Vec3::new(1.0, 0.0, z), Vec3::new(0.0, 1.0, z)],
            n: None,
            uv: None,
            shape: k,
        };
        let mut triangles: Vec<Triangle> = (0..3000).map(|k| tri(k, 0.0)).collect();
        // And a chain of nested sizes, each box inside the last.
        triangles.extend((0..3000).map(|k| {
            let s = 1.0 + k as f32 * 1e-3;
            Triangle { p: [Vec3::new(-s, -s, 1.0), Vec3::new(s, -s, 1.0), Vec3::new(0.0, s, 1.0)], ..tri(k, 1.0) }
        }));
        let bvh = build_bvh(&triangles, &[]);
        assert!(tree_depth(&bvh) < STACK_SIZE, "depth {}", tree_depth(&bvh));
        let mut refs = bvh.prim_refs.clone();
        refs.sort_unstable();
        assert_eq!(refs, (0..triangles.len() as u32).collect::<Vec<_>>());
        for (o, d) in
            [(Vec3::new(0.2, 0.2, 5.0), -Vec3::Z), (Vec3::new(0.2, 0.2, 0.5), -Vec3::Z), (Vec3::new(2.5, 0.0, 5.0), -Vec3::Z)]
        {
            let a = bvh.intersect(&triangles, &[], o, d, f32::INFINITY).map(|h| h.t);
            let b = brute_force_intersect(&triangles, &[], o, d, f32::INFINITY).map(|h| h.t);
            assert_eq!(a, b, "{o} {d}");
        }
    }
}
