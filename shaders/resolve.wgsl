// The SPPM estimate of every pixel into the `image` buffer (rgba32float, row-major).

#import types
#import estimate

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(39) var<storage, read_write> image: array<vec4f>;

@compute @workgroup_size(64)
fn resolve(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let pixel = gid.x + gid.y * groups.x * 64u;
    if pixel >= frame.width * frame.height {
        return;
    }
    image[pixel] = vec4f(pixel_estimate(pixel), 1.0);
}
