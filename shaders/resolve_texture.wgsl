// The SPPM estimate of every pixel into a caller's 2D storage texture, alpha 1. The host
// builds one pipeline per texel format by replacing `rgba32float` below (rgba16float too).

#import types
#import estimate

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(19) var out_image: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(64)
fn resolve_texture(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let pixel = gid.x + gid.y * groups.x * 64u;
    if pixel >= frame.width * frame.height {
        return;
    }
    let xy = vec2u(pixel % frame.width, pixel / frame.width);
    textureStore(out_image, xy, vec4f(pixel_estimate(pixel), 1.0));
}
