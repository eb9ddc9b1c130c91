// The path tracers' estimate of every pixel, the mean of its samples (their weighted mean
// under a splatting filter; black where none has weight yet), as PathTracer's image()
// computes it on the host, into a caller's 2D storage texture, alpha 1. The host builds one
// pipeline per texel format by replacing `rgba32float` below (rgba16float too).

#import types

@group(0) @binding(0) var<uniform> frame: Frame;
// Per pixel: the sum of the samples (rgb) and their count (w), or their weighted sum and
// their weights' sum.
@group(0) @binding(16) var<storage, read> radiance: array<vec4f>;
// bpt and vcm under a splatting filter (frame.filter_reach > 0 with light subpaths): the
// light subpaths' splats summed apart (rgb) and the passes (w), added to the camera's mean.
@group(0) @binding(38) var<storage, read> light_sums: array<vec4f>;
@group(0) @binding(19) var out_image: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(64)
fn path_resolve_texture(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let pixel = gid.x + gid.y * groups.x * 64u;
    if pixel >= frame.width * frame.height {
        return;
    }
    let s = radiance[pixel];
    let xy = vec2u(pixel % frame.width, pixel / frame.width);
    var c = select(vec3f(0.0), s.xyz / s.w, s.w > 0.0);
    if frame.filter_reach > 0u && frame.photon_count > 0u {
        let l = light_sums[pixel];
        c += select(vec3f(0.0), l.xyz / l.w, l.w > 0.0);
    }
    textureStore(out_image, xy, vec4f(c, 1.0));
}
