// The hashed grid of visible points, as src/accel/grid.rs builds it on the host (the CPU
// oracle): cells of GridParams.cell_size from GridParams.origin, hashed to buckets by the
// spatial hash of Teschner et al. 2003; each point is listed in the buckets of the cells its
// box [p - r, p + r] overlaps, at most two per axis.

fn hash_cell(c: vec3u, table_mask: u32) -> u32 {
    return ((c.x * 73856093u) ^ (c.y * 19349663u) ^ (c.z * 83492791u)) & table_mask;
}

// The bucket of the cell holding p, or NO_BUCKET outside the grid (a NaN position too).
fn bucket_of(g: GridParams, p: vec3f) -> u32 {
    let c = floor((p - g.origin) / g.cell_size);
    if !all((c >= vec3f(0.0)) & (c < vec3f(g.res))) {
        return NO_BUCKET;
    }
    return hash_cell(vec3u(c), g.table_mask);
}

const NO_BUCKET: u32 = 0xffffffffu;

// Whether a photon at p is within the radius r of a visible point at vp (the photon pass's
// deposits and photon_gather decide with this one expression; a NaN distance is not).
fn within_radius(vp: vec3f, r: f32, p: vec3f) -> bool {
    let delta = p - vp;
    return !(dot(delta, delta) >= r * r);
}

// Whether a photon travelling along d lights the side that normal n faces (a photon from
// behind a visible point's surface does not light it).
fn lights_side(n: vec3f, d: vec3f) -> bool {
    return !(dot(n, d) >= 0.0);
}

// Whether a photon that scattered `photon_depth` times lights a visible point that its camera
// path reached after `vp_depth` scattering events: the joined path scatters vp_depth + 1 +
// photon_depth times, and max_depth bounds the whole path, as it does a path tracer's (and
// Mitsuba's `path`), so that every method renders the same image.
fn within_depth(vp_depth: u32, photon_depth: u32, max_depth: u32) -> bool {
    return vp_depth + photon_depth < max_depth;
}

// The buckets of the cells the box [p - r, p + r] of a point overlaps, at most two cells per
// axis: h[k] for corner k = x + 2 y + 4 z of the 2x2x2 block from the box's lowest cell, and
// bit k of `keep` set where that cell lies in the box and no earlier corner has its bucket (a
// point is listed once per bucket). `keep` is 0 for no point (radius 0). The loops have
// constant bounds, so a driver can unroll them and keep h in registers.
struct PointBuckets {
    h: array<u32, 8>,
    keep: u32,
}

fn point_buckets(g: GridParams, p: vec3f, r: f32) -> PointBuckets {
    var out: PointBuckets;
    out.keep = 0u;
    if !(r > 0.0) || any(g.res == vec3u(0u)) {
        return out;
    }
    // Float to u32 saturates negative values to 0, as `as u32` does on the host.
    let lo = vec3u(max((p - r - g.origin) / g.cell_size, vec3f(0.0)));
    let hi = min(min(vec3u(max((p + r - g.origin) / g.cell_size, vec3f(0.0))), g.res - 1u), lo + 1u);
    for (var k = 0u; k < 8u; k++) {
        let c = lo + vec3u(k & 1u, (k >> 1u) & 1u, k >> 2u);
        let h = hash_cell(c, g.table_mask);
        out.h[k] = h;
        var seen = any(c > hi);
        for (var j = 0u; j < k; j++) {
            seen = seen || (((out.keep >> j) & 1u) != 0u && out.h[j] == h);
        }
        if !seen {
            out.keep |= 1u << k;
        }
    }
    return out;
}

// A key of a float that orders as the float does (as u32), so that atomicMax finds the
// largest float and, on the complement, the smallest (the bounds of the visible points that
// photon_pass aims environment photons at). Not for NaN.
fn order_key(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    return select(b ^ 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

// The float of an order_key.
fn from_order_key(k: u32) -> f32 {
    return bitcast<f32>(select(~k, k ^ 0x80000000u, (k & 0x80000000u) != 0u));
}
