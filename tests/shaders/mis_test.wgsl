// The oracle of the bidirectional family's MIS weights (shared/vcm.wgsl): for a path of k
// segments from a light vertex x0 to the camera at xk through diffuse vertices, every
// strategy that can make it is weighted as the kernels weight it, from the recursive
// quantities carried along each subpath, and the weights are summed: 1 for a right recursion.
// Strategies: emission hit by the camera subpath, next-event estimation at x1, a connection
// between x(s-1) and x(s) for 1 < s < k, light tracing (x(k-1) joined to the camera) and, with
// merging, a merge at each of the MERGES_A_PATH interior vertices nearest the camera of those
// that merge (its flag: vcm merges only at some materials, bidir.wgsl's vcm_merges_at; only
// at the camera subpath's first vertices that merge, vcm.wgsl; and not at x1, whose light
// vertex comes straight from the light, vcm_merges_light). Each path has its own shares of camera vertices that
// connect (c) and merge (m), the strategies' counts in the heuristic.

#import vcm

struct MisTestParams {
    paths: u32,
    // Light subpaths a pass (n_light), light choice probability and light area.
    n_light: f32,
    pick: f32,
    area: f32,
    // pi r^2 n_light.
    eta_vcm: f32,
    // A pixel's area on the image plane at distance 1 along the camera's axis.
    a_pix: f32,
    _pad: vec2u,
}

// Per path: 8 vertices (xyz, and w = k, the segments, in vertex 0, m in vertex 1), then 8
// normals (of x0 .. x(k-1); w = 1 where the vertex merges), then the camera's axis (w = c).
const MAX_VERTICES: u32 = 8u;
const PATH_WORDS: u32 = 17u;

@group(0) @binding(0) var<uniform> params: MisTestParams;
@group(0) @binding(1) var<storage, read> paths: array<vec4f>;
// Per path: the sum with connections only (BPT), with connections and merges (VCM), and the
// number of strategies of each.
@group(0) @binding(2) var<storage, read_write> sums: array<vec4f>;

var<private> base: u32;

fn x(i: u32) -> vec3f {
    return paths[base + i].xyz;
}

fn n(i: u32) -> vec3f {
    return paths[base + MAX_VERTICES + i].xyz;
}

fn dir(i: u32, j: u32) -> vec3f {
    return normalize(x(j) - x(i));
}

// Whether vertex i merges.
fn merges(i: u32) -> bool {
    return paths[base + MAX_VERTICES + i].w > 0.5;
}

// How many of the vertices from x(i) to the camera merge, at most MERGES_A_PATH: those of a
// camera subpath that reaches x(i).
fn merged_from(k: u32, i: u32) -> u32 {
    var n = 0u;
    for (var j = i; j < k; j++) {
        n += select(0u, 1u, merges(j));
    }
    return min(n, MERGES_A_PATH);
}

// Whether light-side vertex x(i) merges (bidir.wgsl's vcm_merges_light): where it merges,
// but not x1, reached straight from the light.
fn light_merges(i: u32) -> bool {
    return merges(i) && i > 1u;
}

// Whether merging at camera-side vertex x(i) is a strategy: one of the camera subpath's first
// MERGES_A_PATH vertices that merge.
fn camera_merges(k: u32, i: u32) -> bool {
    return merges(i) && merged_from(k, i + 1u) < MERGES_A_PATH;
}

// |cos| at vertex i towards vertex j.
fn cos_at(i: u32, j: u32) -> f32 {
    return abs(dot(n(i), dir(i, j)));
}

// Diffuse BSDF density at vertex i of sampling the direction to j.
fn pdf_w(i: u32, j: u32) -> f32 {
    return cos_at(i, j) / 3.14159265;
}

// Area density at j of a solid-angle density p from vertex i.
fn to_area(p: f32, i: u32, j: u32) -> f32 {
    let d = length(x(j) - x(i));
    return p * cos_at(j, i) / (d * d);
}

// The camera's density, in solid angle per pixel, of the direction to vertex j.
fn camera_pdf_w(k: u32, j: u32) -> f32 {
    let c = dot(dir(k, j), paths[base + 2u * MAX_VERTICES].xyz);
    return 1.0 / (params.a_pix * c * c * c);
}

// The light subpath x0 .. x(last), reached at x(last) and not scattered there.
fn light_subpath(last: u32, f: MisFactors) -> SubpathMis {
    let direct_pdf_a = params.pick / params.area;
    let emission_pdf_w = direct_pdf_a * pdf_w(0u, 1u);
    var m = mis_light_start(direct_pdf_a, emission_pdf_w, cos_at(0u, 1u), false, f);
    m = mis_hit(m, length(x(1u) - x(0u)), cos_at(1u, 0u), true);
    for (var i = 1u; i < last; i++) {
        m = mis_scatter(m, pdf_w(i, i + 1u), pdf_w(i, i - 1u), cos_at(i, i + 1u), false, light_merges(i), i == 1u, f);
        m = mis_hit(m, length(x(i + 1u) - x(i)), cos_at(i + 1u, i), true);
    }
    return m;
}

// The camera subpath xk .. x(first), reached at x(first) and not scattered there.
fn camera_subpath(k: u32, first: u32, f: MisFactors) -> SubpathMis {
    var m = mis_camera_start(camera_pdf_w(k, k - 1u), params.n_light);
    m = mis_hit(m, length(x(k - 1u) - x(k)), cos_at(k - 1u, k), true);
    for (var i = k - 1u; i > first; i--) {
        // At x(i) towards x(i - 1); the reverse is towards the camera's side, x(i + 1) (the
        // camera itself for i = k - 1: a pinhole's direction is not sampled by the BSDF, but
        // the reverse density only enters through d_vc, which is 0 there).
        let rev = select(pdf_w(i, i + 1u), 0.0, i + 1u == k);
        m = mis_scatter(m, pdf_w(i, i - 1u), rev, cos_at(i, i - 1u), false, camera_merges(k, i), i + 1u == k, f);
        m = mis_hit(m, length(x(i - 1u) - x(i)), cos_at(i - 1u, i), true);
    }
    return m;
}

// The reverse density at camera-side vertex i given the direction to j: towards x(i + 1), or
// 0 at the first camera vertex (see camera_subpath).
fn camera_rev(k: u32, i: u32) -> f32 {
    return select(pdf_w(i, i + 1u), 0.0, i + 1u == k);
}

// The sum of the weights of every strategy that makes the path, with factors f; the number
// of strategies in w.
fn weight_sum(k: u32, f: MisFactors, with_merging: bool) -> vec2f {
    var sum = 0.0;
    var count = 0.0;
    let direct_pdf_a = params.pick / params.area;
    // Emission hit by the camera subpath at x0.
    let c0 = camera_subpath(k, 0u, f);
    sum += mis_weight_emission(c0, direct_pdf_a, direct_pdf_a * pdf_w(0u, 1u), camera_merges(k, 1u), f);
    count += 1.0;
    // Next-event estimation at x1.
    let c1 = camera_subpath(k, 1u, f);
    let d01 = length(x(1u) - x(0u));
    let direct_pdf_w = direct_pdf_a * d01 * d01 / cos_at(0u, 1u);
    sum += mis_weight_nee(c1, direct_pdf_w, direct_pdf_a * pdf_w(0u, 1u), cos_at(1u, 0u), cos_at(0u, 1u), pdf_w(1u, 0u),
        camera_rev(k, 1u), false, k == 2u, f);
    count += 1.0;
    // Connections of x(s - 1) to x(s).
    for (var s = 2u; s < k; s++) {
        let l = light_subpath(s - 1u, f);
        let c = camera_subpath(k, s, f);
        sum += mis_weight_connection(c, l, to_area(pdf_w(s, s - 1u), s, s - 1u), camera_rev(k, s),
            to_area(pdf_w(s - 1u, s), s - 1u, s), pdf_w(s - 1u, s - 2u), camera_merges(k, s), merged_from(k, s),
            light_merges(s - 1u), s + 1u == k, s == 2u, f);
        count += 1.0;
    }
    // Light tracing: x(k - 1) joined to the camera.
    let lt = light_subpath(k - 1u, f);
    let camera_pdf_a = to_area(camera_pdf_w(k, k - 1u), k, k - 1u);
    sum += mis_weight_to_camera(lt, camera_pdf_a, pdf_w(k - 1u, k - 2u), params.n_light, light_merges(k - 1u), k == 2u, f);
    count += 1.0;
    // A merge at x(i), one of the MERGES_A_PATH vertices nearest the camera of those that merge,
    // the light subpath's last direction from x(i - 1).
    if with_merging {
        for (var i = 1u; i < k; i++) {
            // x1's light vertex is straight from the light: not in the grid.
            if !camera_merges(k, i) || i == 1u {
                continue;
            }
            let l = light_subpath(i, f);
            let c = camera_subpath(k, i, f);
            sum += mis_weight_merge(c, l, pdf_w(i, i - 1u), camera_rev(k, i), merged_from(k, i), i + 1u == k, i == 1u, f);
            count += 1.0;
        }
    }
    return vec2f(sum, count);
}

@compute @workgroup_size(64)
fn mis_test(@builtin(global_invocation_id) gid: vec3u) {
    if gid.x >= params.paths {
        return;
    }
    base = gid.x * PATH_WORDS;
    let k = u32(paths[base].w);
    let c = paths[base + 2u * MAX_VERTICES].w;
    let eta = paths[base + 1u].w * params.eta_vcm;
    let bpt = weight_sum(k, MisFactors(1.0, 0.0, mis(c)), false);
    let vcm = weight_sum(k, MisFactors(mis(1.0 / eta), mis(eta), mis(c)), true);
    sums[gid.x] = vec4f(bpt.x, vcm.x, bpt.y, vcm.y);
}
