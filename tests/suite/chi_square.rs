//! Chi-square tests of every direction sampler against the density the integrators weight it
//! by, in the manner of pbrt-v4's `bsdfs_test.cpp` and Mitsuba's `chi2` test, on the WGSL
//! itself (`tests/shaders/sampler_test.wgsl`): a million directions from the sampler go into bins
//! of (theta, phi) over the sphere, the density integrated over each bin gives the count
//! expected there, and Pearson's statistic must not reject the match. Samples a sampler
//! gives up on (a glossy reflection below the surface, a refraction back out) go in a
//! bin of their own, expected to hold 1 minus the density's integral. Per sample, the BSDF's
//! f |cos| / pdf must also equal the sampler's weight, and a light sample's pdf the density
//! found by tracing its direction.

use crate::common;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use sppm_gpu::gpu::readback::{read_buffer, staging_buffer};
use sppm_gpu::gpu::scene_buffers::{SceneBuffers, SceneData};
use sppm_gpu::gpu::{GpuContext, Kernel, Resource};
use sppm_gpu::layout::{Frame, MICROFACET_BECKMANN, MICROFACET_GGX};
use sppm_gpu::scene::SceneBuilder;
use std::f64::consts::PI;
use std::mem::{offset_of, size_of};
use wgpu::util::DeviceExt;

/// Directions drawn per test.
const SAMPLES: u32 = 1_000_000;
/// Bins in polar angle; twice as many in azimuth.
const THETA_RES: u32 = 64;
const PHI_RES: u32 = 2 * THETA_RES;
/// Cells expected to hold fewer samples are pooled (the statistic is not chi-square
/// distributed for small expected counts).
const MIN_EXPECTED: f64 = 5.0;
/// Chance of a false alarm over the whole file; each test must reach p > SIGNIFICANCE / TESTS
/// (Bonferroni's correction).
const SIGNIFICANCE: f64 = 0.01;
/// Chi-square tests in this file: cosine 1, glossy 10 of each distribution, rough dielectric
/// 14 of each, lights 3, plastics 11, thin dielectric 2, smooth dielectric 4, environment map
/// 1, phase function 4, free-flight distances 3.
const TESTS: f64 = 77.0;
/// Samples in a bin whose expected count is 0 that are put down to rounding (as pbrt-v4 does:
/// 1e-5 of the samples).
const STRAY: f64 = 1e-5 * SAMPLES as f64;
/// Gauss-Legendre points per bin and dimension (`MAX_POINTS` in the kernel), for bins where
/// the density is smooth.
const POINTS: usize = 16;
/// Midpoint-rule points per bin and dimension, for bins that an edge of the density crosses.
const FINE_POINTS: u32 = 64;
/// How far the density's integral may be from what it should be, besides the noise of the
/// samples it is compared with; the quadrature is good to about 1e-5.
const INTEGRAL_TOLERANCE: f64 = 2e-4;

// `SAMPLER_*` and `PASS_*` in tests/shaders/sampler_test.wgsl.
const SAMPLER_COSINE: u32 = 0;
const SAMPLER_GLOSSY: u32 = 1;
const SAMPLER_ROUGH_DIELECTRIC: u32 = 2;
const SAMPLER_LIGHT: u32 = 3;
const SAMPLER_PLASTIC: u32 = 4;
const SAMPLER_THIN_DIELECTRIC: u32 = 5;
const SAMPLER_SMOOTH_DIELECTRIC: u32 = 6;
const SAMPLER_PHASE: u32 = 7;
const SAMPLER_FLIGHT: u32 = 8;
const PASS_SAMPLE: u32 = 0;
const PASS_INTEGRATE: u32 = 1;

/// `SamplerTestParams` in tests/shaders/sampler_test.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Params {
    sampler: u32,
    pass_kind: u32,
    count: u32,
    seed: u32,
    wo: [f32; 3],
    alpha: f32,
    ns: [f32; 3],
    ior: f32,
    ng: [f32; 3],
    albedo: f32,
    p: [f32; 3],
    radiance: u32,
    x: [f32; 3],
    theta_res: u32,
    y: [f32; 3],
    phi_res: u32,
    z: [f32; 3],
    points: u32,
    breaks: [f32; 4],
    fine: u32,
    distribution: u32,
    fresnel: u32,
    _pad0: u32,
    eta: [f32; 3],
    coat_thickness: f32,
    k: [f32; 3],
    coat_scatterings: u32,
    coat_weight: f32,
    coat_fdr: f32,
    coat_table: u32,
    nonlinear: u32,
    gauss: [[f32; 4]; POINTS],
}

// Numerics.

/// ln Gamma(x) for x >= 0.5 (Lanczos 1964, with g = 7 and the usual nine coefficients).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let t = x + 7.5;
    let sum = C[0] + C.iter().enumerate().skip(1).map(|(i, c)| c / (x + i as f64)).sum::<f64>();
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// The regularized upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a): by the
/// series for P = 1 - Q below x = a + 1, by the continued fraction for Q above (Abramowitz &
/// Stegun 6.5.29 and 6.5.31; the fraction evaluated by Lentz's method).
fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let prefix = (a * x.ln() - x - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        while term > sum * 1e-17 {
            n += 1.0;
            term *= x / n;
            sum += term;
        }
        return (1.0 - prefix * sum).max(0.0);
    }
    let tiny = 1e-300;
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / tiny;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..100_000 {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        d = an * d + b;
        d = if d.abs() < tiny { tiny } else { d };
        c = b + an / c;
        c = if c.abs() < tiny { tiny } else { c };
        d = 1.0 / d;
        h *= d * c;
        if (d * c - 1.0).abs() < 1e-16 {
            break;
        }
    }
    prefix * h
}

/// Chance that a chi-square variable with `dof` degrees of freedom exceeds `statistic`.
fn chi_square_p_value(statistic: f64, dof: usize) -> f64 {
    gamma_q(0.5 * dof as f64, 0.5 * statistic)
}

/// Gauss-Legendre rule of `n` points on [0, 1], as (node, weight): the roots of the Legendre
/// polynomial P_n by Newton's method, with weights 2 / ((1 - x^2) P_n'(x)^2) on [-1, 1].
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    // P_n(x) and P_n'(x) by the three-term recurrence.
    let legendre = |x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        for k in 2..=n {
            let k = k as f64;
            (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
        }
        (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
    };
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(x);
                let dx = p / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            let (_, dp) = legendre(x);
            (0.5 * (1.0 + x), 1.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// What a chi-square test found.
#[derive(Debug)]
struct ChiSquare {
    statistic: f64,
    dof: usize,
    p_value: f64,
}

/// Pearson's test of (observed, expected) counts. Cells expected to hold fewer than
/// MIN_EXPECTED samples are pooled, smallest first, until the pool holds that many; cells
/// expected to hold none may hold at most STRAY samples, and are then left out.
fn chi_square(cells: &[(f64, f64)]) -> Result<ChiSquare, String> {
    let mut cells = cells.to_vec();
    cells.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (mut statistic, mut dof) = (0.0, 0usize);
    let (mut pool_observed, mut pool_expected) = (0.0, 0.0);
    for &(observed, expected) in &cells {
        if expected < 0.0 {
            return Err(format!("a cell is expected to hold {expected} samples"));
        } else if expected == 0.0 {
            if observed > STRAY {
                return Err(format!("{observed} samples in a cell expected to hold none"));
            }
        } else if expected < MIN_EXPECTED || (pool_expected > 0.0 && pool_expected < MIN_EXPECTED) {
            pool_observed += observed;
            pool_expected += expected;
        } else {
            statistic += (observed - expected).powi(2) / expected;
            dof += 1;
        }
    }
    if pool_expected > 0.0 {
        statistic += (pool_observed - pool_expected).powi(2) / pool_expected;
        dof += 1;
    }
    // The counts sum to the number of samples: one constraint.
    let dof = dof.checked_sub(1).filter(|&d| d > 0).ok_or("too few cells for a test")?;
    Ok(ChiSquare { statistic, dof, p_value: chi_square_p_value(statistic, dof) })
}

// The GPU side.

/// The `sampler_test` kernel and its buffers.
struct Bench {
    gpu: GpuContext,
    kernel: Kernel,
    params: wgpu::Buffer,
    out: wgpu::Buffer,
    staging: wgpu::Buffer,
}

/// A scene on the GPU: its buffers and the frame the light code reads.
struct GpuScene {
    data: SceneData,
    buffers: SceneBuffers,
    frame: wgpu::Buffer,
}

impl Bench {
    fn new(gpu: GpuContext) -> Self {
        let kernel = crate::common::test_kernel(&gpu, "sampler_test", &[], &[]);
        let params = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("test_params"),
            size: size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let size = 16 * (2 * SAMPLES).max(THETA_RES * PHI_RES) as u64;
        let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("test_out"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = staging_buffer(&gpu.device, "test_out_staging", size);
        Self { gpu, kernel, params, out, staging }
    }

    fn upload(&self, scene: &sppm_gpu::scene::Scene) -> GpuScene {
        self.upload_data(SceneData::new(scene).unwrap_or_else(|e| panic!("{e}")))
    }

    fn upload_data(&self, data: SceneData) -> GpuScene {
        let frame = Frame {
            emitter_count: data.emitters.len() as u32,
            ray_epsilon: data.ray_epsilon(),
            power_total: data.power_total,
            ..Frame::default()
        };
        let frame = self.gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&frame),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        GpuScene { buffers: SceneBuffers::new(&self.gpu.device, &data), data, frame }
    }

    /// Run one pass; per thread one vec4 (bins) or two (samples).
    fn run(&self, scene: &GpuScene, params: &Params) -> Vec<[f32; 4]> {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
        let mut resources = scene.buffers.resources();
        resources.push(Resource { name: "frame", buffer: &scene.frame });
        resources.push(Resource { name: "test_params", buffer: &self.params });
        resources.push(Resource { name: "test_out", buffer: &self.out });
        let group = self.kernel.bind_group(device, &resources).unwrap_or_else(|e| panic!("{e}"));
        let mut encoder = device.create_command_encoder(&Default::default());
        self.kernel.dispatch(&mut encoder, &group, params.count);
        queue.submit([encoder.finish()]);
        let per_thread = if params.pass_kind == PASS_SAMPLE { 2 } else { 1 };
        read_buffer(device, queue, &self.out, &self.staging, 16 * per_thread * params.count as u64)
            .unwrap_or_else(|e| panic!("{e}"))
    }
}

// The tests' geometry.

fn f32x3(v: DVec3) -> [f32; 3] {
    v.as_vec3().into()
}

fn f64x3(v: [f32; 3]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

/// Two unit vectors completing unit z to a right-handed orthonormal frame.
fn tangents(z: DVec3) -> (DVec3, DVec3) {
    let a = if z.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let x = (a - z * z.dot(a)).normalize();
    (x, z.cross(x))
}

/// The unit vector at `degrees` from unit n, tilted towards t (perpendicular to n).
fn at_angle(n: DVec3, t: DVec3, degrees: f64) -> DVec3 {
    let a = degrees.to_radians();
    (a.cos() * n + a.sin() * t).normalize()
}

/// Parameters for a test whose bins are about pole z.
fn params(sampler: u32, seed: u32, z: DVec3) -> Params {
    let (x, y) = tangents(z);
    let mut gauss = [[0.0; 4]; POINTS];
    for (g, (node, weight)) in gauss.iter_mut().zip(gauss_legendre(POINTS)) {
        *g = [node as f32, weight as f32, 0.0, 0.0];
    }
    Params {
        sampler,
        seed,
        x: f32x3(x),
        y: f32x3(y),
        z: f32x3(z),
        theta_res: THETA_RES,
        phi_res: PHI_RES,
        points: POINTS as u32,
        breaks: [-1.0; 4],
        fine: FINE_POINTS,
        gauss,
        ..Params::zeroed()
    }
}

/// Index of the bin holding direction w, about the frame of `q`.
fn bin_of(q: &Params, w: DVec3) -> usize {
    let w = w.normalize();
    let (x, y, z) = (w.dot(f64x3(q.x)), w.dot(f64x3(q.y)), w.dot(f64x3(q.z)));
    let theta = z.clamp(-1.0, 1.0).acos();
    let phi = y.atan2(x).rem_euclid(2.0 * PI);
    let i = ((theta / PI * THETA_RES as f64) as usize).min(THETA_RES as usize - 1);
    let j = ((phi / (2.0 * PI) * PHI_RES as f64) as usize).min(PHI_RES as usize - 1);
    i * PHI_RES as usize + j
}

/// What one test found.
struct Outcome {
    /// The chi-square test, or why it could not be made.
    test: Result<ChiSquare, String>,
    /// Integral of the density over the sphere.
    integral: f64,
    /// Fraction of the samples the sampler did not give up on.
    usable: f64,
    /// Largest relative error per sample of the weight against f |cos| / pdf (BSDFs), or of
    /// pdf and Le against the traced density and emission (lights), and that sample.
    worst: (f64, String),
    /// Usable samples where the density is 0.
    zero_pdf: usize,
}

/// Draw SAMPLES directions with the sampler of `q`, integrate its density over the bins, and
/// compare.
fn run_test(bench: &Bench, scene: &GpuScene, q: &Params) -> Outcome {
    let light = q.sampler == SAMPLER_LIGHT;
    let samples = bench.run(scene, &Params { pass_kind: PASS_SAMPLE, count: SAMPLES, ..*q });
    let bins = (THETA_RES * PHI_RES) as usize;
    let mut observed = vec![0.0; bins + 1];
    let (mut zero_pdf, mut worst) = (0, (0.0f64, String::new()));
    for s in samples.chunks_exact(2) {
        let ([wx, wy, wz, w], [a, b, c, d]) = (s[0], s[1]);
        if w <= 0.0 {
            observed[bins] += 1.0;
            continue;
        }
        observed[bin_of(q, DVec3::new(wx as f64, wy as f64, wz as f64))] += 1.0;
        // BSDF: weight w against f a, pdf b and |cos| c. Light: cos_l w, pdf a against the
        // traced b, li pdf c against the traced Le d.
        let (cos, error) =
            if light { (w, ((a - b) / b).abs().max(((c - d) / d).abs())) } else { (c, ((a * c / b - w) / w).abs()) };
        // Grazing samples (to the surface, or to the light) are not compared: there the
        // rounding of directions is large against the cosines.
        if cos < 0.05 {
            continue;
        }
        let error = if error.is_nan() { f64::INFINITY } else { error as f64 };
        if b.is_nan() || b <= 0.0 {
            zero_pdf += 1;
        } else if error > worst.0 {
            worst = (error, format!("{:?}", (s[0], s[1])));
        }
    }
    let integrals = bench.run(scene, &Params { pass_kind: PASS_INTEGRATE, count: bins as u32, ..*q });
    let n = SAMPLES as f64;
    let integral: f64 = integrals.iter().map(|v| v[0] as f64).sum();
    let mut cells: Vec<(f64, f64)> = observed.iter().zip(&integrals).map(|(&o, e)| (o, n * e[0] as f64)).collect();
    // The unusable samples: what the density leaves (rounding may make it slightly negative).
    let rest = 1.0 - integral;
    cells.push((observed[bins], if rest.abs() < 1e-4 { n * rest.max(0.0) } else { n * rest }));
    Outcome { test: chi_square(&cells), integral, usable: 1.0 - observed[bins] / n, worst, zero_pdf }
}

/// Whether |x| <= tolerance (false for NaN).
fn within(x: f64, tolerance: f64) -> bool {
    x.abs() <= tolerance
}

/// Check an outcome; a line for the report, or the failures.
fn judge(name: &str, o: &Outcome, failures: &mut Vec<String>) {
    let n = SAMPLES as f64;
    let level = SIGNIFICANCE / TESTS;
    match &o.test {
        Ok(t) => {
            eprintln!(
                "{name:<56} p = {:.4}  chi2 = {:.0} ({} dof)  integral = {:.5}  usable = {:.5}  error {:.1e}",
                t.p_value, t.statistic, t.dof, o.integral, o.usable, o.worst.0
            );
            if t.p_value.is_nan() || t.p_value <= level {
                failures.push(format!("{name}: p = {:.3e} below {level:.1e} ({t:?})", t.p_value));
            }
        }
        Err(e) => failures.push(format!("{name}: {e}")),
    }
    // The density integrates to the fraction of usable samples: a density off by a constant
    // factor fails here whatever the histogram says.
    let sigma = (o.usable * (1.0 - o.usable) / n).sqrt();
    if !within(o.integral - o.usable, INTEGRAL_TOLERANCE + 5.0 * sigma) {
        failures.push(format!("{name}: the density integrates to {:.5}, usable samples {:.5}", o.integral, o.usable));
    }
    if o.zero_pdf > 0 {
        failures.push(format!("{name}: {} usable samples where the density is 0", o.zero_pdf));
    }
    if !within(o.worst.0, 1e-3) {
        failures.push(format!("{name}: relative error {:.2e} in sample {}", o.worst.0, o.worst.1));
    }
}

/// A scene for the BSDF tests, which trace nothing but bind the scene.
fn bsdf_scene(bench: &Bench) -> GpuScene {
    bench.upload(&bsdf_scene_description())
}

fn bsdf_scene_description() -> sppm_gpu::scene::Scene {
    SceneBuilder::new(8, 8)
        .camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0)
        .diffuse("light", [0.0; 3])
        .quad([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "light")
        .emission([1.0; 3])
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A shading normal off every axis, so the samplers' frames are general.
fn shading_normal() -> DVec3 {
    DVec3::new(0.3, -0.5, 0.8).normalize()
}

#[test]
fn p_values_and_quadrature_are_right() {
    // Even dof = 2m: Q(m, x / 2) = exp(-x / 2) sum_{k < m} (x / 2)^k / k!.
    for (dof, x) in [(2usize, 0.5f64), (2, 30.0), (4, 3.0), (10, 25.0), (60, 45.0), (1000, 1000.0), (1200, 1250.0)] {
        let m = dof / 2;
        let (mut term, mut sum) = ((-0.5 * x).exp(), 0.0);
        for k in 0..m {
            sum += term;
            term *= 0.5 * x / (k + 1) as f64;
        }
        let p = chi_square_p_value(x, dof);
        assert!((p - sum).abs() <= 1e-9 + 1e-7 * sum, "dof {dof}, x {x}: {p} against {sum}");
    }
    // Odd dof = 1: P(chi2 > 3.841459) = 0.05.
    assert!((chi_square_p_value(3.841459, 1) - 0.05).abs() < 1e-6);
    // n points integrate polynomials of degree 2n - 1 exactly.
    for n in [1, 8, 16] {
        let rule = gauss_legendre(n);
        let moment = |k: i32| rule.iter().map(|&(x, w)| w * x.powi(k)).sum::<f64>();
        for k in [0, 1, 2 * n as i32 - 1] {
            assert!((moment(k) - 1.0 / (k + 1) as f64).abs() < 1e-13, "{n} points, x^{k}");
        }
    }
    // Counts that fit pass, counts off by 10 % in half the cells fail.
    let fit: Vec<(f64, f64)> = (0..100).map(|i| (1000.0 + if i % 2 == 0 { 20.0 } else { -20.0 }, 1000.0)).collect();
    assert!(chi_square(&fit).unwrap().p_value > 0.5);
    let off: Vec<(f64, f64)> = (0..100).map(|i| (if i % 2 == 0 { 1100.0 } else { 900.0 }, 1000.0)).collect();
    assert!(chi_square(&off).unwrap().p_value < 1e-10);
    assert!(chi_square(&[(100.0, 0.0), (900.0, 1000.0), (1000.0, 1000.0)]).is_err());
}

#[test]
fn sampler_params_match_wgsl() {
    let module = naga::front::wgsl::parse_str(&crate::common::test_kernel_source("sampler_test")).unwrap();
    let (_, ty) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("SamplerTestParams")).unwrap();
    let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("not a struct") };
    let offsets: Vec<usize> = members.iter().map(|m| m.offset as usize).collect();
    let rust = [
        offset_of!(Params, sampler),
        offset_of!(Params, pass_kind),
        offset_of!(Params, count),
        offset_of!(Params, seed),
        offset_of!(Params, wo),
        offset_of!(Params, alpha),
        offset_of!(Params, ns),
        offset_of!(Params, ior),
        offset_of!(Params, ng),
        offset_of!(Params, albedo),
        offset_of!(Params, p),
        offset_of!(Params, radiance),
        offset_of!(Params, x),
        offset_of!(Params, theta_res),
        offset_of!(Params, y),
        offset_of!(Params, phi_res),
        offset_of!(Params, z),
        offset_of!(Params, points),
        offset_of!(Params, breaks),
        offset_of!(Params, fine),
        offset_of!(Params, distribution),
        offset_of!(Params, fresnel),
        offset_of!(Params, _pad0),
        offset_of!(Params, eta),
        offset_of!(Params, coat_thickness),
        offset_of!(Params, k),
        offset_of!(Params, coat_scatterings),
        offset_of!(Params, coat_weight),
        offset_of!(Params, coat_fdr),
        offset_of!(Params, coat_table),
        offset_of!(Params, nonlinear),
        offset_of!(Params, gauss),
    ];
    assert_eq!(offsets, rust);
    assert_eq!(*span as usize, size_of::<Params>());
}

/// sample_cosine_hemisphere against cos(theta) / pi.
#[test]
fn cosine_hemisphere_sampling() {
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let scene = bsdf_scene(&bench);
    let ns = shading_normal();
    let q = Params { ns: f32x3(ns), ..params(SAMPLER_COSINE, 1, ns) };
    let outcome = run_test(&bench, &scene, &q);
    let mut failures = Vec::new();
    judge("cosine hemisphere", &outcome, &mut failures);
    if !within(outcome.integral - 1.0, INTEGRAL_TOLERANCE) {
        failures.push(format!("cos / pi integrates to {}", outcome.integral));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Gold's complex index of refraction as Mitsuba 3 gives it in RGB (`material = "Au"`).
const GOLD: ([f32; 3], [f32; 3]) = ([0.143_036, 0.375_307, 1.442_05], [3.983, 2.385_56, 1.603_36]);

/// rough_conductor_sample against rough_conductor_eval's pdf, for rough to nearly smooth microfacets of
/// `distribution` and incident directions from near the normal to grazing, and once from
/// below the shading normal; with `fresnel`, gold's Fresnel term in the weights and values.
fn glossy_tests(distribution: u32, fresnel: Option<([f32; 3], [f32; 3])>, first_seed: u32) {
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let scene = bsdf_scene(&bench);
    let ns = shading_normal();
    let (t, _) = tangents(ns);
    let label = if distribution == MICROFACET_BECKMANN { "beckmann conductor" } else { "glossy" };
    let mut cases = Vec::new();
    for alpha in [0.05, 0.25, 0.7] {
        for degrees in [10.0, 45.0, 80.0] {
            cases.push((format!("{label} alpha {alpha} at {degrees} deg"), alpha, at_angle(ns, t, degrees)));
        }
    }
    cases.push((format!("{label} alpha 0.25 at 60 deg from below"), 0.25, at_angle(-ns, t, 60.0)));
    let (eta, k) = fresnel.unwrap_or_default();
    let mut failures = Vec::new();
    for (seed, (name, alpha, wo)) in cases.into_iter().enumerate() {
        let q = Params {
            wo: f32x3(wo),
            ns: f32x3(ns),
            alpha,
            albedo: 0.8,
            distribution,
            fresnel: fresnel.is_some() as u32,
            eta,
            k,
            ..params(SAMPLER_GLOSSY, first_seed + seed as u32, ns)
        };
        judge(&name, &run_test(&bench, &scene, &q), &mut failures);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The GGX glossy conductor (Fresnel 1).
#[test]
fn glossy_sampling() {
    glossy_tests(MICROFACET_GGX, None, 100);
}

/// Beckmann's visible normals (sample_beckmann_visible_normal) in a conductor with gold's
/// Fresnel term.
#[test]
fn beckmann_conductor_sampling() {
    glossy_tests(MICROFACET_BECKMANN, Some(GOLD), 300);
}

/// rough_dielectric_sample against rough_dielectric_eval's pdf, microfacets of `distribution`:
/// glass of index 1.5 entered and left, reflection and refraction, for radiance and for
/// photons, and with a shading normal tilted off the geometric one.
fn rough_dielectric_tests(distribution: u32, first_seed: u32) {
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let scene = bsdf_scene(&bench);
    let ng = shading_normal();
    let (t, _) = tangents(ng);
    let label = if distribution == MICROFACET_BECKMANN { "beckmann dielectric" } else { "dielectric" };
    // (name, alpha, wo, ns, radiance)
    let mut cases = Vec::new();
    for alpha in [0.05, 0.3, 0.7] {
        for (side, n) in [("entering", ng), ("leaving", -ng)] {
            for degrees in [30.0, 80.0] {
                let radiance = cases.len() % 2 == 0;
                let name = format!("{label} alpha {alpha} {side} at {degrees} deg");
                cases.push((name, alpha, at_angle(n, t, degrees), ng, radiance));
            }
        }
    }
    // ns 20 degrees off ng, wo 50 degrees off ng on either side.
    let ns = at_angle(ng, t, 20.0);
    cases.push((format!("{label} alpha 0.3 entering, ns tilted"), 0.3, at_angle(ng, t, 50.0), ns, true));
    cases.push((format!("{label} alpha 0.3 leaving, ns tilted"), 0.3, at_angle(-ng, t, 50.0), ns, false));
    let mut failures = Vec::new();
    for (seed, (name, alpha, wo, ns, radiance)) in cases.into_iter().enumerate() {
        let q = Params {
            wo: f32x3(wo),
            ns: f32x3(ns),
            ng: f32x3(ng),
            alpha,
            ior: 1.5,
            radiance: radiance as u32,
            distribution,
            ..params(SAMPLER_ROUGH_DIELECTRIC, first_seed + seed as u32, ns)
        };
        // Refraction needs a microfacet normal h = +-normalize(wo + eta wi) above the surface:
        // the density drops to 0 where h.n = 0, at wi.n = -wo.n / eta with n = ns on wo's side.
        let (wo, ns) = (f64x3(q.wo), f64x3(q.ns));
        let entering = wo.dot(ng) > 0.0;
        let eta = if entering { 1.5 } else { 1.0 / 1.5 };
        let cos_edge = -wo.dot(ns) / eta;
        let q = Params { breaks: [cos_edge.clamp(-1.0, 1.0).acos() as f32, -1.0, -1.0, -1.0], ..q };
        let name = format!("{name} ({})", if radiance { "radiance" } else { "photons" });
        judge(&name, &run_test(&bench, &scene, &q), &mut failures);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The GGX rough dielectric.
#[test]
fn rough_dielectric_sampling() {
    rough_dielectric_tests(MICROFACET_GGX, 200);
}

/// The Beckmann rough dielectric: reflection and transmission through Beckmann's visible
/// normals.
#[test]
fn beckmann_rough_dielectric_sampling() {
    rough_dielectric_tests(MICROFACET_BECKMANN, 400);
}

/// plastic_sample against plastic_eval's mixture density, coatings of index 1.5 over a base
/// of albedo 0.6: smooth (the mirror's samples, a delta, must make up its probability q of the
/// whole), and rough of `distribution`, with the lobe each sample came from weighed against
/// its f and probability times density; `nonlinear`, and pbrt-v4's absorbing layer under the
/// coating and cut walk (`coat_thickness` 0.05, `coat_scatterings` 3), in every other case. A rough coating's
/// transmittance table is appended to the scene's attributes, where coat_table points.
fn plastic_tests(distribution: u32, first_seed: u32) {
    use sppm_gpu::scene::coating::{fresnel_diffuse_reflectance, rough_coating};
    use sppm_gpu::scene::Microfacet;
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let ns = shading_normal();
    let (t, _) = tangents(ns);
    let beckmann = distribution == MICROFACET_BECKMANN;
    let label = if beckmann { "beckmann plastic" } else { "plastic" };
    let mut cases = Vec::new();
    if !beckmann {
        for degrees in [10.0, 60.0, 85.0] {
            cases.push((format!("smooth plastic at {degrees} deg"), 0.0, degrees));
        }
    }
    for alpha in [0.1, 0.5] {
        for degrees in [20.0, 70.0] {
            cases.push((format!("{label} alpha {alpha} at {degrees} deg"), alpha, degrees));
        }
    }
    let albedo = 0.6f32;
    let mut failures = Vec::new();
    for (seed, (name, alpha, degrees)) in cases.into_iter().enumerate() {
        let microfacet = if beckmann { Microfacet::Beckmann } else { Microfacet::Ggx };
        let mut data = SceneData::new(&bsdf_scene_description()).unwrap_or_else(|e| panic!("{e}"));
        let coat_table = data.attributes.len() as u32;
        let coat_fdr = if alpha == 0.0 {
            fresnel_diffuse_reflectance(1.0 / 1.5)
        } else {
            let c = rough_coating(1.5, alpha, microfacet);
            data.attributes.extend(c.transmittance.chunks_exact(4).map(|v| [v[0], v[1], v[2], v[3]]));
            c.internal_reflectance
        };
        let scene = bench.upload_data(data);
        let q = Params {
            wo: f32x3(at_angle(ns, t, degrees)),
            ns: f32x3(ns),
            ng: f32x3(ns),
            alpha,
            ior: 1.5,
            albedo,
            distribution,
            coat_weight: 1.0 / (albedo + 1.0),
            coat_fdr,
            coat_table,
            nonlinear: seed as u32 % 2,
            coat_thickness: if seed % 2 == 1 { 0.05 } else { 0.0 },
            coat_scatterings: if seed % 2 == 1 { 3 } else { 0 },
            ..params(SAMPLER_PLASTIC, first_seed + seed as u32, ns)
        };
        judge(&name, &run_test(&bench, &scene, &q), &mut failures);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// pbrt-v4's `coateddiffuse` (its `LayeredBxDF` with no medium in the layer) walked on the CPU
/// as light goes: through a smooth coating of index 1.5 into the layer (1 - F outside), across
/// it keeping exp(-thickness / c) at cos c inside, scattered by the Lambertian base (albedo,
/// cosine-distributed), back across, out with 1 - F from inside or reflected down again, the
/// base scattering at most `scatterings` times. Returns the mean light leaving through the
/// coating over `paths` walks (the base's directional albedo at cos `mu_o`) and its standard
/// error.
fn pbrt_coated_diffuse_walk(mu_o: f64, albedo: f64, thickness: f64, scatterings: u32, paths: u32) -> (f64, f64) {
    // Fresnel reflectance of a smooth interface of index 1.5 at cos c, from outside or
    // inside ([`specular_pair`]), and the refracted cosine (0 beyond the critical angle).
    let fresnel = |c: f64, outside: bool| -> (f64, f64) {
        let wo = DVec3::new((1.0 - c * c).sqrt(), 0.0, c);
        let (_, refracted, f) = specular_pair(wo, DVec3::Z, if outside { 1.5 } else { 1.0 / 1.5 });
        (f, refracted.map_or(0.0, |t| -t.z))
    };
    let mut rng = common::Rng(7);
    let (f_o, cos_t) = fresnel(mu_o, true);
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..paths {
        let (mut beta, mut out) = ((1.0 - f_o) * (-thickness / cos_t).exp(), 0.0);
        for _ in 0..scatterings {
            // The base, then the way up at a cosine-distributed c.
            let c = rng.uniform().sqrt();
            beta *= albedo * (-thickness / c).exp();
            let (f, _) = fresnel(c, false);
            out += beta * (1.0 - f);
            beta *= f * (-thickness / c).exp();
        }
        sum += out;
        sum2 += out * out;
    }
    let n = paths as f64;
    let mean = sum / n;
    (mean, ((sum2 / n - mean * mean) / n).sqrt())
}

/// A smooth plastic with pbrt-v4's absorbing layer and cut walk (`coat_thickness`,
/// `coat_scatterings`) against pbrt's walk ([`pbrt_coated_diffuse_walk`]): the mean weight of
/// plastic_sample's samples (the mirror's left out, weight 0) is the base's directional
/// albedo, which must match the walk's within 5 standard errors, at 10, 50 and 80 degrees, for
/// pbrt's defaults (thickness 0.01, maxdepth 10: 5 scatterings) and a thick layer cut early.
/// Over a base of albedo 0.8 the kernel without the layer and the cut (Mitsuba's plastic, as the
/// pbrt reader read `coateddiffuse` before) gives 0.593 where the walk gives 0.545 at 10 degrees
/// with pbrt's defaults, 180 standard errors off at a million samples, 90 at a quarter.
#[test]
fn coated_diffuse_matches_pbrt_walk() {
    // Samples and walks of each case: standard errors of some 6e-4 against the 0.05 that the
    // layer and the cut take.
    const WALKS: u32 = 250_000;
    use sppm_gpu::scene::coating::attenuated_internal_reflectance;
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let scene = bsdf_scene(&bench);
    let ns = shading_normal();
    let (t, _) = tangents(ns);
    let albedo = 0.8f32;
    let mut failures = Vec::new();
    for (seed, (thickness, scatterings)) in [(0.01f32, 5u32), (0.1, 2)].into_iter().enumerate() {
        for (k, degrees) in [10.0f64, 50.0, 80.0].into_iter().enumerate() {
            let q = Params {
                pass_kind: PASS_SAMPLE,
                count: WALKS,
                wo: f32x3(at_angle(ns, t, degrees)),
                ns: f32x3(ns),
                ng: f32x3(ns),
                ior: 1.5,
                albedo,
                distribution: MICROFACET_GGX,
                coat_weight: 1.0 / (albedo + 1.0),
                coat_fdr: attenuated_internal_reflectance(1.5, thickness),
                nonlinear: 1,
                coat_thickness: thickness,
                coat_scatterings: scatterings,
                ..params(SAMPLER_PLASTIC, 700 + 3 * seed as u32 + k as u32, ns)
            };
            let weights: Vec<f64> = bench.run(&scene, &q).chunks_exact(2).map(|s| s[0][3] as f64).collect();
            let n = weights.len() as f64;
            let mean = weights.iter().sum::<f64>() / n;
            let error = ((weights.iter().map(|w| w * w).sum::<f64>() / n - mean * mean) / n).sqrt();
            let mu_o = degrees.to_radians().cos();
            let (walk, walk_error) = pbrt_coated_diffuse_walk(mu_o, albedo as f64, thickness as f64, scatterings, WALKS);
            let sigma = (error * error + walk_error * walk_error).sqrt();
            eprintln!(
                "thickness {thickness} scatterings {scatterings} at {degrees} deg: kernel {mean:.5} walk {walk:.5} ({:.1} sigma)",
                (mean - walk) / sigma
            );
            if (mean - walk).abs() > 5.0 * sigma {
                failures.push(format!(
                    "thickness {thickness}, {scatterings} scatterings, {degrees} deg: {mean} against {walk} +- {sigma}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Smooth plastics and GGX rough plastics.
#[test]
fn plastic_sampling() {
    plastic_tests(MICROFACET_GGX, 500);
}

/// Beckmann rough plastics.
#[test]
fn beckmann_plastic_sampling() {
    plastic_tests(MICROFACET_BECKMANN, 600);
}

/// thin_dielectric_sample, a choice between two deltas: every sample is the mirror direction
/// about ns or the incident direction unbent, weighted by the tints (0.9 reflected, 0.7
/// transmitted), and the reflected share is the slab's R' = 2R / (1 + R), R = F(|cos|) at
/// index 1.5, by Pearson's statistic on the two counts; from either side.
#[test]
fn thin_dielectric_sampling() {
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let scene = bsdf_scene(&bench);
    let ns = shading_normal();
    let (t, _) = tangents(ns);
    let mut failures = Vec::new();
    for (seed, (name, wo)) in
        [("thin dielectric at 30 deg", at_angle(ns, t, 30.0)), ("thin dielectric at 75 deg from behind", at_angle(-ns, t, 75.0))]
            .into_iter()
            .enumerate()
    {
        let q = Params {
            wo: f32x3(wo),
            ns: f32x3(ns),
            ng: f32x3(ns),
            ior: 1.5,
            ..params(SAMPLER_THIN_DIELECTRIC, 700 + seed as u32, ns)
        };
        let samples = bench.run(&scene, &Params { pass_kind: PASS_SAMPLE, count: SAMPLES, ..q });
        let n = if wo.dot(ns) > 0.0 { ns } else { -ns };
        let (mirror, _, r) = specular_pair(wo, n, 1.5);
        judge_two_deltas(name, &samples, (mirror, 0.9), (-wo, 0.7), 2.0 * r / (1.0 + r), &mut failures);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A sampler that chooses between two deltas, `a` and `b` (direction, weight): every sample
/// must be one of them (direction within 1e-5, weight within 1e-6 relative), and `a`'s share
/// `p_a` by Pearson's statistic on the two counts.
fn judge_two_deltas(name: &str, samples: &[[f32; 4]], a: (DVec3, f64), b: (DVec3, f64), p_a: f64, failures: &mut Vec<String>) {
    let is = |wi: DVec3, w: f64, (dir, weight): (DVec3, f64)| (wi - dir).length() < 1e-5 && (w - weight).abs() <= 1e-6 * weight;
    let (mut first, mut strays) = (0.0, 0);
    for s in samples.chunks_exact(2) {
        let (wi, w) = (DVec3::new(s[0][0] as f64, s[0][1] as f64, s[0][2] as f64), s[0][3] as f64);
        if is(wi, w, a) {
            first += 1.0;
        } else if !is(wi, w, b) {
            strays += 1;
        }
    }
    let n = (samples.len() / 2) as f64;
    let expected = p_a * n;
    let test = chi_square(&[(first, expected), (n - first, n - expected)]);
    let outcome = Outcome { test, integral: 1.0, usable: 1.0, worst: (0.0, String::new()), zero_pdf: 0 };
    judge(name, &outcome, failures);
    eprintln!("{name}: {first} of {n} the first, expected {expected:.0}");
    if strays > 0 {
        failures.push(format!("{name}: {strays} samples neither of the two directions with its weight"));
    }
}

/// Snell's law about `n` (unit, on wo's side) for wo pointing away from the surface and
/// eta = n_t / n_i: the mirror direction, the refracted one (None under total internal
/// reflection) and the Fresnel reflectance (pbrt-v4 eq. 9.6).
fn specular_pair(wo: DVec3, n: DVec3, eta: f64) -> (DVec3, Option<DVec3>, f64) {
    let c = wo.dot(n);
    let mirror = 2.0 * c * n - wo;
    let sin2_t = (1.0 - c * c) / (eta * eta);
    if sin2_t >= 1.0 {
        return (mirror, None, 1.0);
    }
    let ct = (1.0 - sin2_t).sqrt();
    let (r_par, r_perp) = ((eta * c - ct) / (eta * c + ct), (c - eta * ct) / (c + eta * ct));
    (mirror, Some(-wo / eta + (c / eta - ct) * n), 0.5 * (r_par * r_par + r_perp * r_perp))
}

/// smooth_dielectric_sample, the smooth dielectric, on a smooth-shaded surface (ns 25 degrees off
/// ng): every sample is the mirror direction about ns with weight 1, or the refraction about
/// ns by Snell's law with weight 1 / eta^2 for radiance and 1 for photons, and the reflected
/// share is F(wo.ns) by Pearson's statistic, entering and leaving. Mitsuba 3's dielectric works
/// in the shading frame; refracting about ng instead, as this renderer once did, showed the
/// smooth glass material preview its facets and left a floor of 3.4e-3 under its relMSE
/// (docs/journal/session-14.md). ns tells the side too, as in pbrt-v4's DielectricBxDF and
/// Mitsuba 3's dielectric: the two grazing cases, on opposite sides of ns and ng, once ended
/// every path (the side told by ng; docs/journal/session-39.md).
#[test]
fn smooth_dielectric_sampling() {
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let scene = bsdf_scene(&bench);
    let ns = shading_normal();
    let (t, b) = tangents(ns);
    let ng = at_angle(ns, b, 25.0);
    let mut failures = Vec::new();
    let cases = [
        ("smooth dielectric entering at 40 deg, radiance", at_angle(ns, t, 40.0), 1u32),
        ("smooth dielectric entering at 70 deg, photons", at_angle(ns, -t, 70.0), 0),
        ("smooth dielectric leaving at 20 deg, radiance", at_angle(-ns, t, 20.0), 1),
        ("smooth dielectric leaving at 35 deg, photons", at_angle(-ns, t, 35.0), 0),
        ("smooth dielectric entering at 80 deg, behind ng, radiance", at_angle(ns, -b, 80.0), 1),
        ("smooth dielectric leaving at 80 deg, in front of ng, photons", at_angle(-ns, b, 80.0), 0),
    ];
    for (seed, (name, wo, radiance)) in cases.into_iter().enumerate() {
        let ior = 1.5f64;
        // The side and the law by ns (wo on ns's side is entering).
        let entering = wo.dot(ns) > 0.0;
        let (n, eta) = if entering { (ns, ior) } else { (-ns, 1.0 / ior) };
        assert!(wo.dot(n) > 0.0, "{name}: wo on the side ns faces");
        let (mirror, refracted, f) = specular_pair(wo, n, eta);
        let scale = if radiance == 1 { 1.0 / (eta * eta) } else { 1.0 };
        let q = Params {
            wo: f32x3(wo),
            ns: f32x3(ns),
            ng: f32x3(ng),
            ior: ior as f32,
            radiance,
            ..params(SAMPLER_SMOOTH_DIELECTRIC, 800 + seed as u32, ns)
        };
        let samples = bench.run(&scene, &Params { pass_kind: PASS_SAMPLE, count: SAMPLES, ..q });
        match refracted {
            Some(refracted) => judge_two_deltas(name, &samples, (mirror, 1.0), (refracted, scale), f, &mut failures),
            // Total internal reflection: every sample the mirror direction, weight 1.
            None => {
                let off = samples
                    .chunks_exact(2)
                    .filter(|s| {
                        (DVec3::new(s[0][0] as f64, s[0][1] as f64, s[0][2] as f64) - mirror).length() >= 1e-5 || s[0][3] != 1.0
                    })
                    .count();
                if off > 0 {
                    failures
                        .push(format!("{name}: {off} of {} samples not the mirror direction with weight 1", samples.len() / 2));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A receiving point p that sees a sphere light and a quad light, neither in front of the
/// other.
struct LightSetup {
    name: &'static str,
    p: DVec3,
    /// The sphere: its centre's direction and distance from p, and its radius.
    axis: DVec3,
    dist: f64,
    radius: f32,
    /// The quad: its centre's direction from p (at distance 1.5), how many degrees its
    /// normal is off the direction to p, its longer side.
    quad_dir: DVec3,
    quad_tilt: f64,
    quad_size: f64,
    /// The quad turned away from p (its winding reversed), its emission leaving both sides.
    quad_two_sided_from_behind: bool,
}

/// sample_light against light_pdf at the emitter a traced ray meets. The bins' pole points at
/// the sphere's centre, so its limb is a circle of constant polar angle, where the density
/// rises as an inverse square root and the bins are split.
fn light_test(bench: &Bench, s: &LightSetup, seed: u32, failures: &mut Vec<String>) {
    let center = (s.p + s.dist * s.axis.normalize()).as_vec3();
    let (axis, dist) = ((center.as_dvec3() - s.p).normalize(), (center.as_dvec3() - s.p).length());
    let limb = (s.radius as f64 / dist).asin();
    let dir = s.quad_dir.normalize();
    let normal = at_angle(-dir, tangents(dir).0, s.quad_tilt);
    let (e1, e2) = tangents(normal);
    let (a, b) = (s.quad_size * e1, 0.6 * s.quad_size * e2);
    let corner = s.p + 1.5 * dir - 0.5 * a - 0.5 * b;
    let (a, b) = if s.quad_two_sided_from_behind { (b, a) } else { (a, b) };
    let quad = SceneBuilder::new(8, 8)
        .camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0)
        .diffuse("light", [0.0; 3])
        .quad(corner.as_vec3(), a.as_vec3(), b.as_vec3(), "light")
        .emission([12.0, 8.0, 4.0]);
    let quad = if s.quad_two_sided_from_behind { quad.emission_two_sided() } else { quad };
    let scene = quad.sphere(center, s.radius, "light").emission([0.6, 1.2, 0.9]).build().unwrap_or_else(|e| panic!("{e}"));
    let gpu_scene = bench.upload(&scene);
    // The share of usable samples: all of them, since the quad faces p and the sphere is
    // sampled in the cone it subtends from p.
    let usable: f64 = gpu_scene.data.emitters.iter().map(|e| e.pmf as f64).sum();
    let q = Params { p: f32x3(s.p), breaks: [limb as f32, -1.0, -1.0, -1.0], ..params(SAMPLER_LIGHT, seed, axis) };
    let outcome = run_test(bench, &gpu_scene, &q);
    judge(s.name, &outcome, failures);
    if !within(outcome.integral - usable, INTEGRAL_TOLERANCE) {
        let name = s.name;
        failures
            .push(format!("{name}: the density integrates to {:.5}, the lights' visible share is {usable:.5}", outcome.integral));
    }
}

#[test]
fn light_sampling() {
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let mut failures = Vec::new();
    // Far from the sphere (17 degrees in radius), the quad head-on to the side.
    let far = LightSetup {
        name: "lights: sphere far, quad head-on",
        p: DVec3::new(0.2, 0.1, -0.3),
        axis: DVec3::new(1.0, 0.4, 0.3),
        dist: 3.0,
        radius: 0.9,
        quad_dir: DVec3::new(-0.5, 1.0, 0.2),
        quad_tilt: 0.0,
        quad_size: 1.2,
        quad_two_sided_from_behind: false,
    };
    light_test(&bench, &far, 300, &mut failures);
    // The same, the quad turned away with its emission leaving both sides: seen from behind,
    // sampled as from the front (its power and so its share of the choice doubled).
    let behind = LightSetup { name: "lights: sphere far, two-sided quad from behind", quad_two_sided_from_behind: true, ..far };
    light_test(&bench, &behind, 303, &mut failures);
    // Near the sphere (44 degrees in radius), the quad behind p, turned 70 degrees away.
    let near = LightSetup {
        name: "lights: sphere near, quad at 70 deg",
        p: DVec3::new(-0.4, 0.3, 0.5),
        axis: DVec3::new(-0.2, -1.0, 0.4),
        dist: 1.0,
        radius: 0.7,
        quad_dir: DVec3::new(0.7, 1.0, -0.2),
        quad_tilt: 70.0,
        quad_size: 1.2,
        quad_two_sided_from_behind: false,
    };
    light_test(&bench, &near, 301, &mut failures);
    // A sphere 0.4 degrees in radius, where the cone's 1 - cos(theta_max) comes from its
    // Taylor series.
    let tiny = LightSetup {
        name: "lights: sphere tiny, quad head-on",
        p: DVec3::new(0.1, -0.2, 0.3),
        axis: DVec3::new(0.3, 1.0, -0.5),
        dist: 3.0,
        radius: 0.02,
        quad_dir: DVec3::new(1.0, -0.3, 0.4),
        quad_tilt: 20.0,
        quad_size: 0.8,
        quad_two_sided_from_behind: false,
    };
    light_test(&bench, &tiny, 302, &mut failures);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// sample_light on an environment map (the scene's only light) against the density the
/// integrators weigh escaping rays by (environment_eval, traced_light's miss). The map, 16x9
/// texels with a bright texel and a black one, is turned by a rotation; the bins' frame is the
/// map's own, x along its u = 0 (-z), so that the cells' edges, at u = (i + 1/2) / 16 and v =
/// j / 8, fall on bins' edges (the density is constant within each bin, and the quadrature
/// exact). A dark quad lies in a plane through p, which no ray from p meets but edge-on.
#[test]
fn envmap_sampling() {
    use glam::{Mat3, Vec3};
    use sppm_gpu::scene::envmap::Envmap;
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let (w, h) = (16u32, 9u32);
    let texels = (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            match (x, y) {
                (5, 3) => Vec3::new(30.0, 20.0, 10.0),
                (12, 6) => Vec3::ZERO,
                _ => Vec3::new(0.2 + 0.05 * x as f32, 0.5, 0.1 + 0.1 * y as f32),
            }
        })
        .collect();
    let rotation = Mat3::from_rotation_z(0.3) * Mat3::from_rotation_y(1.1) * Mat3::from_rotation_x(-0.5);
    let map = Envmap::new("chi2.exr".into(), w, h, texels, 2.0, rotation).unwrap();
    let p = DVec3::new(2.0, 1.5, 0.0);
    let scene = SceneBuilder::new(8, 8)
        .camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0)
        .diffuse("dark", [0.0; 3])
        .quad([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "dark")
        .envmap_environment(map)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let gpu_scene = bench.upload(&scene);
    // The map's frame: theta from its +y, phi = 2 pi u = atan2(d.x, -d.z).
    let axis = |v: Vec3| (rotation * v).as_dvec3();
    let q = Params {
        p: f32x3(p),
        x: f32x3(axis(-Vec3::Z)),
        y: f32x3(axis(Vec3::X)),
        z: f32x3(axis(Vec3::Y)),
        ..params(SAMPLER_LIGHT, 303, axis(Vec3::Y))
    };
    let outcome = run_test(&bench, &gpu_scene, &q);
    let mut failures = Vec::new();
    judge("envmap: 16x9, turned", &outcome, &mut failures);
    assert!((outcome.usable - 1.0).abs() < 1e-9, "usable {}", outcome.usable);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// sample_phase (shared/medium.wgsl) against Henyey and Greenstein's phase function phase_hg,
/// isotropic, forward and backward scattering; the weight p / pdf is 1.
#[test]
fn henyey_greenstein_sampling() {
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let scene = bsdf_scene(&bench);
    let ns = shading_normal();
    let (t, _) = tangents(ns);
    let mut failures = Vec::new();
    for (seed, g) in [0.0f32, 0.3, 0.9, -0.6].into_iter().enumerate() {
        let wo = at_angle(ns, t, 40.0);
        let q = Params { wo: f32x3(wo), ns: f32x3(ns), alpha: g, ..params(SAMPLER_PHASE, 900 + seed as u32, ns) };
        let outcome = run_test(&bench, &scene, &q);
        judge(&format!("henyey-greenstein g {g}"), &outcome, &mut failures);
        if !within(outcome.integral - 1.0, INTEGRAL_TOLERANCE) {
            failures.push(format!("henyey-greenstein g {g}: the phase function integrates to {}", outcome.integral));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// sample_flight (shared/medium.wgsl) against its density: distances in 64 bins of equal
/// probability under the mixture over channels p(t) = (1/3) sum_c sigma_t[c] exp(-sigma_t[c] t),
/// and the samples past the segment's end with probability (1/3) sum_c Tr_c(t_max); each
/// weight is Tr(t) / p(t) at an interaction and Tr(t_max) / P(none) past it, per channel.
/// Media: chromatic, grey, and one channel that does not interact at all.
#[test]
fn free_flight_sampling() {
    let Some(gpu) = common::gpu() else { return };
    let bench = Bench::new(gpu);
    let scene = bsdf_scene(&bench);
    let cases: [([f64; 3], [f64; 3], f64); 3] = [
        ([0.2, 0.5, 1.0], [0.8, 1.0, 2.0], 1.5),
        ([0.1, 0.1, 0.1], [0.6, 0.6, 0.6], 4.0),
        ([0.0, 0.3, 0.1], [0.0, 0.7, 1.2], 2.0),
    ];
    let mut failures = Vec::new();
    for (seed, (sigma_a, sigma_s, t_max)) in cases.into_iter().enumerate() {
        let name = format!("free flight sigma_a {sigma_a:?} sigma_s {sigma_s:?} over {t_max}");
        let sigma_t: Vec<f64> = (0..3).map(|c| sigma_a[c] + sigma_s[c]).collect();
        let tr = |t: f64| -> Vec<f64> { sigma_t.iter().map(|s| (-s * t).exp()).collect() };
        // P(t < x), the mixture's distribution function.
        let cdf = |x: f64| tr(x).iter().map(|e| (1.0 - e) / 3.0).sum::<f64>();
        let q = Params {
            ns: sigma_a.map(|x| x as f32),
            ng: sigma_s.map(|x| x as f32),
            alpha: t_max as f32,
            ..params(SAMPLER_FLIGHT, 950 + seed as u32, DVec3::Z)
        };
        let samples = bench.run(&scene, &Params { pass_kind: PASS_SAMPLE, count: SAMPLES, ..q });
        // Bin edges: 64 equal parts of P(t < t_max), by bisection of the distribution function.
        const BINS: usize = 64;
        let inside = cdf(t_max);
        let edges: Vec<f64> = (0..=BINS)
            .map(|k| {
                let goal = inside * k as f64 / BINS as f64;
                let (mut lo, mut hi) = (0.0, t_max);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if cdf(mid) < goal {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                0.5 * (lo + hi)
            })
            .collect();
        let mut observed = vec![0.0; BINS + 1];
        let mut worst = 0.0f64;
        for s in samples.chunks_exact(2) {
            let (t, scattered, weight) = (s[0][0] as f64, s[0][1] > 0.5, [s[0][2] as f64, s[0][3] as f64, s[1][0] as f64]);
            let expected: Vec<f64> = if scattered {
                let tr = tr(t);
                let pdf = (0..3).map(|c| sigma_t[c] * tr[c]).sum::<f64>() / 3.0;
                tr.iter().map(|e| e / pdf).collect()
            } else {
                let tr = tr(t_max);
                let none = tr.iter().sum::<f64>() / 3.0;
                tr.iter().map(|e| e / none).collect()
            };
            for c in 0..3 {
                worst = worst.max((weight[c] - expected[c]).abs() / expected[c].max(1e-3));
            }
            if !scattered {
                observed[BINS] += 1.0;
                if t != t_max {
                    failures.push(format!("{name}: a sample past the end at t = {t}"));
                }
                continue;
            }
            let bin = edges.partition_point(|&e| e <= t).clamp(1, BINS) - 1;
            observed[bin] += 1.0;
        }
        let n = SAMPLES as f64;
        let mut cells: Vec<(f64, f64)> = observed[..BINS].iter().map(|&o| (o, n * inside / BINS as f64)).collect();
        cells.push((observed[BINS], n * (1.0 - inside)));
        match chi_square(&cells) {
            Ok(t) => {
                eprintln!("{name:<72} p = {:.4}  chi2 = {:.0} ({} dof)  weight error {worst:.1e}", t.p_value, t.statistic, t.dof);
                if t.p_value.is_nan() || t.p_value <= SIGNIFICANCE / TESTS {
                    failures.push(format!("{name}: p = {:.3e} ({t:?})", t.p_value));
                }
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
        if !within(worst, 1e-4) {
            failures.push(format!("{name}: weights off by {worst:.2e}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
