//! Acceleration structures against brute force: BVH traversal against testing every
//! primitive, hashed-grid lookups against testing every visible point.

use crate::common::Rng;
use std::time::Instant;

use glam::Vec3;
use sppm_gpu::accel::bvh::{brute_force_intersect, intersect_triangle, Hit, LEAF_BIT, LEAF_COUNT_SHIFT, STACK_SIZE};
use sppm_gpu::accel::grid::{brute_force_within, point_within};
use sppm_gpu::accel::{build_bvh, build_grid, hash_cell, Bvh, HashGrid, SPHERE_BIT};
use sppm_gpu::scene::{Sphere, Triangle};

fn triangle(p: [Vec3; 3]) -> Triangle {
    Triangle { p, n: None, uv: None, shape: 0 }
}

fn random_triangles(rng: &mut Rng, n: usize) -> Vec<Triangle> {
    (0..n)
        .map(|_| {
            let c = rng.vec3(-10.0, 10.0);
            let size = rng.range(0.2, 2.0);
            triangle([0; 3].map(|_| c + size * rng.vec3(-1.0, 1.0)))
        })
        .collect()
}

fn random_spheres(rng: &mut Rng, n: usize) -> Vec<Sphere> {
    (0..n).map(|i| Sphere { center: rng.vec3(-8.0, 8.0), radius: rng.range(0.3, 1.5), shape: i as u32 }).collect()
}

/// 500 random triangles and 20 spheres, and their BVH.
fn random_scene(rng: &mut Rng) -> (Vec<Triangle>, Vec<Sphere>, Bvh) {
    let tris = random_triangles(rng, 500);
    let spheres = random_spheres(rng, 20);
    let bvh = build_bvh(&tris, &spheres);
    (tris, spheres, bvh)
}

fn assert_same_hit(bvh: Option<Hit>, oracle: Option<Hit>, what: &str) {
    match (bvh, oracle) {
        (None, None) => {}
        (Some(a), Some(b)) => {
            assert_eq!(a.prim_ref, b.prim_ref, "{what}: {a:?} vs {b:?}");
            assert!((a.t - b.t).abs() <= 1e-5 * b.t.abs(), "{what}: {a:?} vs {b:?}");
            assert_eq!((a.b1, a.b2), (b.b1, b.b2), "{what}");
        }
        _ => panic!("{what}: BVH {bvh:?}, brute force {oracle:?}"),
    }
}

/// Traces `rays` (origin, direction, t_max) through the BVH and by brute force, and returns
/// how many hit something.
fn compare_rays(bvh: &Bvh, tris: &[Triangle], spheres: &[Sphere], rays: &[(Vec3, Vec3, f32)], what: &str) -> usize {
    let mut hits = 0;
    for (i, &(o, d, t_max)) in rays.iter().enumerate() {
        let oracle = brute_force_intersect(tris, spheres, o, d, t_max);
        let got = bvh.intersect(tris, spheres, o, d, t_max);
        assert_same_hit(got, oracle, &format!("{what}, ray {i} ({o}, {d}, {t_max})"));
        hits += oracle.is_some() as usize;
    }
    hits
}

/// Random rays from inside and around the scene's bounds, some with a finite `t_max`, some
/// with an unnormalized direction.
fn random_rays(rng: &mut Rng, n: usize) -> Vec<(Vec3, Vec3, f32)> {
    (0..n)
        .map(|i| {
            let o = rng.vec3(-12.0, 12.0);
            let d = rng.unit_vec3() * if i % 3 == 0 { rng.range(0.1, 10.0) } else { 1.0 };
            let t_max = if i % 5 == 0 { rng.range(0.5, 20.0) } else { f32::INFINITY };
            (o, d, t_max)
        })
        .collect()
}

/// Checks the layout of a tree over a non-empty scene: every node reachable from the root
/// exactly once, leaves of 1 to 4 primitives, children inside their parent, primitives
/// inside their leaf, each primitive referenced exactly once, 2 * leaves - 1 nodes, depth
/// within the traversal stack.
fn check_tree(bvh: &Bvh, tris: &[Triangle], spheres: &[Sphere]) {
    let inside = |inner_min: [f32; 3], inner_max: [f32; 3], outer: &sppm_gpu::accel::BvhNode| {
        (0..3).all(|a| outer.min[a] <= inner_min[a] && inner_max[a] <= outer.max[a])
    };
    let mut visited = vec![false; bvh.nodes.len()];
    let mut referenced = vec![0u32; tris.len() + spheres.len()];
    let mut leaves = 0;
    let mut todo = vec![(0usize, 0usize)];
    while let Some((i, depth)) = todo.pop() {
        assert!(!visited[i], "node {i} reached twice");
        visited[i] = true;
        assert!(depth < STACK_SIZE);
        let node = &bvh.nodes[i];
        if node.count > 0 {
            leaves += 1;
            assert!(node.count <= 4, "leaf {i} holds {} primitives", node.count);
            for &r in &bvh.prim_refs[node.first as usize..(node.first + node.count) as usize] {
                let (slot, min, max) = if r & SPHERE_BIT != 0 {
                    let s = &spheres[(r & !SPHERE_BIT) as usize];
                    (tris.len() + (r & !SPHERE_BIT) as usize, s.center - s.radius, s.center + s.radius)
                } else {
                    let p = tris[r as usize].p;
                    (r as usize, p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
                };
                referenced[slot] += 1;
                assert!(inside(min.to_array(), max.to_array(), node), "primitive {r:#x} outside leaf {i}");
            }
        } else {
            for c in [node.first as usize, node.first as usize + 1] {
                let child = &bvh.nodes[c];
                assert!(inside(child.min, child.max, node), "child {c} outside parent {i}");
                todo.push((c, depth + 1));
            }
        }
    }
    assert!(visited.iter().all(|&v| v), "unreachable nodes");
    assert!(referenced.iter().all(|&n| n == 1), "primitives not referenced exactly once");
    assert_eq!(bvh.prim_refs.len(), tris.len() + spheres.len());
    assert_eq!(bvh.nodes.len(), 2 * leaves - 1);
    check_packed(bvh);
}

/// Checks the kernels' layout of a tree against the tree: the packed nodes walk the same
/// tree, each child reference names the same leaf range or the packed copy of the same
/// interior node, and each decoded child box contains the child's exact box.
fn check_packed(bvh: &Bvh) {
    let packed = bvh.pack();
    let contains = |q: [u32; 3], node: &sppm_gpu::accel::BvhNode| {
        let (lo, hi) = packed.decode(q);
        (0..3).all(|a| lo[a] <= node.min[a] && node.max[a] <= hi[a])
    };
    let leaf_ref = |node: &sppm_gpu::accel::BvhNode| LEAF_BIT | node.count << LEAF_COUNT_SHIFT | node.first;
    let root = &bvh.nodes[0];
    let is_empty = |q: [u32; 3]| {
        let (lo, hi) = packed.decode(q);
        (0..3).all(|a| lo[a] > hi[a])
    };
    if root.count == 0 && root.min[0] > root.max[0] {
        // Empty scene: a root with two empty children.
        let n = packed.nodes[0];
        assert_eq!(packed.nodes.len(), 1);
        assert!(is_empty(n.box_a) && is_empty(n.box_b), "children of an empty scene's root");
        assert_eq!((n.child_a, n.child_b), (LEAF_BIT, LEAF_BIT));
        return;
    }
    if root.count > 0 {
        let n = packed.nodes[0];
        assert_eq!(packed.nodes.len(), 1);
        assert_eq!(n.child_a, leaf_ref(root));
        assert!(contains(n.box_a, root), "root leaf box");
        assert!(is_empty(n.box_b), "second child of a leaf root is empty");
        return;
    }
    let mut seen = vec![false; packed.nodes.len()];
    // (host interior node, packed node)
    let mut todo = vec![(0usize, 0usize)];
    while let Some((host, dst)) = todo.pop() {
        assert!(!seen[dst], "packed node {dst} reached twice");
        seen[dst] = true;
        let n = packed.nodes[dst];
        let first = bvh.nodes[host].first as usize;
        for (c, q, r) in [(first, n.box_a, n.child_a), (first + 1, n.box_b, n.child_b)] {
            let child = &bvh.nodes[c];
            assert!(contains(q, child), "decoded box of node {c} does not contain it");
            if child.count > 0 {
                assert_eq!(r, leaf_ref(child), "reference to leaf {c}");
            } else {
                assert_eq!(r & LEAF_BIT, 0);
                todo.push((c, r as usize));
            }
        }
    }
    assert!(seen.iter().all(|&s| s), "unreachable packed nodes");
}

#[test]
fn packed_boxes_contain_exact_boxes_far_from_origin() {
    // Coordinates large against the scene: the quantization grid and the f32 decode still
    // give boxes around the exact ones.
    let mut rng = Rng(7);
    let (mut tris, mut spheres, _) = random_scene(&mut rng);
    let offset = Vec3::new(1.0e4, -3.0e4, 512.0);
    for t in &mut tris {
        t.p = t.p.map(|p| p + offset);
    }
    for s in &mut spheres {
        s.center += offset;
    }
    let bvh = build_bvh(&tris, &spheres);
    check_tree(&bvh, &tris, &spheres);
}

#[test]
fn bvh_matches_brute_force_on_random_scene() {
    let mut rng = Rng(1);
    let (tris, spheres, bvh) = random_scene(&mut rng);
    check_tree(&bvh, &tris, &spheres);
    let rays = random_rays(&mut rng, 2000);
    let hits = compare_rays(&bvh, &tris, &spheres, &rays, "random rays");
    assert!(hits > 200 && hits < 1800, "{hits} hits: the test should exercise hits and misses");
}

#[test]
fn bvh_matches_brute_force_from_inside_spheres() {
    let mut rng = Rng(2);
    let (tris, spheres, bvh) = random_scene(&mut rng);
    let rays: Vec<_> = (0..1000)
        .map(|i| {
            let s = &spheres[i % spheres.len()];
            let o = s.center + s.radius * 0.99 * rng.f32() * rng.unit_vec3();
            (o, rng.unit_vec3(), f32::INFINITY)
        })
        .collect();
    compare_rays(&bvh, &tris, &spheres, &rays, "rays from inside spheres");
    // With nothing else in the way, a ray from the centre leaves through the far root.
    let lone = [Sphere { center: Vec3::splat(1.0), radius: 2.0, shape: 0 }];
    let hit = build_bvh(&[], &lone).intersect(&[], &lone, Vec3::splat(1.0), Vec3::X, f32::INFINITY);
    assert_eq!(hit.map(|h| (h.t, h.prim_ref)), Some((2.0, SPHERE_BIT)));
}

#[test]
fn bvh_matches_brute_force_on_axis_aligned_rays() {
    let mut rng = Rng(3);
    let (tris, spheres, bvh) = random_scene(&mut rng);
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    let mut rays = Vec::new();
    for i in 0..3000 {
        let d = axes[i % 6];
        let mut o = rng.vec3(-12.0, 12.0);
        if i % 2 == 0 {
            // Put the origin exactly on box planes parallel to the ray (0 * inf in the slab
            // test): coordinates of vertices, which bound leaf and interior boxes.
            let axis = i % 3;
            for a in (0..3).filter(|&a| d[a] == 0.0) {
                let v = tris[rng.below(tris.len())].p[rng.below(3)];
                o[a] = v[a];
            }
            o[axis] = if d[axis] > 0.0 { -12.0 } else { 12.0 };
        }
        // -0.0 components as well as +0.0.
        let d = if i % 4 < 2 { d } else { Vec3::select(d.cmpeq(Vec3::ZERO), Vec3::splat(-0.0), d) };
        rays.push((o, d, f32::INFINITY));
    }
    let hits = compare_rays(&bvh, &tris, &spheres, &rays, "axis-aligned rays");
    assert!(hits > 100, "{hits} hits");
}

/// The faces of the unit cube as 12 triangles, like the walls of a Cornell box.
fn unit_cube() -> Vec<Triangle> {
    let mut tris = Vec::new();
    for axis in 0..3 {
        let (u, v) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
        for side in [0.0, 1.0] {
            let p0 = Vec3::AXES[axis] * side;
            tris.push(triangle([p0, p0 + u, p0 + u + v]));
            tris.push(triangle([p0, p0 + u + v, p0 + v]));
        }
    }
    tris
}

/// Axis-aligned rays whose origins lie in the planes of the box faces (rays that graze a
/// face along its edge or lie in a slab plane, where the slab test computes 0 * inf): the
/// slab test must not cull the faces they hit on their edges.
#[test]
fn bvh_matches_brute_force_on_rays_along_box_faces() {
    let tris = unit_cube();
    let bvh = build_bvh(&tris, &[]);
    check_tree(&bvh, &tris, &[]);
    let coords = [0.0, 0.3, 1.0];
    let mut hits = 0;
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            for zero in [0.0f32, -0.0] {
                for a in coords {
                    for b in coords {
                        let mut d = Vec3::splat(zero);
                        d[axis] = sign;
                        let mut o = Vec3::ZERO;
                        o[axis] = -2.0 * sign;
                        o[(axis + 1) % 3] = a;
                        o[(axis + 2) % 3] = b;
                        let oracle = brute_force_intersect(&tris, &[], o, d, f32::INFINITY);
                        let got = bvh.intersect(&tris, &[], o, d, f32::INFINITY);
                        // Points on a shared edge hit both triangles at the same t: compare t,
                        // and check that the reported triangle is hit there.
                        assert_eq!(got.map(|h| h.t), oracle.map(|h| h.t), "ray {o} {d}");
                        if let Some(h) = got {
                            let [p0, p1, p2] = tris[h.prim_ref as usize].p;
                            let t = intersect_triangle(p0, p1 - p0, p2 - p0, o, d, f32::INFINITY);
                            assert_eq!(t.map(|t| t.0), Some(h.t));
                            hits += 1;
                        }
                    }
                }
            }
        }
    }
    // Every ray hits the near face, on its edge or inside it.
    assert_eq!(hits, 3 * 2 * 2 * 9);
}

#[test]
fn bvh_ray_missing_everything() {
    let mut rng = Rng(4);
    let (tris, spheres, bvh) = random_scene(&mut rng);
    for (o, d) in [
        (Vec3::new(0.0, 100.0, 0.0), Vec3::Y),
        (Vec3::new(-50.0, 30.0, 0.0), Vec3::new(1.0, 0.0, 0.0)),
        (Vec3::new(0.0, 0.0, 0.0), Vec3::ZERO),
    ] {
        assert_eq!(brute_force_intersect(&tris, &spheres, o, d, f32::INFINITY), None);
        assert_eq!(bvh.intersect(&tris, &spheres, o, d, f32::INFINITY), None);
    }
    // A NaN ray hits nothing either.
    assert_eq!(bvh.intersect(&tris, &spheres, Vec3::NAN, Vec3::X, f32::INFINITY), None);
}

#[test]
fn bvh_of_one_triangle() {
    let tris = [triangle([Vec3::ZERO, Vec3::X, Vec3::Y])];
    let bvh = build_bvh(&tris, &[]);
    assert_eq!(bvh.nodes.len(), 1);
    assert_eq!((bvh.nodes[0].first, bvh.nodes[0].count), (0, 1));
    assert_eq!(bvh.prim_refs, [0]);
    check_tree(&bvh, &tris, &[]);
    let hit = bvh.intersect(&tris, &[], Vec3::new(0.25, 0.25, 1.0), -Vec3::Z, f32::INFINITY).unwrap();
    assert_eq!((hit.t, hit.prim_ref, hit.b1, hit.b2), (1.0, 0, 0.25, 0.25));
    // The triangle's box is flat in z: rays along z pass the slab test with t_near = t_far.
    let mut rng = Rng(5);
    let rays: Vec<_> = (0..500)
        .map(|i| {
            let o = rng.vec3(-0.5, 1.5) * Vec3::new(1.0, 1.0, 0.0) + Vec3::Z * rng.range(-2.0, 2.0);
            let d = if i % 2 == 0 { Vec3::Z * o.z.signum() * -1.0 } else { rng.unit_vec3() };
            (o, d, f32::INFINITY)
        })
        .collect();
    let hits = compare_rays(&bvh, &tris, &[], &rays, "one triangle");
    assert!(hits > 20, "{hits} hits");
}

#[test]
fn bvh_of_spheres_only() {
    let mut rng = Rng(6);
    let spheres = random_spheres(&mut rng, 20);
    let bvh = build_bvh(&[], &spheres);
    check_tree(&bvh, &[], &spheres);
    assert!(bvh.prim_refs.iter().all(|r| r & SPHERE_BIT != 0));
    let rays = random_rays(&mut rng, 2000);
    let hits = compare_rays(&bvh, &[], &spheres, &rays, "spheres only");
    assert!(hits > 50, "{hits} hits");
}

#[test]
fn bvh_of_empty_scene() {
    let bvh = build_bvh(&[], &[]);
    assert_eq!(bvh.nodes.len(), 1);
    let root = bvh.nodes[0];
    assert_eq!((root.first, root.count), (0, 0));
    assert!((0..3).all(|a| root.min[a] > root.max[a]), "root box must be inverted");
    assert!(bvh.prim_refs.is_empty());
    check_packed(&bvh);
    let mut rng = Rng(7);
    let mut rays = random_rays(&mut rng, 200);
    rays.extend([(Vec3::ZERO, Vec3::X, f32::INFINITY), (Vec3::ZERO, Vec3::new(0.0, -0.0, 1.0), 1.0)]);
    assert_eq!(compare_rays(&bvh, &[], &[], &rays, "empty scene"), 0);
}

/// `count` points in a cube of side 10 with radii from 0.02 to 0.6; about one in ten is
/// invalid (zero, negative or non-finite radius, or a NaN position).
fn random_points(rng: &mut Rng, count: usize) -> Vec<[f32; 4]> {
    (0..count)
        .map(|_| {
            let p = rng.vec3(-5.0, 5.0);
            let r = match rng.below(40) {
                0 => 0.0,
                1 => -0.1,
                2 => f32::INFINITY,
                3 => return [f32::NAN, p.y, p.z, 0.3],
                _ => rng.range(0.02, 0.6),
            };
            [p.x, p.y, p.z, r]
        })
        .collect()
}

/// The points the photon kernel would keep at `p`.
fn gathered(grid: &HashGrid, points: &[[f32; 4]], p: Vec3) -> Vec<u32> {
    let c = grid.candidates(p);
    assert!(c.windows(2).all(|w| w[0] < w[1]), "bucket not sorted or with duplicates");
    c.iter().copied().filter(|&i| point_within(&points[i as usize], p)).collect()
}

/// Checks the table layout: offsets from 0 to `entries.len()`, non-decreasing, buckets in
/// increasing point index, only valid points.
fn check_grid(grid: &HashGrid, points: &[[f32; 4]]) {
    let table_size = grid.params.table_mask as usize + 1;
    assert!(table_size.is_power_of_two());
    assert_eq!(grid.cell_start.len(), table_size + 1);
    assert_eq!(grid.cell_start[0], 0);
    assert_eq!(*grid.cell_start.last().unwrap() as usize, grid.entries.len());
    for h in 0..table_size {
        let (a, b) = (grid.cell_start[h] as usize, grid.cell_start[h + 1] as usize);
        assert!(a <= b);
        let bucket = &grid.entries[a..b];
        assert!(bucket.windows(2).all(|w| w[0] < w[1]), "bucket {h} not strictly increasing");
        assert!(bucket.iter().all(|&i| points[i as usize][3] > 0.0 && points[i as usize][3].is_finite()));
    }
}

#[test]
fn grid_matches_brute_force() {
    let mut rng = Rng(10);
    let points = random_points(&mut rng, 3000);
    let grid = build_grid(&points);
    check_grid(&grid, &points);

    let valid: Vec<_> = points.iter().filter(|p| p[3] > 0.0 && p[3].is_finite() && p[0].is_finite()).collect();
    let max_r = valid.iter().map(|p| p[3]).fold(0.0f32, f32::max);
    assert_eq!(grid.params.cell_size, sppm_gpu::accel::grid::CELL_RADII * max_r);
    assert_eq!(grid.params.table_mask as usize + 1, valid.len().next_power_of_two());
    // The grid starts one largest radius below the lowest centre.
    for a in 0..3 {
        let lo = valid.iter().map(|p| p[a]).fold(f32::INFINITY, f32::min);
        assert_eq!(grid.params.origin[a], lo - max_r);
    }

    let mut total = 0;
    for i in 0..5000 {
        let p = if i % 4 == 0 {
            // Near the boundary of some point's sphere, inside or just outside.
            let q = points[rng.below(points.len())];
            Vec3::new(q[0], q[1], q[2]) + q[3].min(1.0) * rng.range(0.98, 1.02) * rng.unit_vec3()
        } else {
            rng.vec3(-7.0, 7.0)
        };
        let expected = brute_force_within(&points, p);
        assert_eq!(gathered(&grid, &points, p), expected, "query {i} at {p}");
        total += expected.len();
    }
    assert!(total > 2000, "{total} points found: the test should find points");
    for p in [Vec3::splat(-100.0), Vec3::splat(100.0), Vec3::NAN, Vec3::INFINITY] {
        assert!(grid.candidates(p).is_empty() && grid.cell_of(p).is_none(), "{p}");
    }
}

#[test]
fn grid_of_no_valid_points() {
    for points in [vec![], vec![[1.0, 2.0, 3.0, 0.0], [0.0, 0.0, 0.0, -1.0], [0.0; 4]]] {
        let grid = build_grid(&points);
        check_grid(&grid, &points);
        assert_eq!(grid.params.res, [0; 3]);
        assert_eq!(grid.params.table_mask, 0);
        assert_eq!(grid.cell_start, [0, 0]);
        assert!(grid.entries.is_empty());
        for p in [Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)] {
            assert!(grid.candidates(p).is_empty() && grid.cell_of(p).is_none());
        }
    }
}

#[test]
fn grid_of_one_point() {
    let points = [[0.0, 0.0, 0.0, 0.0], [1.0, 2.0, 3.0, 0.5]];
    let grid = build_grid(&points);
    check_grid(&grid, &points);
    assert_eq!(grid.params.table_mask, 0);
    assert_eq!(grid.params.origin, [0.5, 1.5, 2.5]);
    // Cells a little over two radii wide: the point's box fits in one.
    assert_eq!(grid.params.res, [1, 1, 1]);
    assert_eq!(grid.entries, [1]);
    assert_eq!(gathered(&grid, &points, Vec3::new(1.0, 2.0, 3.0)), [1]);
    assert_eq!(gathered(&grid, &points, Vec3::new(1.4, 2.0, 3.0)), [1]);
    assert!(gathered(&grid, &points, Vec3::new(1.4, 2.4, 3.0)).is_empty());
    assert!(grid.candidates(Vec3::new(2.6, 2.0, 3.0)).is_empty());
}

#[test]
fn grid_hash_is_teschner() {
    let c = [3u32, 5, 7];
    let expected = (3u32 * 73_856_093) ^ (5u32 * 19_349_663) ^ 7u32.wrapping_mul(83_492_791);
    assert_eq!(hash_cell(c, 0xffff), expected & 0xffff);
}

/// Build time for 2^18 points, timing printed, not asserted. Representative numbers need an
/// optimized build: `cargo test --release --test accel grid_build_time -- --nocapture`.
#[test]
fn grid_build_time() {
    let mut rng = Rng(11);
    let side = 512;
    // Visible points as an SPPM camera pass leaves them, in pixel order: a 512 x 512 image
    // of a unit scene (a floor, a back wall and a box: depth steps), radii around a pixel
    // footprint.
    let mut points: Vec<[f32; 4]> = (0..side * side)
        .map(|i| {
            let (u, v) = ((i % side) as f32 / side as f32, (i / side) as f32 / side as f32);
            let depth = if v < 0.3 {
                v
            } else if (0.3..0.6).contains(&u) && v < 0.6 {
                0.5
            } else {
                1.0
            };
            [u, v, depth, rng.range(1.0, 2.0) / side as f32]
        })
        .collect();
    let time = |points: &[[f32; 4]]| {
        let mut best = f64::INFINITY;
        let mut grid = build_grid(points);
        for _ in 0..5 {
            let start = Instant::now();
            grid = build_grid(points);
            best = best.min(start.elapsed().as_secs_f64());
        }
        check_grid(&grid, points);
        println!(
            "  {:.2} ms (best of 5), res {:?}, table {}, {} entries ({:.2} per point)",
            best * 1e3,
            grid.params.res,
            grid.params.table_mask as usize + 1,
            grid.entries.len(),
            grid.entries.len() as f64 / points.len() as f64
        );
    };
    println!("grid build, {} points in pixel order:", points.len());
    time(&points);
    // Shuffled (Fisher-Yates): no locality in the bucket updates, the worst case.
    for i in (1..points.len()).rev() {
        points.swap(i, rng.below(i + 1));
    }
    println!("grid build, {} points shuffled:", points.len());
    time(&points);
}

/// Primitives with identical boxes (a zero-extent scene box for PLOC's Morton codes), and
/// degenerate triangles.
#[test]
fn bvh_of_coincident_primitives() {
    let spheres = vec![Sphere { center: Vec3::ONE, radius: 0.5, shape: 0 }; 10];
    let p = Vec3::new(1.0, 2.0, 3.0);
    let tris = vec![triangle([p, p, p]); 10];
    let bvh = build_bvh(&tris, &spheres);
    check_tree(&bvh, &tris, &spheres);
    let mut rng = Rng(8);
    let rays: Vec<_> = (0..500).map(|_| (rng.vec3(-3.0, 3.0), rng.unit_vec3(), f32::INFINITY)).collect();
    // All ten spheres are hit at the same t: compare t only.
    for &(o, d, t_max) in &rays {
        let oracle = brute_force_intersect(&tris, &spheres, o, d, t_max);
        let got = bvh.intersect(&tris, &spheres, o, d, t_max);
        assert_eq!(got.map(|h| h.t), oracle.map(|h| h.t), "ray {o} {d}");
    }
}
