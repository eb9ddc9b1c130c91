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

// Whether a photon at x lies on a visible point's side of the point's surface. The sphere of
// the radius reaches through a thin shell (a lamp shade, a box's walls) to the photons on its
// other side, which the direction test (lights_side) does not always tell apart: across a
// box's edge, around a shade's curve, or arriving at a grazing angle. m is the geometric
// normal of the surface the photon hit, turned to the side it arrived from (as decode_normal
// returns it: not of unit length); n the point's, turned to the camera's side (unit length);
// v = x - p, with p the point's position.
// - Where m lies within the angle of cosine SAME_SURFACE_COS of n, the photon counts: one
//   surface, locally, and one side of it. Mitsuba 0.6's photon map stops there
//   (src/librender/photonmap.cpp, RawRadianceQuery, with which its SPPM gathers: a photon
//   with dot(photonNormal, n) < 0.1 is skipped), which also skips the photons across the
//   creases of a room and darkens its corners in a band of the radius' width (cornell-box:
//   the 8x8 blocks along its creases 3.5% darker, some 25%).
// - Beyond that angle, the photon counts where the two surfaces face each other (each in front
//   of the other, dot(v, n) > 0 and dot(v, m) < 0: the floor and a wall at a room's corner) or
//   turn away from each other (each behind the other: two faces of a block, both outside), as
//   every photon within the radius did before. It is skipped where one lies in front of the
//   other but not the other way round (a photon inside a shell, the point outside it) and
//   where they lie in each other's planes (the two faces of one sheet). The two tests agree
//   when dot(v, n) dot(v, m) is negative, here by a margin of CREASE_SIN^2 |v|^2 |m| that the
//   12-bit normals (about 1e-3 radians) cannot cross.
// Consistent: on a surface whose normal is continuous the photons within r of a point have
// normals within an angle O(r) of the point's (the curvature times r), so once r is small
// enough none on the point's own side of its own surface is skipped, and the estimate
// converges as it did without the test. Photons with another normal lie on another surface or
// within r of a crease: the points near a crease whose estimate the test changes lie in a band
// whose area goes to 0 with r, and the photons of another surface are not the point's to
// gather at any radius. A local test cannot see a third surface between the two: a wall seen
// through the gap between itself and a lamp shade's cap gathers photons from inside the shade
// (they face each other) until the radius is smaller than the gap.
// At least 0 (same_side squares it).
const SAME_SURFACE_COS: f32 = 0.1;
const CREASE_SIN: f32 = 0.01;

fn same_side(n: vec3f, m: vec3f, v: vec3f) -> bool {
    // cos > SAME_SURFACE_COS, without a square root: the common case, in the gather's loop.
    let c = dot(n, m);
    let m2 = dot(m, m);
    if c > 0.0 && c * c > SAME_SURFACE_COS * SAME_SURFACE_COS * m2 {
        return true;
    }
    return dot(v, n) * dot(v, m) < -(CREASE_SIN * CREASE_SIN) * dot(v, v) * sqrt(m2);
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

// The bucket of the cell holding p alone (corner 0), as a PointBuckets; none for no point
// (radius 0) or outside the grid.
fn own_bucket(g: GridParams, p: vec3f, r: f32) -> PointBuckets {
    var out: PointBuckets;
    out.h[0] = bucket_of(g, p);
    out.keep = select(0u, 1u, r > 0.0 && out.h[0] != NO_BUCKET);
    return out;
}

// Whether corner k's bucket is one to visit (bit k of b.keep).
fn visits(b: PointBuckets, k: u32) -> bool {
    return ((b.keep >> k) & 1u) != 0u;
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

// The word encode_normal's place holds for a visible point or photon hit in a participating
// medium (shared/medium.wgsl): no direction (its 24 low bits 0, which encode_normal never
// writes), the depth in the top 8.
fn volume_normal(depth: u32) -> u32 {
    return min(depth, 255u) << 24u;
}

// A visible point in a participating medium gathers within VOLUME_RADIUS_SCALE times its slot's
// radius. The radius is set for surfaces (pixel footprints, src/integrators/sppm.rs), where
// photons land on a plane; in a medium they are spread through space, and a sphere of that
// radius holds few of them, while a wider one costs a gather that grows as its volume. At
// equal time (20 s, 128x128, relMSE against references): fog-cornell 1.6e-2 at 1x, 3.1e-3 at
// 2x, 1.35e-3 at 4x; the Cornell box in fog (visible points dense in front of it) 3.7e-3,
// 4.2e-3, 1.0e-2, and 4x darkens both by 0.5 to 1% (docs/journal/session-16.md,
// "Participating media (issue 35)").
const VOLUME_RADIUS_SCALE: f32 = 2.0;

// Whether a visible point's or photon hit's word marks it as in a medium.
fn in_volume(e: u32) -> bool {
    return USES_MEDIA && (e & 0xffffffu) == 0u;
}
