//! Bidirectional path tracing (`bpt`) and vertex connection and merging (`vcm`, bpt with
//! merging: `vcm_*` tests). bpt: it converges to the references on the canonical scenes,
//! glass and mirrors included (where light tracing alone is black and pt-nee misses a point
//! light's caustic) and depth of field, passes the furnace, gives the same bits for the same
//! seed, stays right where pixels share light subpaths (more pixels than the light-vertex store
//! holds subpaths), takes every light kind but the environment, and refuses what it cannot
//! render before any work. The weights' sum over strategies is vcm.rs's oracle.

use crate::common;

use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators;
use sppm_gpu::metrics::{compare, downsample_box};
use sppm_gpu::scene::{Method, Scene};

const SIZE: u32 = 64;

/// 8x8 relMSE of bpt and vcm on Mitsuba's envmap.xml after 32 passes against Mitsuba's
/// render: 4.1e-4 and 5.8e-4 measured (2026-11-29).
const MAX_ENVMAP_REL_MSE: f64 = 2e-3;

/// relMSE and channel mean ratios against the 256x256 reference, both reduced to 8x8.
fn check(scene: &Scene, name: &str, passes: u32, max_rel_mse: f64) {
    check_method(scene, Method::Bpt, name, passes, max_rel_mse, 0.01);
}

fn check_method(scene: &Scene, method: Method, name: &str, passes: u32, max_rel_mse: f64, max_mean_error: f64) {
    check_image(scene, method, name, passes, max_rel_mse, max_mean_error);
}

/// As `check_method`, returning the image and the reference at its size.
fn check_image(
    scene: &Scene,
    method: Method,
    name: &str,
    passes: u32,
    max_rel_mse: f64,
    max_mean_error: f64,
) -> (Rgb32Image, Rgb32Image) {
    let img = common::render_at(scene, method, SIZE, passes);
    let reference = downsample_box(&common::reference(&format!("{name}.exr")), 256 / SIZE).unwrap();
    let c = compare(&img, &reference, 8).unwrap();
    eprintln!("{name} {method:?} {passes} passes (max_depth {}): {c:?}", scene.render.max_depth);
    assert!(c.rel_mse < max_rel_mse, "{name} {method:?}: relMSE {}", c.rel_mse);
    for r in c.mean_ratio {
        assert!((r - 1.0).abs() < max_mean_error, "{name} {method:?}: channel mean ratios {:?}", c.mean_ratio);
    }
    (img, reference)
}

/// The mean of rows `rows` and columns `cols` of an image, over its channels.
fn region_mean(img: &Rgb32Image, rows: std::ops::Range<u32>, cols: std::ops::Range<u32>) -> f64 {
    let region = Rgb32Image::from_fn(cols.len() as u32, rows.len() as u32, |x, y| img.get(cols.start + x, rows.start + y));
    region.mean().iter().sum::<f64>() / 3.0
}

#[test]
fn bpt_matches_the_references() {
    if common::gpu().is_none() {
        return;
    }
    // Noise: cornell-spheres' caustics read relMSE 3.9e-4 at 64 passes, 2.2e-5 at 1,024 (so
    // about 2e-4 at 128); depth-of-field's thin lens (connections and light tracing through
    // points of the lens) 2.4e-5 at 1,024 with a light subpath a pixel, and with one for 16
    // pixels (the default) 4.3e-4 at 64 passes.
    for (name, passes, max_rel_mse) in [
        ("cornell-box", 32, 2e-4),
        ("cornell-spheres", 128, 4e-4),
        ("cornell-glossy", 64, 2e-4),
        ("point-light", 32, 2e-4),
        ("textured", 32, 2e-4),
        ("depth-of-field", 128, 4e-4),
    ] {
        check(&common::load_scene(&format!("{name}.toml")), name, passes, max_rel_mse);
    }
}

/// The light-vertex store holds what a pass's subpaths keep, not `max_depth` slots each: at
/// depth 1,024 and one light subpath a pixel (4,096), a store of every subpath at full depth
/// would hold 2,340 of them in 256 MiB (what it held before the store became a cache); the
/// probe's store holds all 4,096 in under 16 slots a subpath (cornell-box's keep about 3), and
/// loses none. Then with 2,340 asked for, pixel i connects to subpath i mod 2,340, and light
/// tracing counts 2,340 subpaths a pass: the image is the same one (by default 16 pixels
/// share each subpath: the other tests).
#[test]
fn bpt_light_vertex_store_holds_what_subpaths_keep() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("cornell-box.toml");
    scene.render.method = Method::Bpt;
    scene.render.max_depth = 1024;
    scene.render.width = SIZE;
    scene.render.height = SIZE;
    scene.render.light_paths = Some(SIZE * SIZE);
    let full_depth = integrators::light::light_paths(&scene.render, u64::MAX, None).unwrap();
    assert_eq!(full_depth, 2340, "light subpaths at full depth for {} pixels", SIZE * SIZE);
    let mut bpt = integrators::create(&gpu.device, &gpu.queue, &scene).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..2 {
        bpt.run_pass().unwrap_or_else(|e| panic!("{e}"));
    }
    assert_eq!(bpt.work_per_pass(), (SIZE * SIZE) as u64, "light subpaths a pass");
    let store = bpt.gpu_memory().renderer.iter().find(|(name, _)| name == "light_vertices").map(|(_, bytes)| *bytes).unwrap();
    let slots = store / size_of::<sppm_gpu::layout::LightVertex>() as u64;
    assert!(slots < 16 * (SIZE * SIZE) as u64, "{slots} light-vertex slots for {} subpaths", SIZE * SIZE);
    assert_eq!(bpt.warnings().unwrap(), Vec::<String>::new());
    scene.render.light_paths = Some(2340);
    check(&scene, "cornell-box", 32, 2e-4);
}

/// The delta lights against Mitsuba 3's renders of the same files: two spot lights, a point and
/// a directional light (at infinity: its first segments' lengths stay out of the MIS).
#[test]
fn bpt_matches_mitsuba_for_every_light_kind() {
    let Some(gpu) = common::gpu() else { return };
    // relMSE 1.3e-5 (spot) and 9.4e-6 (lights) at 256 passes.
    for name in ["spot", "lights"] {
        common::check_mitsuba_reference(&gpu, name, Method::Bpt, 32, 3e-4);
    }
}

/// An environment map lighting the scene (Mitsuba's envmap.xml) against Mitsuba 3's render:
/// light subpaths leave the map's disk with a light at infinity's densities, and camera
/// subpaths weigh the map they escape to and sample against the light subpaths' strategies;
/// vcm at every strategy (connections and merging) and as its pilot chooses.
#[test]
fn bidirectional_methods_take_the_environment() {
    let Some(gpu) = common::gpu() else { return };
    common::check_mitsuba_reference(&gpu, "envmap", Method::Bpt, 32, MAX_ENVMAP_REL_MSE);
    common::check_mitsuba_reference(&gpu, "envmap", Method::Vcm, 32, MAX_ENVMAP_REL_MSE);
}

/// Every surface has albedo 0.5 and emits 1 in a closed box: radiance 2 everywhere.
#[test]
fn bpt_passes_the_furnace() {
    if common::gpu().is_none() {
        return;
    }
    let img = common::render_at(&common::load_scene("furnace.toml"), Method::Bpt, SIZE, 64);
    let n = img.pixels.len() as f64;
    for c in 0..3 {
        let mean = img.pixels.iter().map(|p| p[c] as f64).sum::<f64>() / n;
        eprintln!("furnace bpt: channel {c} mean {mean}");
        assert!((mean / 2.0 - 1.0).abs() < 0.005, "furnace bpt: mean {mean}, expected 2");
    }
}

/// The same seed gives the same bits; media are refused before any pass, naming the scene.
#[test]
fn bpt_is_bit_exact_and_refuses_what_it_cannot_render() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::load_scene("cornell-box.toml");
    let a = common::render_at(&scene, Method::Bpt, 32, 3);
    assert!(a.pixels == common::render_at(&scene, Method::Bpt, 32, 3).pixels, "two renders of one seed differ");
    let mut other = scene.clone();
    other.render.seed += 1;
    assert!(common::render_at(&other, Method::Bpt, 32, 3).pixels != a.pixels, "another seed gave the same image");
    let name = "media/fog-cornell.xml";
    let mut scene = common::load_scene(name);
    scene.render.method = Method::Bpt;
    let err = match integrators::create(&gpu.device, &gpu.queue, &scene) {
        Ok(_) => panic!("{name}: rendered with bpt"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("participating media") && err.contains("method bpt") && err.contains(name), "{name}: {err}");
}

/// vcm's light subpaths a pass fit the device's buffers: at depth 1,024 (Mitsuba's unbounded
/// depth as read), merging alone and asked for 2^20 light subpaths, a pass keeps 8 merge
/// entries of 16 bytes a light-vertex slot, more than one storage buffer holds on lavapipe (128
/// MiB). It traces as many as fit and renders; before, the pass failed on a binding over the
/// limit (as cornell-glossy did at 512x512 and depth 64 with vcm's default settings, whose
/// pilot chooses merging alone). A small image and radius: the automatic radius of so few
/// pixels would put most of the 400,000 light vertices in every bucket.
#[test]
fn vcm_light_subpaths_fit_the_devices_buffers() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("cornell-glossy.toml");
    let r = &mut scene.render;
    (r.method, r.width, r.height, r.max_depth, r.light_paths, r.radius) = (Method::Vcm, 32, 32, 1024, Some(1 << 20), Some(0.002));
    (r.connect_share, r.merge_share) = (Some(0.0), Some(1.0));
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    let mut vcm = integrators::create(&gpu.device, &gpu.queue, &scene).unwrap_or_else(|e| panic!("{e}"));
    let paths = vcm.work_per_pass();
    assert!(paths > 1 << 16 && paths < 1 << 20, "{paths} light subpaths a pass");
    for (name, bytes) in vcm.gpu_memory().renderer {
        assert!(bytes <= limit, "{name}: {bytes} bytes, over one buffer's {limit}");
    }
    vcm.run_pass().unwrap_or_else(|e| panic!("{e}"));
    let image = vcm.image().unwrap_or_else(|e| panic!("{e}"));
    let mean = image.pixels.iter().map(|p| (p[0] + p[1] + p[2]) as f64).sum::<f64>() / image.pixels.len() as f64;
    assert!(mean.is_finite() && mean > 0.0, "mean {mean}");
    assert_eq!(vcm.warnings().unwrap(), Vec::<String>::new());
}

/// vcm gives the same bits for the same seed: the hashed grid lists a bucket's light vertices
/// in an order that depends on timing, and merge_order.wgsl sorts them so that merging sums
/// in one order (without it, about 80 of 4,096 pixels differed in the last bits).
#[test]
fn vcm_is_bit_exact() {
    if common::gpu().is_none() {
        return;
    }
    let mut scene = common::load_scene("cornell-box.toml");
    // Every camera vertex merges (the pilot leaves merging out here).
    (scene.render.connect_share, scene.render.merge_share) = (Some(1.0), Some(1.0));
    let a = common::render_at(&scene, Method::Vcm, 64, 4);
    for _ in 0..2 {
        assert!(a.pixels == common::render_at(&scene, Method::Vcm, 64, 4).pixels, "two renders of one seed differ");
    }
    let mut other = scene.clone();
    other.render.seed += 1;
    assert!(common::render_at(&other, Method::Vcm, 64, 4).pixels != a.pixels, "another seed gave the same image");
    // Buckets of hundreds of light vertices (16 light subpaths a pixel), which merge_order
    // heapsorts rather than insertion sorts.
    scene.render.light_paths = Some(65536);
    let many = common::render_at(&scene, Method::Vcm, 64, 2);
    assert!(many.pixels == common::render_at(&scene, Method::Vcm, 64, 2).pixels, "two renders of one seed differ (long buckets)");
}

/// vcm converges to the references: merging's bias (the density estimate's blur over the
/// radius, at a surface's edge an underestimate) shrinks with the radius, which falls as
/// i^((alpha - 1) / 2). At 64x64 the automatic radius spans four times the scene that it
/// spans at 256x256: cornell-box's means read 0.9949 at 64 passes and 0.9969 at 512,
/// cornell-spheres' 0.997 and 0.999 (on cornell-box every camera vertex merges: the pilot
/// leaves merging out there).
#[test]
fn vcm_matches_the_references() {
    if common::gpu().is_none() {
        return;
    }
    let mut box_scene = common::load_scene("cornell-box.toml");
    (box_scene.render.connect_share, box_scene.render.merge_share) = (Some(1.0), Some(1.0));
    check_method(&box_scene, Method::Vcm, "cornell-box", 64, 6e-4, 0.01);
    // The spheres (a mirror and glass) seen by the camera: what lies behind them is merged at
    // the camera subpath's first diffuse vertices, whose MIS quantities after a delta lobe hold
    // only their merges (the reverse density left out there made this region 5% bright while
    // the whole image stayed within 0.4%).
    let (img, reference) =
        check_image(&common::load_scene("cornell-spheres.toml"), Method::Vcm, "cornell-spheres", 128, 6e-4, 0.01);
    let spheres = region_mean(&img, 40..56, 16..56) / region_mean(&reference, 40..56, 16..56);
    assert!((spheres - 1.0).abs() < 0.02, "cornell-spheres vcm: the spheres' region {spheres} of the reference's");
    check_method(&common::load_scene("point-light.toml"), Method::Vcm, "point-light", 128, 6e-4, 0.01);
}

/// vcm with a share of its camera vertices connecting and merging (`connect_share`,
/// `merge_share`: each strategy's count in the MIS, a join taken divided by it) renders the
/// same image in expectation: cornell-box with shares between 0 and 1, and point-light (a delta
/// light) with neither connections nor merges (next-event estimation, light tracing and
/// emission alone). A count left out of one weight darkens or brightens the image by the
/// weight it misses (the oracle, vcm::, checks the weights themselves). Without light subpaths
/// (`light_paths = 0`) vcm is pt-nee (vcm_pilot_chooses_from_the_scene_alone).
#[test]
fn vcm_at_shares_matches_the_references() {
    if common::gpu().is_none() {
        return;
    }
    for (name, passes, (connect, merge)) in [("cornell-box", 64, (0.3, 0.6)), ("point-light", 128, (0.0, 0.0))] {
        let mut scene = common::load_scene(&format!("{name}.toml"));
        scene.render.connect_share = Some(connect);
        scene.render.merge_share = Some(merge);
        check_method(&scene, Method::Vcm, name, passes, 6e-4, 0.01);
    }
}

/// vcm's pilot (a scene that sets neither share) chooses from the scene and its seed alone:
/// the same figures twice, and the render the same to the bit as one with the chosen shares
/// set. Its counts of work are the candidates': no connection at connect share 0, no merge
/// candidate at merge share 0, and the subpaths' vertices the same in number a subpath
/// whatever the shares (the passes' numbers differ: within 5% for the camera's, some 45,000 a
/// candidate, and 15% for the light's, some 2,300 of 1,152 subpaths, whose lengths vary more;
/// merging alone traces 4 times the subpaths). On cornell-spheres, whose light reaches the
/// floor through a glass sphere, the pilot weighs only candidates that connect or merge, then,
/// merging alone being the best of them, merging alone with four times the light subpaths, and
/// chooses merging without connections; connections without merging cost the most for their
/// noise (session 23's fixed-pass figures: 5.5x merging without connections; the pilot's few
/// passes miss the rarest paths and see 1.3x). cornell-box, all diffuse, adds light tracing
/// alone beside the camera's strategies and no light subpaths at all, which is pt-nee's
/// estimator (dVCM starts at 0, and nothing connects or merges) and renders by its kernel: the
/// same bits as pt-nee.
#[test]
fn vcm_pilot_chooses_from_the_scene_alone() {
    let Some(gpu) = common::gpu() else { return };
    use sppm_gpu::integrators::shares::{candidates, choose_for, CANDIDATES};
    use sppm_gpu::layout::{WORK_CAMERA_VERTICES, WORK_CONNECTIONS, WORK_LIGHT_VERTICES, WORK_MERGE_CANDIDATES};
    let mut scene = common::load_scene("cornell-spheres.toml");
    (scene.render.width, scene.render.height, scene.render.iterations) = (48, 48, 4);
    scene.render.method = Method::Vcm;
    assert!(sppm_gpu::integrators::light::pilot_chooses_shares(&scene));
    let pilot = choose_for(&gpu.device, &gpu.queue, &scene).unwrap();
    let again = choose_for(&gpu.device, &gpu.queue, &scene).unwrap();
    eprintln!("{pilot}\n{:?}", pilot.candidates);
    for (a, b) in pilot.candidates.iter().zip(&again.candidates) {
        assert_eq!((a.rel_variance, a.cost, a.counts), (b.rel_variance, b.cost, b.counts), "the pilot ran twice");
    }
    // Merging alone is the best of the first three: merging alone with four times its light
    // subpaths, and photon mapping, are weighed after them.
    assert_eq!(pilot.candidates.len(), 5, "{pilot}");
    let [both, merge_only, connect_only, dense, mapping] = [0, 1, 2, 3, 4].map(|k| &pilot.candidates[k]);
    assert_eq!(
        [both.choice, merge_only.choice, connect_only.choice, dense.choice, mapping.choice],
        [0, 1, 2, 5, 6].map(|k| CANDIDATES[k])
    );
    assert_eq!(merge_only.light_paths, 4 * both.light_paths);
    assert_eq!(dense.light_paths, 4 * merge_only.light_paths);
    let count = |c: &sppm_gpu::integrators::shares::Candidate, word: u32| c.counts[word as usize];
    assert_eq!((count(merge_only, WORK_CONNECTIONS), count(dense, WORK_CONNECTIONS)), (0.0, 0.0));
    assert_eq!(count(connect_only, WORK_MERGE_CANDIDATES), 0.0);
    for c in [both, merge_only, connect_only] {
        let per_subpath = |c: &sppm_gpu::integrators::shares::Candidate| count(c, WORK_LIGHT_VERTICES) / c.light_paths as f64;
        for (n, m, within) in
            [(count(c, WORK_CAMERA_VERTICES), count(both, WORK_CAMERA_VERTICES), 0.05), (per_subpath(c), per_subpath(both), 0.15)]
        {
            assert!(n > 0.0 && (n / m - 1.0).abs() < within, "{}: {n} against {m}", c.choice);
        }
    }
    assert!(count(both, WORK_CONNECTIONS) > 0.0 && count(both, WORK_MERGE_CANDIDATES) > 0.0);
    let score = |c: &sppm_gpu::integrators::shares::Candidate| c.rel_variance * c.cost;
    assert!(score(connect_only) > 1.15 * score(merge_only), "{pilot}");
    assert_eq!(pilot.chosen, merge_only.choice, "{pilot}");

    // The render as vcm chooses it, and with the chosen shares set.
    let auto = common::render_at(&scene, Method::Vcm, 48, 4);
    pilot.chosen.apply(&mut scene.render);
    let set = common::render_at(&scene, Method::Vcm, 48, 4);
    assert!(auto.pixels == set.pixels, "the pilot's render differs from one with its shares set");

    // An all-diffuse room: every candidate, the last without light subpaths.
    let mut room = common::load_scene("cornell-box.toml");
    room.render.method = Method::Vcm;
    assert_eq!(candidates(&room), CANDIDATES);
    let mut none = room.clone();
    CANDIDATES[4].apply(&mut none.render);
    assert_eq!(
        (none.render.light_paths, sppm_gpu::integrators::light::light_paths(&none.render, u64::MAX, None).unwrap()),
        (Some(0), 0)
    );
    assert!(!sppm_gpu::integrators::light::pilot_chooses_shares(&none));
    let none_image = common::render_at(&none, Method::Vcm, 32, 3);
    assert!(
        none_image.pixels == common::render_at(&none, Method::PtNee, 32, 3).pixels,
        "vcm without light subpaths is not pt-nee"
    );
}

/// The pilot's merges stand for the render's pass at which the mean of r^(-2) over its passes
/// is reached (for alpha = 2/3, 0.42 of them), its passes its `iterations` or under a time
/// limit those that fit; and each choice reads back from the text a checkpoint keeps.
#[test]
fn vcm_pilot_stands_for_the_renders_passes() {
    use sppm_gpu::integrators::shares::{render_passes, representative_pass, Choice, CANDIDATES};
    for (n, alpha) in [(94.0, 2.0 / 3.0), (640.0, 2.0 / 3.0), (1000.0, 0.5), (50.0, 0.9)] {
        // The mean over passes 1..=n of i^(1 - alpha) against its value at the pass chosen.
        let b = 1.0 - alpha as f64;
        let mean = (1..=n as u32).map(|i| (i as f64).powf(b)).sum::<f64>() / n;
        let k = representative_pass(n, alpha) as f64;
        assert!((k.powf(b) / mean - 1.0).abs() < 0.03, "n {n} alpha {alpha}: pass {k}, {} against {mean}", k.powf(b));
    }
    assert_eq!(representative_pass(94.0, 2.0 / 3.0), 40);
    assert_eq!(representative_pass(0.0, 2.0 / 3.0), 1);
    assert_eq!(representative_pass(100.0, 1.0), 37);
    let mut scene = common::load_scene("cornell-box.toml");
    scene.render.iterations = 64;
    assert_eq!(render_passes(&scene, Some(0.1), 0.0), 64.0);
    scene.render.time_limit = Some(10.0);
    scene.render.iterations = u32::MAX;
    assert_eq!(render_passes(&scene, Some(0.1), 2.0), 80.0);
    assert_eq!(render_passes(&scene, Some(0.1), 20.0), 0.0);
    for choice in CANDIDATES {
        assert_eq!(choice.to_string().parse::<Choice>(), Ok(choice), "{choice}");
    }
    for bad in ["", "1", "1/2", "a/b", "0/1@0", "0/1@", "0.5/1@x", "sppm2"] {
        assert!(bad.parse::<Choice>().is_err(), "{bad}");
    }
}

/// vcm as photon mapping (`RenderSettings::photon_mapping`, which its pilot chooses where that
/// is the best of its configurations: merging at each camera subpath's first diffuse vertex
/// alone) is SPPM's estimator with the global radius schedule, rendered by SPPM's kernels: the
/// same bits as `sppm` with `radius_schedule = "global"`, and its pilot's figures for it those
/// of SPPM's passes (their photons, and a camera path for each direct-light sample).
#[test]
fn vcm_as_photon_mapping_is_sppm_with_the_global_schedule() {
    let Some(gpu) = common::gpu() else { return };
    use sppm_gpu::integrators::shares::{choose_for, Choice, CANDIDATES};
    let mut scene = common::load_scene("cornell-spheres.toml");
    scene.render.photons = 20_000;
    let mut mapping = scene.clone();
    Choice::PHOTON_MAPPING.apply(&mut mapping.render);
    assert!(mapping.render.photon_mapping && !integrators::light::pilot_chooses_shares(&mapping));
    let vcm = common::render_at(&mapping, Method::Vcm, 32, 3);
    scene.render.radius_schedule = sppm_gpu::scene::RadiusSchedule::Global;
    let sppm = common::render_at(&scene, Method::Sppm, 32, 3);
    assert!(vcm.pixels == sppm.pixels, "vcm as photon mapping is not sppm with the global schedule");
    assert!(vcm.pixels.iter().any(|p| p[0] > 0.0));

    // The pilot weighs it where merging alone is the best of the first candidates, with photons
    // in proportion to the pilot's pixels, a visible point's camera paths each pass.
    (scene.render.method, scene.render.width, scene.render.height) = (Method::Vcm, 64, 64);
    let pilot = choose_for(&gpu.device, &gpu.queue, &scene).unwrap();
    let mapped = pilot.candidates.iter().find(|c| c.choice == CANDIDATES[6]).expect("photon mapping weighed");
    assert_eq!(mapped.light_paths, 20_000, "{pilot}");
    let camera_paths = 64.0 * 64.0 * sppm_gpu::integrators::sppm::direct_samples(&scene.render) as f64;
    assert_eq!(mapped.counts[sppm_gpu::layout::WORK_CAMERA_VERTICES as usize], camera_paths);
    assert!(mapped.rel_variance.is_finite() && mapped.rel_variance > 0.0 && mapped.cost > 0.0, "{pilot}");
    // Its bias makes it lose there by far (5x at 64x64): after half its
    // passes and as many paired ones at twice the radius, the pilot runs no more of it.
    use sppm_gpu::integrators::shares::{EARLY_LOSS, PILOT_PASSES};
    let rival = pilot.candidates.iter().filter(|c| c.choice != CANDIDATES[6]).map(|c| c.figure()).fold(f64::INFINITY, f64::min);
    assert!(mapped.bias > 0.0 && mapped.figure() > EARLY_LOSS * rival, "{pilot}");
    assert_eq!(mapped.passes, PILOT_PASSES / 2, "{pilot}");

    // On the room lit through a pane, SPPM's gather takes the light of the tall block's lit top
    // into its front's top rows (a bias the others' merges do not have): the pilot rates photon
    // mapping's noise times cost at about half merging alone's, but its bias, from its passes at
    // two radii (`Candidate::bias`), outweighs its variance over the render's passes (at 60 s,
    // 0.86 of its figure), and it is not chosen.
    let mut skylight = common::load_scene("cornell-skylight.toml");
    (skylight.render.method, skylight.render.width, skylight.render.height) = (Method::Vcm, 64, 64);
    let pilot = choose_for(&gpu.device, &gpu.queue, &skylight).unwrap();
    let mapped = pilot.candidates.iter().find(|c| c.choice == CANDIDATES[6]).expect("photon mapping weighed");
    eprintln!("skylight: photon mapping's bias {:.3e}, relative variance {:.3e}", mapped.bias, mapped.rel_variance);
    assert!(mapped.bias > mapped.rel_variance, "{pilot}");
    assert!(!pilot.chosen.photon_mapping, "{pilot}");
}

/// vcm's pilot weighs its candidates at the light subpaths a pass the render traces: at depth
/// 1,024 (Mitsuba's unbounded depth as read) the store its probe sizes holds merging alone's one
/// for 4 pixels (4,096 at 128x128) and connections' one for 16 (1,024), where a store of every
/// subpath at full depth holds as many as its slots of a stored vertex fit (1,170 on lavapipe's
/// 128 MiB bindings) and the pilot weighed merging alone at a quarter of its light subpaths.
#[test]
fn vcm_pilot_traces_the_renders_light_subpaths() {
    use sppm_gpu::integrators::shares::choose_for;
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("cornell-glossy.toml");
    let r = &mut scene.render;
    (r.method, r.width, r.height, r.max_depth) = (Method::Vcm, 128, 128, 1024);
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    let mut merging = r.clone();
    (merging.connect_share, merging.merge_share) = (Some(0.0), Some(1.0));
    // The store's vertex is a slot's largest part (vcm's merge entry 16 bytes, one a vertex).
    let full_depth = limit.min(integrators::light::LIGHT_VERTEX_BUDGET) / integrators::light::LIGHT_VERTEX_BYTES / 1024;
    assert_eq!(integrators::light::light_paths(&merging, limit, None).unwrap() as u64, full_depth, "at full depth");
    assert!(full_depth < 4096);
    let pilot = choose_for(&gpu.device, &gpu.queue, &scene).unwrap();
    let [both, merge_only] = [0, 1].map(|k| pilot.candidates[k].light_paths);
    assert_eq!((both, merge_only), (1024, 4096), "{pilot}");
}

/// vcm merges only where the BSDF is diffuse (bidir.wgsl's vcm_merges_at): on cornell-glossy
/// with its walls made glossy too, merging's share of the image is black, while with the
/// walls diffuse it carries the room's light (merging on a glossy lobe blurred the reflection:
/// the bias session 20 measured on the gold block).
#[test]
fn vcm_merges_only_at_diffuse_surfaces() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("merge-diffuse");
    let text = std::fs::read_to_string(common::scene_path("cornell-glossy.toml")).unwrap();
    // The walls glossy; the light's black material stays diffuse (it reflects nothing), so
    // that both scenes have the same features and share their kernels.
    let glossy_walls: String = text
        .lines()
        .map(|line| match ["white", "red", "green"].iter().any(|wall| line.starts_with(wall)) {
            true => line.replace("type = \"diffuse\"", "type = \"glossy\", roughness = 0.3") + "\n",
            false => line.to_string() + "\n",
        })
        .collect();
    assert_eq!(glossy_walls.matches("glossy").count(), text.matches("glossy").count() + 3);
    let merge_mean = |scene_text: &str, name: &str| {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, scene_text).unwrap();
        let out = dir.join(format!("{name}.exr"));
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
            .arg(&scene)
            .args(["--method", "vcm", "--width", "24", "--height", "24", "--iterations", "2", "--strategy-images"])
            .args(["--connect-share", "1", "--merge-share", "1", "-o"])
            .arg(&out)
            .output()
            .expect("the binary runs");
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let mean = |strategy: &str| {
            let image = sppm_gpu::image_io::read_image(&dir.join(format!("{name}-{strategy}.exr"))).unwrap();
            image.mean().iter().sum::<f64>() / 3.0
        };
        assert!(mean("connect") > 0.0, "{name}: connections carry no light");
        mean("merge")
    };
    assert_eq!(merge_mean(&glossy_walls, "glossy"), 0.0, "vcm merged at a glossy surface");
    assert!(merge_mean(&text, "diffuse") > 0.0, "vcm did not merge at the diffuse walls");
    let _ = std::fs::remove_dir_all(&dir);
}

/// With merging weighted in, a fixed large radius blurs and brightens corners, and a smaller
/// one less: the error against the reference falls with the radius (the test that merging is
/// there, and converges).
#[test]
fn vcm_error_falls_with_the_radius() {
    if common::gpu().is_none() {
        return;
    }
    let reference = downsample_box(&common::reference("cornell-box.exr"), 256 / SIZE).unwrap();
    let error = |radius: f32| {
        let mut scene = common::load_scene("cornell-box.toml");
        scene.render.radius = Some(radius);
        // Every camera vertex merges (the pilot might leave merging out).
        (scene.render.connect_share, scene.render.merge_share) = (Some(1.0), Some(1.0));
        // alpha near 1: the radius stays near its start over the passes.
        scene.render.alpha = 0.999;
        let c = compare(&common::render_at(&scene, Method::Vcm, SIZE, 16), &reference, 8).unwrap();
        eprintln!("vcm radius {radius}: {c:?}");
        c.rel_mse
    };
    // relMSE 9.3e-3 against 2.3e-4 at 16 passes.
    let (wide, narrow) = (error(0.4), error(0.05));
    assert!(wide > 4.0 * narrow, "relMSE {wide} at radius 0.4, {narrow} at 0.05");
}

/// `--strategy-images`: vcm's image and beside it each strategy's weighted share, rendered
/// again with the same passes and seed, which add up to the image (to f32 rounding), each
/// share carrying light; with the shares left to vcm's pilot too (each strategy's render
/// chooses as the image's did); a method without strategies to weigh is refused before any
/// work.
#[test]
fn strategy_images_add_up_to_the_image() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("strategies");
    let out = dir.join("v.exr");
    let run = |method: &str, shares: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
            .arg(common::scene_path("cornell-spheres.toml"))
            .args(["--method", method, "--width", "32", "--height", "32", "--iterations", "4", "--strategy-images"])
            .args(shares)
            .arg("-o")
            .arg(&out)
            .output()
            .expect("the binary runs")
    };
    let refused = run("sppm", &[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("--strategy-images: method sppm") && !out.exists(), "{stderr}");
    for shares in [&["--connect-share", "1", "--merge-share", "1"][..], &[]] {
        let done = run("vcm", shares);
        let stderr = String::from_utf8_lossy(&done.stderr);
        assert!(done.status.success(), "{stderr}");
        assert_eq!(stderr.contains("vcm's pilot"), shares.is_empty(), "{stderr}");
        let read = |name: &str| sppm_gpu::image_io::read_image(&dir.join(name)).unwrap();
        let image = read("v.exr");
        let mut sum = vec![[0.0f64; 3]; image.pixels.len()];
        for strategy in ["emission", "nee", "connect", "merge", "lt"] {
            let share = read(&format!("v-{strategy}.exr"));
            let total: f64 = share.pixels.iter().flatten().map(|&v| v as f64).sum();
            eprintln!("{shares:?} {strategy}: mean {}", total / (3 * share.pixels.len()) as f64);
            assert!(total > 0.0 || shares.is_empty(), "{strategy} carries no light");
            for (s, p) in sum.iter_mut().zip(&share.pixels) {
                for c in 0..3 {
                    s[c] += p[c] as f64;
                }
            }
        }
        for (s, p) in sum.iter().zip(&image.pixels) {
            for c in 0..3 {
                let close = (s[c] - p[c] as f64).abs() <= 1e-5 * (1.0 + p[c].abs() as f64);
                assert!(close, "{shares:?}: shares add up to {s:?}, the image {p:?}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `compare` renders each method as a render under `--time-limit` alone does, as many passes
/// as fit, and vcm's pilot counts those: its merges stand for a pass of the render it will be
/// (`representative_pass`, 0.42 of its passes), not of the file's `iterations`. compare once
/// left the file's 64 passes to the pilot, whose merges stood for pass 27 of a render that
/// ran 1,100 (Mitsuba's plastic.xml at 30 s).
#[test]
fn compare_pilots_vcm_for_the_passes_that_fit() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("compare-pilot");
    let (scene, reference) = (common::scene_path("cornell-box.toml"), dir.join("ref.exr"));
    let size = ["--width", "32", "--height", "32"];
    let run = |args: &[&std::ffi::OsStr]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_sppm-gpu")).args(args).output().expect("the binary runs");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let os = |s: &'static str| std::ffi::OsStr::new(s);
    let mut render = vec![scene.as_os_str(), os("--iterations"), os("4"), os("-o"), reference.as_os_str()];
    render.extend(size.map(os));
    run(&render);
    // cornell-box.toml says 64 passes; at 32x32 some hundreds fit in 3 s.
    let mut compare = vec![os("compare"), scene.as_os_str(), os("--reference"), reference.as_os_str()];
    compare.extend(["--methods", "vcm", "--time-limit", "3", "--out"].map(os));
    compare.push(dir.as_os_str());
    compare.extend(size.map(os));
    let stderr = run(&compare);
    let pass: u32 = stderr
        .split("merges as at pass ")
        .nth(1)
        .and_then(|rest| rest.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no pilot note: {stderr}"));
    assert!(pass > 64, "the pilot's merges stand for pass {pass}: {stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// vcm's pilot spends on photon mapping only while it can win: at a radius that gathers few
/// photons its noise alone loses to the other candidates' by far (connections do not merge), so
/// after half its passes it runs no more, and its bias (passes at twice the radius, which only
/// add to its figure) is not measured.
#[test]
fn vcm_pilot_stops_weighing_photon_mapping_once_it_has_lost() {
    use sppm_gpu::integrators::shares::{choose_for, CANDIDATES, EARLY_LOSS, PHOTON_MAPPING_MARGIN, PILOT_PASSES};
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("cornell-spheres.toml");
    let r = &mut scene.render;
    (r.method, r.width, r.height, r.radius) = (Method::Vcm, 32, 32, Some(0.002));
    let pilot = choose_for(&gpu.device, &gpu.queue, &scene).unwrap();
    let mapped = pilot.candidates.iter().find(|c| c.choice == CANDIDATES[6]).expect("photon mapping weighed");
    let rival = pilot.candidates.iter().filter(|c| c.choice != CANDIDATES[6]).map(|c| c.figure()).fold(f64::INFINITY, f64::min);
    let alone = mapped.rel_variance * mapped.cost / PHOTON_MAPPING_MARGIN;
    assert!(alone > EARLY_LOSS * rival, "{pilot}");
    assert_eq!(mapped.passes, PILOT_PASSES / 2, "{pilot}");
    assert_eq!(mapped.bias, 0.0, "{pilot}");
    assert!(!pilot.chosen.photon_mapping, "{pilot}");
}

/// Under a time limit vcm's first passes check its pilot's choice (`integrators::check`): the
/// integrator comes back with them done (at least twice `MIN_CHECK_PASSES`, about a tenth of
/// the time the pilot leaves), their seconds in its setup beside the pilot's, and a note of how
/// much they varied against the pilot's reading; on cornell-box, which the pilot reads well,
/// it keeps its choice. A batch's (`FirstPasses::NotRun`, whose first pass must be set before
/// any runs) comes back with none.
#[test]
fn vcm_checks_its_pilots_choice_against_its_first_passes() {
    use sppm_gpu::integrators::{check, create_compiled, FirstPasses};
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::load_scene("cornell-box.toml");
    let r = &mut scene.render;
    (r.method, r.width, r.height, r.iterations, r.time_limit, r.photons) = (Method::Vcm, 32, 32, u32::MAX, Some(4.0), 4000);
    let scene = scene;
    let (checked, _) = create_compiled(&gpu.device, &gpu.queue, &scene, FirstPasses::Checked).unwrap();
    let notes = checked.notes();
    assert_eq!(notes.len(), 2, "{notes:?}");
    let pilot_seconds: f64 = notes[0]
        .split("merges as at pass ")
        .nth(1)
        .and_then(|rest| rest.split(", ").nth(1)?.split(" s)").next()?.parse().ok())
        .unwrap_or_else(|| panic!("no pilot seconds: {}", notes[0]));
    assert!(notes[1].contains("varied") && notes[1].contains("kept, the render goes on"), "{notes:?}");
    assert!(checked.passes() >= 2 * check::MIN_CHECK_PASSES && checked.passes() % 2 == 0, "{} passes", checked.passes());
    assert!(checked.setup_seconds() > pilot_seconds + 0.5 * check::CHECK_SHARE * (4.0 - pilot_seconds) - 0.01, "{notes:?}");
    assert!(checked.setup_seconds() < 4.0, "the check took the whole limit: {notes:?}");
    let (batch, _) = create_compiled(&gpu.device, &gpu.queue, &scene, FirstPasses::NotRun).unwrap();
    assert_eq!((batch.passes(), batch.notes().len()), (0, 1));
}
