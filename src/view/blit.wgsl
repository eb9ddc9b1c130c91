// The preview window's picture: the estimate (linear RGB) times the exposure, or the
// false-colour error map (display values), drawn into the window at an integer or fitted
// scale and centred, with black around it. sRGB-encoded here unless the surface does it.

struct Display {
    // Window pixel -> image texel: (pixel - offset) / scale.
    offset: vec2f,
    scale: f32,
    // 2^stops.
    exposure: f32,
    image_size: vec2u,
    // 1: the texture holds display values (the error map); 0: linear radiance.
    display_values: u32,
    // 1: the surface encodes sRGB on write, so the output is linear.
    surface_srgb: u32,
}

@group(0) @binding(0) var<uniform> display: Display;
@group(0) @binding(1) var picture: texture_2d<f32>;

// One triangle over the whole window.
@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4f {
    let uv = vec2f(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4f(uv * 2.0 - 1.0, 0.0, 1.0);
}

// The sRGB transfer function (IEC 61966-2-1) and its inverse.
fn encode_srgb(c: vec3f) -> vec3f {
    return select(1.055 * pow(c, vec3f(1.0 / 2.4)) - 0.055, 12.92 * c, c <= vec3f(0.0031308));
}

fn decode_srgb(c: vec3f) -> vec3f {
    return select(pow((c + 0.055) / 1.055, vec3f(2.4)), c / 12.92, c <= vec3f(0.04045));
}

@fragment
fn fs(@builtin(position) pixel: vec4f) -> @location(0) vec4f {
    let texel = (pixel.xy - display.offset) / display.scale;
    if any(texel < vec2f(0.0)) || any(texel >= vec2f(display.image_size)) {
        return vec4f(0.0, 0.0, 0.0, 1.0);
    }
    let c = textureLoad(picture, vec2u(texel), 0).rgb;
    // Display values for the window: the estimate exposed and clamped, as a PNG shows it.
    var shown = c;
    if display.display_values == 0u {
        shown = encode_srgb(clamp(c * display.exposure, vec3f(0.0), vec3f(1.0)));
    }
    if display.surface_srgb != 0u {
        shown = decode_srgb(shown);
    }
    return vec4f(shown, 1.0);
}
