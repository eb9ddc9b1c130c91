// The SPPM estimate of a pixel after the passes so far (Hachisuka & Jensen 2009, eq. 11):
// L = ld / k + tau / (k * photons_per_pass * pi * r^2), averaged over the pixel's samples,
// with k = frame.pass_index + 1 - frame.first_pass passes. With a global radius schedule
// tau is already a sum of densities (update_stats.wgsl): L = ld / k + tau / (k *
// photons_per_pass), the mean of the passes' own estimates (Knaus & Zwicker 2011). Never NaN
// or infinite: such a value reads as 0. Under a splatting filter (frame.filter_reach > 0,
// global schedule) the passes' estimates were splatted (filter_splat, camera_pass.wgsl): the
// pixel's weighted sum over its weights, plus the mean of the direct light summed apart.

@group(0) @binding(10) var<storage, read> vp_stats: array<VpStats>;
// Under a splatting filter, per pixel: the weighted sum of the passes' estimates (rgb) and
// of their weights (w), and the direct light summed apart (rgb) over passes (w); placeholders
// else.
@group(0) @binding(16) var<storage, read> radiance: array<vec4f>;
@group(0) @binding(40) var<storage, read> direct_sums: array<vec4f>;

fn pixel_estimate(pixel: u32) -> vec3f {
    if frame.filter_reach > 0u {
        let s = radiance[pixel];
        let direct = direct_sums[pixel];
        let l = select(vec3f(0.0), s.xyz / s.w, s.w > 0.0) + select(vec3f(0.0), direct.xyz / direct.w, direct.w > 0.0);
        return select(vec3f(0.0), l, (l == l) & (abs(l) < vec3f(3.0e38)));
    }
    let k = f32(frame.pass_index + 1u - frame.first_pass);
    let photons = k * f32(frame.photon_count);
    var sum = vec3f(0.0);
    for (var s = 0u; s < frame.spp; s++) {
        let st = vp_stats[pixel * frame.spp + s];
        let area = select(PI * st.radius * st.radius, 1.0, frame.global_radius > 0.0);
        sum += st.ld / k + st.tau * frame.power_total / (photons * area);
    }
    let l = sum / f32(frame.spp);
    return select(vec3f(0.0), l, (l == l) & (abs(l) < vec3f(3.0e38)));
}
