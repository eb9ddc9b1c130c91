//! The compressed 8-wide BVH (CWBVH) of Ylitie, Karras and Laine, "Efficient incoherent ray
//! traversal on GPUs through compressed wide BVHs" (HPG 2017), for scenes too large to be
//! traced by code ([`crate::gpu::baked_bvh`]).
//!
//! obvhs builds the tree (PLOC over the primitives' boxes, one primitive a leaf, then the
//! paper's SAH-optimal collapse to 8-wide nodes with up to 3 primitives a leaf, children
//! placed in slots by the direction they lie in from the node's centre). Each node is 80 bytes
//! ([`CwNode`]): its box's lower corner, a power-of-two grid step per axis, and the boxes of
//! up to 8 children quantized to 8 bits on that grid. A traversal step loads one node and
//! tests 8 children, where the binary layout ([`GpuBvhNode`](crate::layout::GpuBvhNode)) loads 32 bytes to
//! test 2: on a CPU driver, where each load at a per-ray address is a loop over the SIMD
//! lanes, loads per child box are what the time is made of.
//!
//! obvhs quantizes with `f32` arithmetic that may round a child's box inwards by an ulp;
//! [`build_cwbvh`] quantizes every node again from the exact boxes so that a box decoded in
//! `f32` (`p + q * e`, exact product) contains the child's exact box. The slab test works in
//! the node's grid, a fused multiply-add a plane, its planes moved outwards by a bound on
//! its rounding ([`CwNode`]'s `hit_mask`): a ray can only lose a box that it also misses
//! exactly, and the closest hit is the same triangle at the same `t` as the binary
//! traversal's, bit for bit (primitives at exactly the same distance aside).
//!
//! [`CwBvh::intersect`] and [`CwBvh::occluded`] traverse the tree on the CPU exactly as
//! `shaders/shared/cwbvh.wgsl` does (same slot order, same group stack): the oracle its
//! kernels are tested against.

use std::time::Duration;

use glam::Vec3;
use obvhs::{aabb::Aabb, cwbvh::builder::build_cwbvh as obvhs_build_cwbvh, BvhBuildParams};

use super::bvh::{intersect_prim, primitive_aabbs, Hit, SPHERE_BIT};
use crate::scene::{Sphere, Triangle};

/// Entries of the traversal's stack of node groups, here and in the kernels. A group is
/// pushed at most once per level, so this bounds the tree's depth; [`build_cwbvh`] gives no
/// tree deeper than this.
pub const CW_STACK_SIZE: usize = 32;

/// One CWBVH node as the kernels read it (80 bytes, five `vec4u`). The byte layout is
/// obvhs's `CwBvhNode`.
///
/// Child `i` (slot `i`) is described by byte `i` of `meta`: 0 for an empty slot; for an
/// interior child `0b001_00000 | (24 + i)`, the child being node `child_base + k` with `k`
/// the number of interior children in slots below `i` (bit `i` of `imask` set); for a leaf,
/// the primitive count in unary in the top 3 bits and in the low 5 bits its first
/// primitive's offset from `prim_base` in [`CwBvh::prim_refs`]. Its box on axis `a` is
/// `p[a] + q * e[a]` for `q` its bytes `i` of the `q` words of that axis (lower then upper
/// bounds, each 8 bytes in two words: x lower, x upper, y lower, y upper, z lower, z upper).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CwNode {
    /// Lower corner of the node's quantization grid.
    pub p: [f32; 3],
    /// The grid step's biased `f32` exponent per axis in bytes 0 to 2 (step
    /// `f32::from_bits(e << 23)`), `imask` in byte 3.
    pub e_imask: u32,
    /// Index of the first interior child in [`CwBvh::nodes`]; a node's interior children are
    /// adjacent.
    pub child_base: u32,
    /// Index in [`CwBvh::prim_refs`] of the first primitive of the node's leaves.
    pub prim_base: u32,
    /// Child descriptions, one byte a slot (slots 0 to 3 in the first word).
    pub meta: [u32; 2],
    /// Quantized child boxes, one byte a slot: lower x, upper x, lower y, upper y, lower z,
    /// upper z, each in two words.
    pub q: [u32; 12],
}

/// A CWBVH over a scene's triangles and spheres, in the kernels' layout.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CwBvh {
    /// Nodes, root first.
    pub nodes: Vec<CwNode>,
    /// Primitive references in leaf order (a triangle index, or a sphere index |
    /// [`SPHERE_BIT`]).
    pub prim_refs: Vec<u32>,
    /// Levels of nodes on the longest path from the root (1 for a root with only leaves).
    pub depth: usize,
}

/// Builds the CWBVH over `triangles` (references `0..triangles.len()`) and `spheres`
/// (references `i | SPHERE_BIT`), boxes swept over the shutter by `velocity` as in
/// [`super::build_bvh_moving`]. `None` for fewer than two primitives, or a tree deeper than
/// [`CW_STACK_SIZE`] (the binary traversal takes those).
pub fn build_cwbvh(triangles: &[Triangle], spheres: &[Sphere], velocity: impl Fn(u32) -> Vec3) -> Option<CwBvh> {
    let aabbs = primitive_aabbs(triangles, spheres, velocity);
    if aabbs.len() < 2 {
        return None;
    }
    let params = BvhBuildParams { max_prims_per_leaf: 3, ..BvhBuildParams::medium_build() };
    let tree = obvhs_build_cwbvh(&aabbs, params, &mut Duration::default());
    if tree.nodes.is_empty() {
        return None;
    }
    let triangle_count = triangles.len() as u32;
    let prim_refs: Vec<u32> = tree
        .primitive_indices
        .iter()
        .map(|&id| if id < triangle_count { id } else { (id - triangle_count) | SPHERE_BIT })
        .collect();
    let mut nodes: Vec<CwNode> = bytemuck::cast_slice(&tree.nodes).to_vec();
    let mut exact = vec![Aabb::empty(); nodes.len()];
    let depth = requantize(&mut nodes, &tree.primitive_indices, &aabbs, &mut exact, 0);
    if depth > CW_STACK_SIZE {
        return None;
    }
    Some(CwBvh { nodes, prim_refs, depth })
}

/// The step of a quantization grid from `lo` that reaches `hi` in 255 steps as the kernels
/// decode it (`lo + 255 * step` in `f32`): the least such power of two, as its biased
/// exponent.
fn grid_exponent(lo: f32, hi: f32) -> u32 {
    // 2^-100 for flat boxes (any positive step would do: q = 0 decodes to lo exactly).
    let mut exponent = ((hi as f64 - lo as f64) / 255.0).max(1e-30).log2().ceil().max(-100.0) as i32 + 127;
    while lo + 255.0 * f32::from_bits((exponent as u32) << 23) < hi {
        exponent += 1;
    }
    // A step of one exponent less may also reach: the log above rounds.
    while exponent > 27 && lo + 255.0 * f32::from_bits(((exponent - 1) as u32) << 23) >= hi {
        exponent -= 1;
    }
    assert!((1..255).contains(&exponent), "scene coordinates beyond f32's range");
    exponent as u32
}

/// Quantizes the child boxes of node `index` (and its subtree) again from their exact boxes,
/// conservatively for the kernels' decode, and returns the subtree's depth. `exact[index]`
/// receives the node's exact box.
fn requantize(nodes: &mut [CwNode], indices: &[u32], aabbs: &[Aabb], exact: &mut [Aabb], index: usize) -> usize {
    let node = nodes[index];
    let meta = |i: usize| (node.meta[i / 4] >> (8 * (i % 4))) & 0xff;
    let imask = node.e_imask >> 24;
    // Exact child boxes: interior children's from their subtrees, leaves' from their
    // primitives.
    let mut boxes = [Aabb::empty(); 8];
    let mut depth = 1;
    for (i, b) in boxes.iter_mut().enumerate() {
        let m = meta(i);
        if m == 0 {
            continue;
        }
        if imask & (1 << i) != 0 {
            let child = node.child_base as usize + (imask & ((1 << i) - 1)).count_ones() as usize;
            depth = depth.max(1 + requantize(nodes, indices, aabbs, exact, child));
            *b = exact[child];
        } else {
            let first = (node.prim_base + (m & 0x1f)) as usize;
            for &id in &indices[first..first + (m >> 5).count_ones() as usize] {
                *b = b.union(&aabbs[id as usize]);
            }
        }
    }
    let total = boxes.iter().fold(Aabb::empty(), |acc, b| acc.union(b));
    exact[index] = total;
    let (lo, hi) = (Vec3::from(total.min), Vec3::from(total.max));
    let e = [0, 1, 2].map(|a| grid_exponent(lo[a], hi[a]));
    let step = e.map(|x| f32::from_bits(x << 23));
    let decode = |a: usize, q: u32| lo[a] + q as f32 * step[a];
    let mut q = [0u32; 12];
    for (i, b) in boxes.iter().enumerate() {
        if meta(i) == 0 {
            continue;
        }
        for a in 0..3 {
            let (cmin, cmax) = (b.min[a], b.max[a]);
            let scaled = |x: f32| (x as f64 - lo[a] as f64) / step[a] as f64;
            let mut q_lo = scaled(cmin).floor().clamp(0.0, 255.0) as u32;
            while q_lo > 0 && decode(a, q_lo) > cmin {
                q_lo -= 1;
            }
            let mut q_hi = scaled(cmax).ceil().clamp(0.0, 255.0) as u32;
            while q_hi < 255 && decode(a, q_hi) < cmax {
                q_hi += 1;
            }
            debug_assert!(decode(a, q_lo) <= cmin && decode(a, q_hi) >= cmax);
            let shift = 8 * (i % 4);
            q[4 * a + i / 4] |= q_lo << shift;
            q[4 * a + 2 + i / 4] |= q_hi << shift;
        }
    }
    let n = &mut nodes[index];
    n.p = lo.to_array();
    n.e_imask = e[0] | e[1] << 8 | e[2] << 16 | imask << 24;
    n.q = q;
    depth
}

/// `ray_get_octant_inv4` of obvhs: per byte, the slot bits of the octants the ray does not
/// point into (bit 2 for +x, 1 for +y, 0 for +z).
fn octant_inv(dir: Vec3) -> u32 {
    (if dir.x < 0.0 { 0 } else { 4 }) | (if dir.y < 0.0 { 0 } else { 2 }) | (if dir.z < 0.0 { 0 } else { 1 })
}

impl CwNode {
    /// The box of child slot `i` as the kernels decode it.
    pub fn child_box(&self, i: usize) -> (Vec3, Vec3) {
        let byte = |w: u32| ((w >> (8 * (i % 4))) & 0xff) as f32;
        let step = |a: u32| f32::from_bits(((self.e_imask >> (8 * a)) & 0xff) << 23);
        let p = Vec3::from(self.p);
        let e = Vec3::new(step(0), step(1), step(2));
        let w = |k: usize| self.q[k + i / 4];
        (p + Vec3::new(byte(w(0)), byte(w(4)), byte(w(8))) * e, p + Vec3::new(byte(w(2)), byte(w(6)), byte(w(10))) * e)
    }

    /// The hit mask of the children the segment `0 < t < t_max` enters: interior children
    /// at bit `24 + (slot ^ oct_inv)`, the primitives of leaves at bits `offset ..`.
    ///
    /// The slab test in the node's grid, as the kernels do it: plane `p + q e` at
    /// `t = q (e inv_dir) + (p - origin) inv_dir`, one fused multiply-add a plane, near planes
    /// moved towards the origin and far ones away by `1e-6 (|p - origin| + |p| + 255 e)
    /// |inv_dir|`, which bounds the rounding of that form, of `inv_dir`, and of the `f32`
    /// decode the boxes were made to contain (a few ulps of those magnitudes each): a ray is
    /// kept wherever it enters a child's exact box. A zero direction component gives NaN
    /// planes, which (compared, as in the binary tree's slab test) narrow nothing.
    fn hit_mask(&self, origin: Vec3, inv_dir: Vec3, oct_inv: u32, t_max: f32) -> u32 {
        let step = |a: u32| f32::from_bits(((self.e_imask >> (8 * a)) & 0xff) << 23);
        let (p, e) = (Vec3::from(self.p), Vec3::new(step(0), step(1), step(2)));
        let po = p - origin;
        let scale = e * inv_dir;
        let b = po * inv_dir;
        let slack = 1e-6 * (po.abs() + p.abs() + 255.0 * e) * inv_dir.abs();
        let (b_near, b_far) = (b - slack, b + slack);
        let negative = inv_dir.cmplt(Vec3::ZERO);
        let mut mask = 0;
        for i in 0..8 {
            let m = (self.meta[i / 4] >> (8 * (i % 4))) & 0xff;
            if m == 0 {
                continue;
            }
            let byte = |k: usize| ((self.q[k + i / 4] >> (8 * (i % 4))) & 0xff) as f32;
            let (lo, hi) = (Vec3::new(byte(0), byte(4), byte(8)), Vec3::new(byte(2), byte(6), byte(10)));
            let (q_near, q_far) = (Vec3::select(negative, hi, lo), Vec3::select(negative, lo, hi));
            let (mut t0, mut t1) = (0.0f32, t_max);
            for a in 0..3 {
                let near = q_near[a].mul_add(scale[a], b_near[a]);
                let far = q_far[a].mul_add(scale[a], b_far[a]);
                if near > t0 {
                    t0 = near;
                }
                if far < t1 {
                    t1 = far;
                }
            }
            // t0 and t1 are never NaN: NaN planes were not taken.
            if t0 > t1 {
                continue;
            }
            let inner = m & (m << 1) & 0x10 != 0;
            let bit = (m ^ if inner { oct_inv } else { 0 }) & 0x1f;
            mask |= ((m >> 5) & 7) << bit;
        }
        mask
    }
}

impl CwBvh {
    /// Nearest intersection with `0 < t < t_max` along `origin + t * dir`, or `None`; the
    /// kernels' `trace_closest` through this tree, step for step.
    pub fn intersect(&self, triangles: &[Triangle], spheres: &[Sphere], origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        self.traverse(triangles, spheres, origin, dir, t_max, false)
    }

    /// Whether anything lies along `origin + t * dir` for `0 < t < t_max` (the traversal
    /// stops at the first hit, as the kernels' `occluded`).
    pub fn occluded(&self, triangles: &[Triangle], spheres: &[Sphere], origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        self.traverse(triangles, spheres, origin, dir, t_max, true).is_some()
    }

    fn traverse(
        &self,
        triangles: &[Triangle],
        spheres: &[Sphere],
        origin: Vec3,
        dir: Vec3,
        t_max: f32,
        any_hit: bool,
    ) -> Option<Hit> {
        if !(origin.is_finite() && dir.is_finite()) || self.nodes.is_empty() {
            return None;
        }
        let inv_dir = 1.0 / dir;
        let oct_inv = octant_inv(dir);
        let mut t_max = t_max;
        let mut hit = None;
        let mut stack = [(0u32, 0u32); CW_STACK_SIZE];
        let mut sp = 0;
        // (first child node, hit bits of interior children << 24 | imask); the root is the
        // one interior "child" of a virtual node at 0.
        let mut group = (0u32, 0x8000_0000u32);
        loop {
            let mut prims = (0u32, 0u32);
            if group.1 & 0xff00_0000 != 0 {
                let bits = group.1;
                let bit = 31 - bits.leading_zeros();
                group.1 &= !(1 << bit);
                if group.1 & 0xff00_0000 != 0 {
                    stack[sp] = group;
                    sp += 1;
                }
                let slot = (bit - 24) ^ oct_inv;
                let node = &self.nodes[(group.0 + (bits & !(u32::MAX << slot)).count_ones()) as usize];
                let mask = node.hit_mask(origin, inv_dir, oct_inv, t_max);
                group = (node.child_base, (mask & 0xff00_0000) | (node.e_imask >> 24));
                prims = (node.prim_base, mask & 0x00ff_ffff);
            }
            while prims.1 != 0 {
                let bit = 31 - prims.1.leading_zeros();
                prims.1 &= !(1 << bit);
                let prim_ref = self.prim_refs[(prims.0 + bit) as usize];
                if let Some(h) = intersect_prim(triangles, spheres, prim_ref, origin, dir, t_max) {
                    t_max = h.t;
                    hit = Some(h);
                    if any_hit {
                        return hit;
                    }
                }
            }
            if group.1 & 0xff00_0000 == 0 {
                if sp == 0 {
                    break;
                }
                sp -= 1;
                group = stack[sp];
            }
        }
        hit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_is_80_bytes_as_obvhs() {
        assert_eq!(std::mem::size_of::<CwNode>(), 80);
        assert_eq!(std::mem::size_of::<obvhs::cwbvh::node::CwBvhNode>(), 80);
    }

    #[test]
    fn grid_reaches_the_top() {
        for (lo, hi) in [(0.0f32, 1.0f32), (-3.0, -2.999), (1e6, 1e6 + 1.0), (5.0, 5.0), (-1e-3, 7.5)] {
            let e = grid_exponent(lo, hi);
            assert!(lo + 255.0 * f32::from_bits(e << 23) >= hi, "{lo} {hi}");
        }
    }
}
