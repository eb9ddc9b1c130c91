//! Hashed uniform grid over the SPPM visible points (Hachisuka & Jensen 2009, section 4.2).
//! Its cells also sort photon hits into buckets for `photon_gather`, where each point walks
//! the buckets its box overlaps; the points' lists are built for photons that deposit at once
//! (threads resumed when the room for hits ran out): a photon landing at `p` looks at the
//! points listed in the hash bucket of the grid cell containing `p`, and keeps those within
//! their radius.
//!
//! Each point is a sphere `|p - xyz| < r` (radius in `w`). Cells are cubes of side
//! `CELL_RADII * max r`. Smaller cells mean fewer candidates per photon lookup (a lookup
//! tests the points whose boxes touch its cell, about `(cell + 2r)^2` of surface against the
//! `pi r^2` it keeps) but more cells per point. Two radii per cell (a point's box overlaps at
//! most 2 cells per axis, 3 if rounding nudges a box of the largest radius across a third)
//! measured faster overall than one on the 512x512 Cornell spheres: with one, the grid has 4x
//! the entries, takes 4x as long to build, and its buckets collide more. Cells map to
//! `table_size` buckets with the spatial hash of Teschner et al. 2003 ("Optimized Spatial
//! Hashing for Collision Detection of Deformable Objects"); cells that share a bucket share
//! its list, and the distance test filters out the extra candidates.
//!
//! Layout (the GPU reads these three arrays as they are): [`GridParams`], `cell_start`
//! (`table_size + 1` offsets) and `entries` (point indices); bucket `h` lists
//! `entries[cell_start[h] .. cell_start[h + 1]]`, in increasing point index, each point at
//! most once.
//!
//! Lookups must compute cells as [`GridParams::cell_of`] does: the integer part of
//! `(p - origin) / cell_size`. Host and kernel rounding may differ, but a different
//! cell is only found for query points within rounding error of a point's box boundary,
//! which is outside or on the edge of the point's sphere.
//!
//! Cost of [`build_grid`], which runs every SPPM pass: one pass over the points for the
//! bounds, then two passes that visit each point's cells (a counting sort on the bucket
//! index: count, exclusive prefix sum over the table, fill), so O(n k + table_size) time with
//! k <= 8 cells per point (about 4 on average in the tests), single-threaded, and no
//! allocation besides the output arrays: `4 (table_size + 1)` bytes of offsets and `4 n k`
//! bytes of entries. The cells of a point are enumerated in both passes rather than stored
//! between them (no `n k` temporary array). Both passes update buckets scattered over the table, so they are
//! bound by cache misses on `cell_start` and `entries`, and points in pixel order (as the
//! camera pass leaves them) build about twice as fast as shuffled ones: for 2^18 points,
//! about 20 ms in pixel order and 35 ms shuffled on the 2-core development machine (release
//! build; `cargo test --release --test accel grid_build_time -- --nocapture`).

use glam::Vec3;

use crate::layout::GridParams;

/// Cell side in units of the largest radius: 2, and a little more, so that a point's box
/// (2 r wide) spans at most two cells per axis despite rounding; cell ranges are clamped to
/// two per axis as well, which bounds the entries at 8 per point.
pub const CELL_RADII: f32 = 2.002;

/// Cells per axis at most; a scene far larger than its radius gets larger cells instead.
pub const MAX_RES: u32 = 1 << 20;

/// The grid: parameters, bucket offsets and point indices (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct HashGrid {
    /// Origin, cell size, resolution and table mask, as the kernels read them.
    pub params: GridParams,
    /// `table_size + 1` offsets into `entries`.
    pub cell_start: Vec<u32>,
    /// Point indices, grouped by bucket, increasing within a bucket.
    pub entries: Vec<u32>,
}

/// Spatial hash of a cell (Teschner et al. 2003), with wrapping `u32` arithmetic as in WGSL.
#[inline]
pub fn hash_cell(c: [u32; 3], table_mask: u32) -> u32 {
    (c[0].wrapping_mul(73_856_093) ^ c[1].wrapping_mul(19_349_663) ^ c[2].wrapping_mul(83_492_791)) & table_mask
}

impl GridParams {
    /// Parameters of a grid for points of radius at most `max_r` centred in the box `lo`..`hi`,
    /// with `table_size` buckets (a power of two): cells of [`CELL_RADII`] `max_r` (larger if
    /// that would need more than [`MAX_RES`] per axis) from `lo - max_r`. `grid_setup.wgsl`
    /// computes the same.
    pub fn covering(lo: Vec3, hi: Vec3, max_r: f32, table_size: u32) -> Self {
        assert!(table_size.is_power_of_two());
        let origin = lo - max_r;
        let extent = (hi + max_r - origin).max_element();
        let cell_size = (CELL_RADII * max_r).max(extent / MAX_RES as f32);
        let mut params = GridParams { origin: origin.to_array(), cell_size, res: [0; 3], table_mask: table_size - 1 };
        params.res = [0, 1, 2].map(|axis| ((params.cell_coord(hi[axis] + max_r, axis) as u32).saturating_add(1)).min(MAX_RES));
        params
    }

    /// Grid coordinate of `x` along `axis`, in cells from `origin`: cell `c` spans
    /// `[c, c + 1)`. Build and lookups go through this one function, which is monotone in `x`,
    /// so a query point inside a point's box finds a cell of that box. Cells are taken as
    /// `coord as u32` of non-negative coordinates, a truncation, which is the floor there
    /// without a call to `floorf`.
    #[inline]
    pub fn cell_coord(&self, x: f32, axis: usize) -> f32 {
        (x - self.origin[axis]) / self.cell_size
    }

    /// Bucket of the cell containing `p`, or `None` outside the grid (or for non-finite `p`).
    #[inline]
    fn bucket_of(&self, p: Vec3) -> Option<usize> {
        self.cell_of(p).map(|c| hash_cell(c, self.table_mask) as usize)
    }

    /// Cell containing `p`, or `None` when it is outside `[0, res)` on some axis.
    #[inline]
    pub fn cell_of(&self, p: Vec3) -> Option<[u32; 3]> {
        let mut cell = [0u32; 3];
        for axis in 0..3 {
            let c = self.cell_coord(p[axis], axis);
            // Written so that NaN fails. For an integer `res`, `c < res` iff `floor(c) < res`.
            if !(c >= 0.0 && c < self.res[axis] as f32) {
                return None;
            }
            cell[axis] = c as u32;
        }
        Some(cell)
    }

    /// Appends to `buckets` the distinct buckets of the cells that the box
    /// `[center - r, center + r]` overlaps, clamped to the grid.
    #[inline]
    fn buckets_of_box(&self, center: Vec3, r: f32, buckets: &mut Vec<u32>) {
        let mut lo = [0u32; 3];
        let mut hi = [0u32; 3];
        for axis in 0..3 {
            // `as u32` truncates, and saturates negative values (and NaN) to 0.
            lo[axis] = self.cell_coord(center[axis] - r, axis) as u32;
            hi[axis] = (self.cell_coord(center[axis] + r, axis) as u32).min(self.res[axis] - 1).min(lo[axis] + 1);
        }
        for z in lo[2]..hi[2] + 1 {
            for y in lo[1]..hi[1] + 1 {
                for x in lo[0]..hi[0] + 1 {
                    let h = hash_cell([x, y, z], self.table_mask);
                    // Distinct buckets only: a linear scan, of at most 8 for most points.
                    if !buckets.contains(&h) {
                        buckets.push(h);
                    }
                }
            }
        }
    }
}

/// Whether `p[3]` is a usable radius and the position is finite.
#[inline]
fn is_valid(p: &[f32; 4]) -> bool {
    p[3] > 0.0 && p[3].is_finite() && p[0].is_finite() && p[1].is_finite() && p[2].is_finite()
}

/// Position and radius of a point.
#[inline]
fn split(p: &[f32; 4]) -> (Vec3, f32) {
    (Vec3::new(p[0], p[1], p[2]), p[3])
}

/// Whether `p` is strictly inside the sphere of `point` (`xyz`, radius `w`): the test the
/// photon kernel applies to each candidate.
#[inline]
pub fn point_within(point: &[f32; 4], p: Vec3) -> bool {
    let (center, r) = split(point);
    (p - center).length_squared() < r * r
}

/// Builds the grid over `points` (`xyz` = position, `w` = radius). Points with `w <= 0`, a
/// non-finite radius or a non-finite position are "no point here" and left out.
pub fn build_grid(points: &[[f32; 4]]) -> HashGrid {
    let valid = || points.iter().enumerate().filter(|(_, p)| is_valid(p));

    // Bounds of the points' centres and largest radius.
    let mut lo = Vec3::INFINITY;
    let mut hi = Vec3::NEG_INFINITY;
    let mut max_r = 0.0f32;
    let mut count = 0usize;
    for (_, p) in valid() {
        let (center, r) = split(p);
        lo = lo.min(center);
        hi = hi.max(center);
        max_r = max_r.max(r);
        count += 1;
    }
    if count == 0 {
        return HashGrid {
            params: GridParams { origin: [0.0; 3], cell_size: 1.0, res: [0; 3], table_mask: 0 },
            cell_start: vec![0, 0],
            entries: Vec::new(),
        };
    }
    assert!(count <= 1 << 31, "too many points for a u32 hash table");

    let params = GridParams::covering(lo, hi, max_r, count.next_power_of_two() as u32);
    build_grid_in(points, params)
}

/// The grid over the valid points of `points` with the given parameters (see
/// [`GridParams::covering`]); the kernels build the same one on the GPU.
pub fn build_grid_in(points: &[[f32; 4]], params: GridParams) -> HashGrid {
    let valid = || points.iter().enumerate().filter(|(_, p)| is_valid(p));
    let table_size = params.table_mask as usize + 1;
    let mut cell_start = vec![0u32; table_size + 1];
    let mut buckets = Vec::with_capacity(27);
    for (_, p) in valid() {
        let (center, r) = split(p);
        buckets.clear();
        params.buckets_of_box(center, r, &mut buckets);
        for &h in &buckets {
            cell_start[h as usize + 1] += 1;
        }
    }
    let mut sum = 0u32;
    for start in &mut cell_start[1..] {
        let n = *start;
        *start = sum;
        sum = sum.checked_add(n).expect("more than 2^32 grid entries");
    }
    let mut entries = vec![0u32; sum as usize];
    for (i, p) in valid() {
        let (center, r) = split(p);
        buckets.clear();
        params.buckets_of_box(center, r, &mut buckets);
        for &h in &buckets {
            let slot = &mut cell_start[h as usize + 1];
            entries[*slot as usize] = i as u32;
            *slot += 1;
        }
    }
    HashGrid { params, cell_start, entries }
}

impl HashGrid {
    /// Cell containing `p`, or `None` outside the grid.
    pub fn cell_of(&self, p: Vec3) -> Option<[u32; 3]> {
        self.params.cell_of(p)
    }

    /// The points listed in the bucket of the cell containing `p` (empty outside the grid):
    /// a superset of the points whose sphere contains `p`. The photon kernel does the same,
    /// then keeps the candidates for which [`point_within`] holds.
    pub fn candidates(&self, p: Vec3) -> &[u32] {
        match self.params.bucket_of(p) {
            Some(h) => &self.entries[self.cell_start[h] as usize..self.cell_start[h + 1] as usize],
            None => &[],
        }
    }
}

/// Indices `i` of the valid points with `|p - xyz_i| < w_i` ([`point_within`]), in
/// increasing order: the oracle for [`HashGrid::candidates`].
pub fn brute_force_within(points: &[[f32; 4]], p: Vec3) -> Vec<u32> {
    (0..points.len() as u32)
        .filter(|&i| {
            let point = &points[i as usize];
            is_valid(point) && point_within(point, p)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_are_32_bytes() {
        assert_eq!(std::mem::size_of::<GridParams>(), 32);
    }

    #[test]
    fn hash_wraps() {
        assert_eq!(hash_cell([0, 0, 0], u32::MAX), 0);
        assert_eq!(hash_cell([1, 1, 1], u32::MAX), 73_856_093 ^ 19_349_663 ^ 83_492_791);
        assert_eq!(hash_cell([u32::MAX, 0, 0], u32::MAX), 73_856_093u32.wrapping_neg());
    }
}
