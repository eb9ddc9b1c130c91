// The grid build's steps 2 and 4 (grid_count.wgsl, grid_fill.wgsl) walk the same cells: each
// visible point the buckets of the cells its box overlaps (point_buckets in shared/grid.wgsl),
// or with LISTS_OWN_CELL the bucket of its own cell (own_bucket), counting itself in each, then
// listing itself.

#import types
#import grid

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(2) var<storage, read> grid_params: GridParams;
@group(0) @binding(3) var<storage, read_write> grid_cell_count: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read> visible_points: array<VisiblePoint>;

// Each point listed only in the bucket of the cell holding it (vcm's light vertices, which a
// merge looks up from the cells its own box overlaps), not in those of every cell its box
// overlaps (SPPM's visible points, which a photon looks up from its own cell).
override LISTS_OWN_CELL: bool = false;

// Thread gid's visible point and its buckets; none to visit past the last point.
struct PointWalk {
    index: u32,
    buckets: PointBuckets,
}

fn point_walk(gid: vec3u, groups: vec3u) -> PointWalk {
    var walk: PointWalk;
    walk.index = gid.x + gid.y * groups.x * 64u;
    if walk.index < frame.vp_count {
        let q = visible_points[walk.index];
        if LISTS_OWN_CELL {
            walk.buckets = own_bucket(grid_params, q.p, q.radius);
        } else {
            walk.buckets = point_buckets(grid_params, q.p, q.radius);
        }
    }
    return walk;
}
