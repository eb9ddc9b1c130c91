//! Rays per second through the BVH traversal alone: the `trace_rays` kernel (the same
//! `trace_closest` the camera, photon and path-tracing kernels run), specialized per scene,
//! over incoherent rays: origins uniform in the scene's box, directions uniform on the sphere.
//!
//! `cargo bench --bench traversal [-- SCENE.toml ...]`; without arguments, cornell-box,
//! cornell-spheres and the gallery's glass dragon (11k triangles). `VARIANTS="A=1,B=0;A=0"`
//! compares kernels with other override constants, interleaved in one run, and counts the
//! rays whose hit is not the first variant's bit for bit (a variant meant to change only the
//! speed must read 0). Besides the kernels' overrides, `CWBVH=0` traces the binary tree (the
//! data traversal, or the baked one), `CWBVH=1` the compressed 8-wide BVH, whatever the
//! scene's own choice; `ANY_HIT=1` times shadow-ray queries instead of closest hits.

use std::path::PathBuf;
use std::time::Instant;

use glam::Vec3;
use sppm_gpu::accel::build_cwbvh;
use sppm_gpu::gpu::baked_bvh::replacements;
use sppm_gpu::gpu::readback::{read_buffer, staging_buffer};
use sppm_gpu::gpu::scene_buffers::{storage_buffer, SceneBuffers, SceneData};
use sppm_gpu::gpu::{GpuContext, Kernel, Resource};
use sppm_gpu::layout::Features;

/// The test kernel that traces a buffer of rays (`tests/shaders/trace_rays.wgsl`).
const TRACE_RAYS: &str = include_str!("../tests/shaders/trace_rays.wgsl");
use wgpu::util::DeviceExt;

const RAYS: usize = 1 << 20;
const REPEATS: usize = 8;

/// SplitMix64: a small seeded generator, so every run traces the same rays.
struct Rng(u64);

impl Rng {
    fn f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut scenes: Vec<PathBuf> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).map(PathBuf::from).collect();
    if scenes.is_empty() {
        scenes = ["scenes/cornell-box.toml", "scenes/cornell-spheres.toml", "scenes/gallery/glass-dragon.toml"]
            .iter()
            .map(|s| root.join(s))
            .collect();
    }
    let variants: Vec<(String, Vec<(String, f64)>)> = std::env::var("VARIANTS")
        .unwrap_or_default()
        .split(';')
        .map(|v| {
            let constants = v
                .split(',')
                .filter(|kv| !kv.is_empty())
                .map(|kv| {
                    let (k, x) = kv.split_once('=').expect("VARIANTS: NAME=VALUE,...;...");
                    (k.to_string(), x.parse().expect("VARIANTS: a number"))
                })
                .collect();
            (v.to_string(), constants)
        })
        .collect();
    let gpu = GpuContext::new().unwrap_or_else(|e| panic!("{e}"));
    println!("{RAYS} rays per dispatch, best of {REPEATS} dispatches, variants interleaved");
    for path in scenes {
        let scene = sppm_gpu::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let data = SceneData::new(&scene).unwrap_or_else(|e| panic!("{e}"));
        let (lo, hi) = data.swept_bounds();
        let (lo, hi) = (lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo));
        let mut rand = Rng(7);
        let rays: Vec<[f32; 4]> = (0..RAYS)
            .flat_map(|_| {
                let o = lo + (hi - lo) * Vec3::new(rand.f32(), rand.f32(), rand.f32());
                // Uniform on the sphere (pbrt-v4 A.5.2).
                let z = 1.0 - 2.0 * rand.f32();
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = 2.0 * std::f32::consts::PI * rand.f32();
                [[o.x, o.y, o.z, 3.4e38], [r * phi.cos(), r * phi.sin(), z, 0.0]]
            })
            .collect();
        // The scene's own tree (its layout as `SceneData::new` chose), and both layouts for
        // the CWBVH=0 and CWBVH=1 variants (the binary tree's data traversal, the CWBVH).
        let own = SceneBuffers::new(&gpu.device, &data);
        let mut data = data;
        let own_cwbvh = data.cwbvh.is_some();
        let cw = data.cwbvh.take().or_else(|| {
            build_cwbvh(&scene.triangles, &scene.spheres, |s| scene.shapes[s as usize].velocity.unwrap_or(Vec3::ZERO))
        });
        let binary = SceneBuffers::new(&gpu.device, &data);
        data.cwbvh = cw;
        let cwbvh = SceneBuffers::new(&gpu.device, &data);
        let mut variant_buffers = Vec::new();
        let kernels: Vec<Kernel> = variants
            .iter()
            .map(|(_, extra)| {
                let mut constants = Features::of(&data).constants();
                constants.extend(extra.iter().map(|(k, x)| (k.as_str(), *x)));
                let forced = constants.iter().find(|(k, _)| *k == "CWBVH").map(|(_, x)| *x != 0.0);
                let use_cw = forced.unwrap_or(own_cwbvh);
                variant_buffers.push(match forced {
                    None => &own,
                    Some(true) => &cwbvh,
                    Some(false) => &binary,
                });
                constants.push(("BVH_LAYOUT", if use_cw { 2.0 } else { 1.0 }));
                let no_bake = use_cw || constants.iter().any(|(k, x)| *k == "BAKED" && *x == 0.0);
                let baked = if no_bake { vec![] } else { replacements(&data) };
                let replace: Vec<(&str, &str)> = baked.iter().map(|(t, c)| (*t, c.as_str())).collect();
                Kernel::from_wgsl(&gpu.device, "trace_rays", TRACE_RAYS, &replace, &constants).unwrap()
            })
            .collect();
        let ray_buffer = storage_buffer(&gpu.device, "rays", &rays);
        let hits = storage_buffer(&gpu.device, "hits", &vec![[0f32; 4]; RAYS]);
        let frame = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&sppm_gpu::layout::Frame::default()),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let groups: Vec<wgpu::BindGroup> = kernels
            .iter()
            .zip(&variant_buffers)
            .map(|(k, buffers)| {
                let mut resources = buffers.resources();
                resources.push(Resource { name: "frame", buffer: &frame });
                resources.push(Resource { name: "rays", buffer: &ray_buffer });
                resources.push(Resource { name: "hits", buffer: &hits });
                k.bind_group(&gpu.device, &resources).unwrap()
            })
            .collect();
        let staging = staging_buffer(&gpu.device, "hits_staging", hits.size());
        let mut best = vec![f64::INFINITY; kernels.len()];
        let mut hit_counts = vec![0; kernels.len()];
        // Rays whose hit differs from the first variant's, bit for bit.
        let mut first_hits: Vec<[u32; 4]> = Vec::new();
        let mut differing = vec![0; kernels.len()];
        // Of those, the rays whose t differs too (not a tie between primitives at one t).
        let mut other_t = vec![0; kernels.len()];
        // The first round compiles the kernels (lavapipe compiles at first use): untimed.
        for round in 0..=REPEATS {
            for (k, (kernel, group)) in kernels.iter().zip(&groups).enumerate() {
                let start = Instant::now();
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                kernel.dispatch(&mut encoder, group, RAYS as u32);
                gpu.queue.submit([encoder.finish()]);
                let out: Vec<[f32; 4]> = read_buffer(&gpu.device, &gpu.queue, &hits, &staging, hits.size()).unwrap();
                // A kernel the device refused leaves the hits as they were: fail, do not time it.
                gpu.check().unwrap_or_else(|e| panic!("{e}"));
                if round > 0 {
                    best[k] = best[k].min(start.elapsed().as_secs_f64());
                }
                hit_counts[k] = out.iter().filter(|h| h[1].to_bits() != u32::MAX).count();
                let bits: Vec<[u32; 4]> = out.iter().map(|h| h.map(f32::to_bits)).collect();
                if k == 0 {
                    first_hits = bits;
                } else {
                    differing[k] = bits.iter().zip(&first_hits).filter(|(a, b)| a != b).count();
                    other_t[k] = bits.iter().zip(&first_hits).filter(|(a, b)| a[0] != b[0]).count();
                }
            }
        }
        for (k, (name, _)) in variants.iter().enumerate() {
            println!(
                "{:<22} {:>7} primitives {:>6.2} M rays/s ({:.1}% hit, {} hits not those of the first variant, {} at another t) {}",
                path.file_name().unwrap().to_string_lossy(),
                scene.triangles.len() + scene.spheres.len(),
                RAYS as f64 / best[k] / 1e6,
                100.0 * hit_counts[k] as f64 / RAYS as f64,
                differing[k],
                other_t[k],
                name
            );
        }
    }
}
