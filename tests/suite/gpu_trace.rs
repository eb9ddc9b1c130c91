//! The WGSL BVH traversals (`trace_rays`, which runs the same `trace_closest` and `occluded` as
//! the camera and photon passes) find the same closest hits as the CPU oracles in `accel`:
//! baked, binary data and CWBVH.

use crate::common;

use crate::common::Rng;
use glam::Vec3;
use sppm_gpu::accel::build_cwbvh;
use sppm_gpu::accel::bvh::brute_force_intersect;
use sppm_gpu::gpu::baked_bvh::{baked_trace, PLACEHOLDER};
use sppm_gpu::gpu::scene_buffers::SceneData;
use sppm_gpu::scene::*;
use std::path::PathBuf;

fn random_scene(rand: &mut Rng, triangles: usize, spheres: usize) -> Scene {
    let mut scene = common::load_scene("cornell-box.toml");
    scene.path = PathBuf::from("random");
    scene.shapes.truncate(1);
    scene.shapes[0].emission = Some(Vec3::ONE);
    scene.triangles = (0..triangles)
        .map(|_| {
            let c = rand.vec3(-1.0, 1.0);
            Triangle { p: [c, c + rand.vec3(-0.2, 0.2), c + rand.vec3(-0.2, 0.2)], n: None, uv: None, shape: 0 }
        })
        .collect();
    scene.spheres =
        (0..spheres).map(|_| Sphere { center: rand.vec3(-1.0, 1.0), radius: 0.02 + 0.2 * rand.f32(), shape: 0 }).collect();
    scene
}

/// Rays from a box of half-size `extent` about a cloud of primitives in [-1, 1]^3, some axis-aligned (zero
/// direction components), some with a short t_max.
fn cloud_rays(rand: &mut Rng, n: usize, extent: f32) -> Vec<[f32; 4]> {
    let mut rays = Vec::with_capacity(2 * n);
    for i in 0..n {
        let o = rand.vec3(-extent, extent);
        let mut d = rand.vec3(-1.0, 1.0);
        if i % 7 == 0 {
            d = Vec3::new(0.0, 0.0, if i % 2 == 0 { 1.0 } else { -1.0 });
        }
        let t_max = if i % 5 == 0 { 0.5 } else { 1.0e30 };
        rays.push([o.x, o.y, o.z, t_max]);
        rays.push([d.x, d.y, d.z, 0.0]);
    }
    rays
}

/// The GPU's hits of `rays` against the CPU BVH and brute force.
fn check_against_oracle(gpu_hits: &[[f32; 4]], scene: &Scene, data: &SceneData, rays: &[[f32; 4]]) {
    let n = rays.len() / 2;
    let mut hit_count = 0;
    for i in 0..n {
        let o = Vec3::from_slice(&rays[2 * i][..3]);
        let d = Vec3::from_slice(&rays[2 * i + 1][..3]);
        let cpu = data.bvh.intersect(&scene.triangles, &scene.spheres, o, d, rays[2 * i][3]);
        let brute = brute_force_intersect(&scene.triangles, &scene.spheres, o, d, rays[2 * i][3]);
        assert_eq!(cpu.map(|h| h.prim_ref), brute.map(|h| h.prim_ref), "CPU BVH vs brute force, ray {i}");
        let g = gpu_hits[i];
        let prim_ref = g[1].to_bits();
        match cpu {
            None => assert_eq!(prim_ref, u32::MAX, "ray {i}: GPU hit {prim_ref:#x} at t {}, CPU none", g[0]),
            Some(h) => {
                hit_count += 1;
                assert_eq!(prim_ref, h.prim_ref, "ray {i}: GPU t {} CPU t {}", g[0], h.t);
                assert!((g[0] - h.t).abs() <= 1e-4 * h.t.max(1.0), "ray {i}: t {} vs {}", g[0], h.t);
                assert!((g[2] - h.b1).abs() < 1e-3 && (g[3] - h.b2).abs() < 1e-3, "ray {i}: barycentrics");
            }
        }
    }
    // The test means something only if many rays hit and many miss.
    assert!(hit_count > n / 8 && hit_count < n * 15 / 16, "{hit_count} of {n} rays hit");
}

#[test]
fn gpu_traversal_matches_cpu_oracle() {
    let Some(gpu) = common::gpu() else { return };
    let mut rand = Rng(12345);
    let scene = random_scene(&mut rand, 600, 24);
    let mut data = SceneData::new(&scene).unwrap();
    assert!(baked_trace(&data).is_none(), "too many primitives to bake: the data traversal");
    // The binary tree (this scene's own is the CWBVH: cwbvh_traversal_matches_cpu_oracle).
    assert!(data.cwbvh.take().is_some());
    let rays = cloud_rays(&mut rand, 4096, 1.5);
    // Every feature on: the general traversal (tests/suite/features.rs compares the specialized ones).
    let gpu_hits = common::trace_rays(&gpu, &data, &rays, &[]);
    check_against_oracle(&gpu_hits, &scene, &data, &rays);
    gpu.check().unwrap();
}

/// A small scene's BVH written as code finds the same hits as the oracle, and the same as the
/// data traversal bit for bit (both run the same intersection tests on the same numbers).
#[test]
fn baked_traversal_matches_cpu_oracle() {
    let Some(gpu) = common::gpu() else { return };
    let mut rand = Rng(777);
    let scene = random_scene(&mut rand, 240, 16);
    let data = SceneData::new(&scene).unwrap();
    let code = baked_trace(&data).expect("256 primitives, the most that are baked");
    // From inside the sparser cloud, so that enough rays hit.
    let rays = cloud_rays(&mut rand, 4096, 0.5);
    let baked = common::trace_rays_with(&gpu, &data, &rays, &[], &[(PLACEHOLDER, &code)]);
    check_against_oracle(&baked, &scene, &data, &rays);
    let loaded = common::trace_rays(&gpu, &data, &rays, &[]);
    let bits = |h: &[f32; 4]| h.map(f32::to_bits);
    let differ = baked.iter().zip(&loaded).filter(|(a, b)| bits(a) != bits(b)).count();
    assert_eq!(differ, 0, "baked and data traversal differ on {differ} rays");
    gpu.check().unwrap();
}

/// The scene's primitives and rays like the traversal bench's: origins uniform in the box,
/// directions uniform.
fn box_rays(rand: &mut Rng, data: &SceneData, n: usize) -> Vec<[f32; 4]> {
    let (lo, hi) = data.swept_bounds();
    let (lo, hi) = (lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo));
    (0..n)
        .flat_map(|i| {
            let o = lo + (hi - lo) * Vec3::new(rand.f32(), rand.f32(), rand.f32());
            let d = rand.unit_vec3();
            let t_max = if i % 5 == 0 { 0.3 } else { 3.4e38 };
            [[o.x, o.y, o.z, t_max], [d.x, d.y, d.z, 0.0]]
        })
        .collect()
}

/// The CWBVH traversal (`shaders/shared/cwbvh.wgsl`): closest hits as the CPU oracle's, and
/// the same as the binary data traversal's bit for bit; shadow rays (`occluded`) blocked
/// exactly where the oracle finds a hit. On a random cloud (triangles and spheres) and on the
/// Cornell box (flat, axis-aligned boxes).
#[test]
fn cwbvh_traversal_matches_cpu_oracle() {
    let Some(gpu) = common::gpu() else { return };
    let mut rand = Rng(2424);
    let cloud = random_scene(&mut rand, 3000, 24);
    let cornell = common::load_scene("cornell-box.toml");
    for (name, scene, extent) in [("cloud", cloud, 1.5), ("cornell-box", cornell, 0.0)] {
        let mut data = SceneData::new(&scene).unwrap();
        if extent == 0.0 {
            assert!(data.cwbvh.is_none(), "a small scene is baked");
            data.cwbvh = build_cwbvh(&scene.triangles, &scene.spheres, |_| Vec3::ZERO);
        }
        let cw = data.cwbvh.clone().expect("a large scene takes the CWBVH");
        let rays = if extent == 0.0 { box_rays(&mut rand, &data, 8192) } else { cloud_rays(&mut rand, 8192, extent) };
        // The runtime choice (bvh.tree_kind) and the compiled-in one.
        let closest = common::trace_rays(&gpu, &data, &rays, &[]);
        if name == "cloud" {
            check_against_oracle(&closest, &scene, &data, &rays);
        }
        let compiled = common::trace_rays(&gpu, &data, &rays, &[("BVH_LAYOUT", 2.0)]);
        let any = common::trace_rays(&gpu, &data, &rays, &[("ANY_HIT", 1.0), ("BVH_LAYOUT", 2.0)]);
        data.cwbvh = None;
        let binary = common::trace_rays(&gpu, &data, &rays, &[("BVH_LAYOUT", 1.0)]);
        let bits = |h: &[f32; 4]| h.map(f32::to_bits);
        let (mut hits, mut ties) = (0, 0);
        for i in 0..rays.len() / 2 {
            let o = Vec3::from_slice(&rays[2 * i][..3]);
            let d = Vec3::from_slice(&rays[2 * i + 1][..3]);
            let oracle = cw.intersect(&scene.triangles, &scene.spheres, o, d, rays[2 * i][3]);
            // The host's traversal of the same tree takes the same steps: the same primitive,
            // coplanar ones (a box standing on the floor) included; the device's arithmetic
            // may round t and the barycentrics differently.
            let got = bits(&closest[i]);
            assert_eq!(got[1], oracle.map_or(u32::MAX, |h| h.prim_ref), "{name}, ray {i}");
            if let Some(h) = oracle {
                let g = closest[i];
                assert!((g[0] - h.t).abs() <= 1e-5 * h.t.max(1.0), "{name}, ray {i}: t {} vs {}", g[0], h.t);
                assert!((g[2] - h.b1).abs() < 1e-4 && (g[3] - h.b2).abs() < 1e-4, "{name}, ray {i}: barycentrics");
                hits += 1;
            }
            assert_eq!(got, bits(&compiled[i]), "{name}, ray {i}: runtime and compiled-in layout");
            let blocked = any[i][1].to_bits() == 0;
            assert_eq!(blocked, oracle.is_some(), "{name}, ray {i}: occluded");
            // The binary traversal: the same t; another primitive only at the same t.
            let other = bits(&binary[i]);
            assert_eq!(other[0], got[0], "{name}, ray {i}: t of the binary traversal");
            ties += (other != got) as usize;
        }
        assert!(hits > rays.len() / 8, "{name}: {hits} hits");
        if name == "cloud" {
            assert_eq!(ties, 0, "{name}: CWBVH and binary traversal differ on {ties} rays");
        }
    }
    gpu.check().unwrap();
}

/// Every kernel that traces binds a scene traced through the CWBVH (its nodes and leaf
/// primitives share one binding: the photon pass has no storage buffer to spare) and
/// renders it: SPPM and both path tracers on the bunny box.
#[test]
fn every_method_renders_a_cwbvh_scene() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("gallery/bunny-cube.toml");
    assert!(SceneData::new(&scene).unwrap().cwbvh.is_some());
    (scene.render.width, scene.render.height, scene.render.photons) = (24, 24, 20_000);
    for method in [Method::Sppm, Method::Pt, Method::PtNee] {
        scene.render.method = method;
        let mut integrator = sppm_gpu::integrators::create(&gpu.device, &gpu.queue, &scene).unwrap_or_else(|e| panic!("{e}"));
        integrator.run_pass().unwrap();
        let mean = integrator.image().unwrap().mean();
        assert!(mean.iter().all(|c| c.is_finite() && *c > 0.0), "{method:?}: mean {mean:?}");
    }
    gpu.check().unwrap();
}
