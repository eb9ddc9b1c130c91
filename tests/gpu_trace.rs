//! The WGSL BVH traversal (`trace_rays`, which runs the same `trace_closest` as the camera and
//! photon passes) finds the same closest hits as the CPU oracle in `accel::bvh`.

mod common;

use common::Rng;
use glam::Vec3;
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
    let data = SceneData::new(&scene).unwrap();
    assert!(baked_trace(&data).is_none(), "too many primitives to bake: the data traversal");
    let rays = cloud_rays(&mut rand, 4096, 1.5);
    // Every feature on: the general traversal (tests/features.rs compares the specialized ones).
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
