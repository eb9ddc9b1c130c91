// The envmap environment (src/scene/envmap.rs, which this mirrors): radiance from an
// equirectangular image at infinity, looked up as Mitsuba 3's envmap, and sampled by a
// piecewise-constant distribution over the cells between texel centres by luminance times
// sin(theta) (pbrt-v4 sec. A.5.2, 12.5.2).
//
// The environment emitter's prim_ref is the first of its entries in `texels`, NO_TEXTURE for
// a constant environment; its radiance is the map's scale. From there:
//   [0]: (W, H as bits, -, -);
//   [1..3]: the columns of to_world (the map's frame to the world; orthonormal);
//   [4, 4 + W H): texel (x, y) at 4 + y W + x, linear RGB, and in w for y < H - 1 the
//     running sum over cells 0..x of row y of P(cell | row), the last 1;
//   then the running sums of P(row) over the H - 1 rows, four to an entry, the last 1.

// Whether the scene's environment is an image (src/scene/emitter/environment.rs).
override USES_ENVMAP: bool = true;

// Whether environment emitter e is an image, without a load where the scene says.
fn is_envmap(e: Emitter) -> bool {
    return USES_ENVMAP && e.prim_ref != NO_TEXTURE;
}

fn envmap_size(base: u32) -> vec2u {
    let h = texels[base];
    return vec2u(bitcast<u32>(h.x), bitcast<u32>(h.y));
}

// Running sum of P(row) up to row j of the map at base of size n.
fn envmap_marginal(base: u32, n: vec2u, j: u32) -> f32 {
    return texels[base + 4u + n.x * n.y + j / 4u][j % 4u];
}

// Running sum of P(cell | row j) up to cell i.
fn envmap_conditional(base: u32, n: vec2u, i: u32, j: u32) -> f32 {
    return texels[base + 4u + j * n.x + i].w;
}

fn envmap_texel(base: u32, n: vec2u, i: u32, j: u32) -> vec3f {
    return texels[base + 4u + j * n.x + i].xyz;
}

// The cell (i, j) holding (u, v) and the offsets (s, t) in it: x = u W - 1/2, wrapped, and
// y = v (H - 1), as Mitsuba's lookup places texel centres.
struct EnvmapCell {
    i: u32,
    j: u32,
    st: vec2f,
}

fn envmap_cell(n: vec2u, uv: vec2f) -> EnvmapCell {
    var x = uv.x * f32(n.x) - 0.5;
    x = select(x, x + f32(n.x), x < 0.0);
    let y = clamp(uv.y, 0.0, 1.0) * f32(n.y - 1u);
    let i = min(u32(max(x, 0.0)), n.x - 1u);
    let j = min(u32(max(y, 0.0)), n.y - 2u);
    return EnvmapCell(i, j, vec2f(x - f32(i), y - f32(j)));
}

// Mitsuba 3's bilinear lookup at (u, v), before the scale.
fn envmap_lookup(base: u32, n: vec2u, c: EnvmapCell) -> vec3f {
    let i1 = select(c.i + 1u, 0u, c.i + 1u == n.x);
    let top = mix(envmap_texel(base, n, c.i, c.j), envmap_texel(base, n, i1, c.j), c.st.x);
    let bottom = mix(envmap_texel(base, n, c.i, c.j + 1u), envmap_texel(base, n, i1, c.j + 1u), c.st.x);
    return mix(top, bottom, c.st.y);
}

// Density over [0, 1]^2 of cell c: P(row) P(cell | row) W (H - 1), by differences of the
// running sums, as the sampler chooses.
fn envmap_pdf_uv(base: u32, n: vec2u, c: EnvmapCell) -> f32 {
    let pm = envmap_marginal(base, n, c.j) - select(0.0, envmap_marginal(base, n, c.j - 1u), c.j > 0u);
    let pc = envmap_conditional(base, n, c.i, c.j) - select(0.0, envmap_conditional(base, n, c.i - 1u, c.j), c.i > 0u);
    return pm * pc * f32(n.x * (n.y - 1u));
}

// World direction w in the map's frame (to_world transposed).
fn envmap_local(base: u32, w: vec3f) -> vec3f {
    return vec3f(dot(texels[base + 1u].xyz, w), dot(texels[base + 2u].xyz, w), dot(texels[base + 3u].xyz, w));
}

// Mitsuba 3's direction_to_uv: u = atan2(d.x, -d.z) / 2 pi, wrapped into [0, 1), v = acos(d.y)
// / pi.
fn envmap_uv(d: vec3f) -> vec2f {
    let u = atan2(d.x, -d.z) * (0.5 * INV_PI);
    return vec2f(u - floor(u), acos(clamp(d.y, -1.0, 1.0)) * INV_PI);
}

// Radiance and solid-angle density (without the light's pmf) of direction w (unit) of the
// environment map of e.
struct EnvmapEval {
    l: vec3f,
    pdf: f32,
}

fn envmap_eval(e: Emitter, w: vec3f) -> EnvmapEval {
    let base = e.prim_ref;
    let n = envmap_size(base);
    let d = envmap_local(base, w);
    let c = envmap_cell(n, envmap_uv(d));
    let sin_theta = length(d.xz);
    // d omega = 2 pi^2 sin(theta) du dv.
    let pdf = select(0.0, envmap_pdf_uv(base, n, c) / (2.0 * PI * PI * sin_theta), sin_theta > 0.0);
    return EnvmapEval(e.radiance * envmap_lookup(base, n, c), pdf);
}

// A direction of the environment map of e (world, unit) for the numbers u in [0, 1)^2, with
// its radiance and solid-angle density (without the pmf): a row by the marginal running sums
// (u.y), a cell by its row's (u.x), each number reused for the point within the cell.
struct EnvmapSample {
    wi: vec3f,
    l: vec3f,
    pdf: f32,
}

fn sample_envmap(e: Emitter, u: vec2f) -> EnvmapSample {
    let base = e.prim_ref;
    let n = envmap_size(base);
    let j = find_cdf(Cdf(CDF_ENVMAP_ROWS, base, n, 0u), n.y - 1u, u.y);
    let m0 = select(0.0, envmap_marginal(base, n, j - 1u), j > 0u);
    let pm = envmap_marginal(base, n, j) - m0;
    let i = find_cdf(Cdf(CDF_ENVMAP_CELLS, base, n, j), n.x, u.x);
    let c0 = select(0.0, envmap_conditional(base, n, i - 1u, j), i > 0u);
    let pc = envmap_conditional(base, n, i, j) - c0;
    let st = clamp(vec2f((u.x - c0) / pc, (u.y - m0) / pm), vec2f(0.0), vec2f(1.0));
    // Back to (u, v): x = i + s = u W - 1/2, y = j + t = v (H - 1).
    let x = (f32(i) + st.x + 0.5) / f32(n.x);
    let v = (f32(j) + st.y) / f32(n.y - 1u);
    let theta = v * PI;
    let phi = (x - floor(x)) * (2.0 * PI);
    let sin_theta = sin(theta);
    let d = vec3f(sin(phi) * sin_theta, cos(theta), -cos(phi) * sin_theta);
    let wi = texels[base + 1u].xyz * d.x + texels[base + 2u].xyz * d.y + texels[base + 3u].xyz * d.z;
    let pdf = select(0.0, pm * pc * f32(n.x * (n.y - 1u)) / (2.0 * PI * PI * sin_theta), sin_theta > 0.0);
    let c = EnvmapCell(min(i, n.x - 1u), j, st);
    return EnvmapSample(wi, e.radiance * envmap_lookup(base, n, c), pdf);
}
