//! The Sobol sampler (`sampler = "sobol"`, `shaders/shared/sobol.wgsl`): the kernels draw
//! what its CPU mirror (`src/sampler.rs`) draws, bit for bit, falling back to the PCG stream
//! after `SOBOL_PATTERNS` draws; every pattern's points of a pixel are stratified as a
//! (0,k,2)-net after any 2^k samples, and patterns are uniform against each other (the
//! pairs the integrators form across draws: a light's choice with the point on it, a
//! direction with its lobe, ...). Broken scrambles fail those tests. The renders converge to
//! the references with either sampler.

use crate::common;

use sppm_gpu::gpu::readback::{read_buffer, staging_buffer};
use sppm_gpu::gpu::Resource;
use sppm_gpu::sampler::{owen_scramble, pcg_hash, sobol_1d, sobol_2d, sobol_2d_bits, Sampler, Scramble, OWEN, SOBOL_PATTERNS};
use wgpu::util::DeviceExt;

/// `SobolTestParams` in tests/shaders/sobol_test.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    seed: u32,
    first: u32,
    count: u32,
    draws: u32,
}

/// The draws of samples `first..first + count` of sequence `seed` by the `sobol_test` kernel
/// with `SAMPLER_SOBOL` = `sobol`.
fn gpu_draws(gpu: &sppm_gpu::gpu::GpuContext, sobol: bool, p: Params) -> Vec<[f32; 2]> {
    let constants = [("SAMPLER_SOBOL", sobol as u32 as f64)];
    let kernel = crate::common::test_kernel(gpu, "sobol_test", &[], &constants);
    let params = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("sobol_params"),
        contents: bytemuck::bytes_of(&p),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let size = 8 * (p.count * p.draws) as u64;
    let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sobol_out"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = staging_buffer(&gpu.device, "sobol_out_staging", size);
    let resources = [Resource { name: "sobol_params", buffer: &params }, Resource { name: "sobol_out", buffer: &out }];
    let group = kernel.bind_group(&gpu.device, &resources).unwrap_or_else(|e| panic!("{e}"));
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    kernel.dispatch(&mut encoder, &group, p.count);
    gpu.queue.submit([encoder.finish()]);
    read_buffer(&gpu.device, &gpu.queue, &out, &staging, size).unwrap_or_else(|e| panic!("{e}"))
}

/// `rng_new` and `rng_next` of shaders/shared/rng.wgsl.
struct Pcg(u32);

impl Pcg {
    fn new(seed: u32, pass: u32, stream: u32, index: u32) -> Self {
        Pcg(pcg_hash(seed ^ pcg_hash(pass ^ pcg_hash(stream ^ pcg_hash(index)))))
    }
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        let s = self.0;
        let word = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
        (((word >> 22) ^ word) >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

/// What `sobol_test` draws, on the CPU.
fn cpu_draws(sobol: bool, p: Params) -> Vec<[f32; 2]> {
    let mut out = Vec::new();
    for i in 0..p.count {
        let mut pcg = Pcg::new(p.seed, 0, 0, i);
        for d in 0..p.draws {
            let from_sobol = sobol && d < SOBOL_PATTERNS;
            out.push(match (d % 2 == 0, from_sobol) {
                (true, true) => sobol_2d(p.first + i, p.seed, d),
                (false, true) => [sobol_1d(p.first + i, p.seed, d), 0.0],
                (true, false) => [pcg.next(), pcg.next()],
                (false, false) => [pcg.next(), 0.0],
            });
        }
    }
    out
}

#[test]
fn kernels_draw_what_the_mirror_draws() {
    let Some(gpu) = common::gpu() else { return };
    // Past SOBOL_PATTERNS, the PCG stream; samples from an index past 2^31.
    for (sobol, first) in [(true, 0), (true, 0x8000_1000), (false, 5)] {
        let p = Params { seed: 0x1234_5678, first, count: 2048, draws: SOBOL_PATTERNS + 8 };
        let (a, b) = (gpu_draws(&gpu, sobol, p), cpu_draws(sobol, p));
        let same = a.iter().zip(&b).filter(|(x, y)| x[0].to_bits() == y[0].to_bits() && x[1].to_bits() == y[1].to_bits()).count();
        assert_eq!(same, a.len(), "sobol {sobol} first {first}: {} of {} draws differ", a.len() - same, a.len());
    }
}

// Stratification.

/// Whether the 2D points `pts` (32-bit fractions), 2^k of them, are a (0,k,2)-net: one point
/// in every elementary interval of area 2^-k. The first failing shape, if any.
fn net_failure(pts: &[[u32; 2]], k: u32) -> Option<String> {
    assert_eq!(pts.len(), 1 << k);
    for a in 0..=k {
        let b = k - a;
        let mut seen = vec![false; 1 << k];
        for p in pts {
            let x = if a == 0 { 0 } else { (p[0] >> (32 - a)) as usize };
            let y = if b == 0 { 0 } else { (p[1] >> (32 - b)) as usize };
            let cell = (x << b) | y;
            if seen[cell] {
                return Some(format!("two points in a cell of the {}x{} grid", 1 << a, 1 << b));
            }
            seen[cell] = true;
        }
    }
    None
}

/// The first failure of the nets of pattern `dim` of sequence `seed`: its samples
/// `first..first + 2^k` for each k up to 12 and `first` aligned to 2^k (a pixel's first 2^k
/// samples, and a later batch of passes).
fn pattern_failure(seed: u32, dim: u32, s: Scramble) -> Option<String> {
    for k in 1..=12u32 {
        for first in [0u32, 7 << k, 0x4000_0000] {
            let pts: Vec<[u32; 2]> = (first..first + (1 << k)).map(|i| sobol_2d_bits(i, seed, dim, s)).collect();
            if let Some(f) = net_failure(&pts, k) {
                return Some(format!("pattern {dim}, samples {first}..+2^{k}: {f}"));
            }
        }
    }
    None
}

/// Pixels' seeds as the kernels make them (`sobol_seed`), for a few pixels of each stream.
fn pixel_seeds() -> Vec<u32> {
    let mut seeds = Vec::new();
    for stream in [0, 1, 2] {
        for pixel in [0, 1, 255, 65535, 1 << 20] {
            seeds.push(sppm_gpu::sampler::sobol_seed(0, stream, pixel));
        }
    }
    seeds.push(sppm_gpu::sampler::sobol_seed(7, 2, 12345));
    seeds
}

/// Every pattern the kernels draw, 1D (its first coordinate) and 2D, is a (0,k,2)-net over any
/// aligned 2^k samples of a pixel, for every pixel seed tried.
#[test]
fn every_pattern_of_a_pixel_is_stratified() {
    for seed in pixel_seeds() {
        for dim in 0..SOBOL_PATTERNS {
            if let Some(f) = pattern_failure(seed, dim, OWEN) {
                panic!("seed {seed:#x}: {f}");
            }
        }
    }
}

/// Chi-square statistic of `pts` in `[0,1)^2` over an n x n grid, and its z-score by the
/// Wilson-Hilferty approximation (n^2 - 1 degrees of freedom).
fn chi_square_z(pts: &[[f32; 2]], n: usize) -> f64 {
    let mut counts = vec![0u32; n * n];
    for p in pts {
        let (x, y) = ((p[0] * n as f32) as usize, (p[1] * n as f32) as usize);
        counts[x.min(n - 1) * n + y.min(n - 1)] += 1;
    }
    let expected = pts.len() as f64 / (n * n) as f64;
    let stat: f64 = counts.iter().map(|&c| (c as f64 - expected).powi(2) / expected).sum();
    let k = (n * n - 1) as f64;
    ((stat / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt()
}

/// The numbers one sample draws, as the kernels' draws make them: pattern d is a pair when
/// d is even, one number when odd (`sobol_test`'s order; the integrators mix both), flattened
/// into dimensions.
fn sample_dims(i: u32, seed: u32, patterns: u32, s: Scramble) -> Vec<f32> {
    let mut dims = Vec::new();
    for d in 0..patterns {
        let [x, y] = sobol_2d_bits(i, seed, d, s);
        dims.push(sppm_gpu::sampler::to_unit(x));
        if d % 2 == 0 {
            dims.push(sppm_gpu::sampler::to_unit(y));
        }
    }
    dims
}

/// The largest chi-square z-score over every pair of the first `patterns` patterns'
/// dimensions, over 4096 samples of one pixel on a 16 x 16 grid, and the pair.
fn worst_pair(seed: u32, patterns: u32, s: Scramble, stride: u32) -> (f64, usize, usize) {
    let samples: Vec<Vec<f32>> = (0..4096).map(|i| sample_dims(i * stride, seed, patterns, s)).collect();
    let n = samples[0].len();
    let mut worst = (f64::MIN, 0, 0);
    for a in 0..n {
        for b in a + 1..n {
            let pts: Vec<[f32; 2]> = samples.iter().map(|v| [v[a], v[b]]).collect();
            let z = chi_square_z(&pts, 16);
            if z > worst.0 {
                worst = (z, a, b);
            }
        }
    }
    worst
}

/// Any two dimensions a sample draws, within a pattern or across patterns (a light's choice
/// against the point on it, a direction against its lobe and Russian roulette), are uniform
/// in the unit square: chi-square over a 16 x 16 grid, every pair of the first 12 patterns'
/// 18 dimensions, for 16 pixels. Samples i and i xor 1 (and i xor 2) of a pixel are
/// antithetic in every pattern alike (an Owen scramble flips their top bits together), which
/// raises the statistic's variance for consecutive samples: there the bound is z < 12 (a
/// shared shuffle scores above 20, `broken_scrambles_fail`); for samples 4 apart (passes 0,
/// 4, 8, ... of a pixel) the points must pass as independent: z < 4.5 (p about 3e-6 a pair,
/// some 2500 pairs; independent points' worst is about 3).
#[test]
fn every_pair_of_dimensions_is_uniform() {
    for seed in pixel_seeds() {
        let (z, a, b) = worst_pair(seed, 12, OWEN, 4);
        let (z1, a1, b1) = worst_pair(seed, 12, OWEN, 1);
        eprintln!("seed {seed:#x}: worst pair ({a}, {b}) z = {z:.2} 4 apart; ({a1}, {b1}) z = {z1:.2} consecutive");
        assert!(z < 4.5, "seed {seed:#x}: dimensions {a} and {b} have chi-square z = {z:.2}");
        assert!(z1 < 12.0, "seed {seed:#x}: dimensions {a1} and {b1} have chi-square z = {z1:.2}");
    }
}

/// Broken scrambles are caught: values hashed whole rather than nested (no stratification
/// left), an index shuffle nested from the bottom bit up (prefixes of a pixel's samples are no
/// longer aligned blocks of the sequence), and one shuffle for every pattern (patterns
/// correlated with each other).
#[test]
fn broken_scrambles_fail() {
    let seed = pixel_seeds()[3];
    let whole_hash = Scramble { shuffle: owen_scramble, values: |v, s| pcg_hash(v ^ s) };
    let bottom_up = Scramble { shuffle: |i, s| owen_scramble(i.reverse_bits(), s).reverse_bits(), values: owen_scramble };
    let shared_shuffle = Scramble { shuffle: |i, _| owen_scramble(i, 0x2545_f491), values: owen_scramble };
    for (name, broken) in [("whole hash", whole_hash), ("bottom-up shuffle", bottom_up)] {
        let failures = (0..SOBOL_PATTERNS).filter(|&d| pattern_failure(seed, d, broken).is_some()).count();
        eprintln!("{name}: {failures} of {SOBOL_PATTERNS} patterns are not nets");
        assert!(failures as u32 == SOBOL_PATTERNS, "{name}: only {failures} patterns fail the net test");
    }
    // The shared shuffle keeps each pattern a net but ties the patterns together.
    assert!(pattern_failure(seed, 3, shared_shuffle).is_none());
    let (z, a, b) = worst_pair(seed, 12, shared_shuffle, 1);
    eprintln!("shared shuffle: worst pair ({a}, {b}), z = {z:.2}");
    assert!(z > 20.0, "a shuffle shared by all patterns passes the pair test: z = {z:.2}");
}

// Renders.

/// A scene of the canonical set at `size` pixels with `sampler`.
fn scene(name: &str, size: u32, sampler: Sampler) -> sppm_gpu::scene::Scene {
    let mut scene = common::load_scene(&format!("{name}.toml"));
    scene.render.width = size;
    scene.render.height = size;
    scene.render.sampler = sampler;
    scene
}

fn render(scene: &sppm_gpu::scene::Scene, passes: u32) -> sppm_gpu::image_io::Rgb32Image {
    use sppm_gpu::integrators::{self, Integrator};
    let gpu = common::gpu().expect("checked by the caller");
    let mut r: Box<dyn Integrator> = integrators::create(&gpu.device, &gpu.queue, scene).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..passes {
        r.run_pass().unwrap();
    }
    let img = r.image().unwrap();
    assert_eq!(sppm_gpu::metrics::count_non_finite(&img), 0, "NaN or infinite pixels");
    assert_eq!(sppm_gpu::metrics::count_negative(&img), 0, "negative pixels");
    img
}

/// The sampler the scenes do not get by default: the default one is tested against the
/// references by tests/suite/path.rs and tests/suite/sppm.rs.
fn other_sampler() -> Sampler {
    if Sampler::DEFAULT == Sampler::Sobol {
        Sampler::Independent
    } else {
        Sampler::Sobol
    }
}

/// The furnace's 2 everywhere, by pt, pt-nee and SPPM, with the non-default sampler.
#[test]
fn furnace_with_the_other_sampler() {
    if common::gpu().is_none() {
        return;
    }
    use sppm_gpu::scene::Method;
    for method in [Method::Pt, Method::PtNee, Method::Sppm] {
        let mut s = scene("furnace", 64, other_sampler());
        s.render.method = method;
        let passes = if method == Method::Sppm { s.render.iterations } else { 64 };
        let mean = render(&s, passes).mean();
        for c in mean {
            assert!((c - 2.0).abs() < 0.02, "{method:?} {:?}: furnace mean {mean:?}", other_sampler());
        }
    }
}

/// pt-nee (64 x 64, 64 passes) and SPPM (128 x 128, 12 passes of 100 000 photons) with the
/// non-default sampler against the references, with tests/suite/path.rs's and tests/suite/sppm.rs's
/// tolerances. pt-nee's passes: at 128 (2026-11-28) its relMSE read 2.3e-4 (cornell-box) and
/// 5.3e-4 (cornell-glossy), its channel means within 0.4%; pt-nee is unbiased, so 64 passes
/// at most double the variance part (about 4.5e-4 and 1.1e-3, under 3e-3 by 2.8x or more; the
/// means' noise within 0.6%, against 3%). SPPM's work: with the independent sampler at 12
/// passes of 100 000 photons (2026-11-30) its relMSE read 2.9e-4 (cornell-box), 5.3e-4
/// (cornell-spheres) and 3.3e-4 (cornell-glossy), its channel means within 0.34%: under the
/// bounds (3e-3, 1e-2, 6e-3; 2 to 3%) by 10x or more (at 24 passes of 200 000: 1.2e-4, 2.7e-4
/// and 1.5e-4, within 0.2%).
#[test]
fn canonical_scenes_with_the_other_sampler() {
    if common::gpu().is_none() {
        return;
    }
    use sppm_gpu::metrics::{compare, downsample_box};
    use sppm_gpu::scene::Method;
    let sampler = other_sampler();
    for (name, method, max_rel_mse, max_ratio) in [
        ("cornell-box", Method::PtNee, 0.003, 0.03),
        ("cornell-glossy", Method::PtNee, 0.003, 0.03),
        ("cornell-box", Method::Sppm, 0.003, 0.02),
        ("cornell-spheres", Method::Sppm, 0.01, 0.03),
        ("cornell-glossy", Method::Sppm, 0.006, 0.03),
    ] {
        let size = if method == Method::Sppm { 128 } else { 64 };
        let mut s = scene(name, size, sampler);
        s.render.method = method;
        s.render.photons = 100_000;
        let passes = if method == Method::Sppm { 12 } else { 64 };
        let img = render(&s, passes);
        let reference = downsample_box(&common::reference(&format!("{name}.exr")), 256 / size).unwrap();
        let c = compare(&img, &reference, if method == Method::Sppm { 4 } else { 8 }).unwrap();
        eprintln!("{name} {method:?} {sampler:?}: {c:?}");
        assert!(c.rel_mse < max_rel_mse, "{name} {method:?} {sampler:?}: relMSE {}", c.rel_mse);
        for r in c.mean_ratio {
            assert!((r - 1.0).abs() < max_ratio, "{name} {method:?} {sampler:?}: channel mean ratios {:?}", c.mean_ratio);
        }
    }
}

// Settings.

/// `sampler` in `[render]`, its default, a bad value, and Mitsuba's sampler kinds.
#[test]
fn the_sampler_is_read_from_toml_and_mitsuba_xml() {
    let dir = common::scratch("sobol-sampler");
    let toml = std::fs::read_to_string(common::scene_path("cornell-box.toml")).unwrap();
    assert!(toml.contains("[render]\n") && !toml.contains("sampler"));
    assert_eq!(common::load_scene("cornell-box.toml").render.sampler, Sampler::DEFAULT);
    for (value, expected) in
        [("\"independent\"", Some(Sampler::Independent)), ("\"sobol\"", Some(Sampler::Sobol)), ("\"halton\"", None)]
    {
        let path = dir.join("scene.toml");
        std::fs::write(&path, toml.replace("[render]\n", &format!("[render]\nsampler = {value}\n"))).unwrap();
        match (sppm_gpu::scene::load(&path), expected) {
            (Ok(scene), Some(s)) => assert_eq!(scene.render.sampler, s, "{value}"),
            (Err(e), None) => assert!(e.to_string().contains("sampler"), "{e}"),
            (r, _) => panic!("sampler = {value}: {:?}", r.map(|s| s.render.sampler)),
        }
    }
    let xml = std::fs::read_to_string(common::scene_path("mitsuba/box.xml")).unwrap();
    assert!(xml.contains("<sampler type=\"independent\">"));
    for (kind, expected) in [
        ("independent", Sampler::Independent),
        ("ldsampler", Sampler::Sobol),
        ("multijitter", Sampler::Sobol),
        ("stratified", Sampler::Sobol),
        ("orthogonal", Sampler::Sobol),
        ("sobol", Sampler::Sobol),
    ] {
        let path = common::scene_path(&format!("mitsuba/sampler-test-{kind}-{}.xml", std::process::id()));
        std::fs::write(&path, xml.replace("<sampler type=\"independent\">", &format!("<sampler type=\"{kind}\">"))).unwrap();
        let scene = sppm_gpu::scene::load(&path);
        std::fs::remove_file(&path).unwrap();
        assert_eq!(scene.unwrap_or_else(|e| panic!("{kind}: {e}")).render.sampler, expected, "{kind}");
    }
}
