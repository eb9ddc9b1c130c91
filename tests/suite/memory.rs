//! The GPU memory a render takes (`--stats`) follows the scene and the image: the scene's
//! buffers grow with its primitives and not with the image, the renderer's with the pixels and
//! the photons.

use crate::common;

use sppm_gpu::integrators;
use sppm_gpu::scene::Scene;

fn memory(gpu: &sppm_gpu::gpu::GpuContext, scene: &Scene) -> integrators::GpuMemory {
    integrators::create(&gpu.device, &gpu.queue, scene).unwrap().gpu_memory()
}

#[test]
fn renderer_memory_follows_the_pixels_and_photons_scene_memory_the_primitives() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("cornell-box.toml");
    scene.render.width = 64;
    scene.render.height = 64;
    // Fewer photons than 32 a visible point, so that both images gather their hits.
    scene.render.photons = 100_000;
    let small = memory(&gpu, &scene);
    scene.render.width = 128;
    scene.render.height = 128;
    let large = memory(&gpu, &scene);
    assert_eq!(small.scene, large.scene, "the scene's buffers do not depend on the image");
    // About 172 bytes a pixel at one sample a pixel: per visible point its statistics 32,
    // flux 32, the point 32, its grid entries 32 and bucket lists up to 12, and 32 a pixel (the
    // image and its staging copy).
    let per_pixel = (large.renderer_bytes() - small.renderer_bytes()) as f64 / (128.0 * 128.0 - 64.0 * 64.0);
    assert!((160.0..185.0).contains(&per_pixel), "{per_pixel} bytes per pixel");
    // And per photon, whatever the image: room for two hits of 48 bytes, and a sixteenth of
    // a photon thread's saved state (64 bytes a thread of 16 photons).
    let photons = scene.render.photons;
    scene.render.photons = photons / 2;
    let fewer = memory(&gpu, &scene);
    let per_photon = (large.renderer_bytes() - fewer.renderer_bytes()) as f64 / (photons - photons / 2) as f64;
    assert_eq!(per_photon, 100.0, "bytes per photon");
    // Up to a cap: past a million photons a pass gathers more than once, and the memory stays
    // (at 1024x1024, below 32 photons a visible point).
    let need = |photons: u32, size: u32| {
        let mut s = scene.clone();
        (s.render.photons, s.render.width, s.render.height) = (photons, size, size);
        integrators::memory_need(&gpu.device, &s).renderer
    };
    assert!(need(1 << 20, 1024) > need(1 << 19, 1024), "the memory grows with the photons up to the cap");
    assert_eq!(need(1 << 20, 1024), need(1 << 24, 1024), "past the cap the memory stays");
    // From 32 photons a visible point the hits are added at once: no room for them at all.
    assert!(need(600_000, 128) < need(400_000, 128), "36 photons a point need no room for hits, 24 do");
    assert_eq!(need(600_000, 128), need(1 << 24, 128), "nor more photons");
    scene.render.photons = photons;

    // A scene with a mesh of thousands of triangles (the CWBVH, a leaf-order copy of each
    // primitive, shading normals): about 155 bytes a primitive.
    let bunny = common::load_scene("gallery/bunny-cube.toml");
    let prims = (bunny.triangles.len() + bunny.spheres.len()) as f64;
    let mesh = memory(&gpu, &bunny);
    let per_prim = mesh.scene_bytes() as f64 / prims;
    assert!(prims > 3_000.0 && per_prim > 48.0 && per_prim < 200.0, "{per_prim} bytes per primitive, {prims} primitives");
    let cornell_prims = (scene.triangles.len() + scene.spheres.len()) as f64;
    assert!((small.scene_bytes() as f64 / cornell_prims) < 160.0);

    // The path tracers hold the scene and a sum per pixel.
    scene.render.method = sppm_gpu::scene::Method::PtNee;
    let pt = memory(&gpu, &scene);
    assert_eq!(pt.scene, large.scene);
    assert!(pt.renderer_bytes() < 40 * 128 * 128, "{} bytes", pt.renderer_bytes());
}

/// The memory check's estimate, made before allocating: the renderer's buffers exactly as
/// they are then allocated (one band or several, SPPM or a path tracer), and the scene's at
/// least as large as they are.
#[test]
fn memory_need_matches_what_is_allocated() {
    let Some(gpu) = common::gpu() else { return };
    // A device whose buffers hold 64 KiB makes a 64x56 SPPM image go in bands.
    let small =
        sppm_gpu::gpu::GpuContext::with_limits(|l| wgpu::Limits { max_storage_buffer_binding_size: 64 << 10, ..l }).unwrap();
    let bunny = common::load_scene("gallery/bunny-cube.toml");
    use sppm_gpu::scene::RadiusRule::{Adaptive, Shrink};
    // SPPM splatting its passes under a gaussian (the global schedule): the rows of visible
    // points a band's filter reaches beyond it, and the pixels' sums.
    let splat = Some(sppm_gpu::scene::PixelFilter::Gaussian { stddev: 0.5 });
    for (context, name, method, size, rule, filter) in [
        (&gpu, "cornell-box.toml", sppm_gpu::scene::Method::Sppm, 48, Shrink, None),
        (&gpu, "cornell-box.toml", sppm_gpu::scene::Method::PtNee, 48, Shrink, None),
        (&small, "cornell-box.toml", sppm_gpu::scene::Method::Sppm, 64, Shrink, None),
        (&gpu, "gallery/bunny-cube.toml", sppm_gpu::scene::Method::Sppm, 32, Shrink, None),
        // The adaptive radius rule's wider accumulator and per-point tests, whole and in bands.
        (&gpu, "cornell-box.toml", sppm_gpu::scene::Method::Sppm, 48, Adaptive, None),
        (&small, "cornell-box.toml", sppm_gpu::scene::Method::Sppm, 64, Adaptive, None),
        (&gpu, "cornell-box.toml", sppm_gpu::scene::Method::Sppm, 48, Shrink, splat),
        (&small, "cornell-box.toml", sppm_gpu::scene::Method::Sppm, 64, Shrink, splat),
    ] {
        let mut scene = if name.contains("bunny") { bunny.clone() } else { common::load_scene(name) };
        scene.render.method = method;
        scene.render.radius_rule = rule;
        if let Some(filter) = filter {
            (scene.render.filter, scene.render.radius_schedule) = (filter, sppm_gpu::scene::RadiusSchedule::Global);
        }
        scene.render.width = size;
        scene.render.height = size - 8;
        if std::ptr::eq(context, &small) {
            assert!(integrators::max_rows(&small.device, &scene) < scene.render.height, "the small device bands");
        }
        let need = integrators::memory_need(&context.device, &scene);
        let got = memory(context, &scene);
        assert_eq!(need.renderer, got.renderer_bytes(), "{name} {method:?} {size} {rule:?}: the renderer's buffers");
        assert!(need.scene >= got.scene_bytes(), "{name}: scene estimate {} below {}", need.scene, got.scene_bytes());
        assert!(
            need.scene < 3 * got.scene_bytes() + 65536,
            "{name}: scene estimate {} far above {}",
            need.scene,
            got.scene_bytes()
        );
        assert_eq!(need.host, size as u64 * (size as u64 - 8) * 40);
    }
}
