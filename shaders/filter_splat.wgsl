// The end of a pass whose camera samples are splatted through a wide pixel filter
// (frame.filter_reach > 0): each pixel gathers the pass's samples of the pixels within the
// filter's reach, weighted by the filter at each sample's offset from the pixel's centre,
// and adds their weighted sum (rgb) and the weights' sum (w) to its sums. The image is their
// ratio, Mitsuba's weighted splatting (a pixel averages the samples of about 3 pixels under
// its default gaussian, where filter importance sampling averages its own alone), written
// as a gather so that no two threads add to one pixel.

#import types
#import rng
#import sampling
#import camera
#import camera_samples

@group(0) @binding(0) var<uniform> frame: Frame;
// Per pixel: the sum of the passes' weighted samples (rgb) and of their weights (w).
@group(0) @binding(16) var<storage, read_write> radiance: array<vec4f>;

@compute @workgroup_size(64)
fn filter_splat(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let pixel = gid.x + gid.y * groups.x * 64u;
    if pixel >= frame.width * frame.height {
        return;
    }
    let rows = vec2i(splat_rows());
    let x = i32(pixel % frame.width);
    let y = i32(frame.row_offset + pixel / frame.width);
    let reach = i32(frame.filter_reach);
    var sum = vec3f(0.0);
    var weights = 0.0;
    for (var dy = -reach; dy <= reach; dy++) {
        let row = y + dy;
        if row < rows.x || row >= rows.y {
            continue;
        }
        for (var dx = -reach; dx <= reach; dx++) {
            let column = x + dx;
            if column < 0 || column >= i32(frame.width) {
                continue;
            }
            let s = camera_samples[u32(row - rows.x) * frame.width + u32(column)];
            // The sample's offset from this pixel's centre.
            let d = vec2f(f32(dx), f32(dy)) + camera_sample_jitter(s) - 0.5;
            let w = filter_density(d.x) * filter_density(d.y);
            sum += w * camera_sample_radiance(s);
            weights += w;
        }
    }
    radiance[pixel] += vec4f(sum, weights);
}
