//! Pixel filters by filter importance sampling (`sample_filter` in shaders/shared/camera.wgsl):
//! the offsets `camera_ray` draws follow each filter's density (a KS test per axis and a
//! chi-square test of the pair, on the WGSL itself, and mutants of the samplers fail them);
//! the box draws the same numbers and rays as before filters, bit for bit; SPPM's camera pass
//! uses the filter too. And by weighted splatting (the path tracers', bpt's and vcm's camera
//! samples, shaders/filter_splat.wgsl): a sharp edge rendered with each filter (pt) is the step
//! convolved with the normalized filter, pixel by pixel; a pixel averages as many pixels'
//! samples as the filter's shape says; bands and texture resolves give the host's image.

use crate::common;

use glam::Vec3;
use sppm_gpu::gpu::readback::{read_buffer, staging_buffer};
use sppm_gpu::gpu::scene_buffers::storage_buffer;
use sppm_gpu::gpu::{GpuContext, Kernel, Resource};
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators::filter::{gaussian_filter_cdf, pixel_filter_constants};
use sppm_gpu::integrators::{self, set_pixel_filter, Integrator};
use sppm_gpu::layout::{Frame, FILTER_TABLE_SIZE};
use sppm_gpu::scene::{Method, PixelFilter, Scene, SceneBuilder};
use wgpu::util::DeviceExt;

// The oracle: each filter's normalized density and CDF, in f64, written from Mitsuba 3's
// definitions independently of the code under test.

/// erf by its Taylor series (Abramowitz & Stegun 7.1.5), good to about 1e-14 for |x| <= 3.
fn erf(x: f64) -> f64 {
    let (mut term, mut sum, x2) = (x, x, x * x);
    for n in 1..200 {
        term *= -x2 / n as f64;
        let add = term / (2 * n + 1) as f64;
        sum += add;
        if add.abs() < 1e-17 {
            break;
        }
    }
    sum * 2.0 / std::f64::consts::PI.sqrt()
}

/// Half-width of the filter's support, pixels.
fn support(filter: PixelFilter) -> f64 {
    match filter {
        PixelFilter::Box => 0.5,
        PixelFilter::Tent { radius } => radius as f64,
        PixelFilter::Gaussian { stddev } => 4.0 * stddev as f64,
    }
}

/// P(offset < x) for an offset drawn from the normalized filter.
fn filter_cdf(filter: PixelFilter, x: f64) -> f64 {
    let r = support(filter);
    let x = x.clamp(-r, r);
    match filter {
        PixelFilter::Box => x + 0.5,
        PixelFilter::Tent { .. } if x < 0.0 => 0.5 * (1.0 + x / r).powi(2),
        PixelFilter::Tent { .. } => 1.0 - 0.5 * (1.0 - x / r).powi(2),
        PixelFilter::Gaussian { stddev } => {
            // The integral of exp(-x^2 / (2 s^2)) - exp(-8) from -4 s to x, over that to 4 s.
            let s = stddev as f64;
            let bias = (-8.0f64).exp();
            let integral = |x: f64| {
                s * (std::f64::consts::PI / 2.0).sqrt() * (erf(x / (s * 2f64.sqrt())) + erf(2.0 * 2f64.sqrt())) - bias * (x + r)
            };
            integral(x) / integral(r)
        }
    }
}

/// The x with filter_cdf(x) = p, by bisection.
fn filter_quantile(filter: PixelFilter, p: f64) -> f64 {
    let (mut lo, mut hi) = (-support(filter), support(filter));
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if filter_cdf(filter, mid) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

const TENT: PixelFilter = PixelFilter::Tent { radius: 1.0 };
const GAUSSIAN: PixelFilter = PixelFilter::Gaussian { stddev: 0.5 };

#[test]
fn the_oracle_is_right() {
    assert!((erf(1.0) - 0.842_700_792_949_714_9).abs() < 1e-14);
    assert!((erf(2.0 * 2f64.sqrt()) - 0.999_936_657_516_334_3).abs() < 1e-13);
    for filter in [TENT, PixelFilter::Tent { radius: 1.7 }, GAUSSIAN, PixelFilter::Gaussian { stddev: 0.8 }] {
        let r = support(filter);
        assert!(filter_cdf(filter, -r).abs() < 1e-12 && (filter_cdf(filter, r) - 1.0).abs() < 1e-12);
        assert!((filter_cdf(filter, 0.0) - 0.5).abs() < 1e-12, "{filter:?} is symmetric");
        // The CDF's slope is the filter over its integral (Simpson's rule on 2000 panels, a
        // node at the tent's kink): compare at a few points.
        let f = |x: f64| match filter {
            PixelFilter::Tent { .. } => (1.0 - x.abs() / r).max(0.0),
            PixelFilter::Gaussian { stddev } => {
                let s = stddev as f64;
                ((-x * x / (2.0 * s * s)).exp() - (-8.0f64).exp()).max(0.0)
            }
            PixelFilter::Box => unreachable!(),
        };
        let h = 2.0 * r / 2000.0;
        let norm = h / 3.0
            * (0..=2000)
                .map(|k| [1.0, 4.0, 2.0][if k == 0 || k == 2000 { 0 } else { 2 - k % 2 }] * f(-r + h * k as f64))
                .sum::<f64>();
        for x in [-0.7, 0.1, 0.3, 0.45, 0.9] {
            let x = x * r;
            let slope = (filter_cdf(filter, x + 1e-5) - filter_cdf(filter, x - 1e-5)) / 2e-5;
            assert!((slope - f(x) / norm).abs() < 1e-6, "{filter:?} at {x}: {slope} against {}", f(x) / norm);
        }
    }
}

/// The gaussian's table holds the CDF of the half filter at its nodes, increasing to 1, and a
/// filter width that is not a positive number is refused.
#[test]
fn the_gaussian_table_is_its_cdf() {
    let table = gaussian_filter_cdf();
    let n = FILTER_TABLE_SIZE as usize;
    let c = |j: usize| if j == 0 { 0.0 } else { table[(j - 1) / 4][(j - 1) % 4] };
    assert_eq!(c(n), 1.0);
    for j in 1..=n {
        assert!(c(j) > c(j - 1) || j > n - 8, "C_{j} = {} after {}", c(j), c(j - 1));
        // In standard deviations the half filter's CDF is 2 F(t) - 1 for the filter of stddev 1.
        let t = 4.0 * j as f64 / n as f64;
        let expected = 2.0 * filter_cdf(PixelFilter::Gaussian { stddev: 1.0 }, t) - 1.0;
        assert!((c(j) as f64 - expected).abs() < 2e-7, "C_{j} = {} against {expected}", c(j));
    }
    let mut frame = Frame::default();
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(set_pixel_filter(&mut frame, PixelFilter::Tent { radius: bad }).is_err());
        assert!(set_pixel_filter(&mut frame, PixelFilter::Gaussian { stddev: bad }).is_err());
    }
}

// camera_ray on the GPU: the trace_rays kernel with its body replaced by a call of it (and
// the files it needs added), so the test runs the WGSL that the integrators run.

/// shaders/shared/camera.wgsl before pixel filters, for the test that the box is unchanged.
const CAMERA_BEFORE_FILTERS: &str = r#"// Primary rays: a uniform point in the pixel's square (box filter), through a pinhole or a
// thin lens.

struct Ray {
    o: vec3f,
    d: vec3f,
}

// The ray through pixel (px, py) of this renderer's rows: row py + frame.row_offset of the
// image. Draws four numbers from rng, lens or not, so that what
// follows sees the same stream either way.
fn camera_ray(px: u32, py: u32, rng: ptr<function, Rng>) -> Ray {
    // The image plane at distance 1: cam_right and cam_up span half its width and height.
    let jitter = rng_next2(rng);
    let sx = 2.0 * (f32(px) + jitter.x) / f32(frame.width) - 1.0;
    let sy = 1.0 - 2.0 * (f32(py + frame.row_offset) + jitter.y) / f32(frame.image_height);
    let dir_pinhole = frame.cam_forward + sx * frame.cam_right + sy * frame.cam_up;
    let lens_u = rng_next2(rng);
    if frame.lens_radius > 0.0 {
        // Thin lens: aim through the point that the pinhole ray meets on the focal plane.
        let lens = frame.lens_radius * sample_disk(lens_u);
        let focus = frame.cam_position + frame.focus_distance * dir_pinhole;
        let o = frame.cam_position + lens.x * normalize(frame.cam_right) + lens.y * normalize(frame.cam_up);
        return Ray(o, normalize(focus - o));
    }
    return Ray(frame.cam_position, normalize(dir_pinhole));
}
"#;

const CAMERA: &str = include_str!("../../shaders/shared/camera.wgsl");
const ENTRY: &str = "@compute @workgroup_size(64)\nfn trace_rays";
const BODY: &str = "    let o = rays[2u * index];
    let d = rays[2u * index + 1u].xyz;
    if ANY_HIT {
        let blocked = occluded(o.xyz, d, o.w);
        hits[index] = vec4f(0.0, bitcast<f32>(select(0xffffffffu, 0u, blocked)), 0.0, 0.0);
        return;
    }
    let hit = trace_closest(o.xyz, d, o.w);
    hits[index] = vec4f(hit.t, bitcast<f32>(hit.prim_ref), hit.b.x, hit.b.y);
";
/// Sample i: the ray of pixel (i % width, i / width % height) from the stream keyed by i, and
/// the next number of that stream, as (o, next) and (d, 0).
const CAMERA_BODY: &str = "    if index >= arrayLength(&hits) / 2u {
        return;
    }
    let px = index % frame.width;
    let py = index / frame.width % frame.height;
    var rng = rng_new(frame.seed, frame.pass_index, 0u, index);
    let ray = camera_ray(px, py, &rng);
    hits[2u * index] = vec4f(ray.o, rng_next(&rng));
    hits[2u * index + 1u] = vec4f(ray.d, 0.0);
";

/// A kernel running `camera` (the text of shaders/shared/camera.wgsl, or a variant of it)
/// with pipeline constants `constants`.
fn camera_kernel(gpu: &GpuContext, camera: &str, constants: &[(&str, f64)]) -> Kernel {
    let source = crate::common::test_kernel_source("trace_rays");
    assert!(source.contains(ENTRY) && source.contains(BODY), "trace_rays.wgsl changed: update this test");
    // rng.wgsl's import of the Sobol sampler spelled out (its SAMPLER_SOBOL left false).
    let rng =
        include_str!("../../shaders/shared/rng.wgsl").replace("#import sobol", include_str!("../../shaders/shared/sobol.wgsl"));
    let prefix = [rng.as_str(), include_str!("../../shaders/shared/sampling.wgsl"), camera, ENTRY].join("\n");
    crate::common::test_kernel(gpu, "trace_rays", &[(ENTRY, &prefix), (BODY, CAMERA_BODY)], constants)
}

/// `count` samples of `kernel` under `frame`: per sample (origin, next number) and (direction, 0).
fn camera_rays(gpu: &GpuContext, kernel: &Kernel, frame: &Frame, count: u32) -> Vec<[[f32; 4]; 2]> {
    let hits = storage_buffer(&gpu.device, "hits", &vec![[0f32; 4]; 2 * count as usize]);
    let frame_buffer = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("frame"),
        contents: bytemuck::bytes_of(frame),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let resources = [Resource { name: "frame", buffer: &frame_buffer }, Resource { name: "hits", buffer: &hits }];
    let group = kernel.bind_group(&gpu.device, &resources).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    kernel.dispatch(&mut encoder, &group, count);
    gpu.queue.submit([encoder.finish()]);
    let staging = staging_buffer(&gpu.device, "hits_staging", hits.size());
    let out: Vec<[f32; 4]> = read_buffer(&gpu.device, &gpu.queue, &hits, &staging, hits.size()).unwrap();
    out.chunks(2).map(|c| [c[0], c[1]]).collect()
}

/// A frame whose image plane maps raster (x, y) to the direction (x - 1, 1 - y, 1): a 2 x 2
/// image of which this renderer has row 1 (row_offset 1), so the y offsets pass through the
/// band's offset too.
fn offset_frame(filter: PixelFilter) -> Frame {
    let mut frame = Frame {
        cam_forward: [0.0, 0.0, 1.0],
        cam_right: [1.0, 0.0, 0.0],
        cam_up: [0.0, 1.0, 0.0],
        width: 2,
        height: 1,
        image_height: 2,
        row_offset: 1,
        seed: 11,
        ..Frame::default()
    };
    set_pixel_filter(&mut frame, filter).unwrap();
    frame
}

/// The samples' offsets from their pixels' centres, (x, y) in pixels, from their directions.
fn offsets(rays: &[[[f32; 4]; 2]]) -> Vec<[f64; 2]> {
    rays.iter()
        .enumerate()
        .map(|(i, r)| {
            let d = r[1].map(f64::from);
            let (raster_x, raster_y) = (d[0] / d[2] + 1.0, 1.0 - d[1] / d[2]);
            [raster_x - ((i % 2) as f64 + 0.5), raster_y - 1.5]
        })
        .collect()
}

/// Whether two samples are the same, bit for bit.
fn same_bits(a: &[[f32; 4]; 2], b: &[[f32; 4]; 2]) -> bool {
    a.as_flattened().iter().map(|v| v.to_bits()).eq(b.as_flattened().iter().map(|v| v.to_bits()))
}

/// Kolmogorov-Smirnov statistic of `samples` against `cdf`.
fn ks_statistic(mut samples: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len() as f64;
    samples.iter().enumerate().map(|(i, &x)| (cdf(x) - i as f64 / n).max((i + 1) as f64 / n - cdf(x))).fold(0.0, f64::max)
}

/// Samples per density test.
const SAMPLES: u32 = 1 << 20;
/// Chance of a false alarm of one test; under 1e-5 over the file.
const ALPHA: f64 = 1e-7;

/// The KS statistic beyond which the test rejects: P(D > d) <= 2 exp(-2 n d^2) (the
/// Dvoretzky-Kiefer-Wolfowitz inequality with Massart's constant), set to ALPHA. With 2^20
/// samples d = 0.0028; the sampled density differs from the filter's by at most 3e-5 of its
/// peak (the gaussian's table), far below it.
fn ks_limit(n: usize) -> f64 {
    ((2.0 / ALPHA).ln() / (2.0 * n as f64)).sqrt()
}

/// Whether `offsets` pass as drawn from `filter` (a KS test per axis, a chi-square test of
/// the pair on 10 x 10 cells of equal expected counts: the density is the product of the
/// axes'); the statistics, for the messages.
fn follows(filter: PixelFilter, offsets: &[[f64; 2]]) -> (bool, String) {
    let n = offsets.len();
    let ks = [0, 1].map(|axis| ks_statistic(offsets.iter().map(|o| o[axis]).collect(), |x| filter_cdf(filter, x)));
    const CELLS: usize = 10;
    let edges: Vec<f64> = (1..CELLS).map(|k| filter_quantile(filter, k as f64 / CELLS as f64)).collect();
    let cell = |x: f64| edges.partition_point(|&e| e <= x);
    let mut counts = [[0u32; CELLS]; CELLS];
    for o in offsets {
        counts[cell(o[0])][cell(o[1])] += 1;
    }
    let expected = n as f64 / (CELLS * CELLS) as f64;
    let chi2: f64 = counts.iter().flatten().map(|&c| (c as f64 - expected).powi(2) / expected).sum();
    // The chi-square quantile for p = ALPHA (z = 5.2) by Wilson & Hilferty's approximation.
    let dof = (CELLS * CELLS - 1) as f64;
    let chi2_limit = dof * (1.0 - 2.0 / (9.0 * dof) + 5.2 * (2.0 / (9.0 * dof)).sqrt()).powi(3);
    let ok = ks.iter().all(|&d| d < ks_limit(n)) && chi2 < chi2_limit;
    (ok, format!("KS x {:.5} y {:.5} (limit {:.5}), chi2 {chi2:.1} (limit {chi2_limit:.1})", ks[0], ks[1], ks_limit(n)))
}

#[test]
fn camera_samples_follow_the_filters() {
    let Some(gpu) = common::gpu() else { return };
    // Kernels for any filter (the constants' defaults), as the integrators' are for theirs.
    let any = camera_kernel(&gpu, CAMERA, &[]);
    for filter in [PixelFilter::Box, TENT, PixelFilter::Tent { radius: 1.7 }, GAUSSIAN, PixelFilter::Gaussian { stddev: 0.8 }] {
        let frame = offset_frame(filter);
        let rays = camera_rays(&gpu, &any, &frame, SAMPLES);
        let (ok, stats) = follows(filter, &offsets(&rays));
        eprintln!("{filter:?}: {stats}");
        assert!(ok, "{filter:?}: {stats}");
        // The kernel compiled for this filter alone draws the same rays.
        let own = camera_kernel(&gpu, CAMERA, &pixel_filter_constants(filter));
        let own_rays = camera_rays(&gpu, &own, &frame, SAMPLES);
        assert!(rays.iter().zip(&own_rays).all(|(a, b)| same_bits(a, b)), "{filter:?}: its own kernel differs");
    }
    // Mutants: a wrong tent inverse, a gaussian 5% too wide. The tests must catch them.
    let mutants = [
        (TENT, "sqrt(2.0 * u) - 1.0", "sqrt(u) - 1.0"),
        (GAUSSIAN, "return select(t, -t, u < 0.5) * stddev;", "return select(t, -t, u < 0.5) * stddev * 1.05;"),
    ];
    for (filter, from, to) in mutants {
        assert!(CAMERA.contains(from), "camera.wgsl changed: update the mutant `{from}`");
        let kernel = camera_kernel(&gpu, &CAMERA.replace(from, to), &[]);
        let (ok, stats) = follows(filter, &offsets(&camera_rays(&gpu, &kernel, &offset_frame(filter), SAMPLES)));
        eprintln!("{filter:?} with `{to}`: {stats}");
        assert!(!ok, "the mutant `{to}` of {filter:?} passes: {stats}");
    }
    gpu.check().unwrap();
}

/// The box draws the numbers it drew before filters and makes the same rays, bit for bit, with
/// and without a lens, in the kernel compiled for it and in the one for any filter; the number
/// after them is the same too, so everything downstream of camera_ray is unchanged.
#[test]
fn the_box_is_unchanged_bit_for_bit() {
    let Some(gpu) = common::gpu() else { return };
    let scene = SceneBuilder::new(16, 12)
        .camera([0.3, -0.2, 4.0], [0.1, 0.2, 0.0], [0.0, 1.0, 0.0], 37.0)
        .diffuse("light", [0.0; 3])
        .quad([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "light")
        .emission([1.0; 3])
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let before = camera_kernel(&gpu, CAMERA_BEFORE_FILTERS, &[]);
    let kernels = [camera_kernel(&gpu, CAMERA, &[]), camera_kernel(&gpu, CAMERA, &pixel_filter_constants(PixelFilter::Box))];
    for lens_radius in [0.0, 0.07] {
        // A band: rows 3..11 of the 12.
        let mut frame = integrators::camera_frame_for(&scene.camera, 16, 12);
        (frame.height, frame.row_offset, frame.seed, frame.pass_index) = (8, 3, 5, 9);
        (frame.lens_radius, frame.focus_distance) = (lens_radius, 3.5);
        set_pixel_filter(&mut frame, PixelFilter::Box).unwrap();
        let expected = camera_rays(&gpu, &before, &frame, 1 << 16);
        for kernel in &kernels {
            let rays = camera_rays(&gpu, kernel, &frame, 1 << 16);
            let differ = expected.iter().zip(&rays).filter(|(a, b)| !same_bits(a, b)).count();
            assert_eq!(differ, 0, "lens {lens_radius}: {differ} samples differ");
        }
    }
    gpu.check().unwrap();
}

// Images of a sharp edge: an emitting quad (radiance 1) covers the image plane left of raster
// x = EDGE, black beyond, so a pixel is the fraction of its samples that land left of the
// edge: F(EDGE - centre), F the CDF of the filter's offsets.

const WIDTH: u32 = 16;
const HEIGHT: u32 = 16;

/// The edge scene for `method` and `filter`, the edge at raster x = `edge`.
fn edge_scene(edge: f32, method: Method, filter: PixelFilter) -> Scene {
    let fov = 40.0f32;
    let tan_half = (0.5 * fov.to_radians()).tan();
    // The image plane at distance 1 spans x in [-tan_half aspect, tan_half aspect].
    let x_edge = (2.0 * edge / WIDTH as f32 - 1.0) * tan_half * (WIDTH as f32 / HEIGHT as f32);
    let mut scene = SceneBuilder::new(WIDTH, HEIGHT)
        .method(method)
        .camera([0.0; 3], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0], fov)
        .diffuse("black", [0.0; 3])
        .quad(Vec3::new(-10.0, -10.0, -1.0), Vec3::new(x_edge + 10.0, 0.0, 0.0), Vec3::new(0.0, 20.0, 0.0), "black")
        .emission([1.0; 3])
        .photons(1000)
        .seed(3)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    scene.render.filter = filter;
    scene
}

/// `passes` passes of `scene`, recorded 256 to a submission.
fn render(gpu: &GpuContext, scene: &Scene, passes: u32) -> Rgb32Image {
    let mut integrator = integrators::create(&gpu.device, &gpu.queue, scene).unwrap();
    let mut done = 0;
    while done < passes {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        for _ in done..passes.min(done + 256) {
            integrator.record_pass(&mut encoder);
        }
        done = passes.min(done + 256);
        gpu.queue.submit([encoder.finish()]);
    }
    integrator.image().unwrap()
}

/// How far the mean of `n` independent samples in [0, 1] of mean p may stray from p:
/// Bernstein's inequality, P(|mean - p| >= t) <= 2 exp(-n t^2 / (2 v + 2 t / 3)) with
/// v = p (1 - p) the variance of a 0-or-1 sample, set to ALPHA and solved for t. Where p is 0
/// or 1 the samples are all equal and the mean exact (sums of 0 and 1 in f32 are exact).
fn noise_bound(p: f64, n: f64) -> f64 {
    let l = (2.0 / ALPHA).ln();
    let v = p * (1.0 - p);
    (2.0 * l / 3.0 + ((2.0 * l / 3.0).powi(2) + 8.0 * n * l * v).sqrt()) / (2.0 * n)
}

/// Error margin of the expected values themselves: the gaussian's table and f32 rays.
const MODEL_ERROR: f64 = 1e-5;

/// Whether `img` (`samples` a pixel) is the edge at `edge` seen through `filter`, pixel by
/// pixel and column by column (each column's rows are samples of one value); the worst
/// deviation in units of its bound, for the messages.
fn matches_edge(img: &Rgb32Image, samples: u32, edge: f64, filter: PixelFilter) -> (bool, f64) {
    let expected = |x: u32| filter_cdf(filter, edge - (x as f64 + 0.5));
    let mut worst: f64 = 0.0;
    for x in 0..WIDTH {
        let p = expected(x);
        let mut column = 0.0;
        for y in 0..HEIGHT {
            let v = img.pixels[(y * WIDTH + x) as usize][0] as f64;
            column += v / HEIGHT as f64;
            worst = worst.max((v - p).abs() / (noise_bound(p, samples as f64) + MODEL_ERROR));
        }
        worst = worst.max((column - p).abs() / (noise_bound(p, (samples * HEIGHT) as f64) + MODEL_ERROR));
    }
    (worst <= 1.0, worst)
}

#[test]
fn an_edge_is_the_step_convolved_with_the_filter() {
    let Some(gpu) = common::gpu() else { return };
    // 0.3 pixel into column 8: the box's column 8 is 0.3.
    let edge = 8.3;
    let passes = 8192;
    let filters = [PixelFilter::Box, TENT, GAUSSIAN];
    for filter in filters {
        let img = render(&gpu, &edge_scene(edge as f32, Method::Pt, filter), passes);
        let (ok, worst) = matches_edge(&img, passes, edge, filter);
        let row: Vec<String> = (5..11).map(|x| format!("{:.4}", img.pixels[x][0])).collect();
        eprintln!("{filter:?}: columns 5..11 of row 0 {row:?}, worst deviation {worst:.3} of its bound");
        assert!(ok, "{filter:?}: a pixel or column is {worst:.3} times its bound from the convolved edge");
        // The test tells the filters apart: the others' edges do not match.
        for other in filters.iter().filter(|&&o| o != filter) {
            assert!(!matches_edge(&img, passes, edge, *other).0, "{filter:?}'s image passes for {other:?}'s");
        }
    }
    gpu.check().unwrap();
}

/// SPPM's camera pass draws its samples from the filter too: with the edge at the image's
/// middle, the gaussian's columns are the convolved edge, and the image's mean stays the
/// box's (a symmetric filter moves as much light across the edge each way: F(a) + F(-a) = 1
/// for the columns a pixel either side, so both means are 1/2).
#[test]
fn sppm_camera_pass_uses_the_filter() {
    let Some(gpu) = common::gpu() else { return };
    let edge = WIDTH as f64 / 2.0;
    let passes = 64;
    let mut means = Vec::new();
    for filter in [PixelFilter::Box, GAUSSIAN] {
        let mut scene = edge_scene(edge as f32, Method::Sppm, filter);
        scene.render.spp = 16;
        let img = render(&gpu, &scene, passes);
        let samples = passes * scene.render.spp;
        let (ok, worst) = matches_edge(&img, samples, edge, filter);
        assert!(ok, "SPPM {filter:?}: a pixel or column is {worst:.3} times its bound from the convolved edge");
        means.push(img.mean()[0]);
    }
    // The mean of WIDTH * HEIGHT pixels of `samples` each; the variance of a pixel's mean is at
    // most 1/4 over its samples, and only the 4 columns the gaussian reaches across vary.
    let samples = (passes * 16 * 4 * HEIGHT) as f64;
    let bound = 4.0 / WIDTH as f64 * noise_bound(0.5, samples);
    eprintln!("SPPM image means: box {}, gaussian {} (bound {bound:.5})", means[0], means[1]);
    assert!((means[0] - 0.5).abs() < MODEL_ERROR, "box mean {}", means[0]);
    assert!((means[1] - means[0]).abs() < bound, "gaussian mean {} against the box's {}", means[1], means[0]);
    gpu.check().unwrap();
}

/// `scene` as it splats its camera samples under a wide filter: SPPM with the global radius
/// schedule and one visible point a pixel (its passes then estimate on their own), the
/// others as they are.
fn splatting(mut scene: Scene) -> Scene {
    if scene.render.method == Method::Sppm {
        (scene.render.radius_schedule, scene.render.spp) = (sppm_gpu::scene::RadiusSchedule::Global, 1);
    }
    scene
}

/// SPPM with the global radius schedule splats each pass's estimate of a visible point as the
/// path tracers splat their samples, its first camera path's direct light with it and the
/// other paths' summed apart: the edge is the step convolved with the filter, pixel by pixel
/// and column by column, with one path a point and with four, and not the other filter's.
#[test]
fn sppm_splats_its_passes_under_the_global_schedule() {
    let Some(gpu) = common::gpu() else { return };
    let edge = 7.6;
    let passes = 1024;
    for (filter, paths) in [(GAUSSIAN, 1), (TENT, 4)] {
        let mut scene = splatting(edge_scene(edge as f32, Method::Sppm, filter));
        scene.render.direct_samples = Some(paths);
        assert_eq!(sppm_gpu::integrators::sppm::splat_reach_of(&scene.render), filter.splat_reach());
        let img = render(&gpu, &scene, passes);
        let (ok, worst) = matches_edge(&img, passes, edge, filter);
        eprintln!("SPPM splatted, {filter:?}, {paths} paths a point: worst deviation {worst:.3} of its bound");
        assert!(ok, "SPPM {filter:?}, {paths} paths: a pixel or column is {worst:.3} times its bound from the convolved edge");
        let other = if filter == TENT { GAUSSIAN } else { TENT };
        assert!(!matches_edge(&img, passes, edge, other).0, "SPPM {filter:?}'s image passes for {other:?}'s");
    }
    gpu.check().unwrap();
}

/// Banded images: bands of rows give the whole image's gaussian-filtered pixels bit for bit
/// (a sample's raster position and random numbers depend on its row in the whole image; a
/// band traces the rows its filter reaches beyond it), for pt-nee, for bpt, whose light
/// subpaths' splats each band sums apart, and for SPPM's splatted passes (its visible points
/// of those rows gather the same photons in every band).
#[test]
fn gaussian_bands_equal_the_whole_image() {
    let Some(gpu) = common::gpu() else { return };
    for method in [Method::PtNee, Method::Bpt, Method::Sppm] {
        let scene = splatting(edge_scene(7.6, method, GAUSSIAN));
        let whole = render(&gpu, &scene, 16);
        let mut bands = integrators::Bands::new(&gpu.device, &gpu.queue, &scene, 6).unwrap();
        assert_eq!(bands.band_count(), 3);
        for _ in 0..16 {
            bands.run_pass().unwrap();
        }
        let banded = bands.image().unwrap();
        assert!(whole.pixels == banded.pixels, "{method:?}: the bands differ from the whole image");
    }
    gpu.check().unwrap();
}

/// The filter's density up to its normalization, from the oracle's definitions.
fn filter_shape(filter: PixelFilter, x: f64) -> f64 {
    let r = support(filter);
    match filter {
        _ if x.abs() > r => 0.0,
        PixelFilter::Box => 1.0,
        PixelFilter::Tent { .. } => 1.0 - x.abs() / r,
        PixelFilter::Gaussian { stddev } => (-0.5 * (x / stddev as f64).powi(2)).exp() - (-8.0f64).exp(),
    }
}

/// How many pixels' samples a splatted pixel averages: `((∫f)^2 / ∫f^2)^2` for the separable
/// filter f (pi for the gaussian of standard deviation 1/2, 9/4 for the tent of radius 1), by
/// the midpoint rule.
fn splat_gain(filter: PixelFilter) -> f64 {
    let (r, n) = (support(filter), 100_000);
    let dx = 2.0 * r / n as f64;
    let xs = (0..n).map(|i| -r + (i as f64 + 0.5) * dx);
    let (f, f2) = xs.fold((0.0, 0.0), |(a, b), x| (a + filter_shape(filter, x) * dx, b + filter_shape(filter, x).powi(2) * dx));
    (f * f / f2).powi(2)
}

/// A white wall filling the view, lit by a square light behind the camera: naive path
/// tracing's samples, one bounce each, are 0 or the light's radiance reflected, independent
/// noise about a flat image (the independent sampler: Sobol points stratify a pixel's own
/// samples, which on this two-dimensional integrand the splat's weights partly undo).
fn noisy_wall(filter: PixelFilter, seed: u32, size: u32) -> Scene {
    let mut scene = SceneBuilder::new(size, size)
        .method(Method::Pt)
        .camera([0.0; 3], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0], 40.0)
        .diffuse("white", [0.8; 3])
        .quad(Vec3::new(-10.0, -10.0, -1.0), Vec3::new(20.0, 0.0, 0.0), Vec3::new(0.0, 20.0, 0.0), "white")
        // Facing the wall (-z), behind the camera.
        .quad(Vec3::new(-1.0, -1.0, 0.5), Vec3::new(0.0, 2.0, 0.0), Vec3::new(2.0, 0.0, 0.0), "white")
        .emission([1.0; 3])
        .max_depth(1)
        .photons(1000)
        .seed(seed)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    (scene.render.filter, scene.render.sampler) = (filter, sppm_gpu::sampler::Sampler::Independent);
    scene
}

/// Weighted splatting, the path tracers' estimator under a filter wider than the box: a pixel
/// averages the samples of every pixel its filter reaches, so on a flat, noisy image its
/// variance is one sample's over ((∫f)^2 / ∫f^2)^2 samples a pass, pi of them under Mitsuba's
/// default gaussian and 9/4 under the tent of radius 1, where the box (and filter importance
/// sampling, which fails this) averages one. The variance of each image is read from the
/// difference of two seeds' renders, away from the edges.
#[test]
fn splatting_averages_the_pixels_a_filter_reaches() {
    let Some(gpu) = common::gpu() else { return };
    let (size, passes, border) = (96u32, 64, 3);
    let variance = |filter: PixelFilter| {
        let a = render(&gpu, &noisy_wall(filter, 1, size), passes);
        let b = render(&gpu, &noisy_wall(filter, 2, size), passes);
        let (mut sum, mut n) = (0.0, 0.0);
        for y in border..size - border {
            for x in border..size - border {
                let i = (y * size + x) as usize;
                sum += (a.pixels[i][0] as f64 - b.pixels[i][0] as f64).powi(2) / 2.0;
                n += 1.0;
            }
        }
        (sum / n, a.mean()[0])
    };
    let (box_variance, box_mean) = variance(PixelFilter::Box);
    for filter in [GAUSSIAN, TENT] {
        let (v, mean) = variance(filter);
        let (gain, expected) = (box_variance / v, splat_gain(filter));
        eprintln!("{filter:?}: variance {v:.4e} (box {box_variance:.4e}): {gain:.3} pixels' samples, expected {expected:.3}");
        assert!(
            (gain / expected - 1.0).abs() < 0.12,
            "{filter:?}: a pixel averages {gain:.3} pixels' samples, not {expected:.3}"
        );
        // The same light: the flat image's mean is the box's.
        assert!((mean / box_mean - 1.0).abs() < 0.01, "{filter:?}: mean {mean} against the box's {box_mean}");
    }
    gpu.check().unwrap();
}

/// Under a splatting filter the texture resolve (the preview's, an embedding application's)
/// is the host's image to the bit: the camera samples' weighted mean, plus bpt's and vcm's
/// light subpaths' splats, or SPPM's direct light, summed apart.
#[test]
fn splatted_images_resolve_to_textures_as_on_the_host() {
    let Some(gpu) = common::gpu() else { return };
    for method in [Method::PtNee, Method::Bpt, Method::Vcm, Method::Sppm] {
        let scene = splatting(edge_scene(7.6, method, GAUSSIAN));
        let mut integrator = integrators::create(&gpu.device, &gpu.queue, &scene).unwrap();
        for _ in 0..3 {
            integrator.run_pass().unwrap();
        }
        let image = integrator.image().unwrap();
        // An application's Rgba32Float target, as embed.rs makes it.
        let texture = crate::embed::target(&gpu.device, wgpu::TextureFormat::Rgba32Float, WIDTH, HEIGHT);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        integrator.record_resolve_to_texture(&mut encoder, &texture).unwrap();
        gpu.queue.submit([encoder.finish()]);
        let texels = sppm_gpu::gpu::readback::read_texture(&gpu.device, &gpu.queue, &texture).unwrap();
        let resolved = Rgb32Image::from_rgba(WIDTH, HEIGHT, &texels);
        let bits = |img: &Rgb32Image| img.pixels.iter().map(|p| p.map(f32::to_bits)).collect::<Vec<_>>();
        assert!(bits(&resolved) == bits(&image), "{method:?}: the texture's resolve differs from the host's image");
        assert!(image.mean()[0] > 0.1, "{method:?}: a dark image, mean {:?}", image.mean());
    }
    gpu.check().unwrap();
}

/// Which filters splat, and how far: a sample within half a pixel of its pixel's centre
/// reaches the pixels whose centres lie closer than the filter's radius plus 1/2; filters no
/// wider than the box, and those reaching more than 8 pixels, are importance sampled (0).
#[test]
fn splat_reach_is_the_pixels_a_sample_can_weigh_in() {
    let tent = |radius: f32| PixelFilter::Tent { radius };
    let gaussian = |stddev: f32| PixelFilter::Gaussian { stddev };
    for (filter, reach) in [
        (PixelFilter::Box, 0),
        (tent(0.5), 0),
        (tent(0.51), 1),
        (tent(1.0), 1),
        (tent(1.5), 1),
        (tent(1.51), 2),
        (tent(8.5), 8),
        (tent(8.51), 0),
        (gaussian(0.125), 0),
        (gaussian(0.5), 2),
        (gaussian(2.125), 8),
        (gaussian(2.2), 0),
        (tent(f32::NAN), 0),
    ] {
        assert_eq!(filter.splat_reach(), reach, "{filter:?}");
    }
}
