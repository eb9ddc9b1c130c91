//! The bidirectional family's MIS (`shaders/shared/vcm.wgsl`): for random paths through diffuse
//! vertices, the weights of every strategy that can make a path, computed from the recursive
//! quantities (dVCM, dVC, dVM) as the kernels compute them, sum to 1 (`tests/shaders/mis_test.wgsl`),
//! with connections alone (bidirectional path tracing) and with merging too (VCM), merging at
//! every interior vertex or only at some (vcm merges only at diffuse materials), under the
//! balance heuristic and the power heuristic, with every camera vertex connecting and merging
//! or only a share of them (the strategies' counts in the heuristic).

use crate::common::{self, Rng};
use glam::Vec3;
use sppm_gpu::gpu::readback::{read_buffer, staging_buffer};
use sppm_gpu::gpu::scene_buffers::storage_buffer;
use sppm_gpu::gpu::Resource;
use wgpu::util::DeviceExt;

/// `MisTestParams` in tests/shaders/mis_test.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    paths: u32,
    n_light: f32,
    pick: f32,
    area: f32,
    eta_vcm: f32,
    a_pix: f32,
    _pad: [u32; 2],
}

const MAX_VERTICES: usize = 8;
const PATH_WORDS: usize = 17;

fn unit(rng: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(rng.f32() * 2.0 - 1.0, rng.f32() * 2.0 - 1.0, rng.f32() * 2.0 - 1.0);
        if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// A path of `k` segments from a light vertex to the camera through diffuse vertices, as
/// `PATH_WORDS` vec4s (see the kernel), every cosine above 0.1 and every segment longer than
/// 0.1, the interior vertices flagged as merging where `merges` says, with the shares of camera
/// vertices that connect and merge; `None` where the draw is degenerate.
fn random_path(rng: &mut Rng, k: usize, merges: &[bool], (connect, merge): (f32, f32)) -> Option<Vec<[f32; 4]>> {
    let x: Vec<Vec3> = (0..=k).map(|_| Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 2.0 - 1.0).collect();
    let to = |i: usize, j: usize| (x[j] - x[i]).normalize();
    let mut n = vec![Vec3::ZERO; k];
    n[0] = (to(0, 1) + 0.7 * unit(rng)).normalize();
    for (i, ni) in n.iter_mut().enumerate().skip(1) {
        *ni = (to(i, i - 1) + to(i, i + 1) + 0.5 * unit(rng)).normalize();
    }
    let axis = (to(k, k - 1) + 0.3 * unit(rng)).normalize();
    let short = (0..k).any(|i| (x[i + 1] - x[i]).length() < 0.1);
    let grazing = n[0].dot(to(0, 1)) < 0.1
        || (1..k).any(|i| n[i].dot(to(i, i - 1)) < 0.1 || n[i].dot(to(i, i + 1)) < 0.1)
        || axis.dot(to(k, k - 1)) < 0.3;
    if short || grazing {
        return None;
    }
    let mut words = vec![[0.0f32; 4]; PATH_WORDS];
    for (i, p) in x.iter().enumerate() {
        words[i] = [p.x, p.y, p.z, 0.0];
    }
    words[0][3] = k as f32;
    words[1][3] = merge;
    for (i, v) in n.iter().enumerate() {
        words[MAX_VERTICES + i] = [v.x, v.y, v.z, if merges[i] { 1.0 } else { 0.0 }];
    }
    words[2 * MAX_VERTICES] = [axis.x, axis.y, axis.z, connect];
    Some(words)
}

#[test]
fn mis_weights_of_every_strategy_sum_to_one() {
    let Some(gpu) = common::gpu() else { return };
    let mut rng = Rng(7);
    let mut paths: Vec<[f32; 4]> = Vec::new();
    let mut lengths = Vec::new();
    let mut merging = Vec::new();
    while lengths.len() < 4096 {
        let k = 2 + lengths.len() % 6;
        // Every interior vertex merges on a third of the paths, each with probability 1/2 on
        // the rest.
        let all = lengths.len() % 3 == 0;
        let merges: Vec<bool> = (0..k).map(|i| i > 0 && (all || rng.f32() < 0.5)).collect();
        // Every camera vertex connects and merges on a quarter of the paths; on the rest, a
        // share of them, as low as 1%.
        let shares = if lengths.len() % 4 == 0 { (1.0, 1.0) } else { (0.01 + 0.99 * rng.f32(), 0.01 + 0.99 * rng.f32()) };
        if let Some(words) = random_path(&mut rng, k, &merges, shares) {
            paths.extend(words);
            lengths.push(k);
            // The merges: at the two interior vertices nearest the camera that merge, but not
            // at x1, whose light vertex comes straight from the light (vcm_merges_light).
            merging.push((1..k).rev().filter(|&i| merges[i]).take(2).filter(|&i| i > 1).count());
        }
    }
    let count = lengths.len();
    let params = Params {
        paths: count as u32,
        n_light: 65536.0,
        pick: 0.3,
        area: 0.2,
        eta_vcm: std::f32::consts::PI * 0.01 * 0.01 * 65536.0,
        a_pix: 4.0 * 0.4 * 0.4 / 65536.0,
        _pad: [0; 2],
    };
    let uniform = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("params"),
        contents: bytemuck::bytes_of(&params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let path_buffer = storage_buffer(&gpu.device, "paths", &paths);
    let sums = storage_buffer(&gpu.device, "sums", &vec![[0f32; 4]; count]);
    let resources = [
        Resource { name: "params", buffer: &uniform },
        Resource { name: "paths", buffer: &path_buffer },
        Resource { name: "sums", buffer: &sums },
    ];
    // The balance heuristic (bpt's) and the power heuristic (vcm's): the sums must be 1 under
    // either, each density and count squared alike.
    let mut worst = (0.0f32, 0.0f32);
    for power in [false, true] {
        let kernel = common::test_kernel(&gpu, "mis_test", &[], &[("MIS_POWER", if power { 1.0 } else { 0.0 })]);
        let group = kernel.bind_group(&gpu.device, &resources).unwrap_or_else(|e| panic!("{e}"));
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        kernel.dispatch(&mut encoder, &group, count as u32);
        gpu.queue.submit([encoder.finish()]);
        let staging = staging_buffer(&gpu.device, "sums_staging", sums.size());
        let out: Vec<[f32; 4]> = read_buffer(&gpu.device, &gpu.queue, &sums, &staging, sums.size()).unwrap();
        for (i, ((s, k), merges)) in out.iter().zip(&lengths).zip(&merging).enumerate() {
            // Strategies: emission, NEE, k - 2 connections, light tracing; and the merges.
            assert_eq!((s[2], s[3]), ((k + 1) as f32, (k + 1 + merges) as f32), "path {i}: strategies counted");
            assert!((s[0] - 1.0).abs() < 1e-4, "path {i} of {k} segments, power {power}: BPT's weights sum to {}", s[0]);
            assert!((s[1] - 1.0).abs() < 1e-4, "path {i} of {k} segments, power {power}: VCM's weights sum to {}", s[1]);
            worst = (worst.0.max((s[0] - 1.0).abs()), worst.1.max((s[1] - 1.0).abs()));
        }
    }
    eprintln!("{count} paths: largest deviation from 1, BPT {:.2e}, VCM {:.2e}", worst.0, worst.1);
}
