//! The compressed 8-wide BVH (`accel::cwbvh`) against brute force on the CPU: its tree holds
//! every primitive once inside boxes that contain them, and its traversal (the kernels', step
//! for step) finds the closest hit that testing every primitive finds, and occlusion exactly
//! when there is a hit.

use crate::common::Rng;

use glam::Vec3;
use sppm_gpu::accel::bvh::{brute_force_intersect, Hit};
use sppm_gpu::accel::cwbvh::CW_STACK_SIZE;
use sppm_gpu::accel::{build_cwbvh, CwBvh, SPHERE_BIT};
use sppm_gpu::scene::{Sphere, Triangle};

fn triangle(p: [Vec3; 3]) -> Triangle {
    Triangle { p, n: None, uv: None, shape: 0 }
}

fn still(_: u32) -> Vec3 {
    Vec3::ZERO
}

fn random_scene(rng: &mut Rng, triangles: usize, spheres: usize) -> (Vec<Triangle>, Vec<Sphere>) {
    let tris = (0..triangles)
        .map(|_| {
            let c = rng.vec3(-10.0, 10.0);
            let size = rng.range(0.2, 2.0);
            triangle([0; 3].map(|_| c + size * rng.vec3(-1.0, 1.0)))
        })
        .collect();
    let spheres =
        (0..spheres).map(|i| Sphere { center: rng.vec3(-8.0, 8.0), radius: rng.range(0.3, 1.5), shape: i as u32 }).collect();
    (tris, spheres)
}

/// Every primitive referenced once, every child's decoded box holding every primitive of its
/// subtree, depth within the stack, every node reached once.
fn check_tree(cw: &CwBvh, tris: &[Triangle], spheres: &[Sphere]) {
    let mut referenced = vec![0u32; tris.len() + spheres.len()];
    let mut visited = vec![false; cw.nodes.len()];
    check_node(cw, tris, spheres, 0, 1, &mut referenced, &mut visited);
    assert!(visited.iter().all(|&v| v), "unreachable nodes");
    assert!(referenced.iter().all(|&n| n == 1), "primitives not referenced exactly once");
}

/// The exact box of node `i`'s primitives, checking its subtree.
fn check_node(
    cw: &CwBvh,
    tris: &[Triangle],
    spheres: &[Sphere],
    i: usize,
    depth: usize,
    referenced: &mut [u32],
    visited: &mut [bool],
) -> (Vec3, Vec3) {
    assert!(!visited[i], "node {i} reached twice");
    visited[i] = true;
    assert!(depth <= CW_STACK_SIZE && depth <= cw.depth);
    let inside = |inner: (Vec3, Vec3), outer: (Vec3, Vec3)| outer.0.cmple(inner.0).all() && inner.1.cmple(outer.1).all();
    let node = &cw.nodes[i];
    let imask = node.e_imask >> 24;
    let mut interior = 0;
    let mut total = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for slot in 0..8 {
        let m = (node.meta[slot / 4] >> (8 * (slot % 4))) & 0xff;
        if m == 0 {
            continue;
        }
        let exact = if imask & (1 << slot) != 0 {
            assert_eq!(m, 0b0010_0000 | (24 + slot as u32));
            interior += 1;
            check_node(cw, tris, spheres, node.child_base as usize + interior - 1, depth + 1, referenced, visited)
        } else {
            let first = (node.prim_base + (m & 0x1f)) as usize;
            let count = (m >> 5).count_ones() as usize;
            assert!((1..=3).contains(&count) && m >> 5 == (1 << count) - 1);
            let mut b = (Vec3::INFINITY, Vec3::NEG_INFINITY);
            for &r in &cw.prim_refs[first..first + count] {
                let (index, min, max) = if r & SPHERE_BIT != 0 {
                    let s = &spheres[(r & !SPHERE_BIT) as usize];
                    (tris.len() + (r & !SPHERE_BIT) as usize, s.center - s.radius, s.center + s.radius)
                } else {
                    let p = tris[r as usize].p;
                    (r as usize, p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
                };
                referenced[index] += 1;
                b = (b.0.min(min), b.1.max(max));
            }
            b
        };
        assert!(inside(exact, node.child_box(slot)), "slot {slot} of node {i}: decoded box misses its primitives");
        total = (total.0.min(exact.0), total.1.max(exact.1));
    }
    total
}

/// Closest hit and occlusion of each ray through `cw` against brute force; returns the hits.
fn compare(cw: &CwBvh, tris: &[Triangle], spheres: &[Sphere], rays: &[(Vec3, Vec3, f32)], what: &str) -> usize {
    let mut hits = 0;
    for (i, &(o, d, t_max)) in rays.iter().enumerate() {
        let oracle = brute_force_intersect(tris, spheres, o, d, t_max);
        let got = cw.intersect(tris, spheres, o, d, t_max);
        same_hit(got, oracle, &format!("{what}, ray {i} ({o}, {d}, {t_max})"));
        assert_eq!(cw.occluded(tris, spheres, o, d, t_max), oracle.is_some(), "{what}, ray {i}: occlusion");
        hits += oracle.is_some() as usize;
    }
    hits
}

fn same_hit(got: Option<Hit>, oracle: Option<Hit>, what: &str) {
    match (got, oracle) {
        (None, None) => {}
        // The same test on the same triangle: the same numbers.
        (Some(a), Some(b)) => assert_eq!(a, b, "{what}"),
        _ => panic!("{what}: CWBVH {got:?}, brute force {oracle:?}"),
    }
}

fn random_rays(rng: &mut Rng, n: usize, extent: f32) -> Vec<(Vec3, Vec3, f32)> {
    (0..n)
        .map(|i| {
            let o = rng.vec3(-extent, extent);
            let d = rng.unit_vec3() * if i % 3 == 0 { rng.range(0.1, 10.0) } else { 1.0 };
            let t_max = if i % 5 == 0 { rng.range(0.5, 20.0) } else { f32::INFINITY };
            (o, d, t_max)
        })
        .collect()
}

#[test]
fn cwbvh_matches_brute_force_on_random_scene() {
    let mut rng = Rng(24);
    let (tris, spheres) = random_scene(&mut rng, 2000, 40);
    let cw = build_cwbvh(&tris, &spheres, still).unwrap();
    check_tree(&cw, &tris, &spheres);
    assert!(cw.nodes.len() > 50 && cw.depth >= 3, "{} nodes, depth {}", cw.nodes.len(), cw.depth);
    let rays = random_rays(&mut rng, 4000, 12.0);
    let hits = compare(&cw, &tris, &spheres, &rays, "random rays");
    assert!(hits > 1000 && hits < 3900, "{hits} hits");
}

/// Rays parallel to the axes, with origins in the planes of boxes (0 * inf in the slab
/// test) and -0.0 components.
#[test]
fn cwbvh_matches_brute_force_on_axis_aligned_rays() {
    let mut rng = Rng(3);
    let (tris, spheres) = random_scene(&mut rng, 500, 20);
    let cw = build_cwbvh(&tris, &spheres, still).unwrap();
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    let mut rays = Vec::new();
    for i in 0..3000 {
        let d = axes[i % 6];
        let mut o = rng.vec3(-12.0, 12.0);
        if i % 2 == 0 {
            let axis = i % 3;
            for a in (0..3).filter(|&a| d[a] == 0.0) {
                o[a] = tris[rng.below(tris.len())].p[rng.below(3)][a];
            }
            o[axis] = if d[axis] > 0.0 { -12.0 } else { 12.0 };
        }
        let d = if i % 4 < 2 { d } else { Vec3::select(d.cmpeq(Vec3::ZERO), Vec3::splat(-0.0), d) };
        rays.push((o, d, f32::INFINITY));
    }
    assert!(compare(&cw, &tris, &spheres, &rays, "axis-aligned rays") > 100);
}

/// A Cornell box (axis-aligned walls: flat boxes) with a cloud of small triangles, traced
/// from inside: walls seen edge on and boxes with no extent on an axis.
#[test]
fn cwbvh_matches_brute_force_in_a_box() {
    let mut rng = Rng(5);
    let mut tris = Vec::new();
    for axis in 0..3 {
        let (u, v) = (Vec3::AXES[(axis + 1) % 3] * 2.0, Vec3::AXES[(axis + 2) % 3] * 2.0);
        for side in [-1.0, 1.0] {
            let p0 = Vec3::AXES[axis] * side - (u + v) * 0.5;
            tris.push(triangle([p0, p0 + u, p0 + u + v]));
            tris.push(triangle([p0, p0 + u + v, p0 + v]));
        }
    }
    for _ in 0..600 {
        let c = rng.vec3(-0.8, 0.8);
        tris.push(triangle([c, c + rng.vec3(-0.05, 0.05), c + rng.vec3(-0.05, 0.05)]));
    }
    let cw = build_cwbvh(&tris, &[], still).unwrap();
    check_tree(&cw, &tris, &[]);
    let rays: Vec<_> = (0..4000).map(|_| (rng.vec3(-0.98, 0.98), rng.unit_vec3(), f32::INFINITY)).collect();
    let hits = compare(&cw, &tris, &[], &rays, "rays in a box");
    assert_eq!(hits, rays.len(), "every ray from inside the box hits something");
}

#[test]
fn cwbvh_of_too_few_primitives_is_none() {
    let one = [triangle([Vec3::ZERO, Vec3::X, Vec3::Y])];
    assert!(build_cwbvh(&one, &[], still).is_none());
    assert!(build_cwbvh(&[], &[], still).is_none());
    let two = [one[0].clone(), triangle([Vec3::Z, Vec3::Z + Vec3::X, Vec3::Z + Vec3::Y])];
    let cw = build_cwbvh(&two, &[], still).unwrap();
    check_tree(&cw, &two, &[]);
    let hit = cw.intersect(&two, &[], Vec3::new(0.2, 0.2, 2.0), -Vec3::Z, f32::INFINITY).unwrap();
    assert_eq!((hit.prim_ref, hit.t), (1, 1.0));
}
