//! Kernels compiled per scene: `Features::of` says what each scene has, every kernel compiles
//! with any feature switched off, and a specialized traversal finds exactly the hits of the
//! general one.

use crate::common;

use crate::common::Rng;
use glam::Vec3;
use sppm_gpu::gpu::scene_buffers::SceneData;
use sppm_gpu::gpu::Kernel;
use sppm_gpu::layout::Features;
use sppm_gpu::scene::{self, Sphere, Triangle};

fn features(name: &str) -> Features {
    Features::of(&SceneData::new(&common::load_scene(name)).unwrap())
}

#[test]
fn features_of_the_canonical_scenes() {
    let f = features("cornell-spheres.toml");
    assert!(f.triangles && f.spheres && f.mirror && f.smooth_dielectric && f.triangle_lights);
    assert!(!(f.glossy || f.rough_dielectric || f.textures || f.uvs || f.shading_normals || f.motion));
    assert!(!(f.sphere_lights || f.point_lights || f.directional_lights));
    let f = features("cornell-box.toml");
    assert!(f.triangles && !f.spheres && !f.mirror && !f.smooth_dielectric);
    let f = features("textured.toml");
    assert!(f.textures && f.uvs);
    let f = features("point-light.toml");
    assert!(f.point_lights);
    let f = features("cornell-glossy.toml");
    assert!(f.glossy);
    let f = features("motion-blur.toml");
    assert!(f.motion);
    // Conductor Fresnel terms and Beckmann microfacets come from Mitsuba scenes only.
    for name in ["cornell-spheres.toml", "cornell-glossy.toml", "cornell-box.toml"] {
        let f = features(name);
        assert!(!(f.conductor_fresnel || f.beckmann), "{name}");
    }
    let metals = scene::load(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mitsuba/metals.xml")).unwrap();
    let f = Features::of(&SceneData::new(&metals).unwrap());
    assert!(f.conductor_fresnel && f.beckmann && f.mirror && f.glossy && f.rough_dielectric);
    let box_xml = scene::load(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mitsuba/box.xml")).unwrap();
    let f = Features::of(&SceneData::new(&box_xml).unwrap());
    assert!(f.mirror && f.glossy && !f.conductor_fresnel && !f.beckmann, "material none, ggx: {f:?}");
    assert_eq!(Features::ALL.constants().len(), 24);
    assert!(Features::ALL.constants().iter().all(|(_, v)| *v == 1.0));
}

/// Participating media switch USES_MEDIA on, and only they: the canonical scenes compile their
/// kernels as before media existed.
#[test]
fn media_are_a_feature_of_their_own() {
    for name in ["cornell-box.toml", "cornell-spheres.toml", "cornell-glossy.toml", "point-light.toml", "textured.toml"] {
        let f = features(name);
        assert!(!f.media && f.constants().contains(&("USES_MEDIA", 0.0)), "{name}");
    }
    for name in ["fog-cornell.xml", "murky-water.xml", "volumetric-caustic.xml"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/media").join(name);
        let f = Features::of(&SceneData::new(&scene::load(&path).unwrap()).unwrap());
        assert!(f.media && f.constants().contains(&("USES_MEDIA", 1.0)), "{name}");
    }
}

/// A constant environment switches USES_ENVIRONMENT on, and nothing else does: scenes
/// without one compile their kernels as before it existed.
#[test]
fn the_environment_is_a_feature_of_its_own() {
    for name in ["cornell-box.toml", "cornell-spheres.toml", "point-light.toml", "textured.toml", "motion-blur.toml"] {
        let f = features(name);
        assert!(!f.environment, "{name}");
        assert!(f.constants().contains(&("USES_ENVIRONMENT", 0.0)), "{name}");
    }
    let f = features("furnace-environment.toml");
    assert!(f.environment && !(f.point_lights || f.directional_lights || f.spot_lights || f.triangle_lights), "{f:?}");
    assert!(f.constants().contains(&("USES_ENVIRONMENT", 1.0)));
    // A constant environment leaves the envmap's code out; an envmap puts it in.
    assert!(f.constants().contains(&("USES_ENVMAP", 0.0)));
    let envmap = scene::load(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mitsuba/envmap.xml")).unwrap();
    let f = Features::of(&SceneData::new(&envmap).unwrap());
    assert!(f.environment && f.envmap && !f.triangle_lights, "{f:?}");
}

/// Spot lights switch USES_SPOT_LIGHTS on, and nothing else does: scenes without them
/// compile their kernels without the spot light's code.
#[test]
fn spot_lights_are_a_feature_of_their_own() {
    for name in ["cornell-box.toml", "cornell-spheres.toml", "point-light.toml", "textured.toml", "motion-blur.toml"] {
        let f = features(name);
        assert!(!f.spot_lights, "{name}");
        assert!(f.constants().contains(&("USES_SPOT_LIGHTS", 0.0)), "{name}");
    }
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mitsuba/spot.xml");
    let f = Features::of(&SceneData::new(&sppm_gpu::scene::load(&path).unwrap()).unwrap());
    assert!(f.spot_lights && !(f.point_lights || f.directional_lights || f.triangle_lights || f.sphere_lights), "{f:?}");
    assert!(f.constants().contains(&("USES_SPOT_LIGHTS", 1.0)));
}

/// Each tracing kernel with each feature off in turn, and with all off: the driver compiles
/// every variant without an error. The variants of a kernel share its validated source and
/// shader module (`share_kernels`): only their constants differ.
#[test]
fn every_variant_compiles() {
    let Some(gpu) = common::gpu() else { return };
    let all = Features::ALL.constants();
    let mut variants: Vec<Vec<(&str, f64)>> =
        (0..all.len()).map(|i| all.iter().enumerate().map(|(j, &(n, v))| (n, if i == j { 0.0 } else { v })).collect()).collect();
    variants.push(all.iter().map(|&(n, _)| (n, 0.0)).collect());
    sppm_gpu::gpu::share_kernels(|| {
        for kernel in ["camera_pass", "photon_pass", "path_trace"] {
            for constants in &variants {
                Kernel::specialized(&gpu.device, kernel, &[], constants).unwrap_or_else(|e| panic!("{kernel}: {e}"));
            }
        }
        for constants in &variants {
            common::test_kernel(&gpu, "trace_rays", &[], constants);
        }
    });
    let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
    gpu.check().unwrap();
}

/// Kernels made beside each other on two threads (`join_sharing_kernels`, as SPPM makes its
/// camera and photon kernels) find what this thread's `share_kernels` made, and what the other
/// thread made is found here after: on a device of its own (whose kernels the process does not
/// keep), the second thread's kernel is the first's pipeline, and this thread finds the one
/// the second thread made. Without it SPPM's camera kernel was made again by every renderer.
#[test]
fn kernels_made_beside_each_other_share_the_callers_store() {
    let Some(gpu) = common::own_gpu() else { return };
    let make = |name| Kernel::specialized(&gpu.device, name, &[], &Features::ALL.constants()).unwrap();
    sppm_gpu::gpu::share_kernels(|| {
        let first = make("camera_pass");
        let ((again, made_there), ()) = sppm_gpu::gpu::join_sharing_kernels(|| (make("camera_pass"), make("photon_pass")), || ());
        assert!(again.same_pipeline(&first), "the other thread made the caller's kernel again");
        assert!(make("photon_pass").same_pipeline(&made_there), "the other thread's kernel is not found after");
        // A share_kernels of the other thread's own starts empty: there it is made again.
        let (own, ()) = sppm_gpu::gpu::join_sharing_kernels(|| sppm_gpu::gpu::share_kernels(|| make("photon_pass")), || ());
        assert!(!own.same_pipeline(&made_there));
    });
    gpu.check().unwrap();
}

/// The suite's shared device keeps its kernels for the process (`keep_kernels_in_process`);
/// a device of another wgpu instance, whose id may equal the shared one's (wgpu counts ids per
/// instance), is not handed them: the same kernel runs on both and traces the same hits.
#[test]
fn a_device_of_another_instance_makes_its_own_kernels() {
    let (Some(shared), Some(own)) = (common::gpu(), common::own_gpu()) else { return };
    let data = SceneData::new(&common::load_scene("cornell-box.toml")).unwrap();
    let rays: Vec<[f32; 4]> = (0..256)
        .flat_map(|i| {
            let t = i as f32 / 256.0;
            [[0.0, 1.0, 3.0, 1.0e30], [t - 0.5, 0.3 - t, -1.0, 0.0]]
        })
        .collect();
    let constants = Features::ALL.constants();
    let on_shared = common::trace_rays(&shared, &data, &rays, &constants);
    let on_own = common::trace_rays(&own, &data, &rays, &constants);
    own.check().unwrap();
    shared.check().unwrap();
    assert!(on_shared.iter().filter(|h| h[1].to_bits() != u32::MAX).count() > 128, "the rays hit the box");
    assert!(on_shared.iter().zip(&on_own).all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits)));
}

/// A scene of only spheres and one of only triangles (each lit by one of its primitives):
/// the traversal specialized for each finds the same hits as the general one, bit for bit.
#[test]
fn specialized_traversal_finds_the_general_ones_hits() {
    let Some(gpu) = common::gpu() else { return };
    let mut rand = Rng(99);
    let mut base = common::load_scene("cornell-box.toml");
    base.shapes.truncate(1);
    base.shapes[0].emission = Some(Vec3::ONE);
    base.lights.clear();
    let mut spheres_only = base.clone();
    spheres_only.triangles.clear();
    spheres_only.spheres =
        (0..40).map(|_| Sphere { center: rand.vec3(-1.0, 1.0), radius: 0.05 + 0.2 * rand.f32(), shape: 0 }).collect();
    let mut triangles_only = base.clone();
    triangles_only.spheres.clear();
    triangles_only.triangles = (0..300)
        .map(|_| {
            let c = rand.vec3(-1.0, 1.0);
            Triangle { p: [c, c + rand.vec3(-0.3, 0.3), c + rand.vec3(-0.3, 0.3)], n: None, uv: None, shape: 0 }
        })
        .collect();
    let rays: Vec<[f32; 4]> = (0..2048)
        .flat_map(|_| {
            let o = rand.vec3(-1.5, 1.5);
            let d = rand.vec3(-1.0, 1.0);
            [[o.x, o.y, o.z, 1.0e30], [d.x, d.y, d.z, 0.0]]
        })
        .collect();
    for scene in [&spheres_only, &triangles_only] {
        let data = SceneData::new(scene).unwrap();
        let own = Features::of(&data);
        assert!(own.spheres != own.triangles, "one kind of primitive");
        let general = common::trace_rays(&gpu, &data, &rays, &Features::ALL.constants());
        let specialized = common::trace_rays(&gpu, &data, &rays, &own.constants());
        let hits = general.iter().filter(|h| h[1].to_bits() != u32::MAX).count();
        assert!(hits > 200, "{hits} of 2048 rays hit");
        // By bits: a miss's primitive reference 0xffffffff reads as a NaN.
        let bits = |h: &[f32; 4]| h.map(f32::to_bits);
        let differ: Vec<_> = general.iter().zip(&specialized).enumerate().filter(|(_, (a, b))| bits(a) != bits(b)).collect();
        for (i, (a, b)) in differ.iter().take(5) {
            eprintln!("ray {i}: general {a:?} ({:#x}) specialized {b:?} ({:#x})", a[1].to_bits(), b[1].to_bits());
        }
        assert!(differ.is_empty(), "specialized traversal differs on {} rays", differ.len());
    }
    gpu.check().unwrap();
}
