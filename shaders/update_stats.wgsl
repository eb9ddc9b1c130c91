// SPPM per visible point update after a photon pass (Hachisuka & Jensen 2009, eq. 7 and 8;
// in the form of pbrt-v4 sec. 16.3): shrink the radius by the fraction alpha of the new
// photons and scale the accumulated flux tau to the new disc. The pass's flux phi is the
// photons' summed flux (photon_pass.wgsl) times the point's weight. With a global radius schedule
// (Knaus & Zwicker 2011) every pass is an estimate of its own at the pass's radius r: tau
// sums the passes' flux densities phi / (pi r^2), and the radius is the host's to set.

#import types

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(8) var<storage, read> visible_points: array<VisiblePoint>;
@group(0) @binding(10) var<storage, read_write> vp_stats: array<VpStats>;
@group(0) @binding(14) var<storage, read_write> flux_accum: array<u32>;

fn fixed_to_float(lo: u32) -> f32 {
    return f32(flux_accum[lo + 1u]) + f32(flux_accum[lo]) * (1.0 / 4294967296.0);
}

@compute @workgroup_size(64)
fn update_stats(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= frame.vp_count {
        return;
    }
    let base = index * ACCUM_STRIDE;
    let m = f32(flux_accum[base + 6u]);
    if m > 0.0 && frame.global_radius > 0.0 {
        let r = frame.global_radius;
        let phi = visible_points[index].weight * vec3f(fixed_to_float(base), fixed_to_float(base + 2u), fixed_to_float(base + 4u));
        vp_stats[index].tau += phi / (PI * r * r);
        vp_stats[index].n += m;
    } else if m > 0.0 {
        var st = vp_stats[index];
        // Flux relative to frame.power_total; resolve scales it back.
        let phi = visible_points[index].weight * vec3f(fixed_to_float(base), fixed_to_float(base + 2u), fixed_to_float(base + 4u));
        let n_new = st.n + frame.alpha * m;
        let radius_new = st.radius * sqrt(n_new / (st.n + m));
        let shrink = (radius_new * radius_new) / (st.radius * st.radius);
        st.tau = (st.tau + phi) * shrink;
        st.n = n_new;
        st.radius = radius_new;
        vp_stats[index] = st;
    }
    for (var i = 0u; i < ACCUM_STRIDE; i++) {
        flux_accum[base + i] = 0u;
    }
}
