// Sampling routines (pbrt-v4, ch. A.5).

// An orthonormal basis around unit n (Duff et al. 2017).
fn basis(n: vec3f) -> mat3x3f {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = vec3f(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = vec3f(b, s + n.y * n.y * a, -n.y);
    return mat3x3f(t, bt, n);
}

// A visible point's normal and camera depth in 32 bits: unit vector n by the octahedral map
// (Cigolle et al. 2014, "A Survey of Efficient Representations for Independent Unit
// Vectors") in two 12-bit coordinates, about 1e-3 radians of error (the normal only decides
// which side a photon arrives from), and in the top 8 bits the scattering events before the
// point, saturated at 255 (vp_depth).
fn encode_normal(n: vec3f, depth: u32) -> u32 {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    let sign_p = select(vec2f(-1.0), vec2f(1.0), p >= vec2f(0.0));
    let folded = select(p, (1.0 - abs(p.yx)) * sign_p, n.z < 0.0);
    // [-1, 1] to 1..4095, 2048 at 0.
    let q = vec2u(round(clamp(folded, vec2f(-1.0), vec2f(1.0)) * 2047.0) + 2048.0);
    return q.x | (q.y << 12u) | (min(depth, 255u) << 24u);
}

// The direction encode_normal stored, not normalized (its length is between 1/sqrt(3) and 1).
fn decode_normal(e: u32) -> vec3f {
    let f = (vec2f(f32(e & 0xfffu), f32((e >> 12u) & 0xfffu)) - 2048.0) / 2047.0;
    let z = 1.0 - abs(f.x) - abs(f.y);
    let t = max(-z, 0.0);
    return vec3f(f.x - select(-t, t, f.x >= 0.0), f.y - select(-t, t, f.y >= 0.0), z);
}

// The depth encode_normal stored: exact below 255.
fn vp_depth(e: u32) -> u32 {
    return e >> 24u;
}

// Concentric mapping of the unit square to the unit disk (Shirley & Chiu 1997).
fn sample_disk(u: vec2f) -> vec2f {
    let o = 2.0 * u - vec2f(1.0);
    if o.x == 0.0 && o.y == 0.0 {
        return vec2f(0.0);
    }
    var r: f32;
    var theta: f32;
    if abs(o.x) > abs(o.y) {
        r = o.x;
        theta = 0.25 * PI * (o.y / o.x);
    } else {
        r = o.y;
        theta = 0.5 * PI - 0.25 * PI * (o.x / o.y);
    }
    return r * vec2f(cos(theta), sin(theta));
}

// Cosine-weighted direction about unit n; pdf = cos(theta) / pi (Malley's method).
fn sample_cosine_hemisphere(n: vec3f, u: vec2f) -> vec3f {
    let d = sample_disk(u);
    let z = sqrt(max(0.0, 1.0 - dot(d, d)));
    return normalize(basis(n) * vec3f(d.x, d.y, z));
}

// Uniform direction on the unit sphere; pdf = 1 / (4 pi).
fn sample_uniform_sphere(u: vec2f) -> vec3f {
    let z = 1.0 - 2.0 * u.x;
    let r = sqrt(max(0.0, 1.0 - z * z));
    let phi = 2.0 * PI * u.y;
    return vec3f(r * cos(phi), r * sin(phi), z);
}

// Uniform barycentrics (b1, b2) on a triangle (Heitz 2019, "A Low-Distortion Map Between
// Triangle and Square").
fn sample_triangle(u: vec2f) -> vec2f {
    var b0: f32;
    var b1: f32;
    if u.x < u.y {
        b0 = u.x / 2.0;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0;
        b0 = u.x - b1;
    }
    return vec2f(b1, 1.0 - b0 - b1);
}

fn max_component(v: vec3f) -> f32 {
    return max(v.x, max(v.y, v.z));
}

fn average(v: vec3f) -> f32 {
    return (v.x + v.y + v.z) * (1.0 / 3.0);
}
