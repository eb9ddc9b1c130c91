//! CPU oracles for the SPPM kernels with real logic, written from the formulas rather than
//! from the WGSL: `update_stats` (Hachisuka & Jensen 2009 eq. 7 and 8, pbrt-v4 form),
//! `resolve` (eq. 11 with the per-pixel average over samples), the properties of the photon
//! pass's 32.32 fixed-point deposit that can be checked without the photons' hit points, and
//! the hashed grid built over the visible points of a real pass against brute force.
//!
//! The oracles compute in f64 from the f32 values the GPU read and wrote. Each renders a small
//! image (32x32 or 64x64, 20k to 50k photons) so the file runs in seconds on lavapipe.

use crate::common;

use crate::common::Rng;
use glam::Vec3;
use sppm_gpu::accel::build_grid;
use sppm_gpu::accel::grid::{brute_force_within, point_within};
use sppm_gpu::gpu::GpuContext;
use sppm_gpu::integrators::{Deposits, Sppm};
use sppm_gpu::layout::{VpStats, ACCUM_STRIDE};
use sppm_gpu::scene::Scene;
use std::collections::HashSet;

/// Relative tolerance of the f32 kernels against the f64 oracles. Each quantity compared
/// here comes out of at most about ten f32 operations on non-negative operands (no
/// cancellation): additions and multiplications correctly rounded (0.5 ulp), division and
/// sqrt within 2.5 ulp by the WGSL spec, and the radius error entering tau squared. That is
/// a few tens of ulps at most, about 2e-6 relative (1 ulp = 2^-23 = 1.2e-7); 1e-5 leaves a
/// margin of five for fused multiply-adds or a driver's looser division, and is still far
/// below any formula error (a wrong alpha, a missing square, a wrong k is a percent or more).
const REL_TOL: f64 = 1e-5;

/// `gpu` equals the oracle `cpu` to [`REL_TOL`]; an exact zero is required where the oracle
/// is zero (every quantity here is a product or sum of non-negative terms).
fn close(gpu: f32, cpu: f64) -> bool {
    gpu.is_finite() && (gpu as f64 - cpu).abs() <= REL_TOL * cpu.abs()
}

fn scene(name: &str, size: u32, photons: u32) -> Scene {
    let mut scene = common::load_scene(name);
    scene.render.width = size;
    scene.render.height = size;
    scene.render.photons = photons;
    scene
}

fn renderer(gpu: &GpuContext, scene: &Scene) -> Sppm {
    Sppm::new(&gpu.device, &gpu.queue, scene).unwrap_or_else(|e| panic!("{e}"))
}

fn renderer_with(gpu: &GpuContext, scene: &Scene, deposits: Deposits) -> Sppm {
    Sppm::with_deposits(&gpu.device, &gpu.queue, scene, deposits).unwrap_or_else(|e| panic!("{e}"))
}

/// Decode the 32.32 fixed-point pair at `words[0..2]` (lo, hi) exactly.
fn fixed(words: &[u32]) -> f64 {
    words[1] as f64 + words[0] as f64 / 4_294_967_296.0
}

/// Decoded flux (r, g, b) and photon count of one visible point's accumulator slot.
fn slot(accum: &[u32], i: usize) -> ([f64; 3], u32) {
    let s = &accum[i * ACCUM_STRIDE as usize..(i + 1) * ACCUM_STRIDE as usize];
    ([fixed(&s[0..2]), fixed(&s[2..4]), fixed(&s[4..6])], s[6])
}

/// The SPPM update of one visible point after a pass that brought it `m > 0` photons with
/// flux `phi` (relative to the total power), from the paper's equations rather than the
/// kernel: N' = N + alpha M; the disc shrinks so that its area falls by N' / (N + M),
/// r'^2 = r^2 N' / (N + M); the flux gathered so far, tau + phi, is scaled to the new disc by
/// the ratio of areas r'^2 / r^2. `ld` is not touched.
fn update_oracle(before: &VpStats, phi: [f64; 3], m: u32, alpha: f64) -> ([f64; 3], f64, f64) {
    let n = before.n as f64;
    let m = m as f64;
    let n_new = n + alpha * m;
    let area_ratio = n_new / (n + m);
    let r_new = before.radius as f64 * area_ratio.sqrt();
    let tau = [0, 1, 2].map(|c| (before.tau[c] as f64 + phi[c]) * area_ratio);
    (tau, n_new, r_new)
}

/// `update_stats` against the oracle over two passes (the second covers N > 0), on the
/// Cornell spheres, whose caustics give points with very different photon counts.
#[test]
fn update_stats_matches_cpu_oracle() {
    let Some(gpu) = common::gpu() else { return };
    let scene = scene("cornell-spheres.toml", 32, 50_000);
    let mut sppm = renderer(&gpu, &scene);
    let alpha = sppm.frame().alpha as f64;
    assert!(alpha > 0.0 && alpha < 1.0);

    for pass in 0..3 {
        sppm.trace_camera_paths();
        sppm.build_grid().unwrap();
        sppm.trace_photons();
        let accum = sppm.flux_accum().unwrap();
        let points = sppm.visible_points().unwrap();
        let before = sppm.stats().unwrap();
        sppm.update_statistics();
        let after = sppm.stats().unwrap();
        assert_eq!(before.len(), after.len());

        let (mut updated, mut updated_with_history, mut untouched) = (0, 0, 0);
        for (i, (b, a)) in before.iter().zip(&after).enumerate() {
            // The photons' flux times the point's weight (path throughput times albedo / pi).
            let (flux, m) = slot(&accum, i);
            let phi = [0, 1, 2].map(|c| flux[c] * points[i].weight[c] as f64);
            if m == 0 {
                // No photon: the statistics stay exactly as they were.
                assert_eq!(a, b, "pass {pass}, point {i}: changed without photons");
                untouched += 1;
                continue;
            }
            updated += 1;
            if b.n > 0.0 {
                updated_with_history += 1;
            }
            let (tau, n, r) = update_oracle(b, phi, m, alpha);
            let msg = || {
                format!("pass {pass}, point {i}: m {m}, phi {phi:?}, before {b:?}, after {a:?}, oracle tau {tau:?} n {n} r {r}")
            };
            assert!(close(a.n, n), "N: {}", msg());
            assert!(close(a.radius, r), "radius: {}", msg());
            assert!(a.radius < b.radius, "radius did not shrink: {}", msg());
            for (c, (&gpu, &oracle)) in a.tau.iter().zip(&tau).enumerate() {
                assert!(close(gpu, oracle), "tau[{c}]: {}", msg());
            }
            assert_eq!(a.ld, b.ld, "ld changed: {}", msg());
        }
        eprintln!("pass {pass}: {updated} points updated ({updated_with_history} with N > 0), {untouched} without photons");
        // Both branches ran, and from the second pass on the N > 0 case too.
        assert!(updated > before.len() / 2, "pass {pass}: only {updated} points got photons");
        if pass > 0 {
            assert!(updated_with_history > updated / 2, "pass {pass}: {updated_with_history} of {updated} with N > 0");
        } else {
            assert_eq!(updated_with_history, 0, "N > 0 before the first update");
        }

        // update_stats clears the accumulator for the next pass.
        let cleared = sppm.flux_accum().unwrap();
        if let Some(w) = cleared.iter().position(|&w| w != 0) {
            panic!("pass {pass}: flux_accum word {w} is {} after update_stats", cleared[w]);
        }
    }
}

/// The oracle for `resolve`: per pixel, the mean over its `spp` visible points of
/// ld / k + tau * power_total / (k * photons_per_pass * pi * r^2), with k the passes so far
/// (tau is kept relative to the total power); a non-finite value becomes 0.
fn resolve_oracle(stats: &[VpStats], pixel: usize, spp: usize, k: f64, photons: f64, power: f64) -> [f64; 3] {
    let mut l = [0.0f64; 3];
    for st in &stats[pixel * spp..(pixel + 1) * spp] {
        let r = st.radius as f64;
        let area = std::f64::consts::PI * r * r;
        for (c, l) in l.iter_mut().enumerate() {
            *l += (st.ld[c] as f64 / k + st.tau[c] as f64 * power / (k * photons * area)) / spp as f64;
        }
    }
    l.map(|v| if v.is_finite() { v } else { 0.0 })
}

/// `resolve` against the oracle after three passes with two samples per pixel, so that both
/// the division by k and the average over samples matter.
#[test]
fn resolve_matches_cpu_oracle() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = scene("cornell-spheres.toml", 32, 20_000);
    scene.render.spp = 2;
    let mut sppm = renderer(&gpu, &scene);
    for _ in 0..3 {
        sppm.run_pass().unwrap();
    }
    let img = sppm.image().unwrap();
    let stats = sppm.stats().unwrap();
    let f = *sppm.frame();
    let (w, h, spp) = (f.width as usize, f.height as usize, f.spp as usize);
    assert_eq!(spp, 2);
    assert_eq!((img.width as usize, img.height as usize), (w, h));
    assert_eq!(stats.len(), w * h * spp);
    let k = sppm.passes() as f64;
    assert_eq!(k, 3.0);

    let mut lit = 0;
    for (pixel, got) in img.pixels.iter().enumerate() {
        let want = resolve_oracle(&stats, pixel, spp, k, f.photon_count as f64, f.power_total as f64);
        for c in 0..3 {
            assert!(
                close(got[c], want[c]),
                "pixel ({}, {}) channel {c}: GPU {} oracle {} (stats {:?})",
                pixel % w,
                pixel / w,
                got[c],
                want[c],
                &stats[pixel * spp..(pixel + 1) * spp]
            );
        }
        if want.iter().any(|&v| v > 0.0) {
            lit += 1;
        }
    }
    // Not a vacuous comparison of zeros: most pixels see lit surfaces.
    assert!(lit > w * h / 2, "only {lit} lit pixels");
}

/// Bounds on one photon's deposit on the Cornell box, from the emission alone: (largest
/// per-photon flux in any channel, smallest sum over channels of a photon's flux).
///
/// A photon leaves emitter e with beta = Le * pi * area / (pmf * power_total), and
/// pmf = mean(Le) * pi * area / power_total, so beta = Le / mean(Le): its largest component
/// is B = max(Le) / mean(Le). Russian roulette keeps the largest component of beta equal to
/// B at every bounce. The accumulator holds the photons' own flux (the visible point's weight
/// is applied by update_stats), so one deposit is at most B in every channel, and the sum of
/// its channels is at least B.
fn cornell_box_deposit_bounds(scene: &Scene) -> (f64, f64) {
    assert!(scene.lights.is_empty(), "the deposit bounds assume area lights only");
    let b: Vec<f64> =
        scene.shapes.iter().filter_map(|s| s.emission).map(|e| e.max_element() as f64 / (e.element_sum() as f64 / 3.0)).collect();
    assert!(!b.is_empty());
    let (b_min, b_max) = b.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    (b_max, b_min)
}

/// The fixed-point accumulator after one pass, summed by the gather and, with no room for
/// hits, by the photon pass's atomics: every slot is consistent
/// (flux only with photons, photons only at real visible points, the spare word unused),
/// and each point's flux lies between its photon count times the smallest and the largest
/// possible contribution. The upper bound catches swapped or misplaced words; the lower
/// bound, for points with hundreds of photons, catches a lost carry out of the low word
/// (without it no channel could exceed 1).
#[test]
fn deposit_fixed_point_is_consistent() {
    let Some(gpu) = common::gpu() else { return };
    let scene = scene("cornell-box.toml", 32, 50_000);
    // Summed by the gather; with no room for hits, by the atomics of resumed photon threads;
    // and by the atomics of a pass that adds every hit at once (49 photons a point, as the
    // renderer chooses by itself here).
    assert!(renderer(&gpu, &scene).deposits_at_once(), "49 photons a visible point are added at once");
    for (deposits, capacity) in [(Deposits::Gathered, None), (Deposits::Gathered, Some(0)), (Deposits::AtOnce, None)] {
        deposit_fixed_point_is_consistent_with(&gpu, &scene, deposits, capacity);
    }
}

fn deposit_fixed_point_is_consistent_with(gpu: &GpuContext, scene: &Scene, deposits: Deposits, capacity: Option<u32>) {
    let (per_photon_max, per_photon_sum_min) = cornell_box_deposit_bounds(scene);
    let mut sppm = renderer_with(gpu, scene, deposits);
    if let Some(c) = capacity {
        sppm.set_photon_hit_capacity(c);
    }
    sppm.trace_camera_paths();
    sppm.build_grid().unwrap();
    sppm.trace_photons();
    let (gathered, resumed) = sppm.photon_hits_gathered().unwrap();
    assert_eq!(resumed > 0, capacity == Some(0), "{deposits:?} {capacity:?}: {resumed} photon threads resumed");
    assert_eq!(gathered > 0, deposits == Deposits::Gathered && capacity.is_none(), "{deposits:?}: {gathered} hits gathered");
    let accum = sppm.flux_accum().unwrap();
    let points = sppm.visible_point_positions().unwrap();
    assert!(accum.len() >= points.len() * ACCUM_STRIDE as usize);

    // f32 rounding of beta, and the truncation of each addition to
    // 2^-32, move a sum by far less than this relative margin.
    const MARGIN: f64 = 1e-3;
    let (mut with_photons, mut carried) = (0, 0);
    for (i, p) in points.iter().enumerate() {
        let (phi, m) = slot(&accum, i);
        let base = i * ACCUM_STRIDE as usize;
        assert_eq!(accum[base + 7], 0, "point {i}: spare word written");
        for (c, v) in phi.iter().enumerate() {
            assert!(v.is_finite() && *v >= 0.0, "point {i}: flux[{c}] = {v}");
        }
        if p[3] == 0.0 {
            assert_eq!(m, 0, "point {i} has no visible point but {m} photons");
        }
        if m == 0 {
            assert_eq!(phi, [0.0; 3], "point {i}: flux without photons");
            continue;
        }
        with_photons += 1;
        let m = m as f64;
        for (c, v) in phi.iter().enumerate() {
            assert!(*v <= m * per_photon_max * (1.0 + MARGIN), "point {i}: flux[{c}] {v} > {m} photons * {per_photon_max}");
        }
        let sum: f64 = phi.iter().sum();
        assert!(
            sum >= m * per_photon_sum_min * (1.0 - MARGIN),
            "point {i}: flux {phi:?} (sum {sum}) < {m} photons * {per_photon_sum_min}"
        );
        if phi.iter().any(|&v| v >= 1.0) {
            carried += 1;
        }
    }
    eprintln!("{with_photons} of {} points with photons, {carried} with a channel >= 1", points.len());
    assert!(with_photons > points.len() / 2, "only {with_photons} points got photons");
    assert!(carried > with_photons / 4, "only {carried} points exercised the high word");
}

/// Where a photon's flux is added does not change a bit of the sums: after a pass whose hits
/// all go to the gather (photon_gather.wgsl), one with no room for hits (every photon thread
/// stops at its first deposit, and is resumed after the gather to deposit at once through the
/// grid of visible points), one with room for a third, and one that adds every hit at once
/// (`Deposits::AtOnce`, the grid's lists built before the photons), the accumulators are the
/// same word for word.
#[test]
fn gathered_and_direct_deposits_leave_the_same_bits() {
    let Some(gpu) = common::gpu() else { return };
    let scene = scene("cornell-spheres.toml", 32, 20_000);
    let mut at_once = renderer_with(&gpu, &scene, Deposits::AtOnce);
    at_once.trace_camera_paths();
    at_once.build_grid().unwrap();
    at_once.trace_photons();
    assert_eq!(at_once.photon_hits_gathered().unwrap(), (0, 0), "nothing stored, nothing resumed");
    let at_once = at_once.flux_accum().unwrap();
    let one_pass = |capacity: Option<u32>| {
        let mut sppm = renderer(&gpu, &scene);
        assert!(!sppm.deposits_at_once(), "20 photons a visible point are gathered");
        if let Some(c) = capacity {
            sppm.set_photon_hit_capacity(c);
        }
        sppm.trace_camera_paths();
        sppm.build_grid().unwrap();
        sppm.trace_photons();
        (sppm.flux_accum().unwrap(), sppm.photon_hits_gathered().unwrap(), sppm.photon_hit_capacity())
    };
    let (gathered, (hits, resumed), capacity) = one_pass(None);
    assert!(hits > 1000 && hits <= capacity && resumed == 0, "{hits} hits for {capacity} places, {resumed} threads resumed");
    let counted = gathered.chunks(ACCUM_STRIDE as usize).filter(|s| s[6] > 0).count();
    assert!(counted > 100, "only {counted} points got photons");
    if let Some(w) = gathered.iter().zip(&at_once).position(|(x, y)| x != y) {
        let point = w / ACCUM_STRIDE as usize;
        panic!("word {w} (point {point}) {} gathered, {} all added at once", gathered[w], at_once[w]);
    }
    for capacity in [0, hits / 3] {
        let (accum, (some_hits, resumed), _) = one_pass(Some(capacity));
        assert!(
            some_hits == capacity && resumed > 0,
            "capacity {capacity}: {some_hits} hits gathered, {resumed} threads resumed"
        );
        if let Some(w) = gathered.iter().zip(&accum).position(|(x, y)| x != y) {
            let point = w / ACCUM_STRIDE as usize;
            panic!("capacity {capacity}: word {w} (point {point}) {} gathered, {} deposited at once", gathered[w], accum[w]);
        }
    }
}

/// The deposit is order-independent: two renderers with the same scene and seed leave the
/// same bits in the accumulator after one pass, and another seed does not.
#[test]
fn deposit_is_deterministic() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = scene("cornell-spheres.toml", 32, 20_000);
    let one_pass = |scene: &Scene| {
        let mut sppm = renderer(&gpu, scene);
        sppm.trace_camera_paths();
        sppm.build_grid().unwrap();
        sppm.trace_photons();
        sppm.flux_accum().unwrap()
    };
    let a = one_pass(&scene);
    let b = one_pass(&scene);
    let counted = a.chunks(ACCUM_STRIDE as usize).filter(|s| s[6] > 0).count();
    assert!(counted > 0, "no photon reached any visible point");
    if let Some(w) = a.iter().zip(&b).position(|(x, y)| x != y) {
        panic!("same seed, different accumulator: word {w} (point {}) {} vs {}", w / ACCUM_STRIDE as usize, a[w], b[w]);
    }
    scene.render.seed += 1;
    let c = one_pass(&scene);
    assert!(a != c, "a different seed gave the same accumulator");
}

/// The hashed grid built over the visible points of a real pass (the second, so radii
/// differ from point to point): for random query points, the candidates of the query's cell
/// that pass `point_within` are exactly the brute-force set.
#[test]
fn grid_over_gpu_visible_points_matches_brute_force() {
    let Some(gpu) = common::gpu() else { return };
    let scene = scene("cornell-spheres.toml", 64, 20_000);
    let mut sppm = renderer(&gpu, &scene);
    sppm.run_pass().unwrap();
    sppm.trace_camera_paths();
    let points = sppm.visible_point_positions().unwrap();
    let valid: Vec<usize> = (0..points.len()).filter(|&i| points[i][3] > 0.0).collect();
    assert!(valid.len() > points.len() / 2, "only {} visible points", valid.len());
    let radii: HashSet<u32> = valid.iter().map(|&i| points[i][3].to_bits()).collect();
    assert!(radii.len() > 1, "every radius is the same after a pass");
    let max_r = valid.iter().map(|&i| points[i][3]).fold(0.0f32, f32::max);

    // Scene bounds, widened by the largest radius so that some queries fall outside the grid.
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for t in &scene.triangles {
        for p in t.p {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    for s in &scene.spheres {
        lo = lo.min(s.center - s.radius);
        hi = hi.max(s.center + s.radius);
    }
    lo -= Vec3::splat(max_r);
    hi += Vec3::splat(max_r);

    let grid = build_grid(&points);
    let mut rng = Rng(0x005e_ed0f_9a1d);
    let (mut hits, mut total_found) = (0, 0);
    const QUERIES: usize = 4000;
    for q in 0..QUERIES {
        // Half uniform in the scene's box, half near a visible point (inside and just outside
        // its radius), where the answers are not empty.
        let p = if q % 2 == 0 {
            Vec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z))
        } else {
            let v = points[valid[rng.below(valid.len())]];
            Vec3::new(v[0], v[1], v[2]) + rng.unit_vec3() * (v[3] * rng.range(0.0, 1.5))
        };
        let candidates = grid.candidates(p);
        let unique: HashSet<u32> = candidates.iter().copied().collect();
        assert_eq!(unique.len(), candidates.len(), "query {p:?}: a point listed twice in one bucket");
        let found: HashSet<u32> = candidates.iter().copied().filter(|&i| point_within(&points[i as usize], p)).collect();
        let expected: HashSet<u32> = brute_force_within(&points, p).into_iter().collect();
        if found != expected {
            let missed: Vec<_> = expected.difference(&found).collect();
            let extra: Vec<_> = found.difference(&expected).collect();
            panic!("query {q} at {p:?}: grid missed {missed:?}, found extra {extra:?}");
        }
        if !expected.is_empty() {
            hits += 1;
            total_found += expected.len();
        }
    }
    eprintln!("{hits} of {QUERIES} queries found points ({total_found} in all), {} grid entries", grid.entries.len());
    assert!(hits > QUERIES / 3, "only {hits} queries found a point");
}

/// The grid the kernels build (grid_setup, grid_count, grid_scan, grid_fill) against the
/// host's `build_grid_in` over the same points with the same parameters: the parameters
/// follow `GridParams::covering`, every bucket's offset is the same, and every bucket lists
/// the same points (in any order: the GPU fills buckets by atomics).
#[test]
fn gpu_grid_build_matches_cpu_oracle() {
    let Some(gpu) = common::gpu() else { return };
    for name in ["cornell-spheres.toml", "motion-blur.toml"] {
        let scene = scene(name, 48, 20_000);
        let mut sppm = renderer(&gpu, &scene);
        // Two passes first, so that radii differ from point to point (after one, every point
        // with photons has r0 sqrt(alpha)).
        sppm.run_pass().unwrap();
        sppm.run_pass().unwrap();
        sppm.trace_camera_paths();
        sppm.build_grid().unwrap();
        sppm.build_point_grid();
        let points = sppm.visible_point_positions().unwrap();
        let (params, cell_start, entries) = sppm.grid().unwrap();

        let max_r = points.iter().map(|p| p[3]).fold(0.0f32, f32::max);
        let radii: HashSet<u32> = points.iter().map(|p| p[3].to_bits()).collect();
        assert!(radii.len() > 10, "{name}: radii should vary after a pass");
        let data = sppm_gpu::gpu::scene_buffers::SceneData::new(&scene).unwrap();
        let (lo, hi) = data.swept_bounds();
        let table_size = params.table_mask + 1;
        let expected = sppm_gpu::layout::GridParams::covering(lo, hi, max_r, table_size);
        assert_eq!(params, expected, "{name}: grid parameters");

        let cpu = sppm_gpu::accel::build_grid_in(&points, params);
        assert_eq!(cell_start[..cpu.cell_start.len()], cpu.cell_start[..], "{name}: bucket offsets");
        let total = *cpu.cell_start.last().unwrap() as usize;
        assert!(total > points.len(), "{name}: points should be listed in several buckets");
        for h in 0..table_size as usize {
            let range = cpu.cell_start[h] as usize..cpu.cell_start[h + 1] as usize;
            let mut a = entries[range.clone()].to_vec();
            let mut b = cpu.entries[range].to_vec();
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!(a, b, "{name}: bucket {h}");
        }
    }
}

/// The octahedral map of `encode_normal` (shaders/shared/sampling.wgsl) undone on the host,
/// from its two 12-bit coordinates (x in bits 0-11, y in 12-23; 2048 is 0), normalized.
fn decode_normal(e: u32) -> Vec3 {
    let coordinate = |h: u32| ((h & 0xfff) as f32 - 2048.0) / 2047.0;
    let (x, y) = (coordinate(e), coordinate(e >> 12));
    let z = 1.0 - x.abs() - y.abs();
    let t = (-z).max(0.0);
    Vec3::new(x - t.copysign(x), y - t.copysign(y), z).normalize()
}

/// Each visible point keeps its surface's normal, facing the camera, within 1.1e-3 radians,
/// and its camera depth 0 in the top 8 bits: on a diffuse sphere seen from all sides and on
/// the walls of a box around it. The bound is the octahedral map's in 2 x 12 bits: half a
/// step, e = 1 / 4094, per coordinate moves v = (x, y, 1 - |x| - |y|) by at most sqrt(6) e,
/// and v / |v| by at most sqrt(3) times that (|v| >= 1 / sqrt(3)): sqrt(18) e = 1.04e-3.
#[test]
fn visible_points_keep_their_normals() {
    let Some(gpu) = common::gpu() else { return };
    let (center, radius) = (Vec3::new(0.1, -0.05, 0.0), 0.7);
    let scene = sppm_gpu::scene::SceneBuilder::new(96, 96)
        .photons(1000)
        .camera([0.3, 0.4, 3.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 60.0)
        .diffuse("white", [0.5, 0.5, 0.5])
        .sphere(center, radius, "white")
        .quad([-2.0, -1.0, -1.5], [4.0, 0.0, 0.0], [0.0, 3.0, 0.0], "white")
        .emission([1.0, 1.0, 1.0])
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let mut sppm = renderer(&gpu, &scene);
    sppm.trace_camera_paths();
    let positions = sppm.visible_point_positions().unwrap();
    let points = sppm.visible_points().unwrap();
    let (mut on_sphere, mut on_wall, mut worst) = (0, 0, 0.0f32);
    for (q, vp) in positions.iter().zip(&points) {
        if q[3] == 0.0 {
            continue;
        }
        let p = Vec3::new(q[0], q[1], q[2]);
        let expected = if ((p - center).length() - radius).abs() < 1e-3 {
            on_sphere += 1;
            (p - center).normalize()
        } else {
            assert!((p.z + 1.5).abs() < 1e-3, "a visible point off both surfaces at {p}");
            on_wall += 1;
            Vec3::Z
        };
        // The chord between unit vectors, which is the angle for small angles (acos of a dot
        // product near 1 loses it to f32 rounding).
        let angle = (decode_normal(vp.normal) - expected).length();
        worst = worst.max(angle);
        assert!(angle < 1.1e-3, "normal at {p}: {} against {expected}, {angle} rad", decode_normal(vp.normal));
        assert_eq!(vp.normal >> 24, 0, "camera depth of the point at {p}");
    }
    eprintln!("{on_sphere} points on the sphere, {on_wall} on the wall, worst angle {worst:.2e} rad");
    assert!(on_sphere > 1000 && on_wall > 1000, "{on_sphere} on the sphere, {on_wall} on the wall");
}
