// The hashed grid of visible points, as src/accel/grid.rs builds it on the host (the CPU
// oracle): cells of GridParams.cell_size from GridParams.origin, hashed to buckets by the
// spatial hash of Teschner et al. 2003; each point is listed in the buckets of the cells its
// box [p - r, p + r] overlaps, at most two per axis.

fn hash_cell(c: vec3u, table_mask: u32) -> u32 {
    return ((c.x * 73856093u) ^ (c.y * 19349663u) ^ (c.z * 83492791u)) & table_mask;
}

// The distinct buckets of the cells the box of point q (xyz, radius w) overlaps; count 0 for
// no point (radius 0).
struct PointBuckets {
    h: array<u32, 8>,
    count: u32,
}

fn point_buckets(g: GridParams, q: vec4f) -> PointBuckets {
    var out: PointBuckets;
    out.count = 0u;
    if !(q.w > 0.0) || any(g.res == vec3u(0u)) {
        return out;
    }
    // Float to u32 saturates negative values to 0, as `as u32` does on the host.
    let lo = vec3u(max((q.xyz - q.w - g.origin) / g.cell_size, vec3f(0.0)));
    let hi = min(min(vec3u(max((q.xyz + q.w - g.origin) / g.cell_size, vec3f(0.0))), g.res - 1u), lo + 1u);
    for (var z = lo.z; z <= hi.z; z++) {
        for (var y = lo.y; y <= hi.y; y++) {
            for (var x = lo.x; x <= hi.x; x++) {
                let h = hash_cell(vec3u(x, y, z), g.table_mask);
                var seen = false;
                for (var i = 0u; i < out.count; i++) {
                    seen = seen || out.h[i] == h;
                }
                if !seen {
                    out.h[out.count] = h;
                    out.count += 1u;
                }
            }
        }
    }
    return out;
}
