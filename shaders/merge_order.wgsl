// vcm, after the grid build: each bucket's entries made the slots of their light vertices
// (light_vertex.wgsl: a merge point's `normal`), in ascending order. The grid build
// (grid_fill.wgsl) lists a bucket's points in an order that depends on timing, and the merge
// points are appended (light_trace.wgsl) in the order the subpaths reach them; merging
// (bidir_connect.wgsl's merge_light_vertices) sums in the bucket's order, so only a fixed
// order makes a seed's image the same bit for bit. One thread a bucket, an insertion sort: a
// bucket lists tens of points.

#import types
#import light_vertex

@group(0) @binding(12) var<storage, read> grid_cell_start: array<u32>;
@group(0) @binding(13) var<storage, read_write> grid_entries: array<u32>;

@compute @workgroup_size(64)
fn merge_order(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let h = gid.x + gid.y * groups.x * 64u;
    if h + 1u >= arrayLength(&grid_cell_start) {
        return;
    }
    let first = grid_cell_start[h];
    let end = min(grid_cell_start[h + 1u], arrayLength(&grid_entries));
    for (var i = first; i < end; i++) {
        grid_entries[i] = visible_points[grid_entries[i]].normal;
    }
    for (var i = first + 1u; i < end; i++) {
        let slot = grid_entries[i];
        var j = i;
        while j > first && grid_entries[j - 1u] > slot {
            grid_entries[j] = grid_entries[j - 1u];
            j--;
        }
        grid_entries[j] = slot;
    }
}
