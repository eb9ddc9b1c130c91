// The SPPM estimate of each pixel after the passes so far (Hachisuka & Jensen 2009, eq. 11):
// L = ld / k + tau / (k * photons_per_pass * pi * r^2), averaged over the pixel's samples.

#import types

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(10) var<storage, read> vp_stats: array<VpStats>;
@group(0) @binding(16) var<storage, read_write> image: array<vec4f>;

@compute @workgroup_size(64)
fn resolve(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let pixel = gid.x + gid.y * groups.x * 64u;
    if pixel >= frame.width * frame.height {
        return;
    }
    let k = f32(frame.pass_index + 1u);
    let photons = k * f32(frame.photon_count);
    var sum = vec3f(0.0);
    for (var s = 0u; s < frame.spp; s++) {
        let st = vp_stats[pixel * frame.spp + s];
        let area = PI * st.radius * st.radius;
        sum += st.ld / k + st.tau * frame.power_total / (photons * area);
    }
    var l = sum / f32(frame.spp);
    // Never let a NaN or infinity reach an image.
    l = select(vec3f(0.0), l, (l == l) & (abs(l) < vec3f(3.0e38)));
    image[pixel] = vec4f(l, 1.0);
}
