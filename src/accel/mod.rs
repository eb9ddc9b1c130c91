//! Acceleration structures built on the host: the BVH over scene primitives and the hashed
//! grid over visible points.
//!
//! Both are flat arrays of plain-old-data that are uploaded to storage buffers as they are;
//! the host-side query functions ([`Bvh::intersect`], [`HashGrid::candidates`]) mirror what
//! the WGSL kernels do, and serve as their reference in tests.

pub mod bvh;
pub mod cwbvh;
pub mod grid;

pub use bvh::{build_bvh, build_bvh_moving, Bvh, BvhNode, SPHERE_BIT};
pub use cwbvh::{build_cwbvh, CwBvh, CwNode};
pub use grid::{build_grid, build_grid_in, hash_cell, HashGrid};
