// SPPM per visible point update after a photon pass (Hachisuka & Jensen 2009, eq. 7 and 8;
// in the form of pbrt-v4 sec. 16.3): shrink the radius by the fraction alpha of the new
// photons and scale the accumulated flux tau to the new disc. The pass's flux phi is the
// photons' summed flux (photon_pass.wgsl) times the point's weight. With a global radius schedule
// (Knaus & Zwicker 2011) every pass is an estimate of its own at the pass's radius r: tau
// sums the passes' flux densities phi / (pi r^2), and the radius is the host's to set; under a
// wide pixel filter each pass's estimate is instead a camera sample, splatted (filter_splat).
//
// The adaptive rule (ADAPTIVE_RADIUS, radius_rule = "adaptive"): the disc estimate is biased
// only where the photon density varies over the disc, so a point keeps its radius nearly
// (alpha = ALPHA_UNIFORM) while its photons look uniform over the disc and shrinks by alpha
// once they do not, as Lin et al. 2020 ("CPPM: Chi-squared Progressive Photon Mapping") decide
// with a chi-square test on sector counts. The test here uses the photons' offsets
// u = (x - p) / r instead of sectors: uniform on the unit disc, E[u] = 0, Cov[u] = I / 4 in
// the disc's plane (0 along its normal),
// E[|u|^2] = 1/2, Var[|u|^2] = 1/12 and Cov[u, |u|^2] = 0, so for M photons
//   X^2 = |sum u|^2 / (M / 4) + (sum (|u|^2 - 1/2))^2 / (M / 12)
// is chi-square with 3 degrees of freedom (the score test of a density with a gradient and
// a curvature across the disc, the terms of the disc estimate's bias). Sums run over the
// passes since the last rejection, so the test grows stronger as the estimate's noise falls;
// a rejection restarts them. A pass's alpha is decided by the tests before it, never by its own
// photons. Consistency: a pass's alpha lies in [alpha, ALPHA_UNIFORM], inside (0, 1), so N
// grows without bound, and each pass with M photons scales r^2 by at most
// (N + 0.95 M) / (N + M) = 1 - 0.05 M / (N + M), a product that goes to 0 (N <= the photons so
// far, and sum M_i / sum_{j<=i} M_j diverges): r -> 0, as under the plain rule.
//
// A visible point in a participating medium (in_volume) estimates the fluence from the volume
// photons in its sphere, of volume 4/3 pi r^3: its radius shrinks by the cube root,
// r^3 (N + M) = r'^3 (N + alpha M) (Knaus & Zwicker 2011, sec. 5: the 3D kernel). It gathers
// within k r, k = VOLUME_RADIUS_SCALE (shared/grid.wgsl), and its pass's flux enters tau as
// phi 3 / (4 k^3 r), so that tau / (pi r^2) (resolve.wgsl) is the sphere's density
// tau_3d / (4/3 pi (k r)^3) with tau_3d scaled by (r' / r)^3. The adaptive rule's test, of a
// disc, is not applied to it.

#import types
#import grid
#import camera_samples

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(8) var<storage, read> visible_points: array<VisiblePoint>;
@group(0) @binding(10) var<storage, read_write> vp_stats: array<VpStats>;
@group(0) @binding(14) var<storage, read_write> flux_accum: array<u32>;
// One a visible point with ADAPTIVE_RADIUS (else one in all, unused).
@group(0) @binding(27) var<storage, read_write> radius_tests: array<RadiusTest>;

// What a point in a medium of slot radius r multiplies its pass's flux by, so that tau / (pi r^2)
// is the density over its sphere of radius k r, k = VOLUME_RADIUS_SCALE: 3 / (4 k^3 r).
fn volume_flux_scale(r: f32) -> f32 {
    let k = VOLUME_RADIUS_SCALE;
    return 0.75 / (k * k * k * r);
}

fn fixed_to_float(lo: u32) -> f32 {
    return f32(flux_accum[lo + 1u]) + f32(flux_accum[lo]) * (1.0 / 4294967296.0);
}

// Fold the pass's m photons, with offset moments at words base + 8 .. base + 11, into the
// adaptive rule's test, and test once enough photons are in.
fn radius_test(st: ptr<function, RadiusTest>, base: u32, m: u32) {
    // Exact signed sums: sum (u + 1) OFFSET_SCALE - m OFFSET_SCALE, modulo 2^32.
    let axes = vec3u(flux_accum[base + 8u], flux_accum[base + 9u], flux_accum[base + 10u]) - m * OFFSET_SCALE;
    let sum_u = vec3f(bitcast<vec3i>(axes)) / f32(OFFSET_SCALE);
    let spread = bitcast<i32>(flux_accum[base + 11u] - m * (SPREAD_SCALE / 2u));
    // In 3D: on a flat surface the part along the normal is 0; photons off the disc's plane
    // (on a second wall across an edge, on a curved surface) show in it, and bias the
    // estimate too (the disc's area is then not pi r^2).
    (*st).offset_sum += sum_u;
    (*st).spread_sum += f32(spread) / f32(SPREAD_SCALE);
    (*st).tested += m;
    if (*st).tested < RADIUS_TEST_PHOTONS {
        return;
    }
    let count = f32((*st).tested);
    let g = (*st).offset_sum;
    let chi2 = dot(g, g) / (0.25 * count) + (*st).spread_sum * (*st).spread_sum / (count / 12.0);
    (*st).tests += 1u;
    if chi2 > RADIUS_TEST_CHI2 {
        (*st).shrinking = 1u;
        (*st).rejections += 1u;
        (*st).offset_sum = vec3f(0.0);
        (*st).spread_sum = 0.0;
        (*st).tested = 0u;
    } else {
        (*st).shrinking = 0u;
    }
}

@compute @workgroup_size(64)
fn update_stats(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= frame.vp_count {
        return;
    }
    let base = index * accum_stride();
    let m = f32(flux_accum[base + 6u]);
    if m > 0.0 && frame.global_radius > 0.0 {
        let r = frame.global_radius;
        var phi = visible_points[index].weight * vec3f(fixed_to_float(base), fixed_to_float(base + 2u), fixed_to_float(base + 4u));
        if in_volume(visible_points[index].normal) {
            phi *= volume_flux_scale(r);
        }
        let density = phi / (PI * r * r);
        if frame.filter_reach > 0u {
            // Under a splatting filter the pass's estimate completes the point's camera sample
            // (camera_pass.wgsl): its direct light and this density, scaled as resolve scales
            // tau; filter_splat then splats it.
            let s = camera_samples[index];
            let l = camera_sample_radiance(s) + density * (frame.power_total / f32(frame.photon_count));
            store_camera_sample(index, finite_sample(l), camera_sample_jitter(s));
        } else {
            vp_stats[index].tau += density;
        }
        vp_stats[index].n += m;
    } else if m > 0.0 {
        var st = vp_stats[index];
        // Flux relative to frame.power_total; resolve scales it back.
        var phi = visible_points[index].weight * vec3f(fixed_to_float(base), fixed_to_float(base + 2u), fixed_to_float(base + 4u));
        let volume = in_volume(visible_points[index].normal);
        var alpha = frame.alpha;
        var test: RadiusTest;
        if ADAPTIVE_RADIUS && !volume {
            test = radius_tests[index];
            if test.shrinking == 0u {
                alpha = max(frame.alpha, ALPHA_UNIFORM);
            }
        }
        let n_new = st.n + alpha * m;
        var radius_new = st.radius * sqrt(n_new / (st.n + m));
        if volume {
            radius_new = st.radius * pow(n_new / (st.n + m), 1.0 / 3.0);
            phi *= volume_flux_scale(st.radius);
        }
        let shrink = (radius_new * radius_new) / (st.radius * st.radius);
        st.tau = (st.tau + phi) * shrink;
        st.n = n_new;
        st.radius = radius_new;
        if ADAPTIVE_RADIUS && !volume {
            radius_test(&test, base, flux_accum[base + 6u]);
            radius_tests[index] = test;
        }
        vp_stats[index] = st;
    }
    for (var i = 0u; i < accum_stride(); i++) {
        flux_accum[base + i] = 0u;
    }
}
