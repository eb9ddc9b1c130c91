// A pass's camera samples where they are splatted through a wide pixel filter
// (frame.filter_reach > 0): one a pixel of splat_rows() (shared/camera.wgsl), written by the
// kernel that traces them (path_trace, bidir_camera) and gathered by filter_splat. A sample
// keeps its radiance's bits (xyz) and its place in the pixel from the corner, two 16-bit
// fractions (w).

@group(0) @binding(37) var<storage, read_write> camera_samples: array<vec4u>;

// A sample's radiance, or black where it is NaN or infinite, rather than poisoning its pixel.
fn finite_sample(l: vec3f) -> vec3f {
    return select(vec3f(0.0), l, all(l == l) && all(abs(l) < vec3f(3.0e38)));
}

// Store the pass's sample `item`: radiance l (finite), at `jitter` in its pixel.
fn store_camera_sample(item: u32, l: vec3f, jitter: vec2f) {
    camera_samples[item] = vec4u(bitcast<vec3u>(l), pack2x16unorm(jitter));
}

// A stored sample's radiance.
fn camera_sample_radiance(s: vec4u) -> vec3f {
    return bitcast<vec3f>(s.xyz);
}

// A stored sample's place in its pixel, from the pixel's corner.
fn camera_sample_jitter(s: vec4u) -> vec2f {
    return unpack2x16unorm(s.w);
}
