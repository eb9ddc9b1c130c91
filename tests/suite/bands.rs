//! Images whose visible points do not fit in one set of buffers are rendered in bands of
//! rows, and the bands give the whole image's pixels bit for bit.

use crate::common;

use sppm_gpu::gpu::GpuContext;
use sppm_gpu::integrators::{self, Bands, Integrator, Sppm};

fn render(mut integrator: impl Integrator, passes: u32) -> sppm_gpu::image_io::Rgb32Image {
    common::run_passes(&mut integrator, passes)
}

#[test]
fn bands_equal_the_whole_image_bit_for_bit() {
    let Some(gpu) = common::gpu() else { return };
    // Three samples a pixel and a thin lens: a point's random numbers depend on its index.
    let mut scene = common::load_scene("cornell-spheres.toml");
    scene.render.width = 40;
    scene.render.height = 32;
    scene.render.spp = 3;
    scene.camera.aperture_radius = 0.05;
    scene.camera.focus_distance = 3.5;
    let whole = render(Sppm::new(&gpu.device, &gpu.queue, &scene).unwrap(), 4);
    // Bands of 7 rows: the last one is shorter.
    let bands = Bands::new(&gpu.device, &gpu.queue, &scene, 7).unwrap();
    assert_eq!(bands.band_count(), 5);
    let banded = render(bands, 4);
    assert_eq!(banded.width, whole.width);
    assert_eq!(banded.height, whole.height);
    let differ = whole.pixels.iter().zip(&banded.pixels).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "{differ} pixels differ");
    assert!(whole.mean()[0] > 0.01, "the image is not black");
}

/// On a device whose storage buffers hold 256 KiB, 96x96 visible points (32 bytes each in the
/// largest buffers: 288 KiB) no longer fit in one set: `integrators::create` renders them in
/// bands, and the image is the one an ordinary device gives.
#[test]
fn an_image_beyond_the_buffer_limit_goes_in_bands() {
    let Some(gpu) = common::gpu() else { return };
    let small = GpuContext::with_limits(|l| wgpu::Limits { max_storage_buffer_binding_size: 256 << 10, ..l }).unwrap();
    let mut scene = common::load_scene("cornell-box.toml");
    scene.render.width = 96;
    scene.render.height = 96;
    assert_eq!(Sppm::max_rows(&small.device, &scene), 85);
    assert!(Sppm::new(&small.device, &small.queue, &scene).is_err(), "one renderer cannot hold it");
    let mut banded = integrators::create(&small.device, &small.queue, &scene).unwrap();
    let mut whole = integrators::create(&gpu.device, &gpu.queue, &scene).unwrap();
    for _ in 0..3 {
        banded.run_pass().unwrap();
        whole.run_pass().unwrap();
    }
    assert_eq!(banded.work_per_pass(), whole.work_per_pass(), "the pass's photons, whatever the bands");
    let (a, b) = (banded.image().unwrap(), whole.image().unwrap());
    assert!(a.pixels == b.pixels, "banded image differs from the whole one");
    // The scene's buffers are counted once; the two bands' per-point buffers add up to about
    // the whole's. Room for photon hits (48 bytes) and for the states of photon threads (64
    // bytes, one thread for each 32 hits of room: two a photon, 16 photons a thread) goes by
    // photons, not points: the first band (85 rows) has its own, within the small device's
    // buffer size, so it gathers 74 times a pass. The second (11 rows: 189 photons a visible
    // point) adds its hits at once and has none (buffers of the 16 and 64 bytes minimum).
    let (m_banded, m_whole) = (banded.gpu_memory(), whole.gpu_memory());
    assert_eq!(m_banded.scene, m_whole.scene);
    let by_photons = ["photon_hits", "photon_suspended"];
    let per_point = |m: &integrators::GpuMemory| {
        m.renderer.iter().filter(|(n, _)| !by_photons.contains(&n.as_str())).map(|(_, b)| b).sum::<u64>()
    };
    let ratio = per_point(&m_banded) as f64 / per_point(&m_whole) as f64;
    assert!((0.95..1.3).contains(&ratio), "banded renderer memory {ratio}x the whole one's");
    let hits = (256 << 10) / 48;
    for (name, bands) in by_photons.iter().zip([hits * 48 + 16, hits / 32 * 64 + 64]) {
        let bytes: u64 = m_banded.renderer.iter().filter(|(n, _)| n == name).map(|(_, b)| b).sum();
        assert_eq!(bytes, bands, "two bands' {name}");
    }
    small.check().unwrap();
}

/// The path tracers go in bands the same way (16 bytes a pixel: 128x128 is 256 KiB).
#[test]
fn path_tracer_bands_equal_the_whole_image() {
    let Some(gpu) = common::gpu() else { return };
    let small = GpuContext::with_limits(|l| wgpu::Limits { max_storage_buffer_binding_size: 128 << 10, ..l }).unwrap();
    let mut scene = common::load_scene("cornell-box.toml");
    scene.render.width = 128;
    scene.render.height = 128;
    scene.render.method = sppm_gpu::scene::Method::PtNee;
    assert_eq!(integrators::max_rows(&small.device, &scene), 64);
    let mut banded = integrators::create(&small.device, &small.queue, &scene).unwrap();
    let mut whole = integrators::create(&gpu.device, &gpu.queue, &scene).unwrap();
    for _ in 0..2 {
        banded.run_pass().unwrap();
        whole.run_pass().unwrap();
    }
    assert_eq!(banded.work_per_pass(), whole.work_per_pass(), "a sample per pixel either way");
    assert!(banded.image().unwrap().pixels == whole.image().unwrap().pixels, "banded image differs");
    small.check().unwrap();
}

/// vcm in bands renders its pilot's choice and reports it as a whole image does: its note, its
/// time (which a time limit counts) and its choice (which a checkpoint keeps).
#[test]
fn vcm_bands_report_the_pilot() {
    if common::gpu().is_none() {
        return;
    }
    // The pilot's image (128x128) fits the small device's buffers, the render's does not.
    let small = GpuContext::with_limits(|l| wgpu::Limits { max_storage_buffer_binding_size: 512 << 10, ..l }).unwrap();
    let mut scene = common::load_scene("cornell-box.toml");
    (scene.render.width, scene.render.height, scene.render.iterations) = (256, 256, 16);
    scene.render.method = sppm_gpu::scene::Method::Vcm;
    assert!(integrators::max_rows(&small.device, &scene) < 256, "the small device bands");
    let banded = integrators::create(&small.device, &small.queue, &scene).unwrap();
    let note = banded.notes().join(" ");
    assert!(
        note.contains("vcm's pilot (") && note.contains(&banded.pilot_choice().expect("a choice kept").to_string()),
        "{note}"
    );
    assert!(banded.setup_seconds() > 0.0);
    small.check().unwrap();
}
