// One binary search over the running sums (cdfs) the lights are sampled by: the emitters'
// (lights.wgsl, chosen in proportion to power) and an environment map's rows and cells
// (envmap.wgsl). WGSL passes no functions, so the table is named by a Cdf; imported by
// lights.wgsl, which holds `emitters` and imports envmap.wgsl.

// A table, named by `table`: CDF_EMITTERS, CDF_ENVMAP_ROWS (P(row)) or CDF_ENVMAP_CELLS
// (P(cell | row)).
struct Cdf {
    table: u32,
    // The environment map's first entry and size (envmap.wgsl).
    base: u32,
    n: vec2u,
    // The row whose cells CDF_ENVMAP_CELLS searches.
    row: u32,
}

const CDF_EMITTERS: u32 = 0u;
const CDF_ENVMAP_ROWS: u32 = 1u;
const CDF_ENVMAP_CELLS: u32 = 2u;

// Running sum k of table c.
fn cdf_at(c: Cdf, k: u32) -> f32 {
    if c.table == CDF_EMITTERS {
        return emitters[k].cdf;
    } else if c.table == CDF_ENVMAP_ROWS {
        return envmap_marginal(c.base, c.n, k);
    }
    return envmap_conditional(c.base, c.n, k, c.row);
}

// First index k < count whose running sum exceeds u (the last is 1 > u).
fn find_cdf(c: Cdf, count: u32, u: f32) -> u32 {
    var lo = 0u;
    var hi = count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if cdf_at(c, mid) <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}
